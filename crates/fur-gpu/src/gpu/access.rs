//! Accesses named by intent, and the barriers between them derived, not written.
//!
//! A pass says what it does with each image or buffer ([`Access`]: "read as storage by
//! the hair stages", "the depth attachment"), and [`barrier`] works out the pipeline
//! stages, access masks and layouts from two such lists, the way `vk-sync` (and kajiya
//! after it) names its access types: a read after a read in the same layout needs
//! nothing, a read after a write needs the write made visible, a write after reads
//! needs them finished, a change of layout needs a transition. [`Tracker`] keeps each
//! resource's last accesses through a frame, so the frame's passes declare and the
//! barriers follow.

use ash::vk;

/// What a pass does with an image or buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Access {
    /// Written (and read) as storage by a compute shader: the simulation, the skinning.
    ComputeWrite,
    /// Read as storage by the hair stages (vertex, tessellation control and evaluation,
    /// geometry): the posed body.
    HairStagesRead,
    /// Sampled by the hair stages, in the `GENERAL` layout the simulation writes it in:
    /// the strand positions.
    HairStagesSampled,
    /// Read and written as storage by the tessellation control and geometry stages:
    /// the hair counters.
    CounterStagesReadWrite,
    /// Written by a transfer command (a fill or a copy into it).
    TransferWrite,
    /// Read by a transfer command (a copy or a blit out of it).
    TransferRead,
    /// Tested and written as the depth attachment of a rendering scope.
    DepthAttachment,
    /// Written (and blended) as a colour attachment of a rendering scope.
    ColorAttachment,
    /// Sampled by the geometry and fragment stages (the shadow map as the fur and the
    /// skin read it).
    ShadingSampled,
    /// Read as storage by a compute shader.
    ComputeRead,
    /// Sampled by a compute shader (the body's depth as the compute strand passes read it).
    ComputeSampled,
    /// Read as the arguments of an indirect dispatch or draw.
    IndirectRead,
}

impl Access {
    /// The pipeline stages the access happens in.
    pub fn stages(self) -> vk::PipelineStageFlags2 {
        use vk::PipelineStageFlags2 as S;
        match self {
            Access::ComputeWrite => S::COMPUTE_SHADER,
            Access::HairStagesRead | Access::HairStagesSampled => {
                S::VERTEX_SHADER
                    | S::TESSELLATION_CONTROL_SHADER
                    | S::TESSELLATION_EVALUATION_SHADER
                    | S::GEOMETRY_SHADER
            }
            Access::CounterStagesReadWrite => S::TESSELLATION_CONTROL_SHADER | S::GEOMETRY_SHADER,
            Access::TransferWrite => S::ALL_TRANSFER,
            Access::TransferRead => S::COPY | S::BLIT,
            Access::DepthAttachment => S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
            Access::ColorAttachment => S::COLOR_ATTACHMENT_OUTPUT,
            Access::ShadingSampled => S::GEOMETRY_SHADER | S::FRAGMENT_SHADER,
            Access::ComputeRead | Access::ComputeSampled => S::COMPUTE_SHADER,
            Access::IndirectRead => S::DRAW_INDIRECT,
        }
    }

    /// The memory accesses it makes.
    pub fn access(self) -> vk::AccessFlags2 {
        use vk::AccessFlags2 as A;
        match self {
            Access::ComputeWrite => A::SHADER_STORAGE_WRITE | A::SHADER_STORAGE_READ,
            Access::HairStagesRead => A::SHADER_STORAGE_READ,
            Access::CounterStagesReadWrite => A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE,
            Access::TransferWrite => A::TRANSFER_WRITE,
            Access::TransferRead => A::TRANSFER_READ,
            Access::DepthAttachment => {
                A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE
            }
            Access::ColorAttachment => A::COLOR_ATTACHMENT_READ | A::COLOR_ATTACHMENT_WRITE,
            Access::ShadingSampled | Access::ComputeSampled | Access::HairStagesSampled => {
                A::SHADER_SAMPLED_READ
            }
            Access::ComputeRead => A::SHADER_STORAGE_READ,
            Access::IndirectRead => A::INDIRECT_COMMAND_READ,
        }
    }

    /// The writes among [`Access::access`]: what a later access must wait to see.
    pub fn writes(self) -> vk::AccessFlags2 {
        use vk::AccessFlags2 as A;
        self.access()
            & (A::SHADER_STORAGE_WRITE
                | A::TRANSFER_WRITE
                | A::DEPTH_STENCIL_ATTACHMENT_WRITE
                | A::COLOR_ATTACHMENT_WRITE)
    }

    /// The layout an image is in for this access (`GENERAL` for storage).
    pub fn layout(self) -> vk::ImageLayout {
        use vk::ImageLayout as L;
        match self {
            Access::ComputeWrite
            | Access::HairStagesRead
            | Access::HairStagesSampled
            | Access::CounterStagesReadWrite
            | Access::ComputeRead
            | Access::IndirectRead => L::GENERAL,
            Access::TransferWrite => L::TRANSFER_DST_OPTIMAL,
            Access::TransferRead => L::TRANSFER_SRC_OPTIMAL,
            Access::DepthAttachment => L::DEPTH_ATTACHMENT_OPTIMAL,
            Access::ColorAttachment => L::COLOR_ATTACHMENT_OPTIMAL,
            Access::ShadingSampled | Access::ComputeSampled => L::SHADER_READ_ONLY_OPTIMAL,
        }
    }
}

/// A resource's state between passes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct State {
    /// The accesses since its last write (or the write itself): a write waits for all
    /// of them to finish.
    pub accesses: Vec<Access>,
    /// The last write, while its results may still be invisible to some stage.
    pub write: Option<Access>,
    /// The stages the last write has been made visible to.
    pub visible: vk::PipelineStageFlags2,
    /// Whether the next use overwrites the contents whole (an image then transitions
    /// from `UNDEFINED`).
    pub discard: bool,
}

impl State {
    /// The state of a resource last used by `accesses` (in an earlier frame, perhaps
    /// still in flight), its contents kept.
    pub fn after(accesses: &[Access]) -> Self {
        Self {
            accesses: accesses.to_vec(),
            write: accesses.iter().copied().find(|a| !a.writes().is_empty()),
            visible: vk::PipelineStageFlags2::empty(),
            discard: false,
        }
    }

    /// [`State::after`] for a resource whose next use overwrites it whole.
    pub fn discarded_after(accesses: &[Access]) -> Self {
        Self {
            discard: true,
            ..Self::after(accesses)
        }
    }
}

/// One side of a dependency: the pipeline stages, and the memory accesses of them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Scope {
    pub stages: vk::PipelineStageFlags2,
    pub access: vk::AccessFlags2,
}

impl Scope {
    pub const fn new(stages: vk::PipelineStageFlags2, access: vk::AccessFlags2) -> Self {
        Self { stages, access }
    }

    /// No stage and no access: nothing to wait for (an image's first use).
    pub const NONE: Scope = Scope::new(vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
}

/// The dependency a use needs on what came before: source and destination scopes and,
/// for an image, the layouts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Barrier {
    pub src: Scope,
    pub dst: Scope,
    pub old_layout: vk::ImageLayout,
    pub new_layout: vk::ImageLayout,
}

fn stages_of(list: &[Access]) -> vk::PipelineStageFlags2 {
    list.iter()
        .fold(vk::PipelineStageFlags2::empty(), |s, a| s | a.stages())
}

fn accesses_of(list: &[Access], f: fn(Access) -> vk::AccessFlags2) -> vk::AccessFlags2 {
    list.iter()
        .fold(vk::AccessFlags2::empty(), |s, a| s | f(*a))
}

/// The barrier `next` needs after `before`, or `None` where none is needed: reads after
/// reads (or after a write already visible to their stages) in one layout. `image`
/// says whether layouts count; all of `next` share one layout.
pub fn barrier(before: &State, next: &[Access], image: bool) -> Option<Barrier> {
    let new_layout = next
        .first()
        .map_or(vk::ImageLayout::UNDEFINED, |a| a.layout());
    debug_assert!(!image || next.iter().all(|a| a.layout() == new_layout));
    let old_layout = match (before.discard, before.accesses.first()) {
        (false, Some(a)) => a.layout(),
        _ => vk::ImageLayout::UNDEFINED,
    };
    let next_stages = stages_of(next);
    let writes_next = !accesses_of(next, Access::writes).is_empty();
    let transition = image && (old_layout != new_layout || before.discard);
    let unseen = before
        .write
        .filter(|_| !before.visible.contains(next_stages));
    if !transition && !writes_next && unseen.is_none() {
        return None;
    }
    // The last write is made available to what comes next: a read that has not seen
    // it, a write after it (write-after-write), a layout transition (itself a write).
    let write = before
        .write
        .filter(|_| unseen.is_some() || writes_next || transition);
    let mut src_stages = stages_of(&before.accesses);
    if let Some(w) = write {
        src_stages |= w.stages();
    }
    if src_stages.is_empty() && !transition {
        return None;
    }
    let src_access = write.map_or(vk::AccessFlags2::empty(), Access::writes);
    let dst_access = if src_access.is_empty() && !transition {
        vk::AccessFlags2::empty()
    } else {
        accesses_of(next, Access::access)
    };
    let (old_layout, new_layout) = if image {
        (old_layout, new_layout)
    } else {
        (vk::ImageLayout::UNDEFINED, vk::ImageLayout::UNDEFINED)
    };
    Some(Barrier {
        src: Scope::new(
            if src_stages.is_empty() {
                vk::PipelineStageFlags2::NONE
            } else {
                src_stages
            },
            src_access,
        ),
        dst: Scope::new(next_stages, dst_access),
        old_layout,
        new_layout,
    })
}

/// Each resource's state through a frame: `K` names the resources (the frame's enum of
/// them). [`Tracker::access`] returns the barrier a use needs and records the use.
pub struct Tracker<K> {
    states: Vec<(K, State)>,
    /// The state of a resource at its first use.
    first: fn(K) -> State,
}

impl<K: Copy + PartialEq + std::fmt::Debug> Tracker<K> {
    /// A tracker whose resources start in `initial`'s states (their last use in the
    /// previous frame); a resource not named starts unused.
    pub fn new(initial: Vec<(K, State)>) -> Self {
        Self {
            states: initial,
            first: |_| State::after(&[]),
        }
    }

    /// A tracker in which each resource starts, at its first use, in the state
    /// `first` gives it (how the previous submission left it).
    pub fn starting(first: fn(K) -> State) -> Self {
        Self {
            states: Vec::new(),
            first,
        }
    }

    /// Records that `key` is next used by `next` and returns the barrier that use
    /// needs.
    pub fn access(&mut self, key: K, next: &[Access], image: bool) -> Option<Barrier> {
        let index = match self.states.iter().position(|(k, _)| *k == key) {
            Some(i) => i,
            None => {
                self.states.push((key, (self.first)(key)));
                self.states.len() - 1
            }
        };
        let state = &mut self.states[index].1;
        let needed = barrier(state, next, image);
        let write = next.iter().copied().find(|a| !a.writes().is_empty());
        if write.is_some() {
            state.accesses = next.to_vec();
            state.write = write;
            state.visible = vk::PipelineStageFlags2::empty();
        } else {
            if needed.is_some_and(|b| !b.src.access.is_empty()) {
                state.visible |= stages_of(next);
            }
            // A layout change must be waited for by a later write: it counts as a use.
            if needed.is_some_and(|b| b.old_layout != b.new_layout) {
                state.accesses.clear();
            }
            for a in next {
                if !state.accesses.contains(a) {
                    state.accesses.push(*a);
                }
            }
        }
        state.discard = false;
        needed
    }

    /// The state `key` is in now.
    pub fn state(&self, key: K) -> Option<&State> {
        self.states.iter().find(|(k, _)| *k == key).map(|(_, s)| s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vk::AccessFlags2 as A;
    use vk::PipelineStageFlags2 as S;

    #[test]
    fn a_read_after_a_read_in_one_layout_needs_nothing() {
        let before = State::after(&[Access::HairStagesRead]);
        assert_eq!(barrier(&before, &[Access::HairStagesRead], false), None);
        let sampled = State::after(&[Access::ShadingSampled]);
        assert_eq!(barrier(&sampled, &[Access::ShadingSampled], true), None);
    }

    #[test]
    fn a_read_after_a_write_makes_the_write_visible_to_the_reading_stages() {
        let before = State::after(&[Access::ComputeWrite]);
        let b = barrier(&before, &[Access::HairStagesRead], false).expect("a barrier");
        assert_eq!(b.src.stages, S::COMPUTE_SHADER);
        assert!(b.src.access.contains(A::SHADER_STORAGE_WRITE));
        assert!(
            !b.src.access.contains(A::SHADER_STORAGE_READ),
            "reads are not flushed"
        );
        assert!(b.dst.stages.contains(S::GEOMETRY_SHADER | S::VERTEX_SHADER));
        assert_eq!(b.dst.access, A::SHADER_STORAGE_READ);
    }

    #[test]
    fn a_write_after_reads_waits_for_them_without_a_memory_dependency() {
        let before = State::after(&[Access::HairStagesRead]);
        let b = barrier(&before, &[Access::ComputeWrite], false).expect("a barrier");
        assert_eq!(
            b.src,
            Scope::new(Access::HairStagesRead.stages(), A::empty())
        );
        assert_eq!(b.dst, Scope::new(S::COMPUTE_SHADER, A::empty()));
    }

    #[test]
    fn a_change_of_layout_transitions_and_a_discard_starts_from_undefined() {
        let written = State::after(&[Access::DepthAttachment]);
        let b = barrier(&written, &[Access::ShadingSampled], true).expect("a transition");
        assert_eq!(b.old_layout, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL);
        assert_eq!(b.new_layout, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL);
        assert!(b.src.access.contains(A::DEPTH_STENCIL_ATTACHMENT_WRITE));
        assert_eq!(b.dst.access, A::SHADER_SAMPLED_READ);
        let reused = State::discarded_after(&[Access::ShadingSampled]);
        let b = barrier(&reused, &[Access::DepthAttachment], true).expect("a transition");
        assert_eq!(b.old_layout, vk::ImageLayout::UNDEFINED);
        assert_eq!(
            b.src,
            Scope::new(Access::ShadingSampled.stages(), A::empty())
        );
        assert_eq!(b.new_layout, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL);
    }

    #[test]
    fn the_tracker_makes_a_write_wait_for_every_read_since_the_last_barrier() {
        let mut t = Tracker::new(vec![("map", State::after(&[Access::DepthAttachment]))]);
        assert!(t.access("map", &[Access::ShadingSampled], true).is_some());
        assert!(t.access("map", &[Access::ShadingSampled], true).is_none());
        assert_eq!(
            t.state("map").unwrap().accesses,
            vec![Access::ShadingSampled]
        );
        let mut t = Tracker::new(vec![("buf", State::after(&[Access::ComputeWrite]))]);
        assert!(t.access("buf", &[Access::HairStagesRead], false).is_some());
        assert!(t.access("buf", &[Access::HairStagesRead], false).is_none());
        // The write is not yet visible to the fragment stage: a read there needs it.
        let b = t.access("buf", &[Access::ShadingSampled], false).unwrap();
        assert_eq!(
            b.src.stages,
            S::COMPUTE_SHADER | Access::HairStagesRead.stages()
        );
        assert!(b.src.access.contains(A::SHADER_STORAGE_WRITE));
        let b = t.access("buf", &[Access::TransferWrite], false).unwrap();
        // After the earlier write and every read since it.
        assert_eq!(
            b.src.stages,
            S::COMPUTE_SHADER | Access::HairStagesRead.stages() | Access::ShadingSampled.stages()
        );
    }
}

//! The resources one submission's passes share, compute and raster alike, and the
//! barriers between their uses, derived from what each pass declares.
//!
//! The skinning kernel, the simulation's kernels and the render passes (the raster
//! passes and the compute rasteriser's) each say which of these [`Resource`]s they read
//! or write and how ([`Use`]); [`record_uses`] asks the submission's [`Tracker`] for the
//! barriers those uses need and records them. One tracker runs through a whole
//! submission ([`tracker`]: the skinning, then the simulation, then the frame's passes),
//! so no pass writes a barrier of its own and none assumes what ran before it.
//!
//! A resource is registered here once: its name below and its line in
//! [`Resource::registration`] (whether it has layouts, and how the previous submission
//! left it). A render pass that draws into an image also says which image it is
//! (`render::graph::FrameContext::image`).

use ash::vk;

use crate::gpu::{Access, Barrier, Device, State, Tracker};

/// The images and buffers a submission's passes share.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resource {
    /// The strand positions (both images of the pair: the simulation reads one and
    /// writes the other, storage images in `GENERAL`).
    Positions,
    /// A skinned body's root poses and posed vertices, written by the skinning kernel.
    Posed,
    /// The hair counters (and the capture behind them).
    Counters,
    /// The simulation kernel's arrows (the simulation view).
    Probe,
    /// The slot's shadow map.
    ShadowMap,
    /// The target's depth, its multisampled colour (with MSAA) and its single-sample
    /// colour (resolved into, or drawn into without MSAA).
    Depth,
    Color,
    Resolve,
    /// The compute rasteriser's strands: their counts, vertices and segments.
    Strands,
    /// The compute rasteriser's tiles and the entry pool of their lists.
    TileBins,
    /// The compute rasteriser's hair layer, composited over the target.
    HairLayer,
    /// The compute rasteriser's composited image (storage, `GENERAL`), copied onto the
    /// target's single-sample colour.
    Composited,
}

/// What the tracker needs to know of a resource.
pub struct Registration {
    /// Whether it is an image with layouts (storage images stay in `GENERAL` and are
    /// ordered like buffers).
    pub image: bool,
    /// How the previous submission (perhaps still running) left it.
    pub initial: State,
}

impl Resource {
    /// The resource's registration: whether it has layouts, and every access the
    /// previous submission may have made of it (a barrier's source must wait for all
    /// of them; the first write among them is the one to make visible).
    pub fn registration(self) -> Registration {
        use Access::*;
        let (image, initial) = match self {
            Resource::Positions => (
                false,
                State::after(&[ComputeWrite, ComputeRead, HairStagesSampled, TransferRead]),
            ),
            Resource::Posed => (
                false,
                State::after(&[ComputeWrite, ComputeRead, HairStagesRead]),
            ),
            Resource::Probe => (false, State::after(&[ComputeWrite, HairStagesRead])),
            // Read by the host after the previous submission's fence: nothing to wait for.
            Resource::Counters => (false, State::after(&[])),
            Resource::ShadowMap => (
                true,
                State::discarded_after(&[ShadingSampled, ComputeSampled]),
            ),
            Resource::Depth => (
                true,
                State::discarded_after(&[DepthAttachment, ComputeSampled]),
            ),
            Resource::Strands => (
                false,
                State::after(&[ComputeRead, IndirectRead, ComputeWrite]),
            ),
            Resource::TileBins => (false, State::after(&[ComputeWrite, ComputeRead])),
            Resource::HairLayer => (false, State::after(&[ComputeRead])),
            Resource::Composited => (true, State::discarded_after(&[TransferRead])),
            Resource::Color => (true, State::discarded_after(&[ColorAttachment])),
            Resource::Resolve => (
                true,
                State::discarded_after(&[TransferRead, ColorAttachment, TransferWrite]),
            ),
        };
        Registration { image, initial }
    }
}

/// A pass's use of a resource.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Use {
    pub resource: Resource,
    pub access: Access,
}

/// `resource` used by `access`.
pub const fn uses(resource: Resource, access: Access) -> Use {
    Use { resource, access }
}

/// A submission's tracker: each resource starts, at its first use, as the previous
/// submission left it (its registration).
pub fn tracker() -> Tracker<Resource> {
    Tracker::starting(|r| r.registration().initial)
}

/// Records the barriers `list` (the uses of one pass, or of passes that share a
/// rendering scope) needs after what `tracker` has seen, as one dependency, and records
/// the uses. `image_of` gives the image behind a resource with layouts (None for
/// buffers and storage images, ordered by memory barriers).
pub fn record_uses(
    device: &Device,
    cmd: vk::CommandBuffer,
    tracker: &mut Tracker<Resource>,
    list: &[Use],
    image_of: &dyn Fn(Resource) -> Option<(vk::Image, vk::ImageAspectFlags)>,
) {
    let mut resources: Vec<Resource> = Vec::new();
    for u in list {
        if !resources.contains(&u.resource) {
            resources.push(u.resource);
        }
    }
    let mut memory = Vec::new();
    let mut images = Vec::new();
    for resource in resources {
        let accesses: Vec<Access> = list
            .iter()
            .filter(|u| u.resource == resource)
            .map(|u| u.access)
            .collect();
        let has_layouts = resource.registration().image;
        let Some(b) = tracker.access(resource, &accesses, has_layouts) else {
            continue;
        };
        match image_of(resource) {
            Some((raw, aspect)) => images.push(crate::gpu::image_barrier(
                raw,
                aspect,
                b.src,
                b.dst,
                b.old_layout,
                b.new_layout,
            )),
            None => memory.push(memory_barrier(&b)),
        }
    }
    if memory.is_empty() && images.is_empty() {
        return;
    }
    let dependency = vk::DependencyInfo::default()
        .memory_barriers(&memory)
        .image_memory_barriers(&images);
    // SAFETY: callers pass a command buffer of this device recording outside a
    // rendering scope; `image_of` names images alive while the submission is.
    unsafe { device.raw.cmd_pipeline_barrier2(cmd, &dependency) };
}

/// [`record_uses`] for uses of buffers and storage images only (the kernels').
pub fn record_memory_uses(
    device: &Device,
    cmd: vk::CommandBuffer,
    tracker: &mut Tracker<Resource>,
    list: &[Use],
) {
    record_uses(device, cmd, tracker, list, &|_| None);
}

fn memory_barrier(b: &Barrier) -> vk::MemoryBarrier2<'static> {
    vk::MemoryBarrier2::default()
        .src_stage_mask(b.src.stages)
        .src_access_mask(b.src.access)
        .dst_stage_mask(b.dst.stages)
        .dst_access_mask(b.dst.access)
}

#[cfg(test)]
mod tests {
    use super::*;
    use vk::AccessFlags2 as A;
    use vk::PipelineStageFlags2 as S;

    /// The barrier `tracker` derives for `resource` used by `access`.
    fn next(
        tracker: &mut Tracker<Resource>,
        resource: Resource,
        access: Access,
    ) -> Option<Barrier> {
        tracker.access(resource, &[access], resource.registration().image)
    }

    /// A submission of a skinned body, as the session records it: the skinning, two
    /// simulated frames, then the fur pass. Each step waits for what it must, and only
    /// that (seen failing with the positions starting unused, as if nothing had read
    /// them in the submission before).
    #[test]
    fn a_submissions_kernels_and_passes_wait_for_each_other() {
        let mut t = tracker();
        // The skinning's write waits for the previous frame's draws and simulation to
        // finish reading the posed body.
        let skin = next(&mut t, Resource::Posed, Access::ComputeWrite).expect("a barrier");
        assert!(skin
            .src
            .stages
            .contains(S::VERTEX_SHADER | S::COMPUTE_SHADER));
        // The simulation sees the posed body written.
        let read = next(&mut t, Resource::Posed, Access::ComputeRead).expect("a barrier");
        assert_eq!(read.src.access, A::SHADER_STORAGE_WRITE);
        assert!(read.dst.stages.contains(S::COMPUTE_SHADER));
        // Its first write of the positions waits for the last frame's draws and copies.
        let first = next(&mut t, Resource::Positions, Access::ComputeWrite).expect("a barrier");
        assert!(first
            .src
            .stages
            .contains(S::GEOMETRY_SHADER | S::COPY | S::COMPUTE_SHADER));
        // The second frame's write waits for the first (write after write).
        let second = next(&mut t, Resource::Positions, Access::ComputeWrite).expect("a barrier");
        assert_eq!(second.src.stages, S::COMPUTE_SHADER);
        assert_eq!(second.src.access, A::SHADER_STORAGE_WRITE);
        // The fur pass reads the last positions written, and the posed body; a second
        // pass reading them the same way needs nothing more.
        let draw = next(&mut t, Resource::Positions, Access::HairStagesSampled).expect("a barrier");
        assert_eq!(draw.src.access, A::SHADER_STORAGE_WRITE);
        assert_eq!(draw.dst.access, A::SHADER_SAMPLED_READ);
        assert!(draw
            .dst
            .stages
            .contains(S::VERTEX_SHADER | S::GEOMETRY_SHADER));
        assert!(next(&mut t, Resource::Posed, Access::HairStagesRead).is_some());
        assert_eq!(
            next(&mut t, Resource::Positions, Access::HairStagesSampled),
            None
        );
    }

    /// A resource's first use in a submission waits for what its registration says the
    /// previous one left in flight (seen failing with resources starting unused).
    #[test]
    fn a_first_use_waits_for_the_last_submission() {
        for (resource, access) in [
            (Resource::Positions, Access::ComputeWrite),
            (Resource::Posed, Access::ComputeWrite),
            (Resource::Depth, Access::DepthAttachment),
            (Resource::Resolve, Access::ColorAttachment),
        ] {
            let registration = resource.registration();
            let expected =
                crate::gpu::barrier(&registration.initial, &[access], registration.image);
            assert!(expected.is_some(), "{resource:?}: nothing to wait for");
            assert_eq!(
                next(&mut tracker(), resource, access),
                expected,
                "{resource:?}"
            );
        }
    }
}

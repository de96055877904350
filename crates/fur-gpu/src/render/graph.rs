//! The frame as a list of passes. Each pass says where it draws ([`Attachments`]) and
//! what else it reads and writes ([`Use`]); [`record_frame`] derives the barriers
//! between them from those declarations (through the submission's tracker,
//! [`crate::frame`], which the skinning and the simulation declared their uses to
//! first), opens one
//! rendering scope for consecutive passes drawing into the same attachments (the mesh
//! and the fur share the target's, as a frame graph merges passes), and records them.
//! No pass writes a barrier of its own.

use ash::vk;

use super::bindings::{SET_BODY, SET_FRAME};
use super::pipeline::begin_rendering;
use super::slot::RenderSlot;
use super::target::RenderTarget;
use crate::frame::record_uses;
pub use crate::frame::{uses, Resource, Use};
use crate::gpu::{Access, Device, PipelineLayout, Tracker};
use fur_core::render::uniforms::FrameSettings;

/// The attachments a pass draws into; consecutive passes with the same ones share a
/// rendering scope, the first one clearing them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Attachments {
    /// No rendering scope (transfer or compute work).
    None,
    /// The render target: colour (resolved with MSAA) and depth.
    Target,
    /// The slot's shadow map, depth only.
    ShadowMap,
}

impl Attachments {
    /// The uses drawing into these attachments makes.
    fn uses(self, target: &RenderTarget) -> Vec<Use> {
        match self {
            Attachments::None => Vec::new(),
            Attachments::ShadowMap => vec![uses(Resource::ShadowMap, Access::DepthAttachment)],
            Attachments::Target => {
                let mut list = vec![
                    uses(Resource::Depth, Access::DepthAttachment),
                    uses(Resource::Resolve, Access::ColorAttachment),
                ];
                if target.color.is_some() {
                    list.push(uses(Resource::Color, Access::ColorAttachment));
                }
                list
            }
        }
    }
}

/// What the passes of one frame record with.
pub struct FrameContext<'a> {
    pub device: &'a Device,
    pub layout: &'a PipelineLayout,
    pub slot: &'a RenderSlot,
    /// Which of the two position images the simulation last wrote.
    pub current: usize,
    pub target: &'a RenderTarget,
    pub settings: &'a FrameSettings,
    /// Corners of the body's triangles (the mesh and density passes' vertex count).
    pub index_count: u32,
    /// Corners of the fur pass's patches: the body's triangles, then a drawn groom's
    /// (the fur and shadow passes' vertex count).
    pub hair_index_count: u32,
    pub indices: vk::Buffer,
    /// The body's descriptor set.
    pub body_set: vk::DescriptorSet,
    /// The compute rasteriser's set for this slot (null without it).
    pub raster_set: vk::DescriptorSet,
    /// The compute rasteriser's counts for this slot (its indirect dispatch too).
    pub raster_counts: vk::Buffer,
    /// The compute rasteriser's composited image (null without it).
    pub composited: vk::Image,
}

impl FrameContext<'_> {
    /// Binds the frame set of `view` and the body's set for the graphics pipelines.
    fn bind_sets(&self, cmd: vk::CommandBuffer, view: View) {
        self.bind_sets_at(cmd, view, vk::PipelineBindPoint::GRAPHICS);
    }

    /// Binds the camera's frame set, the body's and the compute rasteriser's for the
    /// compute pipelines.
    pub fn bind_compute_sets(&self, cmd: vk::CommandBuffer) {
        self.bind_sets_at(cmd, View::Camera, vk::PipelineBindPoint::COMPUTE);
    }

    fn bind_sets_at(&self, cmd: vk::CommandBuffer, view: View, point: vk::PipelineBindPoint) {
        let frame_set = match view {
            View::Camera => self.slot.sets[self.current],
            View::Light => self.slot.light_sets[self.current],
        };
        let mut sets = vec![vk::DescriptorSet::null(); 2];
        sets[SET_FRAME as usize] = frame_set;
        sets[SET_BODY as usize] = self.body_set;
        if self.raster_set != vk::DescriptorSet::null() {
            sets.push(self.raster_set);
        }
        // SAFETY: the command buffer is recording; the sets and the layout belong to the
        // renderer, which outlives the frame.
        unsafe {
            self.device
                .raw
                .cmd_bind_descriptor_sets(cmd, point, self.layout.raw(), 0, &sets, &[]);
        }
    }

    /// The image behind `resource`, with its aspect (None for buffers and storage
    /// images, which are ordered by memory barriers).
    fn image(&self, resource: Resource) -> Option<(vk::Image, vk::ImageAspectFlags)> {
        let colour = vk::ImageAspectFlags::COLOR;
        match resource {
            Resource::ShadowMap => {
                Some((self.slot.shadow.image.raw(), vk::ImageAspectFlags::DEPTH))
            }
            Resource::Depth => Some((self.target.depth.raw(), vk::ImageAspectFlags::DEPTH)),
            Resource::Color => self.target.color.as_ref().map(|c| (c.raw(), colour)),
            Resource::Resolve => Some((self.target.resolve.raw(), colour)),
            Resource::Composited => Some((self.composited, colour)),
            Resource::Positions
            | Resource::Posed
            | Resource::Counters
            | Resource::Probe
            | Resource::Strands
            | Resource::TileBins
            | Resource::HairLayer => None,
        }
    }
}

/// Whose view of the frame a pass draws, which decides its frame set: the camera's
/// uniforms or the light's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    Camera,
    Light,
}

/// A unit of a frame: what it draws into, what else it uses, how it records.
pub trait Pass {
    /// Its name, as debug labels and timings show it.
    fn name(&self) -> &'static str;
    /// Where it draws: the render target, unless it says otherwise.
    fn attachments(&self) -> Attachments {
        Attachments::Target
    }
    /// Whose view it draws; [`record_frame`] binds the frame set of that view and the
    /// body's set before the pass, unless they are bound already.
    fn view(&self) -> View {
        View::Camera
    }
    /// What it reads and writes besides its attachments, this frame.
    fn uses(&self, frame: &FrameContext<'_>) -> Vec<Use>;
    /// Records its commands (inside its rendering scope when it has attachments).
    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer);
    /// The timestamp query written once it is recorded (its end, `slot::TS_*`), if it
    /// is timed this frame.
    fn timestamp(&self, _frame: &FrameContext<'_>) -> Option<u32> {
        None
    }
}

/// What [`record_frame`] tells its caller, for the queries around the passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Event {
    /// A rendering scope is about to begin (its barriers recorded).
    ScopeOpening(Attachments),
    /// A rendering scope has begun.
    ScopeOpened(Attachments),
    /// The named pass has been recorded, and the timestamp it asks for then.
    PassRecorded(&'static str, Option<u32>),
    /// A rendering scope has ended.
    ScopeClosed(Attachments),
}

/// Records `passes` in order with the barriers their declarations need after what
/// `tracker` has seen (the submission's skinning and simulation before them), calling
/// `event` around them.
pub fn record_frame(
    frame: &FrameContext<'_>,
    cmd: vk::CommandBuffer,
    tracker: &mut Tracker<Resource>,
    passes: &[&dyn Pass],
    event: &mut dyn FnMut(Event),
) {
    let mut bound: Option<View> = None;
    let mut i = 0;
    while i < passes.len() {
        let attachments = passes[i].attachments();
        // A pass without attachments is a group of its own; others join their
        // neighbours drawing into the same attachments.
        let end = if attachments == Attachments::None {
            i + 1
        } else {
            i + passes[i..]
                .iter()
                .take_while(|p| p.attachments() == attachments)
                .count()
        };
        let group = &passes[i..end];
        let mut all = attachments.uses(frame.target);
        for pass in group {
            all.extend(pass.uses(frame));
        }
        record_uses(frame.device, cmd, tracker, &all, &|r| frame.image(r));
        if attachments != Attachments::None {
            event(Event::ScopeOpening(attachments));
            begin_scope(frame, cmd, attachments);
            event(Event::ScopeOpened(attachments));
        }
        for pass in group {
            // Sets stay bound across passes (and scopes) of the same view: rebinding
            // between draws costs a binning rasteriser a flush of its state.
            if attachments != Attachments::None && bound != Some(pass.view()) {
                frame.bind_sets(cmd, pass.view());
                bound = Some(pass.view());
            }
            frame.device.begin_label(cmd, pass.name());
            pass.record(frame, cmd);
            frame.device.end_label(cmd);
            event(Event::PassRecorded(pass.name(), pass.timestamp(frame)));
        }
        if attachments != Attachments::None {
            // SAFETY: the scope was begun above in this command buffer, which is recording.
            unsafe { frame.device.raw.cmd_end_rendering(cmd) };
            event(Event::ScopeClosed(attachments));
        }
        i = end;
    }
}

/// Begins the rendering scope of `attachments`, cleared.
fn begin_scope(frame: &FrameContext<'_>, cmd: vk::CommandBuffer, attachments: Attachments) {
    let depth_clear = vk::ClearValue {
        depth_stencil: vk::ClearDepthStencilValue {
            depth: 1.0,
            stencil: 0,
        },
    };
    match attachments {
        Attachments::None => {}
        Attachments::ShadowMap => {
            let map = &frame.slot.shadow;
            let extent = vk::Extent2D {
                width: map.resolution,
                height: map.resolution,
            };
            let depth = vk::RenderingAttachmentInfo::default()
                .image_view(map.image.view())
                .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(depth_clear);
            let rendering = vk::RenderingInfo::default()
                .render_area(extent.into())
                .layer_count(1)
                .depth_attachment(&depth);
            begin_rendering(frame.device, cmd, &rendering, extent);
        }
        Attachments::Target => {
            let target = frame.target;
            let background = vk::ClearValue {
                color: vk::ClearColorValue {
                    float32: super::renderer::BACKGROUND.extend(1.0).to_array(),
                },
            };
            let color = [target.color_attachment(background)];
            let depth = vk::RenderingAttachmentInfo::default()
                .image_view(target.depth.view())
                .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                // Kept when the compute strand passes read it.
                .store_op(if frame.raster_set != vk::DescriptorSet::null() {
                    vk::AttachmentStoreOp::STORE
                } else {
                    vk::AttachmentStoreOp::DONT_CARE
                })
                .clear_value(depth_clear);
            let rendering = vk::RenderingInfo::default()
                .render_area(target.extent.into())
                .layer_count(1)
                .color_attachments(&color)
                .depth_attachment(&depth);
            begin_rendering(frame.device, cmd, &rendering, target.extent);
        }
    }
}

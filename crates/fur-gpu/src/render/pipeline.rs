//! Graphics pipelines for dynamic rendering: a description of what differs between the
//! passes (stages, topology, vertex input, sample count, the colour attachments with
//! their blending, the depth attachment with its test), the rest shared: no culling,
//! dynamic viewport and scissor.

use std::sync::Arc;

use ash::vk;

use crate::error::Result;
use crate::gpu::{Device, Pipeline, PipelineLayout, ShaderModule};

/// What differs between the passes.
pub struct GraphicsDesc<'a> {
    pub name: &'a str,
    pub stages: &'a [(vk::ShaderStageFlags, &'a ShaderModule)],
    pub topology: vk::PrimitiveTopology,
    pub vertex_bindings: &'a [vk::VertexInputBindingDescription],
    pub vertex_attributes: &'a [vk::VertexInputAttributeDescription],
    /// Control points per patch when the pipeline tessellates.
    pub patch_control_points: Option<u32>,
    pub samples: vk::SampleCountFlags,
    /// The colour attachments, in location order (none: depth only).
    pub colour: &'a [ColourAttachment],
    /// The depth attachment and its test (None: no depth).
    pub depth: Option<DepthAttachment>,
}

/// A colour attachment: its format and how fragments combine with it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ColourAttachment {
    pub format: vk::Format,
    pub blend: Blend,
}

/// How fragments combine with a colour attachment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Blend {
    /// Overwrite (alpha ignored).
    Opaque,
    /// `src · α + dst · (1 − α)`; the target's alpha stays 1.
    Alpha,
}

/// The depth attachment: its format, the test and whether fragments write it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DepthAttachment {
    pub format: vk::Format,
    pub compare: vk::CompareOp,
    pub write: bool,
}

impl DepthAttachment {
    /// Tested with `LESS` and written: the nearest surface wins.
    pub fn nearest(format: vk::Format) -> Self {
        Self {
            format,
            compare: vk::CompareOp::LESS,
            write: true,
        }
    }
}

fn blend_state(blend: Blend) -> vk::PipelineColorBlendAttachmentState {
    let attachment = vk::PipelineColorBlendAttachmentState::default()
        .color_write_mask(vk::ColorComponentFlags::RGBA);
    match blend {
        Blend::Opaque => attachment,
        Blend::Alpha => attachment
            .blend_enable(true)
            .src_color_blend_factor(vk::BlendFactor::SRC_ALPHA)
            .dst_color_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
            .color_blend_op(vk::BlendOp::ADD)
            .src_alpha_blend_factor(vk::BlendFactor::ZERO)
            .dst_alpha_blend_factor(vk::BlendFactor::ONE)
            .alpha_blend_op(vk::BlendOp::ADD),
    }
}

pub fn graphics_pipeline(
    device: &Arc<Device>,
    layout: &PipelineLayout,
    desc: &GraphicsDesc<'_>,
) -> Result<Pipeline> {
    let stages: Vec<_> = desc
        .stages
        .iter()
        .map(|(stage, module)| {
            vk::PipelineShaderStageCreateInfo::default()
                .stage(*stage)
                .module(module.raw)
                .name(c"main")
        })
        .collect();
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
        .vertex_binding_descriptions(desc.vertex_bindings)
        .vertex_attribute_descriptions(desc.vertex_attributes);
    let input_assembly =
        vk::PipelineInputAssemblyStateCreateInfo::default().topology(desc.topology);
    let tessellation = vk::PipelineTessellationStateCreateInfo::default()
        .patch_control_points(desc.patch_control_points.unwrap_or(0));
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    let rasterization = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(vk::CullModeFlags::NONE)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    let multisample =
        vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(desc.samples);
    let depth = match desc.depth {
        Some(d) => vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(true)
            .depth_write_enable(d.write)
            .depth_compare_op(d.compare),
        None => vk::PipelineDepthStencilStateCreateInfo::default(),
    };
    let blend_attachments: Vec<_> = desc.colour.iter().map(|c| blend_state(c.blend)).collect();
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
    let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    let color_formats: Vec<_> = desc.colour.iter().map(|c| c.format).collect();
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(&color_formats)
        .depth_attachment_format(desc.depth.map_or(vk::Format::UNDEFINED, |d| d.format));
    let mut info = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&input_assembly)
        .viewport_state(&viewport)
        .rasterization_state(&rasterization)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(layout.raw())
        .push_next(&mut rendering);
    if desc.patch_control_points.is_some() {
        info = info.tessellation_state(&tessellation);
    }
    // SAFETY: every structure `info` points at (stages, states, formats) lives until the
    // call returns; the modules and the layout are valid handles of this device.
    let raw = unsafe {
        device
            .raw
            .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
    }
    .map_err(|(_, result)| crate::error::vulkan("vkCreateGraphicsPipelines", result))?[0];
    Ok(Pipeline::from_raw(device, desc.name, raw))
}

/// Begins dynamic rendering with a viewport and scissor covering `extent`.
pub fn begin_rendering(
    device: &Device,
    cmd: vk::CommandBuffer,
    rendering: &vk::RenderingInfo<'_>,
    extent: vk::Extent2D,
) {
    let raw = &device.raw;
    // SAFETY: the command buffer is recording outside a rendering scope; the attachments
    // named in `rendering` are the caller's images, alive while the frame is.
    unsafe {
        raw.cmd_begin_rendering(cmd, rendering);
        raw.cmd_set_viewport(
            cmd,
            0,
            &[vk::Viewport {
                x: 0.0,
                y: 0.0,
                width: extent.width as f32,
                height: extent.height as f32,
                min_depth: 0.0,
                max_depth: 1.0,
            }],
        );
        raw.cmd_set_scissor(cmd, 0, &[extent.into()]);
    }
}

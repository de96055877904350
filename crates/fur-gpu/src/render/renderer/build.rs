//! Building a renderer: the body's buffers (ownership, rest triangles, texture, the
//! patches' indices), the descriptor sets, the per-frame slots and the passes.

use std::sync::Arc;

use ash::vk;

use super::super::bindings::{
    write_body_set, BodyBinding, BodyResources, FrameBinding, SET_BODY, SET_FRAME, SET_RASTER,
};
use super::super::slot::RenderSlot;
use super::super::target::{RenderTarget, TargetSpec};
use super::super::texture::GpuTexture;
use super::compute_raster::ComputeRaster;
use super::fur_pass::FurPass;
use super::mesh_pass::{BodyTraits, MeshPass};
use super::registry::Build;
use super::{registered, Renderer};
use crate::error::{Error, Result};
use crate::gpu::{Buffer, DescriptorPool, DescriptorSetLayout, Device, PipelineLayout};
use crate::strand_textures::StrandTextures;
use fur_core::render::uniforms::StrandShape;
use fur_core::scene::{HairPatches, Mesh, Texture};

impl Renderer {
    /// A renderer with `frames_in_flight` sets of per-frame resources (1 headless),
    /// drawing into a target of `samples` per pixel.
    pub fn new(
        device: &Arc<Device>,
        mesh: &Mesh,
        strands: &StrandTextures,
        extent: vk::Extent2D,
        frames_in_flight: usize,
        samples: u32,
    ) -> Result<Self> {
        Self::textured(
            device,
            mesh,
            None,
            strands,
            extent,
            frames_in_flight,
            samples,
        )
    }

    /// [`Renderer::new`] for a model coloured by `texture` through its corner UVs.
    pub fn textured(
        device: &Arc<Device>,
        mesh: &Mesh,
        texture: Option<&Texture>,
        strands: &StrandTextures,
        extent: vk::Extent2D,
        frames_in_flight: usize,
        samples: u32,
    ) -> Result<Self> {
        let target = TargetSpec {
            extent,
            frames_in_flight,
            samples,
        };
        Self::for_body(
            device,
            mesh,
            &HairPatches::default(),
            texture,
            strands,
            target,
            None,
        )
    }

    /// [`Renderer::textured`] for a skinned body whose posed vertices (position and
    /// normal, two `vec4` each) the skinning pass writes into `posed`; `None` for a
    /// rigid body. The fur's density comes from the rest pose either way.
    pub fn for_body(
        device: &Arc<Device>,
        mesh: &Mesh,
        patches: &HairPatches,
        texture: Option<&Texture>,
        strands: &StrandTextures,
        target: TargetSpec,
        posed: Option<vk::Buffer>,
    ) -> Result<Self> {
        let TargetSpec {
            extent,
            frames_in_flight,
            samples,
        } = target;
        if texture.is_some() && mesh.uvs.len() != mesh.indices.len() {
            return Err(Error::parameter(
                "the model has no texture coordinates (`vt` on every face): a texture needs them",
            ));
        }
        let textured = texture.is_some();
        // Every binding is written, also those a frame's pipelines do not read (Mesa
        // 22.3's lavapipe reads every descriptor of a bound set): without a texture a
        // white texel and no UVs stand in.
        let white = Texture::from_rgba(1, 1, vec![255; 4])?;
        if textured && patches.uvs.len() != patches.indices.len() {
            return Err(Error::parameter(
                "the groom's patches have no texture coordinates: a texture needs them",
            ));
        }
        // The fur pass's patches: the body's triangles, then the groom's own.
        let corner_uvs: Vec<glam::Vec2> = if textured {
            mesh.uvs.iter().chain(&patches.uvs).copied().collect()
        } else {
            vec![glam::Vec2::ZERO]
        };
        let hair_indices: Vec<u32> = mesh
            .indices
            .iter()
            .chain(&patches.indices)
            .copied()
            .collect();
        let mut masks = mesh.ownership_masks();
        masks.extend(&patches.masks);
        let mut rest = rest_triangles(mesh);
        rest.extend(patches.indices.chunks_exact(3).map(|_| glam::Vec4::ZERO));
        let texture = (
            GpuTexture::upload(device, texture.unwrap_or(&white))?,
            Buffer::with_data(
                device,
                "mesh.corner_uvs",
                vk::BufferUsageFlags::STORAGE_BUFFER,
                &corner_uvs,
            )?,
        );
        let target = RenderTarget::new(device, extent, samples)?;
        let (frame_bindings, body_bindings) =
            (FrameBinding::set_layout(), BodyBinding::set_layout());
        let frame_layout =
            DescriptorSetLayout::new(device, "render.frame_set_layout", &frame_bindings)?;
        let body_layout =
            DescriptorSetLayout::new(device, "render.body_set_layout", &body_bindings)?;
        let raster_layout = ComputeRaster::set_layout(device)?;
        // In set order: SET_FRAME, SET_BODY, SET_RASTER.
        const _: () = assert!(SET_FRAME == 0 && SET_BODY == 1 && SET_RASTER == 2);
        let pipeline_layout = PipelineLayout::new(
            device,
            "render.pipeline_layout",
            &[&frame_layout, &body_layout, &raster_layout],
            &[],
        )?;
        let compute_raster = ComputeRaster::new(device, raster_layout, frames_in_flight)?;
        // Four frame sets per slot (two position images, two views), one body set; the
        // pool holds enough of every descriptor type for all of them.
        let set_count = 4 * frames_in_flight.max(1) + 1;
        let all_bindings: Vec<_> = frame_bindings
            .iter()
            .chain(&body_bindings)
            .copied()
            .collect();
        let pool = DescriptorPool::new(
            device,
            "render.descriptor_pool",
            set_count as u32,
            &all_bindings,
        )?;
        let ownership = Buffer::with_data(
            device,
            "render.ownership",
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &masks,
        )?;
        let indices = Buffer::with_data(
            device,
            "mesh.indices",
            vk::BufferUsageFlags::INDEX_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER,
            &hair_indices,
        )?;
        let rest_triangles = Buffer::with_data(
            device,
            "mesh.rest_triangles",
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &rest,
        )?;
        let body_set = pool.allocate(&body_layout, 1)?[0];
        write_body_set(
            device,
            body_set,
            &BodyResources {
                ownership: &ownership,
                texture: &texture.0,
                corner_uvs: &texture.1,
                posed: posed.unwrap_or(rest_triangles.raw()),
                rest_triangles: &rest_triangles,
                indices: &indices,
            },
        );
        let slots = (0..frames_in_flight.max(1))
            .map(|slot| RenderSlot::new(device, slot, &pool, &frame_layout, strands))
            .collect::<Result<Vec<_>>>()?;
        let vertices_per_strand = strands.layout.vertices_per_strand;
        let skinned = posed.is_some();
        let body = BodyTraits { textured, skinned };
        let mesh_pass = MeshPass::new(device, mesh, samples, body)?;
        let fur_pass = FurPass::new(device, vertices_per_strand, samples, body);
        let registered = registered(&Build {
            device,
            body,
            strands: &strands.layout,
        });
        Ok(Self {
            device: device.clone(),
            _set_layouts: (frame_layout, body_layout),
            body_set,
            pipeline_layout,
            _pool: pool,
            slots,
            _ownership: ownership,
            _rest_triangles: rest_triangles,
            body,
            texture,
            indices,
            index_count: mesh.indices.len() as u32,
            hair_index_count: hair_indices.len() as u32,
            shape: StrandShape {
                vertices_per_strand,
                strands_per_row: strands.layout.strands_per_row,
                stub_length: fur_core::render::uniforms::STUB_LIMIT * strands.hair_length,
                coat_height: strands.coat_height,
            },
            bounds: mesh.bounds(),
            hair_length: strands.hair_length,
            mesh_pass,
            fur_pass,
            registered,
            compute_raster,
            target,
            spare: None,
        })
    }
}

/// Per triangle of `mesh` (its rest pose): the lengths of the edges opposite corners
/// 0, 1, 2 (the tessellation's outer levels 0, 1, 2) and the area, as `fur.tesc` reads
/// them for a skinned body, whose live triangles stretch as its joints bend.
fn rest_triangles(mesh: &Mesh) -> Vec<glam::Vec4> {
    mesh.indices
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.positions[i as usize]);
            let area = 0.5 * (b - a).cross(c - a).length();
            glam::Vec4::new(b.distance(c), c.distance(a), a.distance(b), area)
        })
        .collect()
}

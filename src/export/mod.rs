//! One frame as drawn, handed over to a path tracer: the hairs the geometry stage
//! emitted, the posed body, the camera, the lights and the hair's physical parameters,
//! written as USD text (`.usda`; [`write_usda`]).
//!
//! The renderer's lights and materials become physical ones that give the same
//! radiance where the real-time model is exact (an unoccluded diffuse surface):
//! - the mesh pass draws `skin · (ambient + Kd · I · max(n·l, 0))`; a Lambertian body
//!   of albedo ρ = Kd · skin under a distant light of irradiance E = π · I (on a
//!   surface facing it) gives `ρ E cos / π`, the same direct term, and a uniform
//!   environment of radiance `ambient / Kd` gives it the same ambient term where
//!   nothing occludes it;
//! - a hair's colour is its base colour (the ramp and the texture, unlit); the path
//!   tracer turns it into absorption with Chiang et al. 2016's mapping, with the
//!   fibre's roughness, cuticle tilt and index of refraction ([`Fibre`]).

pub mod compare;
pub mod reference;
mod usda;

use glam::{Mat4, Vec3};

pub use fur_core::render::Fibre;
use fur_core::render::FrameSettings;
use fur_core::render::Lighting;
use fur_core::scene::{Mesh, Texture};
use fur_gpu::error::{size_text, Error, Result};
use fur_gpu::render::CapturedHairs;

pub use usda::write_usda;

/// The largest export written, in bytes: an estimate above it is refused before the
/// file is written.
pub const MAX_EXPORT_BYTES: u64 = 8 << 30;

/// The camera as drawn: a perspective camera at `eye` looking at `target`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraExport {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// World to view (right-handed, looking down −Z), as the renderer uses it.
    pub view: Mat4,
    pub fov_y_deg: f32,
    pub width: u32,
    pub height: u32,
    pub near: f32,
    pub far: f32,
}

/// The lights as physical lights (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightExport {
    /// Unit vector towards the light.
    pub direction: Vec3,
    /// Irradiance on a surface facing the light: π · intensity.
    pub irradiance: f32,
    /// Radiance of the uniform environment: ambient / Kd (0 without diffuse).
    pub environment: f32,
}

/// The posed body in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyExport {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub indices: Vec<u32>,
    /// Lambertian albedo, Kd · the skin colour (linear): one colour for the whole body,
    /// or, where a texture colours the skin, one per triangle (the texture at the
    /// triangle's centre, darkened as the mesh pass darkens it).
    pub albedo: Vec<Vec3>,
}

/// Everything one exported frame holds.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameExport {
    pub hairs: CapturedHairs,
    /// None when the frame does not draw the body.
    pub body: Option<BodyExport>,
    pub camera: CameraExport,
    pub light: LightExport,
    pub fibre: Fibre,
}

impl FrameExport {
    /// The frame `settings` draws at `width` × `height` pixels: its captured `hairs` and the
    /// `mesh` with `posed` model-space positions and normals (a skinned body's pose;
    /// the rest pose when None), placed by the settings' head transform, coloured by
    /// `texture` where the frame draws one.
    pub fn new(
        hairs: CapturedHairs,
        mesh: &Mesh,
        texture: Option<&Texture>,
        posed: Option<(Vec<Vec3>, Vec<Vec3>)>,
        settings: &FrameSettings,
        ash::vk::Extent2D { width, height }: ash::vk::Extent2D,
    ) -> Self {
        let camera = &settings.camera;
        let lighting = &settings.lighting;
        let head = settings.head;
        let body = settings.draw_mesh.then(|| {
            let (positions, normals) =
                posed.unwrap_or_else(|| (mesh.positions.clone(), mesh.normals.clone()));
            BodyExport {
                positions: positions
                    .iter()
                    .map(|&p| head.transform_point3(p))
                    .collect(),
                normals: normals
                    .iter()
                    .map(|&n| head.transform_vector3(n).normalize_or_zero())
                    .collect(),
                indices: mesh.indices.clone(),
                albedo: body_albedo(mesh, texture, lighting),
            }
        });
        let view = camera.view();
        let up = view.inverse().transform_vector3(Vec3::Y).normalize();
        let (near, far) = camera.clip_planes();
        Self {
            hairs,
            body,
            camera: CameraExport {
                eye: camera.eye(),
                target: camera.target,
                up,
                view,
                fov_y_deg: camera.fov_y_deg,
                width,
                height,
                near,
                far,
            },
            light: LightExport {
                direction: lighting.light_direction.normalize(),
                irradiance: std::f32::consts::PI * lighting.intensity,
                environment: if lighting.kd > 0.0 {
                    lighting.ambient / lighting.kd
                } else {
                    0.0
                },
            },
            fibre: lighting.fibre,
        }
    }

    /// A generous estimate of the `.usda` text's size in bytes (per hair vertex its
    /// point, widths and colour; per body vertex its point and normal).
    pub fn estimated_bytes(&self) -> u64 {
        let hair_vertices = self.hairs.points.len() as u64;
        let body = self.body.as_ref().map_or(0, |b| {
            b.positions.len() as u64 * 90 + b.indices.len() as u64 * 12
        });
        4096 + hair_vertices * 140 + body
    }

    /// Refuses an export whose estimated size is over [`MAX_EXPORT_BYTES`], saying how
    /// large it would be.
    pub fn check_size(&self) -> Result<()> {
        let bytes = self.estimated_bytes();
        if bytes > MAX_EXPORT_BYTES {
            return Err(Error::parameter(format!(
                "the export of {} hairs ({} vertices) would take about {}, over the limit of \
                 {}; draw fewer hairs (--density-scale, a smaller image)",
                self.hairs.count(),
                self.hairs.points.len(),
                size_text(bytes),
                size_text(MAX_EXPORT_BYTES)
            )));
        }
        Ok(())
    }
}

/// The body's Lambertian albedo as the mesh pass draws it: Kd · the skin colour, or with
/// a texture (and the mesh's UVs) per triangle the texture at the triangle's centre in
/// UV, darkened as the skin colour is to the tip colour (`mesh.frag`).
fn body_albedo(mesh: &Mesh, texture: Option<&Texture>, lighting: &Lighting) -> Vec<Vec3> {
    let skin = lighting.skin_color;
    match texture {
        Some(t) if mesh.uvs.len() == mesh.indices.len() => {
            let darken = (skin / lighting.tip_color.max(Vec3::splat(1e-4))).min(Vec3::ONE);
            mesh.uvs
                .chunks_exact(3)
                .map(|uv| lighting.kd * t.sample((uv[0] + uv[1] + uv[2]) / 3.0) * darken)
                .collect()
        }
        _ => vec![lighting.kd * skin],
    }
}

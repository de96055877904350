//! A style's other forms: measured on a model or per bounding radius, at reference
//! quality, and the tile side it draws with.

use super::{FurStyle, DEFAULT_TILE};
use crate::render::drawing::{Primitive, Raster, Shading};

impl FurStyle {
    /// This style, measured on the model (lengths in bounding radii, density per
    /// square bounding radius), on a model of bounding radius `radius`: in scene units.
    pub fn on_model(&self, radius: f32) -> Self {
        Self {
            density: self.density / (radius * radius),
            lod_distance: self.lod_distance * radius,
            hair_width: self.hair_width * radius,
            jitter: self.jitter * radius,
            ..self.clone()
        }
    }

    /// The inverse of [`FurStyle::on_model`]: this style, in scene units, measured on a
    /// model of bounding radius `radius`.
    pub fn per_radius(&self, radius: f32) -> Self {
        Self {
            density: self.density * radius * radius,
            lod_distance: self.lod_distance / radius,
            hair_width: self.hair_width / radius,
            jitter: self.jitter / radius,
            ..self.clone()
        }
    }

    /// This style at reference quality: 4× MSAA ribbons through the fixed-function
    /// rasteriser, lit per fragment, every strand vertex drawn (density, widths, jitter
    /// and culling kept): the drawing every other is measured against.
    pub fn reference_quality(&self) -> Self {
        Self {
            raster: Raster::Hardware,
            samples: 4,
            primitive: Primitive::Ribbons,
            shading: Shading::Fragment,
            vertex_lod_px: 0.0,
            ..self.clone()
        }
    }

    /// The compute rasteriser's tile side this style draws with, pixels: its own, or
    /// the default ([`DEFAULT_TILE`]).
    pub fn tile_side(&self) -> u32 {
        match self.tile {
            0 => DEFAULT_TILE,
            side => side,
        }
    }
}

//! A borrowed indexed triangle list, the shape geometry works on (a scene's `Mesh`
//! lends its positions and indices as one), and its bounds.

use glam::Vec3;

/// Positions and three indices per triangle, borrowed.
#[derive(Clone, Copy, Debug)]
pub struct Triangles<'a> {
    pub positions: &'a [Vec3],
    /// Three indices per triangle, counter-clockwise seen from outside.
    pub indices: &'a [u32],
}

impl Triangles<'_> {
    /// Axis-aligned bounding box of the vertices (min, max).
    pub fn aabb(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }

    /// Bounding-sphere centre and radius (of the box around the vertices).
    pub fn bounds(&self) -> (Vec3, f32) {
        let (min, max) = self.aabb();
        // In f64: the squared diagonal of a model 1e20 units across overflows f32.
        let diagonal = (max.as_dvec3() - min.as_dvec3()).length();
        ((min * 0.5 + max * 0.5), (diagonal * 0.5) as f32)
    }
}

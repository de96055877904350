//! Helpers of the core's tests (and, through a path, of the GPU tests): seeded cases,
//! rounding bounds, the distance field's error.
#![allow(dead_code)]

use fur_core::scene::Mesh;

pub mod rounding;
pub mod seed;

/// The largest error of `sdf` against exact distances to `mesh` at points whose exact
/// distance lies in `band` (scene units; 40,000 points spread over the grid): how far
/// the collider's idea of the surface can be from the surface there. Exact distances
/// come from a BVH over the mesh's triangles, not from the grid the collider samples.
pub fn field_error(mesh: &Mesh, sdf: &fur_core::sim::Sdf, band: (f32, f32)) -> f64 {
    let extent = glam::Vec3::from_array(sdf.dims.map(|n| (n - 1) as f32)) * sdf.cell;
    let points: Vec<glam::Vec3> = (0..40_000u32)
        .map(|i| {
            let u = glam::Vec3::new(
                fur_core::scene::hash_unit(3 * i),
                fur_core::scene::hash_unit(3 * i + 1),
                fur_core::scene::hash_unit(3 * i + 2),
            );
            sdf.origin + u * extent
        })
        .collect();
    let exact = fur_core::sim::sdf::exact_distances(mesh, &points);
    points
        .iter()
        .zip(&exact)
        .filter(|(_, t)| (band.0..=band.1).contains(*t))
        .map(|(p, t)| {
            let (d, _) = sdf
                .sample(fur_core::sim::V3::<f32>::from_vec3(*p))
                .expect("a point of the grid");
            f64::from((d - t).abs())
        })
        .fold(0.0, f64::max)
}

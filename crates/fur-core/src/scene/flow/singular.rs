//! A direction field's singular points: where the field turns about a point. Walking
//! once round a triangle (or round a vertex where the field has no direction), the
//! field's angle turns by 2π × the index: +1 at a whorl (hair parting from or meeting
//! at a point), −1 at a saddle, 0 where the field is regular. On a closed surface the
//! indices sum to its Euler characteristic (Poincaré–Hopf), 2 for a body shaped like
//! a sphere.

use std::f32::consts::{PI, TAU};

use glam::Vec3;

use super::{heat, Mesh};

/// A point the field turns about.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Singularity {
    /// +1 a whorl, −1 a saddle (higher magnitudes are possible on coarse meshes).
    pub index: i32,
    /// The triangle's centre, or the vertex.
    pub position: Vec3,
    /// The mesh vertices it lies between (a triangle's corners, or one vertex three
    /// times), to place it on the body as posed.
    pub corners: [u32; 3],
}

/// The singular points of `directions` (one per mesh vertex, tangent to the surface,
/// zero at a vertex the field turns about) on `mesh`, its vertices that share a
/// position taken as one.
pub fn singular_points(mesh: &Mesh, directions: &[Vec3]) -> Vec<Singularity> {
    let Ok(surface) = heat::Surface::new(&mesh.positions, &mesh.indices) else {
        return Vec::new();
    };
    let mut field = vec![Vec3::ZERO; surface.len()];
    let mut normal = vec![Vec3::ZERO; surface.len()];
    // Per joined vertex, the first mesh vertex at its position.
    let mut vertex = vec![0u32; surface.len()];
    for (v, &j) in surface.joined.iter().enumerate().rev() {
        field[j as usize] = directions.get(v).copied().unwrap_or(Vec3::ZERO);
        normal[j as usize] = mesh.normals.get(v).copied().unwrap_or(Vec3::ZERO);
        vertex[j as usize] = v as u32;
    }
    let mut points = Vec::new();
    // Round each vertex without a direction: the turning from corner to corner of
    // each of its triangles, in its tangent plane.
    let mut round_vertex = vec![(0.0f32, false); surface.len()];
    for t in &surface.triangles {
        let p = t.map(|i| surface.positions[i as usize].as_vec3());
        let d = t.map(|i| field[i as usize]);
        for k in 0..3 {
            if d[k] != Vec3::ZERO {
                continue;
            }
            let (a, b) = ((k + 1) % 3, (k + 2) % 3);
            let n = normal[t[k] as usize];
            let n = n
                .try_normalize()
                .unwrap_or_else(|| (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero());
            let step = [d[a], d[b]].map(|x| angle(x, n, p[a] - p[k]));
            let entry = &mut round_vertex[t[k] as usize];
            match step {
                [Some(x), Some(y)] => entry.0 += wrap(y - x),
                _ => entry.1 = true,
            }
        }
        if d.contains(&Vec3::ZERO) {
            continue;
        }
        let Some(n) = (p[1] - p[0]).cross(p[2] - p[0]).try_normalize() else {
            continue;
        };
        let angles = [0, 1, 2].map(|k| angle(d[k], n, p[1] - p[0]));
        if let [Some(x), Some(y), Some(z)] = angles {
            let index = ((wrap(y - x) + wrap(z - y) + wrap(x - z)) / TAU).round() as i32;
            if index != 0 {
                points.push(Singularity {
                    index,
                    position: (p[0] + p[1] + p[2]) / 3.0,
                    corners: t.map(|j| vertex[j as usize]),
                });
            }
        }
    }
    for (v, &(turn, broken)) in round_vertex.iter().enumerate() {
        let index = (turn / TAU).round() as i32;
        if field[v] == Vec3::ZERO && !broken && index != 0 {
            points.push(Singularity {
                index,
                position: surface.positions[v].as_vec3(),
                corners: [vertex[v]; 3],
            });
        }
    }
    points
}

/// The angle of `d` in the plane across `n`, from `reference`'s direction in it;
/// `None` if `d` has no part in the plane.
fn angle(d: Vec3, n: Vec3, reference: Vec3) -> Option<f32> {
    let e1 = (reference - reference.dot(n) * n).try_normalize()?;
    let e2 = n.cross(e1);
    let flat = d - d.dot(n) * n;
    if flat.length_squared() < 1e-12 {
        return None;
    }
    Some(flat.dot(e2).atan2(flat.dot(e1)))
}

/// An angle step wrapped into (−π, π]: the field turns the short way along an edge.
fn wrap(step: f32) -> f32 {
    step - TAU * ((step + PI) / TAU).floor()
}

/// The critical points of `value` (one per mesh vertex) as a function linear over each
/// triangle, with their indices: walking round a vertex's neighbours, the value crosses
/// the vertex's own 2k times, and the vertex has index 1 − k (+1 at a minimum or a
/// maximum, −1 at a simple saddle; Banchoff 1967). Equal values are ordered by vertex,
/// so every vertex is either regular or critical, and on a closed surface the indices
/// sum to its Euler characteristic exactly. The singular points of the function's
/// gradient: where a flow made from it turns. Vertices at one position are one; a
/// vertex on a boundary or where the surface is not a manifold counts nothing.
pub fn critical_points(mesh: &Mesh, value: &[f32]) -> Vec<Singularity> {
    let Ok(surface) = heat::Surface::new(&mesh.positions, &mesh.indices) else {
        return Vec::new();
    };
    let mut joined_value = vec![0.0f32; surface.len()];
    let mut vertex = vec![0u32; surface.len()];
    for (v, &j) in surface.joined.iter().enumerate().rev() {
        joined_value[j as usize] = value.get(v).copied().unwrap_or(0.0);
        vertex[j as usize] = v as u32;
    }
    // Per vertex, its link: for each triangle (v, a, b), the edge a → b.
    let mut link: Vec<Vec<(u32, u32)>> = vec![Vec::new(); surface.len()];
    for t in &surface.triangles {
        for k in 0..3 {
            link[t[k] as usize].push((t[(k + 1) % 3], t[(k + 2) % 3]));
        }
    }
    let above = |u: u32, v: u32| {
        let (a, b) = (joined_value[u as usize], joined_value[v as usize]);
        a > b || (a == b && u > v)
    };
    let mut points = Vec::new();
    for (v, edges) in link.iter().enumerate() {
        let Some(cycle) = walk(edges) else {
            continue;
        };
        let v = v as u32;
        let changes = (0..cycle.len())
            .filter(|&k| above(cycle[k], v) != above(cycle[(k + 1) % cycle.len()], v))
            .count();
        let index = 1 - (changes / 2) as i32;
        if index != 0 {
            points.push(Singularity {
                index,
                position: surface.positions[v as usize].as_vec3(),
                corners: [vertex[v as usize]; 3],
            });
        }
    }
    points
}

/// The vertices of a link's edges in order round one cycle; `None` unless the edges
/// close one cycle through all of them.
fn walk(edges: &[(u32, u32)]) -> Option<Vec<u32>> {
    let next: std::collections::HashMap<u32, u32> = edges.iter().copied().collect();
    let &(start, _) = edges.first()?;
    if next.len() != edges.len() {
        return None;
    }
    let mut cycle = vec![start];
    let mut at = *next.get(&start)?;
    while at != start {
        if cycle.len() > edges.len() {
            return None;
        }
        cycle.push(at);
        at = *next.get(&at)?;
    }
    (cycle.len() == edges.len()).then_some(cycle)
}

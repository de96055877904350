//! Implicit surfaces for generated models: signed-distance primitives joined by a smooth
//! union, polygonised by surface nets into one closed, consistently wound triangle mesh.

use std::collections::HashMap;

use glam::{IVec3, Vec3};

/// A signed-distance primitive (negative inside).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Shape {
    /// A capsule whose radius goes linearly from `ra` at `a` to `rb` at `b`.
    Cone { a: Vec3, b: Vec3, ra: f32, rb: f32 },
    /// An axis-aligned ellipsoid.
    Ellipsoid { centre: Vec3, radii: Vec3 },
}

/// A primitive of a smooth union.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Part {
    pub shape: Shape,
    /// The smooth union's blend radius with what comes before it.
    pub blend: f32,
    /// Squashes the shape along a unit axis through `origin` by a factor (> 1: thinner).
    pub squash: Option<(Vec3, Vec3, f32)>,
}

impl Part {
    pub fn new(shape: Shape, blend: f32) -> Self {
        Self {
            shape,
            blend,
            squash: None,
        }
    }

    /// Approximate signed distance of `p` to the part.
    pub fn distance(&self, p: Vec3) -> f32 {
        let (p, divide) = match self.squash {
            Some((origin, axis, factor)) => {
                (p + (factor - 1.0) * (p - origin).dot(axis) * axis, factor)
            }
            None => (p, 1.0),
        };
        let d = match self.shape {
            Shape::Cone { a, b, ra, rb } => {
                let ab = b - a;
                let t = ((p - a).dot(ab) / ab.length_squared().max(1e-12)).clamp(0.0, 1.0);
                p.distance(a + t * ab) - (ra + t * (rb - ra))
            }
            Shape::Ellipsoid { centre, radii } => {
                let q = p - centre;
                let k0 = (q / radii).length();
                let k1 = (q / (radii * radii)).length();
                if k1 > 0.0 {
                    k0 * (k0 - 1.0) / k1
                } else {
                    -radii.min_element()
                }
            }
        };
        d / divide
    }

    /// Bounding box corners of the part.
    fn aabb(&self) -> (Vec3, Vec3) {
        match self.shape {
            Shape::Cone { a, b, ra, rb } => {
                let r = Vec3::splat(ra.max(rb));
                (a.min(b) - r, a.max(b) + r)
            }
            Shape::Ellipsoid { centre, radii } => (centre - radii, centre + radii),
        }
    }
}

/// The smooth union of `parts` (polynomial smooth minimum, folded in order).
pub(crate) fn union(parts: &[Part], p: Vec3) -> f32 {
    parts.iter().fold(f32::MAX, |acc, part| {
        let d = part.distance(p);
        let k = part.blend;
        if k <= 0.0 || acc == f32::MAX {
            return acc.min(d);
        }
        let h = (k - (acc - d).abs()).max(0.0) / k;
        acc.min(d) - h * h * k * 0.25
    })
}

/// Central-difference gradient of the union, normalised.
pub(crate) fn gradient(parts: &[Part], p: Vec3, step: f32) -> Vec3 {
    let d = |o: Vec3| union(parts, p + o) - union(parts, p - o);
    Vec3::new(d(Vec3::X * step), d(Vec3::Y * step), d(Vec3::Z * step))
        .try_normalize()
        .unwrap_or(Vec3::Y)
}

/// Polygonises the union's zero set with surface nets on a grid of spacing `h` whose
/// origin is shifted by `shift` (in cells): one vertex per cell the surface crosses,
/// projected onto the surface, and one quad (two triangles, split on the shorter
/// diagonal) per grid edge it crosses, after untangling the cells where that would
/// not be a manifold; the triangles are then evened out. Keeps the largest connected
/// piece. Returns positions and counter-clockwise (seen from outside) triangles, or
/// `None` should the result still not be a closed 2-manifold (try another shift).
pub(crate) fn surface_nets(parts: &[Part], h: f32, shift: Vec3) -> Option<(Vec<Vec3>, Vec<u32>)> {
    let (lo, hi) = parts.iter().map(Part::aabb).fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), (a, b)| (lo.min(a), hi.max(b)),
    );
    let origin = lo - Vec3::splat(2.0 * h) - shift * h;
    let n = ((hi - origin) / h).ceil().as_ivec3() + IVec3::splat(3);
    let index = |c: IVec3| (c.x + n.x * (c.y + n.y * c.z)) as usize;
    let point = |c: IVec3| origin + c.as_vec3() * h;
    let mut field = vec![0.0f32; (n.x * n.y * n.z) as usize];
    for z in 0..n.z {
        for y in 0..n.y {
            for x in 0..n.x {
                let c = IVec3::new(x, y, z);
                field[index(c)] = union(parts, point(c));
            }
        }
    }
    untangle(&mut field, n, 1e-4 * h);
    let inside = |c: IVec3| field[index(c)] < 0.0;
    // One vertex per crossed cell: the mean of its edge crossings, projected.
    let mut positions = Vec::new();
    let mut cell_vertex: HashMap<IVec3, u32> = HashMap::new();
    for z in 0..n.z - 1 {
        for y in 0..n.y - 1 {
            for x in 0..n.x - 1 {
                let cell = IVec3::new(x, y, z);
                let (mut sum, mut count) = (Vec3::ZERO, 0.0);
                for (i, &ci) in CORNERS.iter().enumerate() {
                    for bit in [1, 2, 4] {
                        if i & bit != 0 {
                            continue;
                        }
                        let (a, b) = (cell + ci, cell + CORNERS[i | bit]);
                        if inside(a) != inside(b) {
                            let (fa, fb) = (field[index(a)], field[index(b)]);
                            let t = (fa / (fa - fb)).clamp(0.0, 1.0);
                            sum += point(a).lerp(point(b), t);
                            count += 1.0;
                        }
                    }
                }
                if count > 0.0 {
                    let (box_lo, box_hi) = (point(cell), point(cell + IVec3::ONE));
                    let mut p = sum / count;
                    for _ in 0..3 {
                        let g = gradient(parts, p, 0.1 * h);
                        p = (p - union(parts, p) * g).clamp(box_lo, box_hi);
                    }
                    cell_vertex.insert(cell, positions.len() as u32);
                    positions.push(p);
                }
            }
        }
    }
    // One quad per crossed grid edge, around the edge counter-clockwise seen from outside.
    let mut indices = Vec::new();
    for (axis, u, v) in [
        (IVec3::X, IVec3::Y, IVec3::Z),
        (IVec3::Y, IVec3::Z, IVec3::X),
        (IVec3::Z, IVec3::X, IVec3::Y),
    ] {
        for z in 1..n.z - 1 {
            for y in 1..n.y - 1 {
                for x in 1..n.x - 1 {
                    let c = IVec3::new(x, y, z);
                    if (c + axis).cmpge(n).any() || inside(c) == inside(c + axis) {
                        continue;
                    }
                    let cells = [c - u - v, c - v, c, c - u];
                    let mut quad = cells.map(|k| cell_vertex[&k]);
                    if !inside(c) {
                        quad.reverse();
                    }
                    let [a, b, cc, d] = quad;
                    let p = |i: u32| positions[i as usize];
                    if p(a).distance_squared(p(cc)) <= p(b).distance_squared(p(d)) {
                        indices.extend_from_slice(&[a, b, cc, a, cc, d]);
                    } else {
                        indices.extend_from_slice(&[a, b, d, b, cc, d]);
                    }
                }
            }
        }
    }
    let (mut positions, indices) = largest_piece(&positions, &indices);
    relax(parts, &mut positions, &indices, h);
    is_closed_manifold(positions.len(), &indices).then_some((positions, indices))
}

/// Corner `i` of a grid cell: offset (bit 0, bit 1, bit 2 of `i`).
const CORNERS: [IVec3; 8] = [
    IVec3::new(0, 0, 0),
    IVec3::new(1, 0, 0),
    IVec3::new(0, 1, 0),
    IVec3::new(1, 1, 0),
    IVec3::new(0, 0, 1),
    IVec3::new(1, 0, 1),
    IVec3::new(0, 1, 1),
    IVec3::new(1, 1, 1),
];

/// Flips grid values (to ±`tiny`) until every crossed cell holds one disc of surface:
/// no face whose corners alternate in sign (surface nets would join four quads at one
/// edge there) and no cell whose inside or outside corners fall apart (two sheets
/// would share its vertex). Each fix flips the corner nearest the surface among those
/// at fault, so the shape moves by less than a cell.
fn untangle(field: &mut [f32], n: IVec3, tiny: f32) {
    let index = |c: IVec3| (c.x + n.x * (c.y + n.y * c.z)) as usize;
    for _ in 0..16 {
        let mut changed = false;
        for z in 0..n.z - 1 {
            for y in 0..n.y - 1 {
                for x in 0..n.x - 1 {
                    let corners = CORNERS.map(|o| index(IVec3::new(x, y, z) + o));
                    let values = corners.map(|i| field[i]);
                    if let Some(k) = fault(&values.map(|f| f < 0.0), &values.map(f32::abs)) {
                        let i = corners[k];
                        field[i] = if field[i] < 0.0 { tiny } else { -tiny };
                        changed = true;
                    }
                }
            }
        }
        if !changed {
            break;
        }
    }
}

/// The corner of a cell (signs `inside`, distances `size`) to flip, if the cell is at
/// fault.
fn fault(inside: &[bool; 8], size: &[f32; 8]) -> Option<usize> {
    let nearest = |corners: &[usize]| {
        corners
            .iter()
            .copied()
            .min_by(|&a, &b| size[a].total_cmp(&size[b]))
    };
    for (bit, u, v) in [(1, 2, 4), (2, 4, 1), (4, 1, 2)] {
        for side in [0, bit] {
            let ring = [side, side | u, side | u | v, side | v];
            let [a, b, c, d] = ring.map(|k| inside[k]);
            if a == c && b == d && a != b {
                return nearest(&ring);
            }
        }
    }
    for class in [true, false] {
        // Connected pieces of the corners of this class, along the cell's edges.
        let mut piece = [usize::MAX; 8];
        let mut pieces: Vec<Vec<usize>> = Vec::new();
        for start in 0..8 {
            if inside[start] != class || piece[start] != usize::MAX {
                continue;
            }
            let mut members = vec![start];
            piece[start] = pieces.len();
            let mut k = 0;
            while k < members.len() {
                for bit in [1, 2, 4] {
                    let next = members[k] ^ bit;
                    if inside[next] == class && piece[next] == usize::MAX {
                        piece[next] = pieces.len();
                        members.push(next);
                    }
                }
                k += 1;
            }
            pieces.push(members);
        }
        if pieces.len() > 1 {
            let largest = (0..pieces.len()).max_by_key(|&p| (pieces[p].len(), usize::MAX - p))?;
            let rest: Vec<usize> = (0..pieces.len())
                .filter(|&p| p != largest)
                .flat_map(|p| pieces[p].clone())
                .collect();
            return nearest(&rest);
        }
    }
    None
}

/// Evens out the triangles: a few rounds of moving each vertex half-way towards the
/// mean of its neighbours along the surface, then back onto it.
fn relax(parts: &[Part], positions: &mut [Vec3], indices: &[u32], h: f32) {
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); positions.len()];
    for t in indices.chunks_exact(3) {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            neighbours[a as usize].push(b);
            neighbours[b as usize].push(a);
        }
    }
    for _ in 0..4 {
        let before = positions.to_vec();
        for (p, around) in positions.iter_mut().zip(&neighbours) {
            let mean = around.iter().map(|&i| before[i as usize]).sum::<Vec3>()
                / around.len().max(1) as f32;
            let g = gradient(parts, *p, 0.1 * h);
            let step = 0.5 * (mean - *p);
            let mut q = *p + step - step.dot(g) * g;
            for _ in 0..2 {
                let g = gradient(parts, q, 0.1 * h);
                q -= union(parts, q) * g;
            }
            *p = q;
        }
    }
}

/// The largest edge-connected piece of a triangle mesh, its vertices renumbered.
fn largest_piece(positions: &[Vec3], indices: &[u32]) -> (Vec<Vec3>, Vec<u32>) {
    let edges = indices
        .chunks_exact(3)
        .flat_map(|t| [(t[0], t[1]), (t[0], t[2])]);
    let (piece, count) = crate::geometry::topology::pieces(positions.len(), edges);
    // Triangles per piece; the most, the first piece on a tie.
    let mut size = vec![0usize; count];
    for t in indices.chunks_exact(3) {
        size[piece[t[0] as usize] as usize] += 1;
    }
    let Some(keep) = (0..count).max_by_key(|&p| (size[p], usize::MAX - p)) else {
        return (Vec::new(), Vec::new());
    };
    let mut renumber = vec![u32::MAX; positions.len()];
    let mut kept = Vec::new();
    let mut out = Vec::new();
    for t in indices.chunks_exact(3) {
        if piece[t[0] as usize] as usize != keep {
            continue;
        }
        for &i in t {
            if renumber[i as usize] == u32::MAX {
                renumber[i as usize] = kept.len() as u32;
                kept.push(positions[i as usize]);
            }
            out.push(renumber[i as usize]);
        }
    }
    (kept, out)
}

/// Whether every directed edge appears once and its reverse once (closed, consistently
/// wound), and every vertex's triangles form one fan (no pinched vertex).
pub(crate) fn is_closed_manifold(vertex_count: usize, indices: &[u32]) -> bool {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    // Per vertex, its link: for each triangle (v, a, b) the edge a -> b.
    let mut link: Vec<Vec<(u32, u32)>> = vec![Vec::new(); vertex_count];
    for t in indices.chunks_exact(3) {
        if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
            return false;
        }
        for k in 0..3 {
            let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            *directed.entry((a, b)).or_default() += 1;
            link[a as usize].push((b, c));
        }
    }
    let edges_ok = directed
        .iter()
        .all(|(&(a, b), &count)| count == 1 && directed.get(&(b, a)) == Some(&1));
    let fans_ok = link.iter().all(|edges| {
        let next: HashMap<u32, u32> = edges.iter().copied().collect();
        if edges.is_empty() || next.len() != edges.len() {
            return false;
        }
        // Walk the cycle from the first edge; it must visit every edge.
        let (start, mut at) = (edges[0].0, edges[0].1);
        let mut steps = 1;
        while at != start && steps <= edges.len() {
            match next.get(&at) {
                Some(&to) => at = to,
                None => return false,
            }
            steps += 1;
        }
        at == start && steps == edges.len()
    });
    edges_ok && fans_ok
}

//! A triangle mesh's connectivity: vertices at one position joined into one (so a model
//! split at its texture seams is one surface), and the connected pieces of a graph.

use std::collections::HashMap;

use glam::Vec3;

/// Per vertex, the index of its joined vertex: vertices within `snap` of each other
/// (on a grid of that spacing) share one, numbered in order of first appearance.
/// Returns the indices and how many joined vertices there are.
pub fn weld(positions: &[Vec3], snap: f32) -> (Vec<u32>, usize) {
    let snap = snap.max(f32::MIN_POSITIVE);
    let mut ids: HashMap<[i64; 3], u32> = HashMap::new();
    let weld = positions
        .iter()
        .map(|p| {
            let key = (*p / snap).round().as_i64vec3().to_array();
            let next = ids.len() as u32;
            *ids.entry(key).or_insert(next)
        })
        .collect();
    (weld, ids.len())
}

/// The connected pieces of `n` vertices joined by `edges`: each vertex's piece
/// (numbered in order of each piece's first vertex), and how many there are.
pub fn pieces(n: usize, edges: impl IntoIterator<Item = (u32, u32)>) -> (Vec<u32>, usize) {
    fn find(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            let up = parent[parent[i as usize] as usize];
            parent[i as usize] = up;
            i = up;
        }
        i
    }
    let mut parent: Vec<u32> = (0..n as u32).collect();
    for (a, b) in edges {
        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
    let mut label = HashMap::new();
    let piece = (0..n as u32)
        .map(|i| {
            let root = find(&mut parent, i);
            let next = label.len() as u32;
            *label.entry(root).or_insert(next)
        })
        .collect();
    (piece, label.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    // A join by exact bits would keep the pair 1e-7 apart as two; pieces labelled by
    // their root vertex would read 0, 0, 2, 3, 3, 5.
    #[test]
    fn weld_joins_near_positions_and_pieces_follow_edges() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::new(1e-7, 0.0, 0.0), Vec3::Y];
        let (ids, n) = weld(&p, 1e-6);
        assert_eq!((ids, n), (vec![0, 1, 0, 2], 3));
        let (piece, n) = pieces(6, [(0, 1), (3, 4), (4, 3)]);
        assert_eq!((piece, n), (vec![0, 0, 1, 2, 2, 3], 4));
    }
}

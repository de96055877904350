//! Strands drawn in compute, the CPU twin: the oracle the GPU's `--raster compute`
//! passes are tested against, and their specification.
//!
//! Three steps, as the GPU runs them:
//! 1. **Bin** ([`mod@bin`]): each segment is listed in every screen tile it can touch,
//!    unless the body's depth hides it from the whole tile. The lists share one pool of
//!    entries; a segment that finds the pool full is counted, not silently lost.
//!    Each tile's list is then sorted front to back into depth bins ([`order`]).
//! 2. **Fine raster**: each pixel of a tile walks its tile's list, takes each segment's
//!    analytic coverage ([`coverage`]) and keeps the nearest fragments in depth order
//!    ([`blend`]), until it is opaque at the end of a depth bin.
//! 3. **Resolve**: the fragments blended front to back over the mesh pass's colour.
//!
//! Positions are in pixels (x right, y down, the pixel `(i, j)` spanning
//! `[i, i + 1) × [j, j + 1)`); widths in pixels; depth is any quantity that grows away
//! from the eye, the body's depth in the same units.

pub mod bin;
pub mod blend;
pub mod coverage;
pub mod order;
pub mod pools;
#[cfg(test)]
mod tests;

use blend::{Fragment, PixelList};

/// A fragment fainter than this is not kept: it cannot change an 8-bit pixel alone,
/// and would take a place in a pixel's list from one that can.
pub const MIN_ALPHA: f32 = 1.0 / 1024.0;

/// One end of a segment, on the screen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrandVertex {
    /// Pixels.
    pub position: [f32; 2],
    pub depth: f32,
    /// The strand's width here, pixels.
    pub width: f32,
    /// The strand's own opacity here (1 for an opaque hair).
    pub alpha: f32,
    /// Its lit colour here, linear.
    pub color: [f32; 3],
}

/// A piece of a strand between two of its vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub a: StrandVertex,
    pub b: StrandVertex,
    /// The strand it belongs to: fragments of one strand in one pixel are one fragment.
    pub strand: u32,
}

impl Segment {
    /// The segment's fragment in the pixel centred at `centre`, if it leaves one. Its
    /// colour is held to the displayable range first, as the fixed-function
    /// rasteriser's 8-bit target holds each sample's: a highlight brighter than white
    /// that covers half a pixel makes it half white, not white.
    pub fn fragment(&self, centre: [f32; 2]) -> Option<Fragment> {
        let (a, b) = (&self.a, &self.b);
        let foot = coverage::footprint(centre, a.position, b.position, a.width, b.width);
        let t = foot.t;
        let mix = |p: f32, q: f32| p + (q - p) * t;
        let alpha = foot.coverage * mix(a.alpha, b.alpha);
        (alpha > MIN_ALPHA).then(|| Fragment {
            depth: mix(a.depth, b.depth),
            strand: self.strand,
            alpha: alpha.min(1.0),
            color: [0, 1, 2].map(|c| mix(a.color[c], b.color[c]).clamp(0.0, 1.0)),
        })
    }

    /// How far from its axis the segment can reach a pixel's centre, pixels: half its
    /// widest width and a pixel's half-diagonal.
    pub fn reach(&self) -> f32 {
        0.5 * self.a.width.max(self.b.width) + std::f32::consts::FRAC_1_SQRT_2
    }
}

/// The bounds the drawing works within.
#[derive(Clone, Copy, Debug)]
pub struct RasterBudget {
    /// Tile side, pixels.
    pub tile: u32,
    /// Fragments a pixel keeps sorted; the rest are blended in the tail.
    pub nearest: usize,
    /// Entries (a segment in a tile) all the tiles' lists share.
    pub entries: usize,
}

/// What the strands are drawn over: the mesh pass's colour and depth.
#[derive(Clone, Debug)]
pub struct Backdrop {
    pub width: u32,
    pub height: u32,
    /// Row by row, linear RGB.
    pub color: Vec<[f32; 3]>,
    /// Row by row; `f32::INFINITY` where no body is.
    pub depth: Vec<f32>,
}

impl Backdrop {
    /// An empty backdrop of one colour.
    pub fn clear(width: u32, height: u32, color: [f32; 3]) -> Self {
        let n = (width * height) as usize;
        Self {
            width,
            height,
            color: vec![color; n],
            depth: vec![f32::INFINITY; n],
        }
    }
}

/// What the drawing counted.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RasterCounts {
    /// Segments drawn (at least one tile entry).
    pub segments: u32,
    /// Entries made, over every tile.
    pub entries: u64,
    /// Entries that found the pool full: their segments are missing from those tiles.
    pub entries_lost: u64,
    /// Segments the body hid from every tile they touch.
    pub hidden: u32,
    /// Fragments blended in a pixel's tail rather than in order.
    pub tail_fragments: u64,
    /// Pixels that stopped walking their tile's list, opaque, before its end.
    pub pixels_stopped: u64,
    /// Fragments the pixels took: every segment's share of a pixel in front of the
    /// body (kept in order, merged with its strand's or blended in a tail).
    pub fragments: u64,
    /// Entries per tile, row by row.
    pub per_tile: Vec<u32>,
}

/// A drawn image and what drawing it counted.
#[derive(Clone, Debug)]
pub struct Raster {
    pub width: u32,
    pub height: u32,
    /// Row by row, linear RGB.
    pub color: Vec<[f32; 3]>,
    pub counts: RasterCounts,
}

/// The tiles of one frame and their lists of segments (indices into the frame's).
#[derive(Clone, Debug, PartialEq)]
pub struct Bins {
    pub columns: u32,
    pub rows: u32,
    /// Row by row, each sorted by depth bin ([`order`]).
    pub lists: Vec<Vec<u32>>,
    /// Row by row: where each depth bin that holds an entry ends in the tile's list.
    pub stops: Vec<Vec<u32>>,
}

/// Bins `segments` into the tiles of `backdrop` within `budget`.
pub fn bin(
    segments: &[Segment],
    backdrop: &Backdrop,
    budget: &RasterBudget,
) -> (Bins, RasterCounts) {
    let tile = budget.tile;
    let columns = backdrop.width.div_ceil(tile);
    let rows = backdrop.height.div_ceil(tile);
    // The farthest the body reaches in each tile: a segment behind it is hidden there.
    let mut body_far = vec![0.0f32; (columns * rows) as usize];
    for y in 0..backdrop.height {
        for x in 0..backdrop.width {
            let at = ((y / tile) * columns + x / tile) as usize;
            body_far[at] = body_far[at].max(backdrop.depth[(y * backdrop.width + x) as usize]);
        }
    }
    let tiles = (columns * rows) as usize;
    let mut bins = Bins {
        columns,
        rows,
        lists: vec![Vec::new(); tiles],
        stops: vec![Vec::new(); tiles],
    };
    // Each tile's range of sort keys, over every segment it lists or would have but for
    // a full pool.
    let mut range = vec![(f32::INFINITY, 0.0f32); tiles];
    let mut counts = RasterCounts::default();
    for (index, segment) in segments.iter().enumerate() {
        let near = segment.a.depth.min(segment.b.depth);
        let key = order::depth_key(segment.a.depth, segment.b.depth);
        let (mut listed, mut touched, mut lost) = (false, false, false);
        bin::tiles_touched(
            segment.a.position,
            segment.b.position,
            segment.reach(),
            tile,
            columns,
            rows,
            |column, row| {
                touched = true;
                let at = (row * columns + column) as usize;
                if near >= body_far[at] {
                    return;
                }
                range[at] = (range[at].0.min(key), range[at].1.max(key));
                if counts.entries as usize >= budget.entries {
                    counts.entries_lost += 1;
                    lost = true;
                    return;
                }
                counts.entries += 1;
                bins.lists[at].push(index as u32);
                listed = true;
            },
        );
        counts.segments += u32::from(listed);
        counts.hidden += u32::from(touched && !listed && !lost);
    }
    for (at, list) in bins.lists.iter_mut().enumerate() {
        let keys: Vec<f32> = list
            .iter()
            .map(|&i| &segments[i as usize])
            .map(|s| order::depth_key(s.a.depth, s.b.depth))
            .collect();
        bins.stops[at] = order::sort_by_depth(list, &keys, range[at].0, range[at].1);
    }
    counts.per_tile = bins.lists.iter().map(|l| l.len() as u32).collect();
    (bins, counts)
}

/// Draws `segments` over `backdrop` within `budget`.
pub fn rasterize(segments: &[Segment], backdrop: &Backdrop, budget: &RasterBudget) -> Raster {
    let (bins, counts) = bin(segments, backdrop, budget);
    draw(segments, &bins, backdrop, budget, counts)
}

/// Draws the tiles' lists `bins` of `segments` over `backdrop`, each pixel taking its
/// tile's list in order (the order within a depth bin matters only to the tail: see
/// [`blend`]) and stopping at the first of the tile's stops where it is opaque.
pub fn draw(
    segments: &[Segment],
    bins: &Bins,
    backdrop: &Backdrop,
    budget: &RasterBudget,
    mut counts: RasterCounts,
) -> Raster {
    let tile = budget.tile;
    let mut color = backdrop.color.clone();
    for row in 0..bins.rows {
        for column in 0..bins.columns {
            let list = &bins.lists[(row * bins.columns + column) as usize];
            let stops = &bins.stops[(row * bins.columns + column) as usize];
            if list.is_empty() {
                continue;
            }
            for y in row * tile..((row + 1) * tile).min(backdrop.height) {
                for x in column * tile..((column + 1) * tile).min(backdrop.width) {
                    let at = (y * backdrop.width + x) as usize;
                    let centre = [x as f32 + 0.5, y as f32 + 0.5];
                    let mut pixel = PixelList::new();
                    let mut next = 0;
                    for (i, &index) in list.iter().enumerate() {
                        if stops.get(next) == Some(&(i as u32)) {
                            if pixel.transmitted() < order::OPAQUE_TRANSMIT {
                                counts.pixels_stopped += 1;
                                break;
                            }
                            next += 1;
                        }
                        if let Some(f) = segments[index as usize].fragment(centre) {
                            if f.depth < backdrop.depth[at] {
                                pixel.add(f, budget.nearest);
                                counts.fragments += 1;
                            }
                        }
                    }
                    counts.tail_fragments += u64::from(pixel.tail_count());
                    color[at] = pixel.resolve(backdrop.color[at]);
                }
            }
        }
    }
    Raster {
        width: backdrop.width,
        height: backdrop.height,
        color,
        counts,
    }
}

//! The compute rasteriser's pools (`--raster compute`): what each holds per pixel of
//! the target, the floors for small images, and their sizes in bytes, which the GPU
//! layer allocates and the documents tabulate. A frame that asks for more than a pool
//! holds is counted, and the pools grow to it for the frames after.

/// The bounds the compute passes draw within, per pixel of the target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoolBudget {
    /// Tile side, pixels.
    pub tile: u32,
    /// Strand vertices, segments and tile entries the pools hold, per pixel.
    pub vertices_per_pixel: u32,
    pub segments_per_pixel: u32,
    pub entries_per_pixel: u32,
    /// The fewest each pool holds whatever the image size ([`MIN_VERTICES`],
    /// [`MIN_SEGMENTS`], [`MIN_ENTRIES`]; tests lower them to overflow the pools).
    pub floor: Demand,
}

impl Default for PoolBudget {
    fn default() -> Self {
        Self {
            tile: 8,
            vertices_per_pixel: 4,
            segments_per_pixel: 3,
            entries_per_pixel: 6,
            floor: Demand {
                vertices: MIN_VERTICES,
                segments: MIN_SEGMENTS,
                entries: MIN_ENTRIES,
            },
        }
    }
}

/// Bytes of one strand vertex, segment, tile (its bin's ten words: its counts, its
/// list's place, its key range, the two words of a CPU driver's scatter halves and a
/// place in the list of the tiles that list something: `TileBin` in
/// strand_raster.glsl), binned entry and sorted entry (its segment and a word of the
/// block masks: a row, or its own mask), and of a pixel of the layer.
pub const VERTEX_BYTES: u64 = 32;
pub const SEGMENT_BYTES: u64 = 8;
pub const TILE_BYTES: u64 = 40;
pub const ENTRY_BYTES: u64 = 4;
pub const SORTED_ENTRY_BYTES: u64 = 8;
pub const LAYER_BYTES: u64 = 16;
/// Bytes of a texel of the vertex pool (a texel buffer: a vertex is two, its position
/// then its colour, or under the Marschner model what lights it until the lighting
/// pass writes its colour there).
pub const VERTEX_TEXEL_BYTES: u64 = VERTEX_BYTES / 2;

/// The fewest strand vertices, segments and entries the pools hold whatever the image
/// size: a small image of dense fur has more strands than pixels.
pub const MIN_VERTICES: u64 = 1 << 20;
pub const MIN_SEGMENTS: u64 = 1 << 20;
pub const MIN_ENTRIES: u64 = 1 << 21;

/// How many strand vertices, segments and entries a frame asked the pools for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Demand {
    pub vertices: u64,
    pub segments: u64,
    pub entries: u64,
}

impl Demand {
    pub fn max(self, other: Demand) -> Demand {
        Demand {
            vertices: self.vertices.max(other.vertices),
            segments: self.segments.max(other.segments),
            entries: self.entries.max(other.entries),
        }
    }

    pub fn exceeds(&self, capacity: &Demand) -> bool {
        self.vertices > capacity.vertices
            || self.segments > capacity.segments
            || self.entries > capacity.entries
    }
}

/// The sizes, in bytes, of the pools for a target of `width` × `height` pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PoolSizes {
    pub vertices: u64,
    pub segments: u64,
    pub tiles: u64,
    /// The entries, binned; and again, each tile's list sorted by depth.
    pub entries: u64,
    pub sorted: u64,
    pub layer: u64,
}

impl PoolSizes {
    /// The budget's pools at `width` × `height`, holding at least `demand`.
    pub fn of(budget: &PoolBudget, width: u32, height: u32, demand: &Demand) -> Self {
        let pixels = u64::from(width) * u64::from(height);
        let tiles =
            u64::from(width.div_ceil(budget.tile)) * u64::from(height.div_ceil(budget.tile));
        let capacity = Self::capacity(budget, pixels, demand);
        Self {
            vertices: capacity.vertices * VERTEX_BYTES,
            segments: capacity.segments * SEGMENT_BYTES,
            tiles: tiles * TILE_BYTES,
            entries: capacity.entries * ENTRY_BYTES,
            sorted: capacity.entries * SORTED_ENTRY_BYTES,
            layer: pixels * LAYER_BYTES,
        }
    }

    /// The elements each pool holds: the budget per pixel, the floors, and `demand`.
    pub fn capacity(budget: &PoolBudget, pixels: u64, demand: &Demand) -> Demand {
        Demand {
            vertices: pixels * u64::from(budget.vertices_per_pixel),
            segments: pixels * u64::from(budget.segments_per_pixel),
            entries: pixels * u64::from(budget.entries_per_pixel),
        }
        .max(budget.floor)
        .max(*demand)
    }

    pub fn total(&self) -> u64 {
        self.vertices + self.segments + self.tiles + self.entries + self.sorted + self.layer
    }

    /// The largest of the pools bound as storage buffers, bytes: the tiles and the
    /// layer, and the vertices and the segments, which the geometry stage writes as
    /// storage buffers (the passes read them as texel buffers).
    pub fn largest_storage(&self) -> u64 {
        [self.tiles, self.layer, self.vertices, self.segments]
            .into_iter()
            .max()
            .unwrap_or(0)
    }

    /// The most texels any of the pools that are texel buffers holds (the vertices,
    /// the segments, both entry pools).
    pub fn most_texels(&self) -> u64 {
        [
            self.vertices / VERTEX_TEXEL_BYTES,
            self.segments / SEGMENT_BYTES,
            self.entries / ENTRY_BYTES,
            self.sorted / SORTED_ENTRY_BYTES,
        ]
        .into_iter()
        .max()
        .unwrap_or(0)
    }
}

/// The image sizes the documents tabulate the pools at.
pub const TABLED_SIZES: [(&str, u32, u32); 3] = [
    ("720p", 1280, 720),
    ("1080p", 1920, 1080),
    ("4K", 3840, 2160),
];

/// The pools' sizes at [`TABLED_SIZES`] under `budget`, as a Markdown table (the
/// documents hold it word for word; a test checks).
pub fn table(budget: &PoolBudget) -> String {
    use crate::error::size_text;
    let mut out = String::from(
        "| image | strand vertices | segments | tiles | entries | sorted entries | hair layer | all |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for (name, width, height) in TABLED_SIZES {
        let s = PoolSizes::of(budget, width, height, &Demand::default());
        out += &format!(
            "| {name} ({width}×{height}) | {} | {} | {} | {} | {} | {} | {} |\n",
            size_text(s.vertices),
            size_text(s.segments),
            size_text(s.tiles),
            size_text(s.entries),
            size_text(s.sorted),
            size_text(s.layer),
            size_text(s.total()),
        );
    }
    let b = budget;
    out += &format!(
        "\nPer pixel: {} strand vertices of {VERTEX_BYTES} bytes, {} segments of \
         {SEGMENT_BYTES} bytes, {} entries of {ENTRY_BYTES} bytes binned and \
         {SORTED_ENTRY_BYTES} sorted, a layer pixel of {LAYER_BYTES} bytes; per {}×{} tile {TILE_BYTES} bytes; at least {} vertices, {} \
         segments and {} entries.\n",
        b.vertices_per_pixel,
        b.segments_per_pixel,
        b.entries_per_pixel,
        b.tile,
        b.tile,
        b.floor.vertices,
        b.floor.segments,
        b.floor.entries,
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pools grow with the image and hold at least their floors and the demand.
    #[test]
    fn pools_follow_the_budget_the_floors_and_the_demand() {
        let budget = PoolBudget::default();
        let small = PoolSizes::of(&budget, 16, 16, &Demand::default());
        assert_eq!(small.vertices, MIN_VERTICES * VERTEX_BYTES);
        let big = PoolSizes::of(&budget, 3840, 2160, &Demand::default());
        let pixels = 3840 * 2160;
        assert_eq!(
            big.segments,
            pixels * u64::from(budget.segments_per_pixel) * SEGMENT_BYTES
        );
        assert_eq!(big.tiles, 480 * 270 * TILE_BYTES);
        let demand = Demand {
            vertices: 1 << 26,
            segments: 3,
            entries: 0,
        };
        let asked = PoolSizes::of(&budget, 16, 16, &demand);
        assert_eq!(asked.vertices, (1 << 26) * VERTEX_BYTES);
        assert_eq!(asked.segments, MIN_SEGMENTS * SEGMENT_BYTES);
        assert_eq!(asked.most_texels(), 2 << 26);
        assert!(table(&budget).contains("| 4K (3840×2160) |"));
    }
}

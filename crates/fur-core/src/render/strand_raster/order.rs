//! Front to back: each tile's list sorted into depth bins, so that a pixel meets its
//! fragments nearly nearest first and can stop once it is opaque.
//!
//! A tile's depth range is that of the segments it lists, each segment taken at its
//! nearer end; the range is cut into [`DEPTH_BINS`] equal bins and the list is sorted by
//! bin (a counting sort; within a bin, in any order). A pixel walking the list may stop
//! only where one bin ends and the next begins (the tile's *stops*), and only when what
//! it has met lets through less than [`OPAQUE_TRANSMIT`] of the light: what lies in the
//! later bins starts farther away than everything it has met began, so it would show
//! through that little at most. Stopping at bin ends, not at any entry, keeps the image
//! independent of the order within a bin: which fragments a pixel meets depends on the
//! bins alone.

/// The depth bins a tile's list is sorted into.
pub const DEPTH_BINS: u32 = 32;

/// The entries of a tile's sorted list whose block masks the sort pass turns into one
/// row a block (a bit an entry: a word), so that the fine pass's search reads one word
/// for that many entries (strand_raster.glsl). It changes no image.
pub const ROW_RUN: u32 = 32;

/// A pixel whose fragments so far let through less light than this stops at the next
/// bin's end: under half of an 8-bit step of what lies behind can still show.
pub const OPAQUE_TRANSMIT: f32 = 1.0 / 512.0;

/// A segment's sort key: its nearer end's depth, negative depths taken as 0 (the GPU
/// orders the keys by their bits, which for floats holds from 0 up).
pub fn depth_key(a_depth: f32, b_depth: f32) -> f32 {
    a_depth.min(b_depth).max(0.0)
}

/// The scale from depth to bins over a tile's range `lo..=hi` of keys: 0 when the range
/// is empty or a point (everything in the first bin).
pub fn bin_scale(lo: f32, hi: f32) -> f32 {
    if hi > lo {
        DEPTH_BINS as f32 / (hi - lo)
    } else {
        0.0
    }
}

/// The bin of `key` in a tile whose range starts at `lo`, with `scale` from
/// [`bin_scale`]: the arithmetic `strand_sort.comp` does, operation for operation.
pub fn depth_bin(key: f32, lo: f32, scale: f32) -> u32 {
    let b = (key - lo) * scale;
    if b > 0.0 {
        (b as u32).min(DEPTH_BINS - 1)
    } else {
        0
    }
}

/// Sorts `list` by the bins of `keys` (one per entry, in the list's order) over the
/// range `lo..=hi`, keeping the order within a bin; returns the tile's stops: where
/// each bin that holds an entry ends in the sorted list, in order.
pub fn sort_by_depth(list: &mut Vec<u32>, keys: &[f32], lo: f32, hi: f32) -> Vec<u32> {
    let scale = bin_scale(lo, hi);
    let bins: Vec<u32> = keys.iter().map(|&k| depth_bin(k, lo, scale)).collect();
    let mut order: Vec<usize> = (0..list.len()).collect();
    order.sort_by_key(|&i| bins[i]);
    *list = order.iter().map(|&i| list[i]).collect();
    bin_ends(&order.iter().map(|&i| bins[i]).collect::<Vec<_>>())
}

/// The stops of a list whose entries lie in `bins`, in the list's order: where an
/// entry's bin differs from the next one's, and the list's end. For a list sorted by
/// bin, where each bin that holds an entry ends; the fine pass finds them so, as it
/// walks (strand_fine.comp).
pub fn bin_ends(bins: &[u32]) -> Vec<u32> {
    (1..=bins.len())
        .filter(|&i| i == bins.len() || bins[i] != bins[i - 1])
        .map(|i| i as u32)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bins cover the range: its ends fall in the first and the last bin, and a key
    /// a bin's width in lies in the next bin.
    /// Seen failing against a scale of `DEPTH_BINS - 1` (the far end past the last bin's
    /// start only at the end).
    #[test]
    fn the_bins_cut_the_range_evenly() {
        let (lo, hi) = (0.25, 0.75);
        let scale = bin_scale(lo, hi);
        assert_eq!(depth_bin(lo, lo, scale), 0);
        assert_eq!(depth_bin(hi, lo, scale), DEPTH_BINS - 1);
        let width = (hi - lo) / DEPTH_BINS as f32;
        assert_eq!(depth_bin(lo + 1.5 * width, lo, scale), 1);
        assert_eq!(depth_bin(lo + 10.5 * width, lo, scale), 10);
        // A point range, and keys below it, fall in the first bin.
        assert_eq!(depth_bin(0.5, 0.5, bin_scale(0.5, 0.5)), 0);
        assert_eq!(depth_bin(0.1, lo, scale), 0);
    }

    /// The sort is by bin, stable within one, and the stops end each bin that holds an
    /// entry. Seen failing against stops at every bin's end (empty ones included).
    #[test]
    fn a_list_is_sorted_by_bin_and_stops_end_the_full_bins() {
        let mut list = vec![10, 11, 12, 13, 14];
        let keys = [0.9, 0.1, 0.9, 0.5, 0.1];
        let stops = sort_by_depth(&mut list, &keys, 0.1, 0.9);
        assert_eq!(list, vec![11, 14, 13, 10, 12]);
        assert_eq!(stops, vec![2, 3, 5]);
        assert_eq!(depth_key(0.4, -0.2), 0.0);
        assert_eq!(depth_key(0.4, 0.3), 0.3);
    }

    /// A list's stops are where its bin changes and its end: one a bin for a sorted
    /// list, more for one that is not (which is how a test tells an unsorted GPU list
    /// from the twin's), none for an empty one. Seen failing against a stop before the
    /// change (an entry early) and without the list's end.
    #[test]
    fn stops_fall_where_the_bin_changes_and_at_the_end() {
        assert_eq!(bin_ends(&[0, 0, 3, 7, 7]), vec![2, 3, 5]);
        assert_eq!(bin_ends(&[7, 0, 7, 0, 0]), vec![1, 2, 3, 5]);
        assert_eq!(bin_ends(&[4]), vec![1]);
        assert!(bin_ends(&[]).is_empty());
    }
}

//! The unit tests' allocator: the system's, counting each thread's bytes, so a test can
//! observe what a reader allocates (its peak and its total), not infer it.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

thread_local! {
    static LIVE: Cell<isize> = const { Cell::new(0) };
    static PEAK: Cell<isize> = const { Cell::new(0) };
    static TOTAL: Cell<usize> = const { Cell::new(0) };
}

fn grew(bytes: usize) {
    let _ = LIVE.try_with(|live| {
        live.set(live.get() + bytes as isize);
        let _ = PEAK.try_with(|peak| peak.set(peak.get().max(live.get())));
    });
    let _ = TOTAL.try_with(|total| total.set(total.get() + bytes));
}

fn shrank(bytes: usize) {
    let _ = LIVE.try_with(|live| live.set(live.get() - bytes as isize));
}

struct Counting;

// SAFETY: every call is passed to the system allocator unchanged; the counters are
// plain thread-locals with no destructor, which allocate nothing.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract is passed on.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract is passed on.
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract is passed on.
        unsafe { System.dealloc(p, layout) };
        shrank(layout.size());
    }

    unsafe fn realloc(&self, p: *mut u8, layout: Layout, size: usize) -> *mut u8 {
        // SAFETY: the caller's contract is passed on.
        let q = unsafe { System.realloc(p, layout, size) };
        if !q.is_null() {
            shrank(layout.size());
            grew(size);
        }
        q
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

/// What a piece of work allocated on this thread.
#[derive(Clone, Copy, Debug)]
pub struct Usage {
    /// The most bytes it held at once.
    pub peak: usize,
    /// Every byte it asked for, freed or not.
    pub total: usize,
}

/// Runs `work`, counting what it allocates on this thread.
pub fn measure<T>(work: impl FnOnce() -> T) -> (T, Usage) {
    let start = LIVE.with(Cell::get);
    PEAK.with(|p| p.set(start));
    let total = TOTAL.with(Cell::get);
    let out = work();
    let usage = Usage {
        peak: (PEAK.with(Cell::get) - start).max(0) as usize,
        total: TOTAL.with(Cell::get) - total,
    };
    (out, usage)
}

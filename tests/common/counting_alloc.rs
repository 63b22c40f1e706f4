//! A counting global allocator for the tests and benchmarks that measure memory
//! (tests/memory.rs, tests/io_memory.rs, benches/optimize.rs). Included with `#[path]` by the
//! crates that want it, never through `mod common`, so no other test runs under it.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering::SeqCst};

/// The system allocator, counting the bytes live now and the most live since the last reset.
pub struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is forwarded to the system allocator unchanged; only counters are added.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded with the caller's guarantees.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            PEAK.fetch_max(LIVE.fetch_add(layout.size(), SeqCst) + layout.size(), SeqCst);
        }
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        // SAFETY: forwarded with the caller's guarantees.
        unsafe { System.dealloc(p, layout) };
        LIVE.fetch_sub(layout.size(), SeqCst);
    }

    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // Counted as a new block while the old one is still held: a moving reallocation holds
        // both at its peak.
        // SAFETY: forwarded with the caller's guarantees.
        let q = unsafe { System.realloc(p, layout, new_size) };
        if !q.is_null() {
            PEAK.fetch_max(LIVE.fetch_add(new_size, SeqCst) + new_size, SeqCst);
            LIVE.fetch_sub(layout.size(), SeqCst);
        }
        q
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

/// Peak heap bytes allocated by `f` beyond what was live when it started (run such
/// measurements one at a time: the counters are process-wide).
pub fn peak_of<R>(f: impl FnOnce() -> R) -> (R, usize) {
    let start = LIVE.load(SeqCst);
    PEAK.store(start, SeqCst);
    let r = f();
    (r, PEAK.load(SeqCst) - start)
}

//! Which threads are running library code: a thread-local marker that the C ABI's quiet
//! panic hook (`crate::ffi`'s `quiet` module) reads to decide whether a panic's message is
//! printed.
//!
//! A thread is inside the library while a C entry point runs on it ([`enter`]`(true)`), apart
//! from the caller's callbacks ([`enter`]`(false)` around them), and for its whole life when it
//! is one of the library's worker threads ([`mark_worker_thread`], called by `crate::pool`).
//! Only the C ABI installs the hook; without it the marker is never read.

use std::cell::Cell;

thread_local! {
    /// Whether this thread is running library code (a C entry point or a worker).
    static INSIDE: Cell<bool> = const { Cell::new(false) };
}

/// Whether the current thread is running library code (false while the thread is being
/// torn down).
pub(crate) fn is_inside() -> bool {
    INSIDE.try_with(Cell::get).unwrap_or(false)
}

/// Marks the current thread, for its lifetime, as running only library code.
pub(crate) fn mark_worker_thread() {
    let _ = INSIDE.try_with(|c| c.set(true));
}

/// Marks the current thread as inside the library (`true`) or in the caller's code (`false`,
/// around a callback) until the returned guard is dropped.
pub(crate) fn enter(inside: bool) -> Scope {
    Scope(INSIDE.try_with(|c| c.replace(inside)).unwrap_or(false))
}

/// Restores the previous state when dropped.
pub(crate) struct Scope(bool);

impl Drop for Scope {
    fn drop(&mut self) {
        let _ = INSIDE.try_with(|c| c.set(self.0));
    }
}

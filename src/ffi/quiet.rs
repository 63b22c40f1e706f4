//! No output on the host's stderr: a panic caught at the C boundary is reported through the
//! status and `quadopt_last_error()` only. Rust prints a panic's message (and, with
//! `RUST_BACKTRACE`, a backtrace) from the panic hook before unwinding starts, so the library
//! installs, once, a hook that stays silent while the panicking thread is inside a quadopt call
//! (or is one of the library's worker threads) and hands every other panic to the hook that was
//! installed before.

use std::cell::Cell;
use std::sync::Once;

thread_local! {
    /// Whether this thread is running library code (a C entry point or a worker).
    static INSIDE: Cell<bool> = const { Cell::new(false) };
}

/// Installs the quiet hook (the first time only).
pub(super) fn install_hook() {
    static INSTALLED: Once = Once::new();
    // The hook cannot be replaced while this thread panics (set_hook would panic).
    if std::thread::panicking() {
        return;
    }
    INSTALLED.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !INSIDE.try_with(Cell::get).unwrap_or(false) {
                previous(info);
            }
        }));
    });
}

/// Marks the current thread, for its lifetime, as running only library code.
pub(crate) fn mark_worker_thread() {
    let _ = INSIDE.try_with(|c| c.set(true));
}

/// Marks the current thread as inside the library (`true`) or in the caller's code (`false`,
/// around a callback) until the returned guard is dropped.
pub(super) fn enter(inside: bool) -> Scope {
    Scope(INSIDE.try_with(|c| c.replace(inside)).unwrap_or(false))
}

/// Restores the previous state when dropped.
pub(super) struct Scope(bool);

impl Drop for Scope {
    fn drop(&mut self) {
        let _ = INSIDE.try_with(|c| c.set(self.0));
    }
}

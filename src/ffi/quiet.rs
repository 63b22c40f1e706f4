//! No output on the host's stderr: a panic caught at the C boundary is reported through the
//! status and `quadopt_last_error()` only. Rust prints a panic's message (and, with
//! `RUST_BACKTRACE`, a backtrace) from the panic hook before unwinding starts, so the library
//! installs, once, a hook that stays silent while the panicking thread is inside a quadopt call
//! (or is one of the library's worker threads: `crate::quiet_threads` keeps that marker) and
//! hands every other panic to the hook that was installed before.

use crate::quiet_threads;
use std::sync::Once;

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
            if !quiet_threads::is_inside() {
                previous(info);
            }
        }));
    });
}

//! The C ABI: `extern "C"` functions over the Rust API, exported from the cdylib and staticlib
//! and described by `include/quadopt.h` (generated from this module by cbindgen, see
//! `cbindgen.toml` and `tests/header.rs`).
//!
//! Every entry point
//! - runs inside a panic boundary ([`std::panic::catch_unwind`]); a panic becomes
//!   `QuadoptStatus::Panic` instead of unwinding into (and aborting) the host program;
//! - checks its pointers, counts, sizes and alignment before touching memory, with
//!   `checked_mul` and the `isize::MAX` byte limit of Rust slices;
//! - copies its inputs into owned Rust values first, computes, and writes the caller's
//!   buffers only at the very end, so nothing is written on any error (cancellation included);
//! - allocates what grows with the input fallibly, and checks that the memory the topology
//!   and the optimizer need at their peak is available before they start (their allocations,
//!   rayon's among them, are not all fallible), so a mesh too large for the memory gives
//!   `QuadoptStatus::OutOfMemory` instead of aborting the host;
//! - runs the optimizer on the library's own worker threads (`src/pool.rs`), which survive
//!   `fork`;
//! - records a detailed message (which quad, which index, which option) in a thread-local
//!   buffer read by `quadopt_last_error`, and prints nothing (`ffi/quiet.rs`). The only other
//!   global state is the worker pool.
//!
//! Faces: every array of faces (`quads`) has four `uint32_t` per face; a triangle stores
//! `QUADOPT_NO_VERTEX` (`face::NO_VERTEX`) in its fourth slot, so quad-only callers see no
//! change and a quad-dominant mesh goes through the same functions (see `boundary.rs`).
//!
//! Enum-valued option fields are plain `u32` in the structs (a C caller can store any integer
//! there, which must never be read as a Rust enum) and are validated when converted.
//! Growable structs (`QuadoptOptions`, `QuadoptReport`) start with `struct_size`: the
//! library reads (or writes) only the prefix the caller declared.
//!
//! # Layout
//!
//! - `boundary.rs`: the panic boundary, the checks of the caller's pointers and counts, the
//!   checked reads of the caller's arrays into owned memory and the write of the coordinates;
//! - `status.rs`: `QuadoptStatus`, the internal error on its way to the caller, the
//!   thread-local last-error message, `quadopt_status_string` and `quadopt_last_error`;
//! - `options.rs`: `QuadoptOptions` and its enums, the progress callback type, reading the
//!   caller's prefix, conversion to the crate's `Options`, and `quadopt_options_init`, the
//!   one way to initialize options;
//! - `report.rs`: `QuadoptQuality`, `QuadoptReport`, writing the caller's prefix, and
//!   `quadopt_report_init`;
//! - `run.rs`: a run on the worker pool with the C progress callback, the memory checks before
//!   it, `quadopt_optimize` and `quadopt_quality`;
//! - `surface.rs`: meshes on curved surfaces in 3D: `quadopt_optimize_surface` and the surface
//!   run `quadopt_optimize` takes for a `dim` 3 mesh that is not planar;
//! - `plane.rs`: the library's one planarity rule for C and C++ callers: `quadopt_is_planar`
//!   (the `dim` 3 entry points decide with the same rule, `boundary.rs`'s `plane_of`);
//! - `handle.rs`: the reusable `QuadoptOptimizer` and its functions;
//! - `version.rs`: the version constants and functions;
//! - `quiet.rs`: the panic hook that keeps caught panics off the host's stderr.
//!
//! The modules are declared in the order of the header: cbindgen follows them in this order and
//! writes the functions in the order it meets them.
//!
//! # Why hidden, and not a crate of its own
//!
//! This module is `pub` (the integration tests, `tests/memory.rs`'s estimates and the fuzz
//! target call it directly; the `#[unsafe(no_mangle)]` symbols are exported from the cdylib
//! and staticlib either way) but `#[doc(hidden)]`:
//! Rust callers use the crate's Rust API, C and C++ callers read `include/quadopt.h`, so the
//! FFI is not part of the documented Rust surface. A separate `quadopt-capi` crate would keep
//! it out just as well, but would duplicate the library build (a second cdylib/staticlib,
//! its own features and profile) and the CMake integration (which builds and links this
//! crate's libraries) for no gain to any user, and it would need internals made public that
//! no Rust caller should see: the worker pool the C calls run on (`pool`), the quiet-panic
//! marker of the threads running library code (`quiet_threads`) and the fallible allocation
//! helper (`alloc`).

// In the header's order (cbindgen writes the functions in the order it meets them); each
// declaration is its own group, so that rustfmt keeps the order.
mod boundary;

mod status;

mod options;

mod report;

mod run;

mod surface;

mod plane;

mod handle;

mod version;

mod quiet;

#[cfg(test)]
mod test_support;

pub use boundary::QUADOPT_NO_VERTEX;
pub use handle::{
    QuadoptOptimizer, quadopt_optimizer_create, quadopt_optimizer_free, quadopt_optimizer_optimize,
};
pub use options::{
    QuadoptBoundary, QuadoptEffort, QuadoptMethod, QuadoptOptions, QuadoptProgress, QuadoptProgressFn,
    QuadoptStopRule, quadopt_options_init,
};
pub use plane::{QuadoptPlanarity, quadopt_is_planar};
pub use report::{QuadoptFaceKindQuality, QuadoptQuality, QuadoptReport, quadopt_report_init};
pub use run::{quadopt_optimize, quadopt_quality, quadopt_verdict_quality, run_bytes, topology_bytes};
pub use status::{QuadoptStatus, quadopt_last_error, quadopt_status_string};
pub use surface::quadopt_optimize_surface;
pub use version::{
    QUADOPT_VERSION_MAJOR, QUADOPT_VERSION_MINOR, QUADOPT_VERSION_PATCH, quadopt_version,
    quadopt_version_numbers,
};

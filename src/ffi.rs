//! The C ABI: `extern "C"` functions over the Rust API, exported from the cdylib and staticlib
//! and described by `include/quadopt.h` (generated from this file by cbindgen, see
//! `cbindgen.toml` and `tests/header.rs`).
//!
//! Every entry point
//! - runs inside a panic boundary ([`std::panic::catch_unwind`]); a panic becomes
//!   [`QuadoptStatus::Panic`] instead of unwinding into (and aborting) the host program;
//! - checks its pointers, counts, sizes and alignment before touching memory, with
//!   `checked_mul` and the `isize::MAX` byte limit of Rust slices;
//! - copies its inputs into owned Rust values first, computes, and writes the caller's
//!   buffers only at the very end, so nothing is written on any error (cancellation included);
//! - allocates what grows with the input fallibly, and checks that the memory the topology
//!   and the optimizer need at their peak is available before they start (their allocations,
//!   rayon's among them, are not all fallible), so a mesh too large for the memory gives
//!   [`QuadoptStatus::OutOfMemory`] instead of aborting the host;
//! - runs the optimizer on the library's own worker threads (`src/pool.rs`), which survive
//!   `fork`;
//! - records a detailed message (which quad, which index, which option) in a thread-local
//!   buffer read by [`quadopt_last_error`], and prints nothing (`ffi/quiet.rs`). The only other
//!   global state is the worker pool.
//!
//! Enum-valued option fields are plain `u32` in the structs (a C caller can store any integer
//! there, which must never be read as a Rust enum) and are validated when converted.
//! Growable structs ([`QuadoptOptions`], [`QuadoptReport`]) start with `struct_size`: the
//! library reads (or writes) only the prefix the caller declared.

use crate::alloc::try_with_capacity;
use crate::error::Error;
use crate::mesh::QuadMesh;
use crate::quality::QualityStats;
use crate::smooth::{BoundaryMode, Method, Optimizer, Options, Progress, Report, StopRule};
use glam::DVec2;
use std::cell::RefCell;
use std::ffi::{CStr, CString, c_char, c_void};
use std::mem::size_of;
use std::panic::{self, AssertUnwindSafe};

pub(crate) mod quiet;

use crate::pool;

/// Major version of the library (the `x` of `x.y.z`).
pub const QUADOPT_VERSION_MAJOR: u32 = 0;
/// Minor version of the library (the `y` of `x.y.z`).
pub const QUADOPT_VERSION_MINOR: u32 = 1;
/// Patch version of the library (the `z` of `x.y.z`).
pub const QUADOPT_VERSION_PATCH: u32 = 0;

/// Result of every fallible function. `QUADOPT_STATUS_OK` (0) is success; on any other
/// value nothing was written to the caller's buffers, and `quadopt_last_error()` describes
/// the failure.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QuadoptStatus {
    /// Success.
    Ok = 0,
    /// A required pointer was NULL (or an array pointer was NULL with a nonzero count).
    NullPointer = 1,
    /// A dimension other than 2 or 3, a count whose byte size overflows, a buffer that is too
    /// small or misaligned, or a `struct_size` smaller than this version's struct.
    InvalidArgument = 2,
    /// An option is out of its range or an enum-valued option is unknown; the message names it.
    InvalidOption = 3,
    /// The mesh has no quads.
    NoQuads = 4,
    /// A quad refers to a vertex index >= vertex_count.
    IndexOutOfRange = 5,
    /// A quad uses the same vertex twice.
    RepeatedVertex = 6,
    /// An edge is shared by more than two quads.
    NonManifold = 7,
    /// An x or y coordinate is NaN or infinite.
    NonFiniteCoordinate = 8,
    /// The quads cannot be oriented consistently (e.g. a Moebius strip).
    NonOrientable = 9,
    /// A handle was used with a different vertex count than it was created for.
    Mismatch = 10,
    /// The progress callback returned false; coordinates and report are untouched.
    Cancelled = 11,
    /// An internal error (a bug) was caught at the API boundary.
    Panic = 12,
    /// Reserved: the mesh is not planar. Not returned by this version (z is ignored).
    NotPlanar = 13,
    /// Not enough memory (or threads) for this mesh: an allocation that grows with the input
    /// failed, the memory the optimizer needs at its peak was not available when checked before
    /// it started, or not even one worker thread could start. Nothing was written; the same
    /// call can succeed with more memory available.
    OutOfMemory = 14,
}

/// Interior smoothing method, stored as a `uint32_t` in `QuadoptOptions::method`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QuadoptMethod {
    /// The embedded polygon method of Akram, Si and Chen (the default).
    EmbeddedPolygon = 0,
    /// Uniform Laplacian smoothing.
    Laplacian = 1,
    /// Cotangent-weighted Laplacian smoothing.
    Cotangent = 2,
    /// Xu and Newman's angle-based smoothing.
    AngleBased = 3,
}

/// Boundary treatment, stored as a `uint32_t` in `QuadoptOptions::boundary`. Corners and
/// fixed vertices never move in any mode.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QuadoptBoundary {
    /// Both approaches in one pass: each boundary vertex takes, every sweep, the slide or the
    /// snap candidate that leaves its star better (the default).
    Auto = 0,
    /// Boundary vertices never move.
    Fixed = 1,
    /// Move boundary vertices along the original boundary polyline only.
    Slide = 2,
    /// Rotate to bisect, then project back onto the original boundary.
    Snap = 3,
}

/// When a run stops, stored as a `uint32_t` in `QuadoptOptions::stop_rule`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QuadoptStopRule {
    /// When the collective energy changes by less than `tau` (per movable vertex, or
    /// absolute with `tau_absolute`), as in the paper.
    Energy = 0,
    /// When the result stops improving (the default): checked every 5 sweeps, stop once the
    /// kept iterate has not changed for 4 windows, or at the second window in a row that
    /// repaired no inverted quad and whose shrinking gains leave less than 5e-3 of minimum and
    /// 4e-3 of average scaled Jacobian to come (their geometric tail).
    Quality = 1,
}

/// Progress of a run, passed to the progress callback after every sweep (and regularly while
/// untangling, with `iteration` 0 and NaN energies).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadoptProgress {
    /// Sweeps done so far in the current pass (1-based; 0 while untangling).
    pub iteration: usize,
    /// The iteration cap of a pass.
    pub max_iterations: usize,
    /// Current pass (1-based). Every mode runs one pass since the automatic mode decides per
    /// vertex; the field stays for compatibility.
    pub pass: usize,
    /// Number of passes planned.
    pub passes: usize,
    /// Collective torsion-spring energy measured during the last sweep.
    pub energy: f64,
    /// Absolute change of the energy in the last sweep.
    pub energy_change: f64,
}

/// Progress callback: called on the calling thread after every sweep with the progress (valid
/// only during the call) and the options' `progress_user_data`. Return false to cancel: the
/// call then fails with `QUADOPT_STATUS_CANCELLED` and writes nothing. The callback may call
/// other quadopt functions, but must not throw a C++ exception or `longjmp` out of itself
/// (that would unwind through Rust frames; catch inside and return false instead), and must
/// not `fork` (the run's worker would be missing in the child).
pub type QuadoptProgressFn =
    Option<unsafe extern "C" fn(progress: *const QuadoptProgress, user_data: *mut c_void) -> bool>;

/// Optimization options. Fill with `quadopt_options_default()` (or
/// `quadopt_options_defaults()`), then change fields. Growable: the library reads only the
/// first `struct_size` bytes; a `struct_size` smaller than this version's struct is
/// `QUADOPT_STATUS_INVALID_ARGUMENT`, bytes beyond this version's struct are ignored.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct QuadoptOptions {
    /// `sizeof(QuadoptOptions)` as the caller compiled it; set by `quadopt_options_default()`.
    pub struct_size: u32,
    /// Interior method, a `QuadoptMethod` value (default `QUADOPT_METHOD_EMBEDDED_POLYGON`).
    pub method: u32,
    /// Boundary treatment, a `QuadoptBoundary` value (default `QUADOPT_BOUNDARY_AUTO`).
    pub boundary: u32,
    /// Iteration cap per pass, >= 1 (default 1000).
    pub max_iterations: u32,
    /// Step factor, in (0, 1] (default 1).
    pub lambda: f64,
    /// Threshold of `QUADOPT_STOP_RULE_ENERGY` on the energy change between sweeps, finite and >= 0: per movable
    /// vertex, or absolute when `tau_absolute` is set (default 1e-7; the default quality rule ignores it).
    pub tau: f64,
    /// Boundary vertices turning by more than this many degrees are corners and never move,
    /// in [0, 180] (default 45).
    pub feature_angle_deg: f64,
    /// Floor of the guarded moves, in (0, 1] (default 0.05).
    pub guard_floor: f64,
    /// Largest allowed distance between a new boundary edge and the original boundary it
    /// replaces, relative to that edge's length; any negative value means unlimited (default
    /// -1). NaN is an invalid option.
    pub max_boundary_deviation: f64,
    /// Nonzero: compare `tau` with the absolute energy change, as the paper does (default 0).
    pub tau_absolute: u8,
    /// Nonzero: guarded moves, so a valid mesh's worst quad never gets worse (default 1).
    pub guard: u8,
    /// Nonzero: untangle inverted quads before smoothing (default 1).
    pub untangle: u8,
    /// Nonzero: return the best iterate seen instead of the last one (default 1).
    pub keep_best: u8,
    /// When to stop, a `QuadoptStopRule` value (default `QUADOPT_STOP_RULE_QUALITY`, 1).
    pub stop_rule: u32,
    /// Progress callback, or NULL for none (default NULL).
    pub progress: QuadoptProgressFn,
    /// Passed unchanged to `progress` (default NULL).
    pub progress_user_data: *mut c_void,
    /// Nonzero: the max-min stage after the sweeps, which raises the worst quad and never
    /// lowers the minimum (default 1). Added in 0.2: a caller's struct without it (its
    /// `struct_size` ends before this field) gets the default.
    pub max_min: u32,
    /// Reserved; set to 0. Ignored by this version.
    pub reserved1: u32,
}

/// Quality statistics of a set of quads (signed scaled Jacobian, Verdict's definition,
/// measured against the mesh's consistent orientation).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct QuadoptQuality {
    /// Smallest scaled Jacobian (the worst quad), in [-1, 1].
    pub min: f64,
    /// Mean scaled Jacobian.
    pub avg: f64,
    /// Largest scaled Jacobian.
    pub max: f64,
    /// Number of quads with a scaled Jacobian <= 0 (inverted or degenerate).
    pub inverted: usize,
}

/// What an optimization did. Growable: set `struct_size` (`quadopt_report_init()` does); the
/// library writes only the first `struct_size` bytes (at most its own struct) and, on success,
/// sets `struct_size` to the number of bytes it filled. A `struct_size` smaller than this
/// version's struct is `QUADOPT_STATUS_INVALID_ARGUMENT`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct QuadoptReport {
    /// `sizeof(QuadoptReport)` as the caller compiled it; on success the bytes filled.
    pub struct_size: u32,
    /// 1 when the energy criterion was met, 0 when the iteration cap was reached.
    pub converged: u32,
    /// Quality of the input.
    pub input: QuadoptQuality,
    /// Quality of the output.
    pub output: QuadoptQuality,
    /// Sweeps performed in the pass whose result was kept.
    pub iterations: usize,
    /// Untangling sweeps performed.
    pub untangle_sweeps: usize,
    /// Quads whose vertex order was reversed internally to make the orientation consistent.
    pub reoriented_quads: usize,
    /// Boundary vertices detected as corners (never moved).
    pub corners: usize,
    /// Vertices the optimizer was allowed to move.
    pub movable: usize,
    /// Quads still inverted in the output.
    pub tangled_quads: usize,
    /// Collective energy of the input.
    pub initial_energy: f64,
    /// Collective energy of the output.
    pub final_energy: f64,
    /// Wall-clock seconds of the run.
    pub seconds: f64,
    /// Largest distance of the new boundary polyline from the original one.
    pub max_boundary_deviation: f64,
    /// Symmetric Hausdorff distance between the new and the original boundary polylines.
    pub hausdorff: f64,
    /// `max_boundary_deviation` divided by the mesh's mean edge length.
    pub max_boundary_deviation_relative: f64,
    /// `hausdorff` divided by the mesh's mean edge length.
    pub hausdorff_relative: f64,
    /// Boundary loops that were optimized in slide mode.
    pub loops_slide: usize,
    /// Boundary loops that were optimized in snap mode.
    pub loops_snap: usize,
    /// Boundary loops whose vertices were kept fixed.
    pub loops_fixed: usize,
    /// 1 when the max-min stage ran and its result was kept, else 0 (then `sweeps` equals
    /// `output`). Added in 0.2: written only when the caller's `struct_size` covers it.
    pub max_min: u32,
    /// Reserved; written as 0.
    pub reserved1: u32,
    /// Quality after the sweeps, before the max-min stage: `output` minus `sweeps` is the
    /// stage's gain.
    pub sweeps: QuadoptQuality,
}

/// A reusable optimizer for one connectivity (quads, fixed flags, vertex count), built once
/// by `quadopt_optimizer_create()` and immutable afterwards: several threads may call
/// `quadopt_optimizer_optimize()` with one handle at the same time. Opaque to C.
#[derive(Debug)]
pub struct QuadoptOptimizer {
    /// The validated mesh at creation (connectivity, fixed flags, orientation).
    mesh: QuadMesh,
    /// The topology built from it.
    optimizer: Optimizer,
}

// ---------------------------------------------------------------------------------------
// Errors, the last-error message and the panic boundary.

/// A failure on its way to the caller: a status and the detailed message.
#[derive(Debug)]
struct FfiError {
    status: QuadoptStatus,
    message: String,
}

impl FfiError {
    fn new(status: QuadoptStatus, message: impl Into<String>) -> Self {
        FfiError { status, message: message.into() }
    }
}

impl From<Error> for FfiError {
    fn from(e: Error) -> Self {
        FfiError { status: status_of(&e), message: e.to_string() }
    }
}

/// The status of a library error. Exhaustive on purpose: a new variant must be mapped here.
fn status_of(e: &Error) -> QuadoptStatus {
    match e {
        Error::NoQuads => QuadoptStatus::NoQuads,
        Error::IndexOutOfRange { .. } => QuadoptStatus::IndexOutOfRange,
        Error::RepeatedVertex { .. } => QuadoptStatus::RepeatedVertex,
        Error::NonManifoldEdge { .. } => QuadoptStatus::NonManifold,
        Error::NonFiniteCoordinate { .. } => QuadoptStatus::NonFiniteCoordinate,
        Error::NonOrientable { .. } => QuadoptStatus::NonOrientable,
        Error::FixedLengthMismatch { .. } => QuadoptStatus::Mismatch,
        Error::VertexCountMismatch { .. } | Error::ConnectivityMismatch { .. } => QuadoptStatus::Mismatch,
        Error::InvalidOption { .. } => QuadoptStatus::InvalidOption,
        Error::NotPlanar { .. } => QuadoptStatus::NotPlanar,
        Error::OutOfMemory { .. } | Error::NoThreads { .. } => QuadoptStatus::OutOfMemory,
    }
}

thread_local! {
    /// The detailed message of the last failed call on this thread.
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_last_error(message: String) {
    // Interior NULs would cut the C string short; make them visible instead.
    let c = CString::new(message.replace('\0', "\\0")).unwrap_or_default();
    // During thread teardown the slot may be gone; then there is nobody to tell.
    let _ = LAST_ERROR.try_with(|slot| *slot.borrow_mut() = c);
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic payload".to_owned()
    }
}

/// Runs the body of entry point `name`: catches panics, records the message of a failure in
/// the thread-local last error and turns the outcome into a status.
fn boundary(name: &str, body: impl FnOnce() -> Result<(), FfiError>) -> QuadoptStatus {
    quiet::install_hook();
    let inside = quiet::enter(true);
    let outcome = panic::catch_unwind(AssertUnwindSafe(body));
    drop(inside);
    match outcome {
        Ok(Ok(())) => QuadoptStatus::Ok,
        Ok(Err(e)) => {
            set_last_error(format!("{name}: {}", e.message));
            e.status
        }
        Err(payload) => {
            set_last_error(format!(
                "{name}: internal error (panic: {}); please report this bug",
                panic_message(payload.as_ref())
            ));
            QuadoptStatus::Panic
        }
    }
}

/// Panic boundary for the functions without a status: a panic returns `fallback`.
fn boundary_or<T>(fallback: T, body: impl FnOnce() -> T) -> T {
    quiet::install_hook();
    let _inside = quiet::enter(true);
    panic::catch_unwind(AssertUnwindSafe(body)).unwrap_or(fallback)
}

// ---------------------------------------------------------------------------------------
// Checked access to the caller's memory.

/// Size of the first published `QuadoptOptions`: callers' structs must be at least this large.
/// Fields added later are appended and read only when the caller's `struct_size` covers them.
/// The first version ended where `max_min` (added in 0.2) begins.
const OPTIONS_V1_SIZE: usize = std::mem::offset_of!(QuadoptOptions, max_min);
/// Size of the first published `QuadoptReport` (the same growth rule): it ended where
/// `max_min` begins.
const REPORT_V1_SIZE: usize = std::mem::offset_of!(QuadoptReport, max_min);

/// Checks the caller's array `ptr[0..len]` without touching it: NULL is accepted only with
/// `len == 0`, the pointer must be aligned and the byte size must fit in `isize::MAX` (what
/// `std::slice::from_raw_parts` requires).
fn check_array<T>(ptr: *const T, len: usize, what: &str) -> Result<(), FfiError> {
    if len == 0 {
        return Ok(());
    }
    if ptr.is_null() {
        return Err(FfiError::new(QuadoptStatus::NullPointer, format!("{what} is NULL (length {len})")));
    }
    if !ptr.is_aligned() {
        return Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!("{what} is not aligned to {} bytes", align_of::<T>()),
        ));
    }
    check_bytes(len, size_of::<T>(), what)?;
    Ok(())
}

/// A read-only view of the caller's array `ptr[0..len]`, after [`check_array`].
///
/// # Safety
/// If `len > 0`, `ptr` must point to `len` initialized values of `T` that stay valid and are
/// not written by anyone for the returned lifetime.
unsafe fn checked_slice<'a, T>(ptr: *const T, len: usize, what: &str) -> Result<&'a [T], FfiError> {
    check_array(ptr, len, what)?;
    if len == 0 {
        return Ok(&[]);
    }
    // SAFETY: non-null and aligned, the byte size fits in isize (checked by check_array), and
    // the caller guarantees `len` valid values not written during the borrow.
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// Checks that `count` elements of `size` bytes fit in `isize::MAX` bytes.
fn check_bytes(count: usize, size: usize, what: &str) -> Result<usize, FfiError> {
    match count.checked_mul(size) {
        Some(bytes) if bytes <= isize::MAX as usize => Ok(bytes),
        _ => Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!("{what}: {count} elements of {size} bytes overflow the address space"),
        )),
    }
}

/// `a * b` for element counts, naming the quantities on overflow.
fn checked_count(a: usize, b: usize, what: &str) -> Result<usize, FfiError> {
    a.checked_mul(b).ok_or_else(|| {
        FfiError::new(QuadoptStatus::InvalidArgument, format!("{what}: {a} * {b} overflows size_t"))
    })
}

fn require_non_null<T>(ptr: *const T, what: &str) -> Result<(), FfiError> {
    if ptr.is_null() {
        return Err(FfiError::new(QuadoptStatus::NullPointer, format!("{what} is NULL")));
    }
    if !ptr.is_aligned() {
        return Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!("{what} is not aligned to {} bytes", align_of::<T>()),
        ));
    }
    Ok(())
}

fn check_dim(dim: u32) -> Result<usize, FfiError> {
    match dim {
        2 | 3 => Ok(dim as usize),
        _ => Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!("dim is {dim}; coordinates must have 2 or 3 components per vertex"),
        )),
    }
}

/// Vertex and quad indices are `uint32_t`, so larger counts cannot be meshes.
fn check_u32_count(count: usize, what: &str) -> Result<(), FfiError> {
    if count > u32::MAX as usize {
        return Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!("{what} is {count}; at most {} are supported (uint32_t indices)", u32::MAX),
        ));
    }
    Ok(())
}

/// Reads `vertex_count` points of `dim` doubles (x and y; z is ignored) into owned memory.
///
/// # Safety
/// `coords` must be NULL with `vertex_count == 0`, or point to `vertex_count * dim` doubles.
unsafe fn read_points(coords: *const f64, dim: u32, vertex_count: usize) -> Result<Vec<DVec2>, FfiError> {
    let dim = check_dim(dim)?;
    check_u32_count(vertex_count, "vertex_count")?;
    let len = checked_count(vertex_count, dim, "vertex_count * dim")?;
    // SAFETY: the caller guarantees `coords` holds `vertex_count * dim` doubles.
    let flat = unsafe { checked_slice(coords, len, "coords") }?;
    let mut points = try_with_capacity(vertex_count, "vertex coordinates")?;
    points.extend(flat.chunks_exact(dim).map(|c| DVec2::new(c[0], c[1])));
    Ok(points)
}

/// Reads `quad_count` quads of four `uint32_t` indices into owned memory.
///
/// # Safety
/// `quads` must be NULL with `quad_count == 0`, or point to `4 * quad_count` indices.
unsafe fn read_quads(quads: *const u32, quad_count: usize) -> Result<Vec<[u32; 4]>, FfiError> {
    check_u32_count(quad_count, "quad_count")?;
    let len = checked_count(quad_count, 4, "quad_count * 4")?;
    // SAFETY: the caller guarantees `quads` holds `4 * quad_count` indices.
    let flat = unsafe { checked_slice(quads, len, "quads") }?;
    let mut out = try_with_capacity(quad_count, "quads")?;
    out.extend(flat.chunks_exact(4).map(|q| [q[0], q[1], q[2], q[3]]));
    Ok(out)
}

/// Reads the optional fixed mask (`vertex_count` bytes, nonzero = fixed).
///
/// # Safety
/// `fixed` must be NULL or point to `vertex_count` bytes.
unsafe fn read_fixed(fixed: *const u8, vertex_count: usize) -> Result<Option<Vec<bool>>, FfiError> {
    if fixed.is_null() {
        return Ok(None);
    }
    // SAFETY: non-null, so the caller guarantees `vertex_count` bytes.
    let flags = unsafe { checked_slice(fixed, vertex_count, "fixed") }?;
    let mut out = try_with_capacity(vertex_count, "fixed flags")?;
    out.extend(flags.iter().map(|&f| f != 0));
    Ok(Some(out))
}

/// Builds and validates a mesh from the caller's arrays.
///
/// # Safety
/// As [`read_points`], [`read_quads`] and [`read_fixed`].
unsafe fn read_mesh(
    coords: *const f64,
    dim: u32,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
    fixed: *const u8,
) -> Result<QuadMesh, FfiError> {
    // Every check of every array first, so no array is read when another one is bad.
    let dim_n = check_dim(dim)?;
    check_u32_count(vertex_count, "vertex_count")?;
    check_u32_count(quad_count, "quad_count")?;
    check_array(coords, checked_count(vertex_count, dim_n, "vertex_count * dim")?, "coords")?;
    check_array(quads, checked_count(quad_count, 4, "quad_count * 4")?, "quads")?;
    if !fixed.is_null() {
        check_array(fixed, vertex_count, "fixed")?;
    }
    // SAFETY: forwarded from this function's contract.
    let points = unsafe { read_points(coords, dim, vertex_count) }?;
    // SAFETY: forwarded from this function's contract.
    let quads = unsafe { read_quads(quads, quad_count) }?;
    // SAFETY: forwarded from this function's contract.
    let fixed = unsafe { read_fixed(fixed, vertex_count) }?;
    Ok(QuadMesh::new(points, quads, fixed)?)
}

/// The caller's options (defaults for NULL), reading only the declared prefix.
///
/// # Safety
/// `options` must be NULL or point to a readable `struct_size` field followed by at least
/// `struct_size - 4` readable bytes.
unsafe fn read_options(options: *const QuadoptOptions) -> Result<QuadoptOptions, FfiError> {
    let mut out = default_options();
    if options.is_null() {
        return Ok(out);
    }
    require_non_null(options, "options")?;
    // SAFETY: non-null and aligned; every version of the struct starts with `struct_size`.
    let declared = unsafe { options.cast::<u32>().read() } as usize;
    let ours = size_of::<QuadoptOptions>();
    if declared < OPTIONS_V1_SIZE {
        return Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!(
                "options->struct_size is {declared}, smaller than the first QuadoptOptions ({OPTIONS_V1_SIZE} bytes)"
            ),
        ));
    }
    // Fields a caller's older, shorter struct lacks keep their defaults.
    let bytes = declared.min(ours);
    // SAFETY: the caller guarantees `declared >= bytes` readable bytes at `options`, and `out`
    // is a distinct local of `ours >= bytes` bytes. Every field is an integer, float, raw
    // pointer or nullable function pointer, for which any initialized bit pattern is valid.
    unsafe {
        std::ptr::copy_nonoverlapping(options.cast::<u8>(), (&raw mut out).cast::<u8>(), bytes);
    }
    Ok(out)
}

/// Converts the C options, validating enum values and ranges and naming the bad field.
fn convert_options(o: &QuadoptOptions) -> Result<Options, FfiError> {
    let bad = |name: &str, reason: String| {
        FfiError::new(QuadoptStatus::InvalidOption, format!("invalid option {name}: {reason}"))
    };
    let method = match o.method {
        0 => Method::EmbeddedPolygon,
        1 => Method::Laplacian,
        2 => Method::Cotangent,
        3 => Method::AngleBased,
        m => return Err(bad("method", format!("{m} is not a QuadoptMethod (0 to 3)"))),
    };
    let boundary = match o.boundary {
        0 => BoundaryMode::Auto,
        1 => BoundaryMode::Fixed,
        2 => BoundaryMode::Slide,
        3 => BoundaryMode::Snap,
        b => return Err(bad("boundary", format!("{b} is not a QuadoptBoundary (0 to 3)"))),
    };
    let stop = match o.stop_rule {
        0 => StopRule::Energy,
        1 => StopRule::Quality,
        r => return Err(bad("stop_rule", format!("{r} is not a QuadoptStopRule (0 or 1)"))),
    };
    let max_boundary_deviation =
        if o.max_boundary_deviation < 0.0 { None } else { Some(o.max_boundary_deviation) };
    let options = Options {
        method,
        boundary,
        lambda: o.lambda,
        stop,
        tau: o.tau,
        tau_absolute: o.tau_absolute != 0,
        max_iterations: o.max_iterations as usize,
        feature_angle_deg: o.feature_angle_deg,
        guard: o.guard != 0,
        guard_floor: o.guard_floor,
        untangle: o.untangle != 0,
        keep_best: o.keep_best != 0,
        max_boundary_deviation,
        max_min: o.max_min != 0,
    };
    options.validate()?;
    Ok(options)
}

/// Reads the caller's declared report size, if a report was asked for.
///
/// # Safety
/// `report` must be NULL or point to a readable, aligned `struct_size` field.
unsafe fn report_size(report: *const QuadoptReport) -> Result<Option<usize>, FfiError> {
    if report.is_null() {
        return Ok(None);
    }
    require_non_null(report, "report")?;
    // SAFETY: non-null and aligned; every version of the struct starts with `struct_size`.
    let declared = unsafe { report.cast::<u32>().read() } as usize;
    let ours = size_of::<QuadoptReport>();
    if declared < REPORT_V1_SIZE {
        return Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!(
                "report->struct_size is {declared}, smaller than the first QuadoptReport ({REPORT_V1_SIZE} bytes)"
            ),
        ));
    }
    Ok(Some(declared.min(ours)))
}

/// Writes the first `bytes` bytes of `value` to `report`, with `struct_size = bytes`.
///
/// # Safety
/// `report` must be aligned and point to at least `bytes <= sizeof(QuadoptReport)` writable
/// bytes (checked by [`report_size`] from the caller's declaration).
unsafe fn write_report(report: *mut QuadoptReport, mut value: QuadoptReport, bytes: usize) {
    value.struct_size = bytes as u32;
    // SAFETY: `bytes` <= size_of::<QuadoptReport>() so the source read stays inside `value`;
    // the destination holds `bytes` writable bytes by this function's contract; `value` is a
    // local, so the two cannot overlap.
    unsafe { std::ptr::copy_nonoverlapping((&raw const value).cast::<u8>(), report.cast::<u8>(), bytes) };
}

/// Writes x and y of every point into the caller's strided array; z is never written.
///
/// # Safety
/// `coords` must be aligned and point to `points.len() * dim` writable doubles.
unsafe fn write_points(coords: *mut f64, dim: usize, points: &[DVec2]) {
    for (i, p) in points.iter().enumerate() {
        // SAFETY: i * dim + 1 < points.len() * dim (dim >= 2), inside the caller's buffer;
        // raw writes create no reference, so no aliasing rule is broken.
        unsafe {
            coords.add(i * dim).write(p.x);
            coords.add(i * dim + 1).write(p.y);
        }
    }
}

fn quality_of(s: &QualityStats) -> QuadoptQuality {
    QuadoptQuality { min: s.min, avg: s.avg, max: s.max, inverted: s.inverted }
}

fn report_of(r: &Report) -> QuadoptReport {
    let count = |mode| r.loop_modes.iter().filter(|&&m| m == mode).count();
    QuadoptReport {
        struct_size: size_of::<QuadoptReport>() as u32,
        converged: u32::from(r.converged),
        input: quality_of(&r.input),
        output: quality_of(&r.output),
        iterations: r.iterations,
        untangle_sweeps: r.untangle_sweeps,
        reoriented_quads: r.reoriented_quads,
        corners: r.corners,
        movable: r.movable,
        tangled_quads: r.tangled.len(),
        initial_energy: r.initial_energy,
        final_energy: r.final_energy,
        seconds: r.seconds,
        max_boundary_deviation: r.fidelity.max_deviation,
        hausdorff: r.fidelity.hausdorff,
        max_boundary_deviation_relative: r.fidelity.max_deviation_relative,
        hausdorff_relative: r.fidelity.hausdorff_relative,
        loops_slide: count(BoundaryMode::Slide),
        loops_snap: count(BoundaryMode::Snap),
        loops_fixed: count(BoundaryMode::Fixed),
        max_min: u32::from(r.max_min.is_some()),
        reserved1: 0,
        sweeps: quality_of(&r.max_min.map_or(r.output, |g| g.before)),
    }
}

fn default_options() -> QuadoptOptions {
    let d = Options::default();
    QuadoptOptions {
        struct_size: size_of::<QuadoptOptions>() as u32,
        method: QuadoptMethod::EmbeddedPolygon as u32,
        boundary: QuadoptBoundary::Auto as u32,
        max_iterations: d.max_iterations as u32,
        lambda: d.lambda,
        tau: d.tau,
        feature_angle_deg: d.feature_angle_deg,
        guard_floor: d.guard_floor,
        max_boundary_deviation: d.max_boundary_deviation.unwrap_or(-1.0),
        tau_absolute: u8::from(d.tau_absolute),
        guard: u8::from(d.guard),
        untangle: u8::from(d.untangle),
        keep_best: u8::from(d.keep_best),
        stop_rule: match d.stop {
            StopRule::Energy => QuadoptStopRule::Energy,
            StopRule::Quality => QuadoptStopRule::Quality,
        } as u32,
        progress: None,
        progress_user_data: std::ptr::null_mut(),
        max_min: u32::from(d.max_min),
        reserved1: 0,
    }
}

// ---------------------------------------------------------------------------------------
// Memory the topology and the optimizer need.

/// Peak bytes of building the optimizer, per vertex or quad (whichever is more) and fixed:
/// measured by tests/memory.rs at up to about 56 per element, 97 for a mesh large enough
/// to be renumbered (its copy in the internal order is alive while its topology is built),
/// with room to spare.
const TOPOLOGY_BYTES_PER_ELEMENT: u128 = 120;
const TOPOLOGY_BYTES_FIXED: u128 = 64 << 10;
/// Peak bytes of a run beyond the mesh and its topology, per vertex or quad, per boundary
/// edge and fixed: measured at up to about 135 per element plus 40 per boundary edge on
/// grids and strips, and 250 per vertex on a 2000-quad fan (the max-min stage's star), with
/// any method and boundary mode.
const RUN_BYTES_PER_ELEMENT: u128 = 220;
const RUN_BYTES_PER_BOUNDARY_EDGE: u128 = 64;
const RUN_BYTES_FIXED: u128 = 64 << 10;

/// Upper estimate of the bytes `Optimizer::new(mesh)` allocates at its peak.
#[doc(hidden)]
pub fn topology_bytes(mesh: &QuadMesh) -> u128 {
    TOPOLOGY_BYTES_PER_ELEMENT * mesh.points().len().max(mesh.quads().len()) as u128 + TOPOLOGY_BYTES_FIXED
}

/// Upper estimate of the bytes one `Optimizer::run` on `mesh` allocates at its peak.
#[doc(hidden)]
pub fn run_bytes(mesh: &QuadMesh) -> u128 {
    let elements = mesh.points().len().max(mesh.quads().len()) as u128;
    RUN_BYTES_PER_ELEMENT * elements
        + RUN_BYTES_PER_BOUNDARY_EDGE * mesh.boundary_edge_count() as u128
        + RUN_BYTES_FIXED
}

/// Checks that `bytes` can be allocated now (in one piece, so also in the many pieces the
/// work will use), and frees them again: an address-space or commit limit too tight for the
/// work fails here, as an error, rather than in an allocation that aborts. The probe is
/// never written, so it costs address space for a moment, not memory.
fn check_memory_for(bytes: u128, what: &'static str) -> Result<(), Error> {
    let fail = || Error::OutOfMemory { what, bytes };
    let probe =
        try_with_capacity::<u8>(usize::try_from(bytes).map_err(|_| fail())?, what).map_err(|_| fail())?;
    drop(probe);
    Ok(())
}

/// Runs the optimizer (`built`, else one built here for `mesh`) on an owned mesh on the
/// library's worker threads, calling the C progress callback on the calling thread, and
/// returns the new positions and the report. Cancellation is an error here, so nothing is
/// written.
fn run(
    built: Option<&Optimizer>,
    mut mesh: QuadMesh,
    o: &QuadoptOptions,
) -> Result<(QuadMesh, Report), FfiError> {
    let options = convert_options(o)?;
    let (callback, user_data) = (o.progress, o.progress_user_data);
    let mut last = None;
    let on_progress = |cp: QuadoptProgress| -> bool {
        let Some(f) = callback else { return true };
        last = Some(cp);
        // A panic of the caller's own Rust code (if any) is not ours to silence.
        let _outside = quiet::enter(false);
        // SAFETY: the caller guarantees that a non-NULL `progress` is a valid function of this
        // signature; `cp` lives for the duration of the call.
        unsafe { f(&cp, user_data) }
    };
    let has_callback = callback.is_some();
    let job = |ask: &mut dyn FnMut(QuadoptProgress) -> bool| {
        let mut forward = |p: &Progress| {
            !has_callback
                || ask(QuadoptProgress {
                    iteration: p.iteration,
                    max_iterations: p.max_iterations,
                    pass: p.pass,
                    passes: p.passes,
                    energy: p.energy,
                    energy_change: p.energy_change,
                })
        };
        // Checked on a worker, once the pool (its stacks, its allocator arenas) exists.
        let needed = run_bytes(&mesh) + built.map_or_else(|| topology_bytes(&mesh), |_| 0);
        check_memory_for(needed, "the optimizer's working memory")?;
        let owned;
        let optimizer = match built {
            Some(optimizer) => optimizer,
            None => {
                owned = Optimizer::new(&mesh);
                &owned
            }
        };
        optimizer.run(&mut mesh, &options, Some(&mut forward)).map(|report| (mesh, report))
    };
    let (mesh, report) = pool::run_with_progress(job, on_progress)
        .map_err(|pool::NoThreads(why)| FfiError::new(QuadoptStatus::OutOfMemory, why))??;
    if report.cancelled {
        let at = last.map_or(String::new(), |p| {
            format!(" at pass {} of {}, iteration {}", p.pass, p.passes, p.iteration)
        });
        return Err(FfiError::new(
            QuadoptStatus::Cancelled,
            format!("cancelled by the progress callback{at}; nothing was written"),
        ));
    }
    Ok((mesh, report))
}

// ---------------------------------------------------------------------------------------
// The exported functions.

/// A static, human-readable name of a status ("ok", "null pointer", ...). Any integer is
/// accepted; values that are not a `QuadoptStatus` give "unknown status". Never NULL.
#[unsafe(no_mangle)]
pub extern "C" fn quadopt_status_string(status: i32) -> *const c_char {
    boundary_or(c"unknown status".as_ptr(), || status_name(status).as_ptr())
}

fn status_name(status: i32) -> &'static CStr {
    match status {
        0 => c"ok",
        1 => c"null pointer",
        2 => c"invalid argument",
        3 => c"invalid option",
        4 => c"no quads",
        5 => c"index out of range",
        6 => c"repeated vertex",
        7 => c"non-manifold edge",
        8 => c"non-finite coordinate",
        9 => c"non-orientable mesh",
        10 => c"mismatch",
        11 => c"cancelled",
        12 => c"internal error (panic)",
        13 => c"not planar",
        14 => c"out of memory",
        _ => c"unknown status",
    }
}

/// The detailed message of the last failed call on this thread (naming the offending quad,
/// index or option), or "" if no call has failed on this thread. Never NULL. The string is
/// owned by the library and valid until the next quadopt call on this thread.
#[unsafe(no_mangle)]
pub extern "C" fn quadopt_last_error() -> *const c_char {
    boundary_or(c"".as_ptr(), || LAST_ERROR.try_with(|slot| slot.borrow().as_ptr()).unwrap_or(c"".as_ptr()))
}

/// Fills `*out` with the default options (the library's recommended settings) and sets
/// `struct_size`. NULL is a no-op. Writes this library's whole struct: a program that may run
/// against a newer library than the header it was built with should use
/// `quadopt_options_init(out, sizeof *out)` instead.
///
/// # Safety
/// `out` must be NULL or point to a writable, aligned `QuadoptOptions`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_options_default(out: *mut QuadoptOptions) {
    boundary_or((), || {
        if out.is_null() || !out.is_aligned() {
            return;
        }
        // SAFETY: non-null and aligned; the caller guarantees a writable QuadoptOptions.
        unsafe { out.write(default_options()) };
    })
}

/// Fills the first `struct_size` bytes of `*out` with the default options: pass
/// `sizeof(QuadoptOptions)` as your header declares it, which may differ from this library's
/// when the program was built against another version of the header. Writes
/// `min(struct_size, sizeof of this library's struct)` bytes, sets `struct_size` to that number
/// and leaves any further bytes of a larger (newer) struct untouched, so it never writes past
/// the caller's struct the way `quadopt_options_default` and `quadopt_options_defaults` could
/// across versions. The recommended way to initialize options.
///
/// Returns `QUADOPT_STATUS_NULL_POINTER` for a NULL `out`, and `QUADOPT_STATUS_INVALID_ARGUMENT`
/// for a misaligned one or a `struct_size` smaller than the first version of the struct
/// (nothing is written then).
///
/// # Safety
/// `out` must be NULL or point to `struct_size` writable, aligned bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_options_init(out: *mut QuadoptOptions, struct_size: usize) -> QuadoptStatus {
    boundary("quadopt_options_init", || {
        require_non_null(out.cast_const(), "out")?;
        if struct_size < OPTIONS_V1_SIZE {
            return Err(FfiError::new(
                QuadoptStatus::InvalidArgument,
                format!(
                    "struct_size is {struct_size}, smaller than the first QuadoptOptions ({OPTIONS_V1_SIZE} bytes)"
                ),
            ));
        }
        let mut value = default_options();
        let bytes = struct_size.min(size_of::<QuadoptOptions>());
        value.struct_size = bytes as u32;
        // SAFETY: `out` is non-null and aligned (checked) and holds `struct_size >= bytes`
        // writable bytes by the caller's contract; `value` is a local of at least `bytes` bytes.
        unsafe { std::ptr::copy_nonoverlapping((&raw const value).cast::<u8>(), out.cast::<u8>(), bytes) };
        Ok(())
    })
}

/// The default options by value, with `struct_size` set. Returning a struct by value is only
/// safe when the program was built against this version of the header; prefer
/// `quadopt_options_init`.
#[unsafe(no_mangle)]
pub extern "C" fn quadopt_options_defaults() -> QuadoptOptions {
    // A panic cannot happen here; the fallback keeps the boundary rule uniform.
    boundary_or(default_options(), default_options)
}

/// A zeroed report with `struct_size = sizeof(QuadoptReport)`, ready to pass to an optimize
/// function. By value, so only safe with this version of the header; across versions zero
/// your own `QuadoptReport` and set its `struct_size = sizeof(QuadoptReport)`.
#[unsafe(no_mangle)]
pub extern "C" fn quadopt_report_init() -> QuadoptReport {
    let init =
        || QuadoptReport { struct_size: size_of::<QuadoptReport>() as u32, ..QuadoptReport::default() };
    boundary_or(init(), init)
}

/// Optimizes a mesh in place: moves the vertices (x and y of each; z, if `dim` is 3, is never
/// written) to raise the quads' scaled Jacobians, keeping connectivity, corners, fixed
/// vertices and the boundary. On any error, cancellation included, neither `coords` nor
/// `report` is written.
///
/// - `coords`: `vertex_count * dim` doubles, read and written; NULL only if `vertex_count` is 0.
/// - `dim`: 2 or 3 doubles per vertex.
/// - `quads`: `4 * quad_count` vertex indices, four per quad in boundary order; NULL only if
///   `quad_count` is 0. Quads may be given clockwise or counter-clockwise.
/// - `fixed`: NULL (no fixed vertices) or `vertex_count` bytes, nonzero = the vertex never moves.
/// - `options`: NULL for the defaults.
/// - `report`: NULL, or a report whose `struct_size` is set (see `quadopt_report_init()`).
///
/// # Safety
/// Every non-NULL pointer must point to (aligned) memory of the size described above, valid
/// for the duration of the call; the buffers must not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_optimize(
    coords: *mut f64,
    dim: u32,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
    fixed: *const u8,
    options: *const QuadoptOptions,
    report: *mut QuadoptReport,
) -> QuadoptStatus {
    boundary("quadopt_optimize", || {
        // SAFETY: forwarded from this function's contract.
        let report_bytes = unsafe { report_size(report) }?;
        // SAFETY: forwarded from this function's contract.
        let o = unsafe { read_options(options) }?;
        convert_options(&o)?;
        // SAFETY: forwarded from this function's contract.
        let mesh = unsafe { read_mesh(coords, dim, vertex_count, quads, quad_count, fixed) }?;
        let (mesh, r) = run(None, mesh, &o)?;
        // SAFETY: `coords` held `vertex_count * dim` doubles (checked by read_mesh), and the
        // report size was checked against the caller's declaration.
        unsafe {
            write_points(coords, dim as usize, mesh.points());
            if let Some(bytes) = report_bytes {
                write_report(report, report_of(&r), bytes);
            }
        }
        Ok(())
    })
}

/// Measures the quality of a mesh without changing it: statistics into `*out` (required)
/// and, if `per_quad` is not NULL, each quad's scaled Jacobian into `per_quad[0..quad_count]`
/// (`per_quad_len` must be >= `quad_count`). Quality is measured against the mesh's
/// consistent orientation, so a mesh given clockwise scores like its mirror image. Arrays as
/// in `quadopt_optimize()`. Nothing is written on error.
///
/// # Safety
/// Every non-NULL pointer must point to (aligned) memory of the size described, valid for the
/// duration of the call; `per_quad` and `out` must not overlap the inputs.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_quality(
    coords: *const f64,
    dim: u32,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
    out: *mut QuadoptQuality,
    per_quad: *mut f64,
    per_quad_len: usize,
) -> QuadoptStatus {
    boundary("quadopt_quality", || {
        require_non_null(out.cast_const(), "out")?;
        if !per_quad.is_null() {
            if per_quad_len < quad_count {
                return Err(FfiError::new(
                    QuadoptStatus::InvalidArgument,
                    format!("per_quad_len is {per_quad_len}, smaller than quad_count = {quad_count}"),
                ));
            }
            require_non_null(per_quad.cast_const(), "per_quad")?;
            check_bytes(per_quad_len, size_of::<f64>(), "per_quad")?;
        }
        // SAFETY: forwarded from this function's contract.
        let mesh = unsafe { read_mesh(coords, dim, vertex_count, quads, quad_count, std::ptr::null()) }?;
        let values = mesh.try_quality_values()?;
        let stats = quality_of(&QualityStats::from_values(&values));
        // SAFETY: `out` is non-null and aligned (checked); `per_quad`, if non-null, is aligned
        // and holds per_quad_len >= quad_count = values.len() doubles (checked).
        unsafe {
            if !per_quad.is_null() {
                std::ptr::copy_nonoverlapping(values.as_ptr(), per_quad, values.len());
            }
            out.write(stats);
        }
        Ok(())
    })
}

/// Creates a reusable optimizer for one connectivity: validates the mesh (arrays as in
/// `quadopt_optimize()`) and builds its topology once. The orientation and the fixed flags are
/// taken from this call. On success `*out` receives the handle (free it with
/// `quadopt_optimizer_free()`); on error `*out` is not written.
///
/// # Safety
/// Pointers as in `quadopt_optimize()`; `out` must point to a writable pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_optimizer_create(
    coords: *const f64,
    dim: u32,
    vertex_count: usize,
    quads: *const u32,
    quad_count: usize,
    fixed: *const u8,
    out: *mut *mut QuadoptOptimizer,
) -> QuadoptStatus {
    boundary("quadopt_optimizer_create", || {
        require_non_null(out.cast_const(), "out")?;
        // SAFETY: forwarded from this function's contract.
        let mesh = unsafe { read_mesh(coords, dim, vertex_count, quads, quad_count, fixed) }?;
        check_memory_for(topology_bytes(&mesh), "the mesh's topology")?;
        let optimizer = Optimizer::new(&mesh);
        let handle = Box::into_raw(Box::new(QuadoptOptimizer { mesh, optimizer }));
        // SAFETY: `out` is non-null and aligned (checked) and writable by the contract.
        unsafe { out.write(handle) };
        Ok(())
    })
}

/// Optimizes `coords` (`vertex_count * dim` doubles, `vertex_count` equal to the handle's,
/// else `QUADOPT_STATUS_MISMATCH`) with the connectivity and fixed flags of `opt`. Options,
/// report and the nothing-written-on-error rule as in `quadopt_optimize()`. The handle is not
/// modified: several threads may use one handle at the same time with different `coords`.
///
/// # Safety
/// `opt` must be NULL or a live handle from `quadopt_optimizer_create()`; other pointers as in
/// `quadopt_optimize()`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_optimizer_optimize(
    opt: *const QuadoptOptimizer,
    coords: *mut f64,
    dim: u32,
    vertex_count: usize,
    options: *const QuadoptOptions,
    report: *mut QuadoptReport,
) -> QuadoptStatus {
    boundary("quadopt_optimizer_optimize", || {
        require_non_null(opt, "opt")?;
        // SAFETY: a non-null `opt` is a live handle by the contract; it is only read.
        let handle = unsafe { &*opt };
        // SAFETY: forwarded from this function's contract.
        let report_bytes = unsafe { report_size(report) }?;
        // SAFETY: forwarded from this function's contract.
        let o = unsafe { read_options(options) }?;
        convert_options(&o)?;
        let expected = handle.mesh.points().len();
        if vertex_count != expected {
            return Err(Error::VertexCountMismatch { expected, got: vertex_count }.into());
        }
        // SAFETY: forwarded from this function's contract.
        let points = unsafe { read_points(coords, dim, vertex_count) }?;
        let mut mesh = handle.mesh.try_clone()?;
        mesh.set_points(&points)?;
        let (mesh, r) = run(Some(&handle.optimizer), mesh, &o)?;
        // SAFETY: as in quadopt_optimize.
        unsafe {
            write_points(coords, dim as usize, mesh.points());
            if let Some(bytes) = report_bytes {
                write_report(report, report_of(&r), bytes);
            }
        }
        Ok(())
    })
}

/// Frees a handle from `quadopt_optimizer_create()`. NULL is a no-op.
///
/// # Safety
/// `opt` must be NULL or a live handle, not in use by another thread, and not used afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_optimizer_free(opt: *mut QuadoptOptimizer) {
    boundary_or((), || {
        if !opt.is_null() {
            // SAFETY: a non-null `opt` came from Box::into_raw in quadopt_optimizer_create and
            // is freed exactly once by the contract.
            drop(unsafe { Box::from_raw(opt) });
        }
    })
}

/// The library version as a static string, e.g. "0.1.0". Never NULL.
#[unsafe(no_mangle)]
pub extern "C" fn quadopt_version() -> *const c_char {
    const VERSION: &CStr =
        match CStr::from_bytes_with_nul(concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes()) {
            Ok(v) => v,
            Err(_) => panic!("the package version contains a NUL"),
        };
    VERSION.as_ptr()
}

/// The library version as numbers, written to each non-NULL argument.
///
/// # Safety
/// Each argument must be NULL or point to a writable, aligned `uint32_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_version_numbers(major: *mut u32, minor: *mut u32, patch: *mut u32) {
    boundary_or((), || {
        for (ptr, value) in
            [(major, QUADOPT_VERSION_MAJOR), (minor, QUADOPT_VERSION_MINOR), (patch, QUADOPT_VERSION_PATCH)]
        {
            if !ptr.is_null() && ptr.is_aligned() {
                // SAFETY: non-null and aligned; writable by the contract.
                unsafe { ptr.write(value) };
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ptr::{null, null_mut};
    use std::sync::atomic::Ordering;

    /// A 2x2 patch of unit squares (vertices 0..9, row by row) whose centre vertex 4 has been
    /// dragged to (1.6, 1.5); with a fixed boundary the optimum puts it back at (1, 1).
    fn patch(dim: usize) -> (Vec<f64>, Vec<u32>) {
        let mut coords = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                coords.push(i as f64);
                coords.push(j as f64);
                if dim == 3 {
                    // A z that is not even a number: it must be neither read nor written.
                    coords.push(f64::from_bits(0x7ff8_dead_beef_0000 + (3 * j + i) as u64));
                }
            }
        }
        coords[4 * dim] = 1.6;
        coords[4 * dim + 1] = 1.5;
        (coords, vec![0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7])
    }

    fn fixed_boundary_options() -> QuadoptOptions {
        QuadoptOptions { boundary: QuadoptBoundary::Fixed as u32, tau: 1e-12, ..default_options() }
    }

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    /// The bytes of a plain-data value.
    fn bytes_of<T: Copy>(v: &T) -> Vec<u8> {
        // SAFETY: reading size_of::<T>() bytes of a live value; the test types have no padding
        // (checked by the layout test), so every byte is initialized.
        unsafe { std::slice::from_raw_parts((v as *const T).cast::<u8>(), size_of::<T>()).to_vec() }
    }

    /// A report full of a recognisable pattern (struct_size set), to detect any write.
    fn sentinel_report() -> QuadoptReport {
        let mut r = QuadoptReport { struct_size: size_of::<QuadoptReport>() as u32, ..Default::default() };
        r.converged = 0xA5A5_A5A5;
        r.iterations = 0xDEAD;
        r.input.min = -7.0;
        r.hausdorff = 42.0;
        r
    }

    fn last_error() -> String {
        // SAFETY: quadopt_last_error never returns NULL and the string stays valid until the
        // next quadopt call on this thread.
        unsafe { CStr::from_ptr(quadopt_last_error()) }.to_string_lossy().into_owned()
    }

    /// Runs quadopt_optimize on a copy of `coords`, asserting that a failure writes nothing.
    fn optimize_status(
        coords: &[f64],
        dim: u32,
        quads: &[u32],
        fixed: Option<&[u8]>,
        options: Option<&QuadoptOptions>,
    ) -> QuadoptStatus {
        let mut c = coords.to_vec();
        let mut report = sentinel_report();
        let before = bytes_of(&report);
        // SAFETY: every pointer refers to a live buffer of the stated length.
        let status = unsafe {
            quadopt_optimize(
                c.as_mut_ptr(),
                dim,
                c.len() / dim.max(1) as usize,
                quads.as_ptr(),
                quads.len() / 4,
                fixed.map_or(null(), |f| f.as_ptr()),
                options.map_or(null(), |o| o as *const _),
                &mut report,
            )
        };
        if status != QuadoptStatus::Ok {
            assert_eq!(bits(&c), bits(coords), "{status:?} wrote coords");
            assert_eq!(bytes_of(&report), before, "{status:?} wrote the report");
            assert!(!last_error().is_empty());
        }
        status
    }

    #[test]
    fn optimize_puts_the_dragged_centre_back_and_fills_the_report() {
        for dim in [2u32, 3] {
            let (mut coords, quads) = patch(dim as usize);
            let before = coords.clone();
            let mut report = quadopt_report_init();
            let o = fixed_boundary_options();
            // SAFETY: live buffers of the stated lengths.
            let status = unsafe {
                quadopt_optimize(coords.as_mut_ptr(), dim, 9, quads.as_ptr(), 4, null(), &o, &mut report)
            };
            assert_eq!(status, QuadoptStatus::Ok, "{}", last_error());
            let d = dim as usize;
            assert!((coords[4 * d] - 1.0).abs() < 1e-3 && (coords[4 * d + 1] - 1.0).abs() < 1e-3);
            for v in 0..9 {
                if v != 4 {
                    // Boundary vertices are fixed: bit-identical.
                    assert_eq!(bits(&coords[v * d..v * d + 2]), bits(&before[v * d..v * d + 2]));
                }
                if dim == 3 {
                    assert_eq!(coords[v * d + 2].to_bits(), before[v * d + 2].to_bits(), "z written");
                }
            }
            assert_eq!(report.struct_size as usize, size_of::<QuadoptReport>());
            // Hand computation: in quad [4, 5, 8, 7] the corner at (1.6, 1.5) is reflex, with
            // edges (0.4, -0.5) and (-0.6, 0.5): cross -0.1 / (sqrt(0.41) sqrt(0.61)).
            let reflex = -0.1 / (0.41f64.sqrt() * 0.61f64.sqrt());
            assert!((report.input.min - reflex).abs() < 1e-12, "{}", report.input.min);
            assert_eq!(report.input.inverted, 1);
            assert!(report.untangle_sweeps >= 1);
            assert!(report.output.min > 0.999);
            assert_eq!((report.output.inverted, report.tangled_quads), (0, 0));
            assert_eq!(report.movable, 1, "only the centre may move");
            assert_eq!((report.loops_fixed, report.loops_slide, report.loops_snap), (1, 0, 0));
            assert_eq!(report.converged, 1);
            assert!(report.iterations >= 1 && report.final_energy <= report.initial_energy);
            assert_eq!((report.max_boundary_deviation, report.hausdorff), (0.0, 0.0));
        }
    }

    #[test]
    fn null_options_and_report_use_defaults() {
        let (mut coords, quads) = patch(2);
        // SAFETY: live buffers of the stated lengths.
        let status = unsafe {
            quadopt_optimize(coords.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), null(), null_mut())
        };
        assert_eq!(status, QuadoptStatus::Ok);
        // The default (automatic) boundary mode may move boundary vertices, but the centre
        // still ends up much closer to (1, 1) than it started.
        assert!((coords[8] - 1.0).hypot(coords[9] - 1.0) < 0.1);
    }

    #[test]
    fn fixed_mask_keeps_vertices_bit_identical() {
        let (coords, quads) = patch(2);
        let mut fixed = [0u8; 9];
        fixed[4] = 7; // any nonzero byte means fixed
        let mut c = coords.clone();
        let o = QuadoptOptions { boundary: QuadoptBoundary::Slide as u32, ..default_options() };
        let mut report = quadopt_report_init();
        // SAFETY: live buffers of the stated lengths.
        let status = unsafe {
            quadopt_optimize(c.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, fixed.as_ptr(), &o, &mut report)
        };
        assert_eq!(status, QuadoptStatus::Ok);
        assert_eq!(bits(&c[8..10]), bits(&coords[8..10]));
        assert_eq!(report.loops_slide, 1);
    }

    #[test]
    fn every_mesh_error_has_its_status_and_writes_nothing() {
        use QuadoptStatus as S;
        let (coords, quads) = patch(2);
        let mut q = quads.clone();
        q[6] = 9;
        assert_eq!(optimize_status(&coords, 2, &q, None, None), S::IndexOutOfRange);
        assert!(last_error().contains("quad 1 corner 2 refers to vertex 9"), "{}", last_error());
        let mut q = quads.clone();
        q[2] = 0;
        assert_eq!(optimize_status(&coords, 2, &q, None, None), S::RepeatedVertex);
        assert!(last_error().contains("quad 0 uses vertex 0"), "{}", last_error());
        assert_eq!(optimize_status(&coords, 2, &[], None, None), S::NoQuads);
        let mut c = coords.clone();
        c[2 * 5 + 1] = f64::INFINITY;
        assert_eq!(optimize_status(&c, 2, &quads, None, None), S::NonFiniteCoordinate);
        assert!(last_error().contains("vertex 5"), "{}", last_error());
        // Three quads on edge (1, 4): add two vertices and a quad [1, 4, 9, 10].
        let mut c = coords.clone();
        c.extend([1.5, 2.5, 0.5, 2.5]);
        let mut q = quads.clone();
        q.extend([1, 4, 9, 10]);
        assert_eq!(optimize_status(&c, 2, &q, None, None), S::NonManifold);
        assert!(last_error().contains("edge (1, 4)"), "{}", last_error());
        // A ring of four quads glued with a half twist.
        let mut c = Vec::new();
        for i in 0..4 {
            c.extend([i as f64, 0.0, i as f64, 1.0]);
        }
        let moebius = [0, 2, 3, 1, 2, 4, 5, 3, 4, 6, 7, 5, 6, 1, 0, 7];
        assert_eq!(optimize_status(&c, 2, &moebius, None, None), S::NonOrientable);
        assert!(last_error().contains("quad"), "{}", last_error());
    }

    #[test]
    fn argument_errors_are_caught_before_any_access() {
        use QuadoptStatus as S;
        let (coords, quads) = patch(2);
        for dim in [0, 1, 4, u32::MAX] {
            assert_eq!(optimize_status(&coords[..18], dim, &quads, None, None), S::InvalidArgument);
            assert!(last_error().contains(&format!("dim is {dim}")), "{}", last_error());
        }
        let mut report = sentinel_report();
        let mut c = coords.clone();
        // SAFETY: the calls fail before touching the (deliberately wrong) lengths' memory.
        unsafe {
            // Counts beyond the uint32_t index range (with 64-bit size_t, the only way
            // vertex_count * dim or 4 * quad_count could overflow), checked for every array
            // before any is read.
            let s = quadopt_optimize(
                c.as_mut_ptr(),
                3,
                usize::MAX / 2,
                quads.as_ptr(),
                4,
                null(),
                null(),
                null_mut(),
            );
            assert_eq!(s, S::InvalidArgument);
            assert!(last_error().contains("vertex_count is"), "{}", last_error());
            let s = quadopt_optimize(
                c.as_mut_ptr(),
                2,
                u32::MAX as usize,
                quads.as_ptr(),
                usize::MAX / 2,
                null(),
                null(),
                null_mut(),
            );
            assert_eq!(s, S::InvalidArgument);
            assert!(last_error().contains("quad_count is"), "{}", last_error());
            assert_eq!(checked_count(usize::MAX / 2, 3, "n").unwrap_err().status, S::InvalidArgument);
            assert_eq!(check_bytes(usize::MAX / 8, 8, "n").unwrap_err().status, S::InvalidArgument);
            assert!(check_bytes(isize::MAX as usize / 8, 8, "n").is_ok());
            // An unreadable fixed mask is not read when the coordinates are bad.
            let s = quadopt_optimize(
                c.as_mut_ptr(),
                5,
                9,
                quads.as_ptr(),
                4,
                std::ptr::dangling::<u8>(),
                null(),
                null_mut(),
            );
            assert_eq!(s, S::InvalidArgument);
            // NULL arrays with nonzero counts.
            let s = quadopt_optimize(null_mut(), 2, 9, quads.as_ptr(), 4, null(), null(), &mut report);
            assert_eq!(s, S::NullPointer);
            assert!(last_error().contains("coords is NULL"), "{}", last_error());
            let s = quadopt_optimize(c.as_mut_ptr(), 2, 9, null(), 4, null(), null(), &mut report);
            assert_eq!(s, S::NullPointer);
            assert!(last_error().contains("quads is NULL"), "{}", last_error());
            // NULL arrays with zero counts are empty arrays.
            let s = quadopt_optimize(null_mut(), 2, 0, null(), 0, null(), null(), &mut report);
            assert_eq!(s, S::NoQuads);
            // A misaligned coordinate pointer.
            let s = quadopt_optimize(
                c.as_mut_ptr().cast::<u8>().add(1).cast(),
                2,
                8,
                quads.as_ptr(),
                4,
                null(),
                null(),
                &mut report,
            );
            assert_eq!(s, S::InvalidArgument);
            assert!(last_error().contains("aligned"), "{}", last_error());
            // A report that declares less than this version's struct.
            let mut small = sentinel_report();
            small.struct_size = 8;
            let s = quadopt_optimize(c.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), null(), &mut small);
            assert_eq!(s, S::InvalidArgument);
            assert!(last_error().contains("report->struct_size is 8"), "{}", last_error());
            let mut expected_small = sentinel_report();
            expected_small.struct_size = 8;
            assert_eq!(bytes_of(&small), bytes_of(&expected_small));
        }
        assert_eq!(bits(&c), bits(&coords));
        assert_eq!(bytes_of(&report), bytes_of(&sentinel_report()));
        let short = QuadoptOptions { struct_size: 16, ..default_options() };
        assert_eq!(optimize_status(&coords, 2, &quads, None, Some(&short)), S::InvalidArgument);
        assert!(last_error().contains("options->struct_size is 16"), "{}", last_error());
    }

    #[test]
    fn every_invalid_option_is_named() {
        let (coords, quads) = patch(2);
        let d = default_options();
        let cases: Vec<(QuadoptOptions, &str)> = vec![
            (QuadoptOptions { method: 4, ..d }, "method"),
            (QuadoptOptions { method: u32::MAX, ..d }, "method"),
            (QuadoptOptions { boundary: 4, ..d }, "boundary"),
            (QuadoptOptions { lambda: 0.0, ..d }, "lambda"),
            (QuadoptOptions { lambda: f64::NAN, ..d }, "lambda"),
            (QuadoptOptions { lambda: 1.5, ..d }, "lambda"),
            (QuadoptOptions { tau: -1.0, ..d }, "tau"),
            (QuadoptOptions { tau: f64::INFINITY, ..d }, "tau"),
            (QuadoptOptions { max_iterations: 0, ..d }, "max_iterations"),
            (QuadoptOptions { feature_angle_deg: 180.5, ..d }, "feature_angle_deg"),
            (QuadoptOptions { guard_floor: 0.0, ..d }, "guard_floor"),
            (QuadoptOptions { max_boundary_deviation: f64::NAN, ..d }, "max_boundary_deviation"),
        ];
        for (o, name) in cases {
            assert_eq!(optimize_status(&coords, 2, &quads, None, Some(&o)), QuadoptStatus::InvalidOption);
            assert!(last_error().contains(&format!("invalid option {name}:")), "{name}: {}", last_error());
        }
        // A bad option is reported even when the mesh is bad too.
        let o = QuadoptOptions { boundary: 77, ..d };
        assert_eq!(optimize_status(&coords, 2, &[], None, Some(&o)), QuadoptStatus::InvalidOption);
        // Any negative deviation means unlimited; nonzero bytes are true.
        let o = QuadoptOptions { max_boundary_deviation: f64::NEG_INFINITY, guard: 200, ..d };
        assert_eq!(optimize_status(&coords, 2, &quads, None, Some(&o)), QuadoptStatus::Ok);
    }

    #[test]
    fn options_init_writes_only_the_callers_struct() {
        // A newer caller's struct: ours followed by 16 bytes this library knows nothing of.
        #[repr(C)]
        struct Newer {
            ours: QuadoptOptions,
            extra: [u64; 2],
        }
        let mut newer = Newer { ours: quadopt_options_defaults(), extra: [0xDEAD_BEEF; 2] };
        newer.ours.lambda = 0.25;
        let status = unsafe { quadopt_options_init(&raw mut newer.ours, size_of::<Newer>()) };
        assert_eq!(status, QuadoptStatus::Ok);
        assert_eq!(newer.ours.lambda, 1.0);
        assert_eq!(newer.ours.struct_size as usize, size_of::<QuadoptOptions>());
        assert_eq!(newer.extra, [0xDEAD_BEEF; 2]);
        // Too small, or NULL: an error, nothing written.
        let mut o = quadopt_options_defaults();
        o.lambda = 0.5;
        let status = unsafe { quadopt_options_init(&raw mut o, OPTIONS_V1_SIZE - 8) };
        assert_eq!(status, QuadoptStatus::InvalidArgument);
        assert_eq!(o.lambda, 0.5);
        let status = unsafe { quadopt_options_init(std::ptr::null_mut(), 64) };
        assert_eq!(status, QuadoptStatus::NullPointer);
    }

    /// The sample mesh data/plate_2holes.vtk as flat arrays: the max-min stage raises its
    /// minimum (0.753 after the sweeps).
    fn plate_2holes() -> (Vec<f64>, Vec<u32>) {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/data/plate_2holes.vtk");
        let data = crate::io::read_mesh(path).unwrap();
        let coords = data.points.iter().flat_map(|p| [p[0], p[1]]).collect();
        (coords, data.quads.iter().flatten().copied().collect())
    }

    fn run_plate(options: &QuadoptOptions, report_size: usize) -> (Vec<f64>, QuadoptReport) {
        let (mut coords, quads) = plate_2holes();
        let mut report = QuadoptReport { struct_size: report_size as u32, ..sentinel_report() };
        report.max_min = 0xA5A5_A5A5;
        report.sweeps.min = -9.0;
        // SAFETY: live buffers of the stated lengths; the report holds its declared bytes.
        let status = unsafe {
            quadopt_optimize(
                coords.as_mut_ptr(),
                2,
                coords.len() / 2,
                quads.as_ptr(),
                quads.len() / 4,
                null(),
                options,
                &mut report,
            )
        };
        assert_eq!(status, QuadoptStatus::Ok, "{}", last_error());
        (coords, report)
    }

    #[test]
    fn the_max_min_stage_is_an_option_and_its_gain_is_reported() {
        let on = default_options();
        assert_eq!(on.max_min, 1, "on by default");
        let (with, r) = run_plate(&on, size_of::<QuadoptReport>());
        assert_eq!(r.max_min, 1);
        assert!(r.output.min > r.sweeps.min + 0.05, "{:?} -> {:?}", r.sweeps, r.output);
        assert!(r.output.avg >= r.sweeps.avg - 1e-3);
        let off = QuadoptOptions { max_min: 0, ..on };
        let (without, r0) = run_plate(&off, size_of::<QuadoptReport>());
        assert_eq!(r0.max_min, 0);
        assert_eq!(bytes_of(&r0.sweeps), bytes_of(&r0.output), "no stage: sweeps == output");
        // (The sweeps themselves differ: before the stage they are kept for their average.)
        assert_ne!(bits(&with), bits(&without));
    }

    #[test]
    fn first_version_structs_get_the_new_defaults_and_their_bytes_only() {
        // A caller compiled against the first header: its options end before `max_min`, its
        // report before `max_min` too.
        let mut v1 = default_options();
        v1.struct_size = OPTIONS_V1_SIZE as u32;
        v1.max_min = 0; // beyond the caller's struct: must not be read
        let (points, r) = run_plate(&v1, REPORT_V1_SIZE);
        let (expected, _) = run_plate(&default_options(), size_of::<QuadoptReport>());
        assert_eq!(bits(&points), bits(&expected), "a v1 caller gets the stage (the default)");
        assert_eq!(r.struct_size as usize, REPORT_V1_SIZE, "bytes filled");
        assert_eq!((r.max_min, r.sweeps.min), (0xA5A5_A5A5, -9.0), "fields beyond v1 written");
        assert_eq!(OPTIONS_V1_SIZE, 80);
        assert_eq!(REPORT_V1_SIZE, 200);
    }

    #[test]
    fn larger_structs_from_newer_callers_are_read_and_written_by_prefix() {
        /// A caller compiled against a future header: the v1 struct plus new fields.
        #[repr(C)]
        #[derive(Clone, Copy)]
        struct Newer<T: Copy> {
            v1: T,
            extra: [u64; 4],
        }
        let (coords, quads) = patch(2);
        let mut options = Newer { v1: fixed_boundary_options(), extra: [u64::MAX; 4] };
        options.v1.struct_size = size_of::<Newer<QuadoptOptions>>() as u32;
        let mut report = Newer { v1: sentinel_report(), extra: [0x1234_5678; 4] };
        report.v1.struct_size = size_of::<Newer<QuadoptReport>>() as u32;
        let mut c = coords.clone();
        // SAFETY: both structs hold at least the bytes they declare.
        let status = unsafe {
            quadopt_optimize(
                c.as_mut_ptr(),
                2,
                9,
                quads.as_ptr(),
                4,
                null(),
                (&raw const options).cast(),
                (&raw mut report).cast(),
            )
        };
        assert_eq!(status, QuadoptStatus::Ok, "{}", last_error());
        assert_eq!(report.extra, [0x1234_5678; 4], "bytes beyond this version's report were written");
        assert_eq!(report.v1.struct_size as usize, size_of::<QuadoptReport>(), "bytes filled");
        assert_eq!(report.v1.loops_fixed, 1);
        assert!((c[8] - 1.0).abs() < 1e-3);
    }

    #[test]
    fn cancel_writes_nothing_and_reports_where() {
        unsafe extern "C" fn cancel_at_third(p: *const QuadoptProgress, user: *mut c_void) -> bool {
            // SAFETY: the library passes a valid progress; user is the counter below.
            let (p, calls) = unsafe { (&*p, &mut *user.cast::<Vec<QuadoptProgress>>()) };
            calls.push(*p);
            calls.len() < 3
        }
        let (coords, quads) = patch(2);
        let mut calls: Vec<QuadoptProgress> = Vec::new();
        let o = QuadoptOptions {
            stop_rule: QuadoptStopRule::Energy as u32,
            tau: 0.0, // never converges: the callback decides
            progress: Some(cancel_at_third),
            progress_user_data: (&raw mut calls).cast(),
            ..fixed_boundary_options()
        };
        assert_eq!(optimize_status(&coords, 2, &quads, None, Some(&o)), QuadoptStatus::Cancelled);
        assert_eq!(calls.len(), 3);
        // The patch has an inverted quad: the first call comes from untangling (iteration 0).
        assert_eq!(calls.iter().map(|p| p.iteration).collect::<Vec<_>>(), [0, 1, 2]);
        assert!(calls.iter().all(|p| p.pass == 1 && p.passes == 1 && p.max_iterations == 1000));
        assert!(last_error().contains("cancelled by the progress callback at pass 1 of 1, iteration 2"));
        // The same callback under the automatic mode, also one pass.
        calls.clear();
        let o = QuadoptOptions { boundary: QuadoptBoundary::Auto as u32, ..o };
        assert_eq!(optimize_status(&coords, 2, &quads, None, Some(&o)), QuadoptStatus::Cancelled);
        assert!(calls.iter().all(|p| p.passes == 1 && p.pass == 1));
    }

    #[test]
    fn quality_matches_hand_computed_values() {
        // Two quads: a unit square and a 60 degree rhombus sharing its edge (1,0)-(1,1)...
        // simpler: a unit square [0,1,4,3] and the parallelogram [1,2,5,4] sheared by 1.
        let s = 2f64.sqrt() / 2.0; // sin 45 degrees
        let coords = [0.0, 0.0, 1.0, 0.0, 2.0, 0.0, 0.0, 1.0, 1.0, 1.0, 3.0, 1.0];
        let quads = [0, 1, 4, 3, 1, 2, 5, 4];
        let mut q = QuadoptQuality::default();
        let mut per = [f64::NAN; 3];
        // SAFETY: live buffers; per has room for 3 >= 2 values.
        let status =
            unsafe { quadopt_quality(coords.as_ptr(), 2, 6, quads.as_ptr(), 2, &mut q, per.as_mut_ptr(), 3) };
        assert_eq!(status, QuadoptStatus::Ok);
        assert_eq!(per[0], 1.0);
        assert!((per[1] - s).abs() < 1e-15, "{}", per[1]);
        assert!(per[2].is_nan(), "beyond quad_count was written");
        assert_eq!((q.min, q.max, q.inverted), (per[1], 1.0, 0));
        assert!((q.avg - (1.0 + s) / 2.0).abs() < 1e-15);
        // Given clockwise, the mesh scores the same (orientation is made consistent).
        let cw = [0, 3, 4, 1, 1, 4, 5, 2];
        let mut q2 = QuadoptQuality::default();
        // SAFETY: live buffers; no per-quad output.
        let status =
            unsafe { quadopt_quality(coords.as_ptr(), 2, 6, cw.as_ptr(), 2, &mut q2, null_mut(), 0) };
        assert_eq!((status, q2), (QuadoptStatus::Ok, q));
        // Errors write nothing.
        let mut q3 = QuadoptQuality { min: 9.0, ..Default::default() };
        let mut per = [7.0; 2];
        // SAFETY: live buffers; the calls fail on the checks.
        unsafe {
            let s = quadopt_quality(coords.as_ptr(), 2, 6, quads.as_ptr(), 2, &mut q3, per.as_mut_ptr(), 1);
            assert_eq!(s, QuadoptStatus::InvalidArgument);
            assert!(last_error().contains("per_quad_len is 1"));
            let s = quadopt_quality(coords.as_ptr(), 2, 6, quads.as_ptr(), 2, null_mut(), null_mut(), 0);
            assert_eq!(s, QuadoptStatus::NullPointer);
            assert!(last_error().contains("out is NULL"));
            let s = quadopt_quality(coords.as_ptr(), 2, 5, quads.as_ptr(), 2, &mut q3, per.as_mut_ptr(), 2);
            assert_eq!(s, QuadoptStatus::IndexOutOfRange);
        }
        assert_eq!((q3.min, per), (9.0, [7.0; 2]));
    }

    #[test]
    fn handle_gives_the_same_result_as_one_shot_and_checks_the_vertex_count() {
        let (coords, quads) = patch(3);
        let mut handle = null_mut();
        let o = fixed_boundary_options();
        // SAFETY: live buffers; `handle` receives a pointer.
        unsafe {
            assert_eq!(
                quadopt_optimizer_create(coords.as_ptr(), 3, 9, quads.as_ptr(), 4, null(), &mut handle),
                QuadoptStatus::Ok
            );
            assert!(!handle.is_null());
            // The handle works with another stride than it was created with.
            let (mut via_handle, _) = patch(2);
            let mut r1 = quadopt_report_init();
            let s = quadopt_optimizer_optimize(handle, via_handle.as_mut_ptr(), 2, 9, &o, &mut r1);
            assert_eq!(s, QuadoptStatus::Ok);
            let (mut one_shot, _) = patch(2);
            let mut r2 = quadopt_report_init();
            let s = quadopt_optimize(one_shot.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), &o, &mut r2);
            assert_eq!(s, QuadoptStatus::Ok);
            assert_eq!(bits(&via_handle), bits(&one_shot));
            assert_eq!((r1.iterations, r1.output), (r2.iterations, r2.output));

            // Wrong vertex count, NULL handle, non-finite coordinates: nothing written.
            let (mut c, _) = patch(2);
            c.extend([5.0, 5.0]);
            let before = bits(&c);
            let mut report = sentinel_report();
            let s = quadopt_optimizer_optimize(handle, c.as_mut_ptr(), 2, 10, &o, &mut report);
            assert_eq!(s, QuadoptStatus::Mismatch);
            assert!(last_error().contains("10 vertices were given, but the mesh has 9"), "{}", last_error());
            let s = quadopt_optimizer_optimize(null(), c.as_mut_ptr(), 2, 9, &o, &mut report);
            assert_eq!(s, QuadoptStatus::NullPointer);
            c[0] = f64::NAN;
            let s = quadopt_optimizer_optimize(handle, c.as_mut_ptr(), 2, 9, &o, &mut report);
            assert_eq!(s, QuadoptStatus::NonFiniteCoordinate);
            assert_eq!(bits(&c[1..]), before[1..]);
            assert_eq!(bytes_of(&report), bytes_of(&sentinel_report()));

            // create: NULL out and an invalid mesh leave *out untouched.
            let s = quadopt_optimizer_create(coords.as_ptr(), 3, 9, quads.as_ptr(), 4, null(), null_mut());
            assert_eq!(s, QuadoptStatus::NullPointer);
            let mut other = 0x10 as *mut QuadoptOptimizer;
            let s = quadopt_optimizer_create(coords.as_ptr(), 3, 9, quads.as_ptr(), 0, null(), &mut other);
            assert_eq!((s, other as usize), (QuadoptStatus::NoQuads, 0x10));

            quadopt_optimizer_free(handle);
            quadopt_optimizer_free(null_mut());
        }
    }

    #[test]
    fn one_handle_is_safe_to_share_between_threads() {
        let (coords, quads) = patch(2);
        let mut handle = null_mut();
        // SAFETY: live buffers.
        let s = unsafe {
            quadopt_optimizer_create(coords.as_ptr(), 2, 9, quads.as_ptr(), 4, null(), &mut handle)
        };
        assert_eq!(s, QuadoptStatus::Ok);
        // SAFETY: the handle is live until freed below, after every thread has finished.
        let shared: &QuadoptOptimizer = unsafe { &*handle };
        let o = fixed_boundary_options();
        let start = |k: usize| {
            let mut c = coords.clone();
            c[8] = 1.0 + 0.1 * k as f64;
            c[9] = 1.0 - 0.05 * k as f64;
            c
        };
        let expected: Vec<Vec<u64>> = (0..8)
            .map(|k| {
                let mut c = start(k);
                // SAFETY: live buffers.
                let s = unsafe { quadopt_optimizer_optimize(shared, c.as_mut_ptr(), 2, 9, &o, null_mut()) };
                assert_eq!(s, QuadoptStatus::Ok);
                bits(&c)
            })
            .collect();
        std::thread::scope(|scope| {
            for t in 0..4 {
                let (expected, start) = (&expected, &start);
                scope.spawn(move || {
                    // Options hold raw pointers (user data), so each thread makes its own.
                    let o = &fixed_boundary_options();
                    for round in 0..5 {
                        let k = (t + round) % 8;
                        let mut c = start(k);
                        // SAFETY: the handle is shared read-only; each thread owns its coords.
                        let s = unsafe {
                            quadopt_optimizer_optimize(shared, c.as_mut_ptr(), 2, 9, o, null_mut())
                        };
                        assert_eq!(s, QuadoptStatus::Ok);
                        assert_eq!(bits(&c), expected[k], "thread {t} round {round}");
                        // Errors on this thread leave other threads' messages alone.
                        // SAFETY: fails on the count check before any access.
                        let s = unsafe {
                            quadopt_optimizer_optimize(shared, c.as_mut_ptr(), 2, 9 + t, o, null_mut())
                        };
                        assert_eq!(s == QuadoptStatus::Ok, t == 0);
                        if t > 0 {
                            assert!(last_error().contains(&format!("{} vertices were given", 9 + t)));
                        }
                    }
                });
            }
        });
        // SAFETY: created above, freed once.
        unsafe { quadopt_optimizer_free(handle) };
    }

    #[test]
    fn panics_are_caught_at_the_boundary() {
        let status = boundary("quadopt_test", || panic!("boom {}", 42));
        assert_eq!(status, QuadoptStatus::Panic);
        assert_eq!(last_error(), "quadopt_test: internal error (panic: boom 42); please report this bug");
        assert_eq!(boundary_or(5, || panic!("static")), 5);
    }

    /// Runs this binary's test `name` again in a fresh process (with `QUADOPT_TEST_CHILD` set,
    /// so the test runs its child half), with the given environment, and checks that exactly
    /// that test ran and passed. Returns the child's stderr.
    fn run_in_child(name: &str, env: &[(&str, &str)]) -> String {
        let exe = std::env::current_exe().unwrap();
        let out = std::process::Command::new(exe)
            .args(["--exact", name, "--nocapture", "--test-threads=1"])
            .env("QUADOPT_TEST_CHILD", name)
            .env_remove("RUST_BACKTRACE")
            .envs(env.iter().copied())
            .output()
            .unwrap();
        let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        assert!(out.status.success() && stdout.contains("1 passed"), "child {name}:\n{stdout}\n{stderr}");
        stderr.into_owned()
    }

    fn is_child(name: &str) -> bool {
        std::env::var("QUADOPT_TEST_CHILD").as_deref() == Ok(name)
    }

    /// Threads of this process.
    fn threads_now() -> usize {
        std::fs::read_dir("/proc/self/task").unwrap().count()
    }

    /// Threads of this process, once the count is `expected` or after a second. A joined
    /// thread can stay listed for a moment: `join` returns when the thread has cleared its id,
    /// which the kernel does before it removes the thread from /proc.
    fn thread_count(expected: usize) -> usize {
        let until = std::time::Instant::now() + std::time::Duration::from_secs(1);
        loop {
            let n = threads_now();
            if n == expected || std::time::Instant::now() > until {
                return n;
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
    }

    /// quadopt_optimize on the jittered patch with a fixed boundary; the status and the result.
    fn optimize_patch(options: &QuadoptOptions) -> (QuadoptStatus, Vec<u64>) {
        let (mut c, quads) = patch(2);
        // SAFETY: live buffers of the stated lengths.
        let s =
            unsafe { quadopt_optimize(c.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), options, null_mut()) };
        (s, bits(&c))
    }

    #[test]
    #[cfg(target_os = "linux")]
    fn a_pool_that_cannot_start_leaves_no_thread_and_later_calls_work() {
        const NAME: &str = "ffi::tests::a_pool_that_cannot_start_leaves_no_thread_and_later_calls_work";
        if !is_child(NAME) {
            run_in_child(NAME, &[("RAYON_NUM_THREADS", "3")]);
            return;
        }
        let o = fixed_boundary_options();
        let (untouched, _) = patch(2);
        let baseline = threads_now();
        // No thread at all can start: a status, nothing written, nothing left running.
        pool::THREAD_LIMIT.store(0, Ordering::SeqCst);
        let (s, c) = optimize_patch(&o);
        assert_eq!(s, QuadoptStatus::OutOfMemory);
        assert!(last_error().contains("cannot start a worker thread"), "{}", last_error());
        assert_eq!((c, thread_count(baseline)), (bits(&untouched), baseline));
        // One thread can start, the pool of three cannot: the started one is joined and the
        // call runs on a single worker, joined too.
        pool::THREAD_LIMIT.store(1, Ordering::SeqCst);
        let (s, single) = optimize_patch(&o);
        assert_eq!((s, thread_count(baseline)), (QuadoptStatus::Ok, baseline), "{}", last_error());
        // Threads available again: the next call builds the pool, with the same result.
        pool::THREAD_LIMIT.store(usize::MAX, Ordering::SeqCst);
        let (s, pooled) = optimize_patch(&o);
        assert_eq!((s, thread_count(baseline + 3)), (QuadoptStatus::Ok, baseline + 3));
        assert_eq!(single, pooled, "the thread count changed the result");
        assert!((f64::from_bits(pooled[8]) - 1.0).abs() < 1e-3);
    }

    #[test]
    fn the_progress_callback_runs_on_the_calling_thread() {
        unsafe extern "C" fn record(_: *const QuadoptProgress, user: *mut c_void) -> bool {
            // SAFETY: user is the vector below, used by this thread only.
            unsafe { &mut *user.cast::<Vec<std::thread::ThreadId>>() }.push(std::thread::current().id());
            true
        }
        let mut seen: Vec<std::thread::ThreadId> = Vec::new();
        let o = QuadoptOptions {
            progress: Some(record),
            progress_user_data: (&raw mut seen).cast(),
            ..fixed_boundary_options()
        };
        assert_eq!(optimize_patch(&o).0, QuadoptStatus::Ok);
        assert!(!seen.is_empty());
        assert!(seen.iter().all(|&t| t == std::thread::current().id()));
    }

    #[test]
    fn nested_calls_from_the_callback_finish_on_a_single_worker() {
        const NAME: &str = "ffi::tests::nested_calls_from_the_callback_finish_on_a_single_worker";
        if !is_child(NAME) {
            run_in_child(NAME, &[("RAYON_NUM_THREADS", "1")]);
            return;
        }
        /// Each callback of the outer three levels optimizes the patch again, one level deeper.
        unsafe extern "C" fn recurse(_: *const QuadoptProgress, user: *mut c_void) -> bool {
            // SAFETY: user is the depth counter below, used by this thread only.
            let depth = unsafe { &mut *user.cast::<usize>() };
            if *depth < 3 {
                *depth += 1;
                let o = QuadoptOptions { max_iterations: 2, ..nested_options(user) };
                assert_eq!(optimize_patch(&o).0, QuadoptStatus::Ok);
                *depth -= 1;
            }
            true
        }
        fn nested_options(user: *mut c_void) -> QuadoptOptions {
            QuadoptOptions { progress: Some(recurse), progress_user_data: user, ..fixed_boundary_options() }
        }
        let mut depth = 0usize;
        let o = QuadoptOptions { max_iterations: 3, ..nested_options((&raw mut depth).cast()) };
        let (s, c) = optimize_patch(&o);
        assert_eq!((s, depth), (QuadoptStatus::Ok, 0), "{}", last_error());
        let (_, plain) = optimize_patch(&QuadoptOptions { max_iterations: 3, ..fixed_boundary_options() });
        assert_eq!(c, plain);
    }

    #[test]
    fn a_caught_panic_prints_nothing_and_others_still_reach_the_previous_hook() {
        const NAME: &str =
            "ffi::tests::a_caught_panic_prints_nothing_and_others_still_reach_the_previous_hook";
        if !is_child(NAME) {
            for backtrace in ["0", "1", "full"] {
                let stderr = run_in_child(NAME, &[("RUST_BACKTRACE", backtrace)]);
                // Only the panic outside the library reached the default hook.
                assert!(stderr.contains("panicked") && stderr.contains("outside the library"), "{stderr}");
                assert!(!stderr.contains("boom"), "RUST_BACKTRACE={backtrace}:\n{stderr}");
            }
            return;
        }
        // On the calling thread, in both kinds of boundary.
        assert_eq!(boundary("quadopt_test", || panic!("boom 1")), QuadoptStatus::Panic);
        assert_eq!(boundary_or(7, || panic!("boom 2")), 7);
        // On a worker thread, resumed on the calling thread.
        let status = boundary("quadopt_test", || {
            let _ = pool::run_with_progress(|_| -> () { panic!("boom 3") }, |_: ()| true);
            Ok(())
        });
        assert_eq!(status, QuadoptStatus::Panic);
        assert!(last_error().contains("boom 3"), "{}", last_error());
        // The pool survives a panicking job.
        assert_eq!(optimize_patch(&fixed_boundary_options()).0, QuadoptStatus::Ok);
        assert!(panic::catch_unwind(|| panic!("outside the library")).is_err());
    }

    #[test]
    fn every_library_error_maps_to_its_status() {
        use QuadoptStatus as S;
        let cases = [
            (Error::NoQuads, S::NoQuads),
            (Error::IndexOutOfRange { quad: 0, corner: 0, index: 0, vertex_count: 0 }, S::IndexOutOfRange),
            (Error::RepeatedVertex { quad: 0, vertex: 0 }, S::RepeatedVertex),
            (Error::NonManifoldEdge { a: 0, b: 1, count: 3, first: 0, second: 1 }, S::NonManifold),
            (Error::NonFiniteCoordinate { vertex: 0 }, S::NonFiniteCoordinate),
            (Error::NonOrientable { quad: 0 }, S::NonOrientable),
            (Error::FixedLengthMismatch { expected: 1, got: 2 }, S::Mismatch),
            (Error::VertexCountMismatch { expected: 1, got: 2 }, S::Mismatch),
            (Error::ConnectivityMismatch { expected: 1, got: 2 }, S::Mismatch),
            (Error::InvalidOption { name: "x", reason: String::new() }, S::InvalidOption),
            (Error::NotPlanar { vertex: 0, distance: 1.0, tolerance: 0.5 }, S::NotPlanar),
            (Error::OutOfMemory { what: "points", bytes: 16 }, S::OutOfMemory),
        ];
        for (e, s) in cases {
            let f = FfiError::from(e.clone());
            assert_eq!((f.status, f.message), (s, e.to_string()));
        }
    }

    #[test]
    fn status_strings_cover_every_integer() {
        let name = |s: i32| {
            // SAFETY: quadopt_status_string returns a static C string.
            unsafe { CStr::from_ptr(quadopt_status_string(s)) }.to_str().unwrap().to_owned()
        };
        let known: Vec<String> = (0..=14).map(name).collect();
        assert_eq!(known[0], "ok");
        assert_eq!(known[11], "cancelled");
        let mut unique = known.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), 15, "status strings must be distinct");
        for s in [-1, 15, i32::MIN, i32::MAX] {
            assert_eq!(name(s), "unknown status");
        }
        assert_eq!(QuadoptStatus::NotPlanar as i32, 13);
        assert_eq!((QuadoptStatus::OutOfMemory as i32, known[14].as_str()), (14, "out of memory"));
    }

    #[test]
    fn last_error_is_empty_on_a_fresh_thread() {
        std::thread::spawn(|| assert_eq!(last_error(), "")).join().unwrap();
    }

    #[test]
    fn defaults_and_version() {
        let mut o = QuadoptOptions { struct_size: 0, method: 9, ..default_options() };
        // SAFETY: `o` is a writable QuadoptOptions; NULL is a no-op.
        unsafe {
            quadopt_options_default(&mut o);
            quadopt_options_default(null_mut());
        }
        let by_value = quadopt_options_defaults();
        assert_eq!(bytes_of(&o), bytes_of(&by_value));
        assert_eq!(o.struct_size as usize, size_of::<QuadoptOptions>());
        assert_eq!((o.method, o.boundary, o.max_iterations), (0, 0, 1000));
        assert_eq!((o.lambda, o.tau, o.feature_angle_deg, o.guard_floor), (1.0, 1e-7, 45.0, 0.05));
        assert_eq!(o.max_boundary_deviation, -1.0);
        assert_eq!((o.tau_absolute, o.guard, o.untangle, o.keep_best), (0, 1, 1, 1));
        assert!(o.progress.is_none() && o.progress_user_data.is_null());
        assert_eq!(convert_options(&o).unwrap(), Options::default());
        let r = quadopt_report_init();
        assert_eq!(bytes_of(&r)[4..], vec![0; size_of::<QuadoptReport>() - 4][..]);

        // SAFETY: static string.
        let v = unsafe { CStr::from_ptr(quadopt_version()) }.to_str().unwrap();
        assert_eq!(v, env!("CARGO_PKG_VERSION"));
        let (mut a, mut b, mut c) = (9, 9, 9);
        // SAFETY: writable u32s or NULL.
        unsafe {
            quadopt_version_numbers(&mut a, &mut b, &mut c);
            quadopt_version_numbers(null_mut(), null_mut(), null_mut());
        }
        assert_eq!(format!("{a}.{b}.{c}"), v);
        assert_eq!(
            (QUADOPT_VERSION_MAJOR, QUADOPT_VERSION_MINOR, QUADOPT_VERSION_PATCH),
            (a, b, c),
            "update the QUADOPT_VERSION_* constants with Cargo.toml's version"
        );
    }

    #[test]
    fn struct_layouts_have_no_padding_on_64_bit() {
        // The spec's field order packs without holes on LP64 (checked so that the byte copies
        // of the prefix protocol never copy padding, and as a guard against reordering).
        if size_of::<usize>() == 8 {
            assert_eq!(size_of::<QuadoptOptions>(), 88);
            assert_eq!(size_of::<QuadoptReport>(), 240);
            assert_eq!(size_of::<QuadoptQuality>(), 32);
            assert_eq!(size_of::<QuadoptProgress>(), 48);
            assert_eq!(std::mem::offset_of!(QuadoptOptions, progress), 64);
            assert_eq!(std::mem::offset_of!(QuadoptReport, loops_fixed), 192);
            assert_eq!(std::mem::offset_of!(QuadoptOptions, max_min), 80);
            assert_eq!(std::mem::offset_of!(QuadoptReport, sweeps), 208);
        }
        assert_eq!(size_of::<QuadoptStatus>(), size_of::<std::ffi::c_int>());
    }
}

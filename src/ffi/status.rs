//! Status and messages: [`QuadoptStatus`], the failure on its way to the caller
//! (`FfiError`), the mapping of the library's errors to statuses, the thread-local last-error
//! message, and the two functions that name a status and read the message.

use crate::error::Error;
use std::cell::RefCell;
use std::ffi::{CStr, CString, c_char};

use super::boundary::boundary_or;

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
    /// small or misaligned, or a `struct_size` smaller than this version's struct. (Also the
    /// status of a face with other than 3 or 4 vertices, which the four-slot face layout
    /// cannot express; the C++ adapters use it for such faces of a mesh library's mesh.)
    InvalidArgument = 2,
    /// An option is out of its range or an enum-valued option is unknown; the message names it.
    InvalidOption = 3,
    /// The mesh has no faces (no quads and no triangles).
    NoQuads = 4,
    /// A face refers to a vertex index >= vertex_count (`QUADOPT_NO_VERTEX` anywhere but in
    /// a face's fourth slot included).
    IndexOutOfRange = 5,
    /// A face uses the same vertex twice.
    RepeatedVertex = 6,
    /// An edge is shared by more than two faces.
    NonManifold = 7,
    /// A coordinate that is read (x or y; z too on a surface) is NaN or infinite.
    NonFiniteCoordinate = 8,
    /// The quads cannot be oriented consistently (e.g. a Moebius strip).
    NonOrientable = 9,
    /// A handle was used with a different vertex count than it was created for.
    Mismatch = 10,
    /// The progress callback returned false; coordinates and report are untouched.
    Cancelled = 11,
    /// An internal error (a bug) was caught at the API boundary.
    Panic = 12,
    /// The mesh is not planar where only a planar mesh is accepted: `dim` 3 coordinates that do
    /// not lie on one plane to within rounding (`quadopt_is_planar()`'s rule) given to a reusable
    /// optimizer (`quadopt_optimizer_create()`, where it comes before any other check of the
    /// mesh, and `quadopt_optimizer_optimize()`). `quadopt_optimize()` optimizes such a mesh on
    /// its surface instead (as `quadopt_optimize_surface()`); the C++ adapters' `NotPlanar` uses
    /// it too.
    NotPlanar = 13,
    /// Not enough memory (or threads) for this mesh: an allocation that grows with the input
    /// failed, the memory the optimizer needs at its peak was not available when checked before
    /// it started, or not even one worker thread could start. Nothing was written; the same
    /// call can succeed with more memory available.
    OutOfMemory = 14,
    /// The mesh, or a connected part of it, is closed: it has no boundary edge (every vertex
    /// is interior, as in a periodic grid whose quads wrap around). A closed surface cannot lie
    /// flat in a plane without folds, so it has no orientation that makes every quad valid.
    /// (Only planar runs refuse it: on a surface in 3D a closed mesh is accepted.)
    ClosedMesh = 15,
}

/// A failure on its way to the caller: a status and the detailed message.
#[derive(Debug)]
pub(super) struct FfiError {
    pub(super) status: QuadoptStatus,
    pub(super) message: String,
}

impl FfiError {
    pub(super) fn new(status: QuadoptStatus, message: impl Into<String>) -> Self {
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
        Error::ClosedMesh { .. } => QuadoptStatus::ClosedMesh,
        Error::FixedLengthMismatch { .. } => QuadoptStatus::Mismatch,
        Error::VertexCountMismatch { .. } | Error::ConnectivityMismatch { .. } => QuadoptStatus::Mismatch,
        Error::InvalidOption { .. } => QuadoptStatus::InvalidOption,
        Error::NotPlanar { .. } => QuadoptStatus::NotPlanar,
        Error::UnsupportedFace { .. } => QuadoptStatus::InvalidArgument,
        Error::OutOfMemory { .. } | Error::NoThreads { .. } => QuadoptStatus::OutOfMemory,
    }
}

thread_local! {
    /// The detailed message of the last failed call on this thread.
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

pub(super) fn set_last_error(message: String) {
    // Interior NULs would cut the C string short; make them visible instead.
    let c = CString::new(message.replace('\0', "\\0")).unwrap_or_default();
    // During thread teardown the slot may be gone; then there is nobody to tell.
    let _ = LAST_ERROR.try_with(|slot| *slot.borrow_mut() = c);
}

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
        15 => c"closed mesh",
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffi::test_support::*;

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
            (Error::ClosedMesh { quad: 0, whole_mesh: true }, S::ClosedMesh),
            (Error::FixedLengthMismatch { expected: 1, got: 2 }, S::Mismatch),
            (Error::VertexCountMismatch { expected: 1, got: 2 }, S::Mismatch),
            (Error::ConnectivityMismatch { expected: 1, got: 2 }, S::Mismatch),
            (Error::InvalidOption { name: "x", reason: String::new() }, S::InvalidOption),
            (Error::NotPlanar { vertex: 0, distance: 1.0, tolerance: 0.5 }, S::NotPlanar),
            (Error::OutOfMemory { what: "points", bytes: 16 }, S::OutOfMemory),
            (Error::UnsupportedFace { face: 0, corners: 5 }, S::InvalidArgument),
            (Error::NoThreads { why: String::new() }, S::OutOfMemory),
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
        let known: Vec<String> = (0..=15).map(name).collect();
        assert_eq!(known[0], "ok");
        assert_eq!(known[11], "cancelled");
        let mut unique = known.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), 16, "status strings must be distinct");
        for s in [-1, 16, i32::MIN, i32::MAX] {
            assert_eq!(name(s), "unknown status");
        }
        assert_eq!(QuadoptStatus::NotPlanar as i32, 13);
        assert_eq!((QuadoptStatus::OutOfMemory as i32, known[14].as_str()), (14, "out of memory"));
        assert_eq!((QuadoptStatus::ClosedMesh as i32, known[15].as_str()), (15, "closed mesh"));
    }

    #[test]
    fn last_error_is_empty_on_a_fresh_thread() {
        std::thread::spawn(|| assert_eq!(last_error(), "")).join().unwrap();
    }
}

//! The C entry points (`src/ffi/`) with arbitrary arrays, counts, dimensions, flags, options
//! and report sizes. Every pointer passed points into a buffer this target owns, at least as
//! long as the count passed with it says (or is NULL); the library must check everything
//! else. Checked: no call panics (`QUADOPT_STATUS_PANIC` is a bug), none of these small inputs
//! is refused for memory (`QUADOPT_STATUS_OUT_OF_MEMORY`), nothing is written on any error, z
//! is never written, the progress callback runs on the calling thread, and a successful run
//! gives exactly what the Rust API gives.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use quadopt::ffi::{
    self, QuadoptOptimizer, QuadoptOptions, QuadoptProgress, QuadoptQuality, QuadoptReport, QuadoptStatus,
};
use quadopt::{BoundaryMode, DVec2, Mesh, Method, Options, StopRule};
use quadopt_fuzz::{MAX_ITERATIONS, RawMesh};
use std::ffi::{CStr, c_void};
use std::mem::size_of;

/// Options as a C caller might fill them, enum fields included out of range.
#[derive(Debug, Arbitrary)]
struct COptions {
    /// 0: sizeof, 1: sizeof + 32 (a newer caller), 2: sizeof - 8 (an older one), 3: 0.
    size: u8,
    method: u8,
    boundary: u8,
    max_iterations: u8,
    lambda: Option<f64>,
    tau: Option<f64>,
    feature_angle_deg: Option<f64>,
    guard_floor: Option<f64>,
    max_boundary_deviation: Option<f64>,
    flags: u8,
    /// Cancel in the progress callback after this many calls.
    cancel_after: Option<u8>,
}

#[derive(Debug, Arbitrary)]
struct Input {
    mesh: RawMesh,
    /// Doubles per vertex, 0 to 4 (only 2 and 3 are valid).
    dim: u8,
    /// Added to the real vertex count (the buffer always holds what is announced).
    vertex_delta: i8,
    quad_delta: i8,
    /// NULL arrays, and an absurd count with them (0: none, else a huge value).
    null_coords: Option<u8>,
    null_quads: Option<u8>,
    /// Fixed mask bytes (NULL when absent); missing entries are 0.
    fixed: Option<Vec<u8>>,
    /// Pass `coords` one byte off its alignment.
    misaligned: bool,
    options: Option<COptions>,
    /// Report: None = NULL, 0: sizeof, 1: larger, 2: smaller.
    report: Option<u8>,
    /// Use the handle API (create, optimize, free) instead of `quadopt_optimize`.
    handle: bool,
    /// Vertex count passed to `quadopt_optimizer_optimize` differs by this much.
    handle_delta: i8,
    per_quad_len: Option<u8>,
    status: i32,
}

const HUGE: [usize; 4] = [usize::MAX, usize::MAX / 2, u32::MAX as usize + 1, 1 << 40];

/// A C options struct with room behind it, so a declared size larger than ours stays inside
/// memory this target owns.
#[repr(C)]
struct OptionsBuffer {
    options: QuadoptOptions,
    tail: [u64; 8],
}

#[repr(C)]
#[derive(Clone, Copy, PartialEq)]
struct ReportBuffer {
    report: QuadoptReport,
    tail: [u64; 8],
}

/// What the progress callback sees: calls so far, the call after which it cancels, and the
/// thread that called quadopt (the callback must run on it).
struct CancelState {
    calls: u32,
    limit: u32,
    caller: std::thread::ThreadId,
    on_another_thread: bool,
}

unsafe extern "C" fn progress(_: *const QuadoptProgress, user_data: *mut c_void) -> bool {
    // SAFETY: user_data points to the CancelState of the running test case.
    let state = unsafe { &mut *user_data.cast::<CancelState>() };
    state.on_another_thread |= std::thread::current().id() != state.caller;
    state.calls += 1;
    state.calls <= state.limit
}

/// Statistics compared bitwise, so NaN statistics (overflowing coordinates) compare equal.
fn quality_bits(x: &QuadoptQuality) -> (u64, u64, u64, usize) {
    (x.min.to_bits(), x.avg.to_bits(), x.max.to_bits(), x.inverted)
}

fn count(base: usize, delta: i8) -> usize {
    (base as i64 + delta as i64).max(0) as usize
}

fn assert_not_panic(s: QuadoptStatus) {
    assert_ne!(s, QuadoptStatus::Panic, "a C entry point panicked: {:?}", last_error());
    assert_ne!(s, QuadoptStatus::OutOfMemory, "a small input was refused: {:?}", last_error());
}

/// The default options, as a C caller gets them from `quadopt_options_init`.
fn default_options() -> QuadoptOptions {
    let mut o = std::mem::MaybeUninit::<QuadoptOptions>::zeroed();
    // SAFETY: `o` holds size_of::<QuadoptOptions>() writable, aligned bytes.
    let s = unsafe { ffi::quadopt_options_init(o.as_mut_ptr(), size_of::<QuadoptOptions>()) };
    assert_eq!(s, QuadoptStatus::Ok);
    // SAFETY: zeroed (a valid QuadoptOptions: integers, floats, NULL pointers), then filled.
    unsafe { o.assume_init() }
}

fn last_error() -> String {
    let p = ffi::quadopt_last_error();
    assert!(!p.is_null());
    // SAFETY: the library returns a NUL-terminated thread-local string.
    unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
}

/// The Rust options the C options stand for (None when the C enum values are invalid).
fn rust_options(o: &QuadoptOptions) -> Option<Options> {
    Some(
        Options::DEFAULT
            .with_method(match o.method {
                0 => Method::EmbeddedPolygon,
                1 => Method::Laplacian,
                2 => Method::Cotangent,
                3 => Method::AngleBased,
                _ => return None,
            })
            .with_boundary(match o.boundary {
                0 => BoundaryMode::Auto,
                1 => BoundaryMode::Fixed,
                2 => BoundaryMode::Slide,
                3 => BoundaryMode::Snap,
                _ => return None,
            })
            .with_lambda(o.lambda)
            .with_stop(match o.stop_rule {
                0 => StopRule::Energy,
                1 => StopRule::Quality,
                _ => return None,
            })
            .with_tau(o.tau)
            .with_tau_absolute(o.tau_absolute != 0)
            .with_max_iterations(o.max_iterations as usize)
            .with_feature_angle_deg(o.feature_angle_deg)
            .with_guard(o.guard != 0)
            .with_guard_floor(o.guard_floor)
            .with_untangle(o.untangle != 0)
            .with_keep_best(o.keep_best != 0)
            // Negative means unlimited; NaN is kept (and refused by validation).
            .with_max_boundary_deviation(if o.max_boundary_deviation < 0.0 {
                None
            } else {
                Some(o.max_boundary_deviation)
            })
            .with_max_min(o.max_min != 0),
    )
}

fn run(input: Input) {
    // Status strings for any integer.
    assert!(!ffi::quadopt_status_string(input.status).is_null());

    // The mesh's own fixed flags are not used: the C mask comes from `input.fixed`.
    let (points, quads, _) = input.mesh.arrays();
    let dim = (input.dim % 5) as usize;
    let n = count(points.len(), input.vertex_delta);
    let m = count(quads.len(), input.quad_delta);

    // Coordinates: x, y from the mesh (zero beyond it), z a marker that must survive (the same
    // at every vertex: a planar mesh; a z that varies would be optimized on its surface).
    let mut coords = vec![0.0f64; n * dim + 1];
    for i in 0..n {
        let p = points.get(i).copied().unwrap_or(DVec2::ZERO);
        for k in 0..dim {
            coords[i * dim + k] = match k {
                0 => p.x,
                1 => p.y,
                _ => -7.25,
            };
        }
    }
    let mut flat_quads = vec![0u32; 4 * m];
    for (i, q) in quads.iter().take(m).enumerate() {
        flat_quads[4 * i..4 * i + 4].copy_from_slice(q);
    }
    let fixed_bytes: Option<Vec<u8>> =
        input.fixed.as_ref().map(|f| (0..n).map(|i| f.get(i).copied().unwrap_or(0)).collect());

    // A misaligned copy: the same doubles stored one byte further (its length still covers
    // the announced count, so the library may only refuse it).
    let mut bytes = vec![0u8; (n * dim + 1) * 8 + 1];
    let misaligned_ptr = bytes[1..].as_mut_ptr().cast::<f64>();

    let (coords_ptr, n_pass) = match (input.null_coords, input.misaligned) {
        (Some(h), _) => (std::ptr::null_mut(), if h == 0 { n } else { HUGE[h as usize % 4] }),
        (None, true) if n * dim > 0 => (misaligned_ptr, n),
        _ => (coords.as_mut_ptr(), n),
    };
    let (quads_ptr, m_pass) = match input.null_quads {
        Some(h) => (std::ptr::null(), if h == 0 { m } else { HUGE[h as usize % 4] }),
        None => (flat_quads.as_ptr(), m),
    };
    let fixed_ptr = fixed_bytes.as_ref().map_or(std::ptr::null(), |f| f.as_ptr());

    // Options.
    let mut cancel_state = CancelState {
        calls: 0,
        limit: u32::MAX,
        caller: std::thread::current().id(),
        on_another_thread: false,
    };
    let mut options_buffer = OptionsBuffer { options: default_options(), tail: [0; 8] };
    let options_ptr: *const QuadoptOptions = match &input.options {
        None => std::ptr::null(),
        Some(c) => {
            let o = &mut options_buffer.options;
            let ours = size_of::<QuadoptOptions>() as u32;
            o.struct_size = match c.size % 4 {
                0 => ours,
                1 => ours + 32,
                2 => ours - 8,
                _ => 0,
            };
            o.method = c.method as u32 % 5;
            o.boundary = c.boundary as u32 % 5;
            o.max_iterations = c.max_iterations as u32 % (MAX_ITERATIONS as u32 + 1);
            o.lambda = c.lambda.unwrap_or(o.lambda);
            o.tau = c.tau.unwrap_or(o.tau);
            o.feature_angle_deg = c.feature_angle_deg.unwrap_or(o.feature_angle_deg);
            o.guard_floor = c.guard_floor.unwrap_or(o.guard_floor);
            o.max_boundary_deviation = c.max_boundary_deviation.unwrap_or(o.max_boundary_deviation);
            o.tau_absolute = c.flags & 1;
            o.guard = u8::from(c.flags & 2 == 0);
            o.untangle = u8::from(c.flags & 4 == 0);
            o.keep_best = u8::from(c.flags & 8 == 0);
            if let Some(limit) = c.cancel_after {
                cancel_state.limit = limit as u32;
                o.progress = Some(progress);
                o.progress_user_data = (&raw mut cancel_state).cast();
            }
            &raw const options_buffer.options
        }
    };
    if input.options.is_none() {
        // NULL options mean the defaults, whose 1000 iterations are too slow here.
        if n > 16 {
            return;
        }
    }

    // Report.
    let ours = size_of::<QuadoptReport>() as u32;
    let mut report_buffer = ReportBuffer { report: ffi::quadopt_report_init(), tail: [0x5a5a; 8] };
    if let Some(r) = input.report {
        report_buffer.report.struct_size = match r % 3 {
            0 => ours,
            1 => ours + 48,
            _ => ours / 2,
        };
    }
    let report_before = report_buffer;
    let report_ptr: *mut QuadoptReport =
        if input.report.is_some() { &raw mut report_buffer.report } else { std::ptr::null_mut() };

    let coords_before = coords.clone();
    let bytes_before = bytes.clone();
    let dim_pass = input.dim as u32 % 5;

    let status = if input.handle {
        let mut handle: *mut QuadoptOptimizer = std::ptr::null_mut();
        // SAFETY: every pointer is NULL or into a live buffer holding what the counts announce.
        let s = unsafe {
            ffi::quadopt_optimizer_create(
                coords_ptr,
                dim_pass,
                n_pass,
                quads_ptr,
                m_pass,
                fixed_ptr,
                &mut handle,
            )
        };
        assert_not_panic(s);
        if s != QuadoptStatus::Ok {
            assert!(handle.is_null(), "create wrote its out-parameter on error");
            assert!(!last_error().is_empty());
            return;
        }
        assert!(!handle.is_null());
        let n2 = count(n, input.handle_delta).min(n);
        // SAFETY: the handle is live; coords holds n >= n2 vertices of dim doubles.
        let s = unsafe {
            ffi::quadopt_optimizer_optimize(handle, coords_ptr, dim_pass, n2, options_ptr, report_ptr)
        };
        // SAFETY: the handle is live and freed once.
        unsafe { ffi::quadopt_optimizer_free(handle) };
        s
    } else {
        // SAFETY: as above.
        unsafe {
            ffi::quadopt_optimize(
                coords_ptr,
                dim_pass,
                n_pass,
                quads_ptr,
                m_pass,
                fixed_ptr,
                options_ptr,
                report_ptr,
            )
        }
    };
    assert_not_panic(status);
    assert!(!cancel_state.on_another_thread, "the progress callback ran on another thread");
    if status != QuadoptStatus::Ok {
        assert!(!last_error().is_empty(), "no message for {status:?}");
        assert!(
            coords.iter().zip(&coords_before).all(|(a, b)| a.to_bits() == b.to_bits()),
            "coords written on error"
        );
        assert!(bytes == bytes_before, "coords written on error");
        assert!(report_buffer == report_before, "report written on error");
        return;
    }

    // Success: the Rust API must give the same result.
    assert!(dim == 2 || dim == 3);
    assert!(!input.misaligned || n * dim == 0);
    let given: Vec<DVec2> =
        (0..n).map(|i| DVec2::new(coords_before[i * dim], coords_before[i * dim + 1])).collect();
    let quads_given: Vec<[u32; 4]> = flat_quads.chunks_exact(4).map(|q| [q[0], q[1], q[2], q[3]]).collect();
    let fixed = fixed_bytes.map(|f| f.iter().map(|&b| b != 0).collect());
    let mut mesh = Mesh::new(given, quads_given.clone(), fixed).expect("the library accepted this mesh");
    let options = rust_options(&options_buffer.options).expect("the library accepted these options");
    let options = if input.options.is_some() { options } else { Options::default() };
    let r = quadopt::optimize(&mut mesh, &options).expect("the library accepted these options");
    for i in 0..n {
        let p = mesh.points()[i];
        assert_eq!(coords[i * dim].to_bits(), p.x.to_bits(), "vertex {i} x differs from the Rust API");
        assert_eq!(coords[i * dim + 1].to_bits(), p.y.to_bits(), "vertex {i} y differs from the Rust API");
        if dim == 3 {
            assert_eq!(coords[i * dim + 2].to_bits(), coords_before[i * dim + 2].to_bits(), "z written");
        }
    }
    if !report_ptr.is_null() {
        let rep = &report_buffer.report;
        assert_eq!(rep.struct_size, ours.min(report_before.report.struct_size));
        let expected = QuadoptQuality {
            min: r.output.min,
            avg: r.output.avg,
            max: r.output.max,
            inverted: r.output.inverted,
        };
        assert_eq!(quality_bits(&rep.output), quality_bits(&expected));
        assert_eq!(rep.iterations, r.iterations);
        assert!(report_buffer.tail == report_before.tail, "wrote past the report");
    }

    // Quality of the result, with a per-quad buffer of arbitrary (truthful) length.
    let mut stats = QuadoptQuality::default();
    let per_len = input.per_quad_len.map_or(0, |l| l as usize);
    let mut per_quad = vec![f64::NAN; per_len];
    let per_ptr = if input.per_quad_len.is_some() { per_quad.as_mut_ptr() } else { std::ptr::null_mut() };
    // SAFETY: coords holds n vertices of dim doubles, quads m quads; per_quad per_len doubles.
    let s = unsafe {
        ffi::quadopt_quality(
            coords.as_ptr(),
            dim as u32,
            n,
            flat_quads.as_ptr(),
            m,
            &mut stats,
            per_ptr,
            per_len,
        )
    };
    assert_not_panic(s);
    // `quadopt_quality` infers the orientation from the output geometry, which on a tangled
    // mesh can differ from the input's (tests/properties.rs,
    // remeasured_output_quality_matches_the_report), so compare with the same measurement.
    let again = Mesh::new(mesh.points().to_vec(), quads_given, None).expect("the output is a valid mesh");
    let values = again.quality_values();
    if !per_ptr.is_null() && per_len < m {
        assert_eq!(s, QuadoptStatus::InvalidArgument);
        assert!(per_quad.iter().all(|v| v.is_nan()), "per_quad written on error");
    } else {
        assert_eq!(s, QuadoptStatus::Ok);
        let q = again.quality();
        let expected = QuadoptQuality { min: q.min, avg: q.avg, max: q.max, inverted: q.inverted };
        assert_eq!(quality_bits(&stats), quality_bits(&expected));
        if !per_ptr.is_null() {
            for (a, b) in per_quad.iter().zip(&values) {
                assert_eq!(a.to_bits(), b.to_bits());
            }
        }
    }
}

fuzz_target!(|input: Input| run(input));

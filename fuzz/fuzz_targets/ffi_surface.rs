//! `quadopt_optimize_surface` (src/ffi/surface.rs) with arbitrary meshes bent into 3D, fixed
//! masks, marked feature edges (some out of range or not edges), options and reports. Every
//! pointer passed points into a buffer this target owns, as long as its count says. Checked:
//! no call panics or is refused for memory, nothing is written on any error (cancellation
//! included), fixed vertices keep their bits, the report says it is a surface run, and a
//! successful run gives exactly what the Rust API (`SurfaceMesh`, `SurfaceOptimizer`) gives.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use quadopt::ffi::{self, QuadoptOptions, QuadoptProgress, QuadoptReport, QuadoptStatus};
use quadopt::surface::{SurfaceMesh, SurfaceOptimizer};
use quadopt::{DVec3, Effort};
use quadopt_fuzz::{MAX_ITERATIONS, RawMesh};
use std::ffi::c_void;
use std::mem::size_of;

#[derive(Debug, Arbitrary)]
struct Input {
    mesh: RawMesh,
    /// z = bend * (x^2 + y^2) / 64 + twist * x * y / 64: a paraboloid, a saddle, or flat.
    bend: i8,
    twist: i8,
    /// Marked feature edges, vertex indices modulo the vertex count plus 2 (some out of
    /// range), some of them not edges of the mesh.
    marked: Vec<(u8, u8)>,
    /// Fixed mask bytes (NULL when absent); missing entries are 0.
    fixed: Option<Vec<u8>>,
    effort: u8,
    max_iterations: u8,
    feature_angle_deg: Option<f64>,
    /// Cancel in the progress callback after this many calls.
    cancel_after: Option<u8>,
    /// Pass a report (sizeof, or NULL).
    report: bool,
}

unsafe extern "C" fn progress(_: *const QuadoptProgress, user_data: *mut c_void) -> bool {
    // SAFETY: user_data points to the call counter and limit of the running test case.
    let (calls, limit) = unsafe { &mut *user_data.cast::<(u32, u32)>() };
    *calls += 1;
    *calls <= *limit
}

fn run(input: Input) {
    let (points, faces, _) = input.mesh.arrays();
    let n = points.len();
    let (bend, twist) = (f64::from(input.bend) / 64.0, f64::from(input.twist) / 64.0);
    let lifted: Vec<DVec3> =
        points.iter().map(|p| DVec3::new(p.x, p.y, bend * (p.x * p.x + p.y * p.y) + twist * p.x * p.y)).collect();
    let mut coords: Vec<f64> = lifted.iter().flat_map(|p| p.to_array()).collect();
    let before = coords.clone();
    let flat_faces: Vec<u32> = faces.iter().flatten().copied().collect();
    let fixed_bytes: Option<Vec<u8>> =
        input.fixed.as_ref().map(|f| (0..n).map(|i| f.get(i).copied().unwrap_or(0)).collect());
    let m = n as u32 + 2;
    let marked: Vec<[u32; 2]> =
        input.marked.iter().take(16).map(|&(a, b)| [u32::from(a) % m, u32::from(b) % m]).collect();
    let flat_marked: Vec<u32> = marked.iter().flatten().copied().collect();

    let mut options = std::mem::MaybeUninit::<QuadoptOptions>::zeroed();
    // SAFETY: `options` holds size_of::<QuadoptOptions>() writable, aligned bytes.
    let s = unsafe { ffi::quadopt_options_init(options.as_mut_ptr(), size_of::<QuadoptOptions>()) };
    assert_eq!(s, QuadoptStatus::Ok);
    // SAFETY: zeroed, then filled by quadopt_options_init.
    let mut options = unsafe { options.assume_init() };
    // QuadoptEffort: 0 balanced, 1 fast, 2 best.
    options.effort = u32::from(input.effort % 3);
    let effort = [Effort::Balanced, Effort::Fast, Effort::Best][options.effort as usize];
    options.max_iterations = input.max_iterations as u32 % MAX_ITERATIONS as u32 + 1;
    options.feature_angle_deg = input.feature_angle_deg.unwrap_or(options.feature_angle_deg);
    let mut counter = (0u32, u32::MAX);
    if let Some(limit) = input.cancel_after {
        counter.1 = u32::from(limit);
        options.progress = Some(progress);
        options.progress_user_data = (&raw mut counter).cast();
    }
    let mut report: QuadoptReport = ffi::quadopt_report_init();
    let report_ptr: *mut QuadoptReport = if input.report { &raw mut report } else { std::ptr::null_mut() };

    // SAFETY: every array holds what its count announces; options and report are whole.
    let status = unsafe {
        ffi::quadopt_optimize_surface(
            if n == 0 { std::ptr::null_mut() } else { coords.as_mut_ptr() },
            n,
            if faces.is_empty() { std::ptr::null() } else { flat_faces.as_ptr() },
            faces.len(),
            fixed_bytes.as_ref().map_or(std::ptr::null(), |f| f.as_ptr()),
            if marked.is_empty() { std::ptr::null() } else { flat_marked.as_ptr() },
            marked.len(),
            &options,
            report_ptr,
        )
    };
    assert_ne!(status, QuadoptStatus::Panic, "quadopt_optimize_surface panicked");
    assert_ne!(status, QuadoptStatus::OutOfMemory, "a small input was refused for memory");
    let same_bits = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
    if status != QuadoptStatus::Ok {
        assert!(same_bits(&coords, &before), "coordinates written on error {status:?}");
        return;
    }
    if let Some(f) = &fixed_bytes {
        for v in (0..n).filter(|&v| f[v] != 0) {
            assert!(same_bits(&coords[3 * v..3 * v + 3], &before[3 * v..3 * v + 3]), "fixed vertex {v} moved");
        }
    }
    if input.report {
        assert_eq!(report.surface, 1);
    }
    // The Rust API, with the same mesh, marks and options, gives the same coordinates.
    let fixed = fixed_bytes.map(|f| f.iter().map(|&b| b != 0).collect());
    let mut mesh = SurfaceMesh::new(lifted, faces, fixed).expect("the C API accepted the mesh");
    let optimizer = SurfaceOptimizer::new(&mesh, options.feature_angle_deg, &marked).expect("and its features");
    let rust_options = quadopt::Options::DEFAULT
        .with_effort(effort)
        .with_max_iterations(options.max_iterations as usize)
        .with_feature_angle_deg(options.feature_angle_deg);
    optimizer.run(&mut mesh, &rust_options, None).expect("and the run");
    let rust: Vec<f64> = mesh.points().iter().flat_map(|p| p.to_array()).collect();
    assert!(same_bits(&coords, &rust), "the C API and the Rust API differ");
}

fuzz_target!(|input: Input| run(input));

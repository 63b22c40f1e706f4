//! Helpers shared by the unit tests of the C ABI: a small jittered patch, sentinel reports that
//! detect any write, the last-error message, and running a test again in a child process.

use super::options::*;
use super::report::*;
use super::run::quadopt_optimize;
use super::status::{QuadoptStatus, quadopt_last_error};
use std::ffi::CStr;
use std::mem::size_of;
use std::ptr::{null, null_mut};

/// A 2x2 patch of unit squares (vertices 0..9, row by row) whose centre vertex 4 has been
/// dragged to (1.6, 1.5); with a fixed boundary the optimum puts it back at (1, 1).
pub(super) fn patch(dim: usize) -> (Vec<f64>, Vec<u32>) {
    let mut coords = Vec::new();
    for j in 0..3 {
        for i in 0..3 {
            coords.push(i as f64);
            coords.push(j as f64);
            if dim == 3 {
                // A z that is not even a number, the same NaN at every vertex: a planar mesh
                // (its z never changes), whose z must be neither used nor written.
                coords.push(f64::from_bits(0x7ff8_dead_beef_0000));
            }
        }
    }
    coords[4 * dim] = 1.6;
    coords[4 * dim + 1] = 1.5;
    (coords, vec![0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7])
}

pub(super) fn fixed_boundary_options() -> QuadoptOptions {
    QuadoptOptions { boundary: QuadoptBoundary::Fixed as u32, tau: 1e-12, ..default_options() }
}

pub(super) fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The bytes of a plain-data value.
pub(super) fn bytes_of<T: Copy>(v: &T) -> Vec<u8> {
    // SAFETY: reading size_of::<T>() bytes of a live value; the test types have no padding
    // (checked by the layout test), so every byte is initialized.
    unsafe { std::slice::from_raw_parts((v as *const T).cast::<u8>(), size_of::<T>()).to_vec() }
}

/// A report full of a recognisable pattern (struct_size set), to detect any write.
pub(super) fn sentinel_report() -> QuadoptReport {
    let mut r = QuadoptReport { struct_size: size_of::<QuadoptReport>() as u32, ..Default::default() };
    r.converged = 0xA5A5_A5A5;
    r.iterations = 0xDEAD;
    r.input.min = -7.0;
    r.hausdorff = 42.0;
    r
}

pub(super) fn last_error() -> String {
    // SAFETY: quadopt_last_error never returns NULL and the string stays valid until the
    // next quadopt call on this thread.
    unsafe { CStr::from_ptr(quadopt_last_error()) }.to_string_lossy().into_owned()
}

/// Runs quadopt_optimize on a copy of `coords`, asserting that a failure writes nothing.
pub(super) fn optimize_status(
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

/// The sample mesh data/plate_2holes.vtk as flat arrays: the max-min stage raises its
/// minimum (0.753 after the sweeps).
pub(super) fn plate_2holes() -> (Vec<f64>, Vec<u32>) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/data/plate_2holes.vtk");
    let data = crate::io::read_mesh(path).unwrap();
    let coords = data.points.iter().flat_map(|p| [p[0], p[1]]).collect();
    (coords, data.quads.iter().flatten().copied().collect())
}

pub(super) fn run_plate(options: &QuadoptOptions, report_size: usize) -> (Vec<f64>, QuadoptReport) {
    let (mut coords, quads) = plate_2holes();
    let mut report = QuadoptReport { struct_size: report_size as u32, ..sentinel_report() };
    report.max_min = 0xA5A5_A5A5;
    report.sweeps.min = -9.0;
    report.effort = 0xA5A5_A5A5;
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

/// Runs this binary's test `name` again in a fresh process (with `QUADOPT_TEST_CHILD` set,
/// so the test runs its child half), with the given environment, and checks that exactly
/// that test ran and passed. Returns the child's stderr.
pub(super) fn run_in_child(name: &str, env: &[(&str, &str)]) -> String {
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

pub(super) fn is_child(name: &str) -> bool {
    std::env::var("QUADOPT_TEST_CHILD").as_deref() == Ok(name)
}

/// quadopt_optimize on the jittered patch with a fixed boundary; the status and the result.
pub(super) fn optimize_patch(options: &QuadoptOptions) -> (QuadoptStatus, Vec<u64>) {
    let (mut c, quads) = patch(2);
    // SAFETY: live buffers of the stated lengths.
    let s = unsafe { quadopt_optimize(c.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), options, null_mut()) };
    (s, bits(&c))
}

//! One planarity rule for every interface (`src/io/planar.rs`, `quadopt_is_planar`): a mesh is
//! planar when the vertices used by its faces lie on one plane to within rounding; anything
//! else is a surface, optimized on itself and never flattened. The CLI and the C ABI agree on
//! a sheet whose z wobbles by 1e-4 of its size (a surface: its vertices stay on it) and on an
//! exactly planar grid in a tilted plane (planar: optimized in its plane, the same bits from
//! both). A reusable handle refuses a closed curved mesh as not planar, not as closed.

mod common;

use common::surfaces::cube_sphere;
use quadopt::ffi::*;
use serde_json::Value;
use std::ffi::CStr;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::ptr::{null, null_mut};

const N: u32 = 12;

/// An `N` x `N` grid over the unit square, its interior vertices jittered, placed by `f(s, t)`:
/// coordinates (3 per vertex) and faces.
fn sheet(f: impl Fn(f64, f64) -> [f64; 3]) -> (Vec<f64>, Vec<u32>) {
    let n = f64::from(N);
    let mut coords = Vec::new();
    for j in 0..=N {
        for i in 0..=N {
            let (mut s, mut t) = (f64::from(i) / n, f64::from(j) / n);
            if 0 < i && i < N && 0 < j && j < N {
                let (fi, fj) = (f64::from(i), f64::from(j));
                s += 0.3 / n * (7.0 * fi + 3.0 * fj).sin();
                t += 0.3 / n * (5.0 * fi - 2.0 * fj).cos();
            }
            coords.extend(f(s, t));
        }
    }
    let id = |i: u32, j: u32| j * (N + 1) + i;
    let faces = (0..N * N).flat_map(|c| {
        [id(c % N, c / N), id(c % N + 1, c / N), id(c % N + 1, c / N + 1), id(c % N, c / N + 1)]
    });
    (coords, faces.collect())
}

/// z wobbles by 1e-4 (of a unit sheet): a surface, by 1e-4 of its size.
fn wobble(s: f64, t: f64) -> [f64; 3] {
    use std::f64::consts::TAU;
    [s, t, 1e-4 * (TAU * s).sin() * (TAU * t).cos()]
}

/// The tilted plane z = 0.3 x + 0.7 y, coordinates rounded to doubles: planar.
fn tilted(s: f64, t: f64) -> [f64; 3] {
    [s, t, 0.3 * s + 0.7 * t]
}

fn last_error() -> String {
    // SAFETY: never NULL, valid until the next call on this thread.
    unsafe { CStr::from_ptr(quadopt_last_error()) }.to_string_lossy().into_owned()
}

fn planarity(coords: &[f64], faces: &[u32]) -> QuadoptPlanarity {
    let mut p = QuadoptPlanarity::default();
    // SAFETY: live buffers of the stated lengths.
    let s = unsafe {
        quadopt_is_planar(coords.as_ptr(), coords.len() / 3, faces.as_ptr(), faces.len() / 4, &mut p)
    };
    assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
    p
}

/// quadopt_optimize with dim 3 and the defaults: the coordinates and the report.
fn optimize_c(coords: &[f64], faces: &[u32]) -> (Vec<f64>, QuadoptReport) {
    let mut c = coords.to_vec();
    let mut report = quadopt_report_init();
    // SAFETY: live buffers of the stated lengths.
    let s = unsafe {
        quadopt_optimize(
            c.as_mut_ptr(),
            3,
            c.len() / 3,
            faces.as_ptr(),
            faces.len() / 4,
            null(),
            null(),
            &mut report,
        )
    };
    assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
    (c, report)
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("quadopt-planarity-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes an OBJ file, every coordinate in shortest round-trip form.
fn write_obj(path: &Path, coords: &[f64], faces: &[u32]) {
    let mut text = String::new();
    for p in coords.chunks(3) {
        text += &format!("v {:?} {:?} {:?}\n", p[0], p[1], p[2]);
    }
    for f in faces.chunks(4) {
        text += &format!("f {} {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1, f[3] + 1);
    }
    std::fs::write(path, text).unwrap();
}

/// The vertex coordinates of an OBJ file quadopt wrote.
fn read_obj(path: &Path) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter_map(|l| l.strip_prefix("v "))
        .flat_map(|l| l.split_whitespace().map(|x| x.parse::<f64>().unwrap()).collect::<Vec<_>>())
        .collect()
}

/// Runs the CLI; its stdout as JSON.
fn cli_json(args: &[&str]) -> Value {
    let out = Command::new(env!("CARGO_BIN_EXE_quadopt")).args(args).arg("--json").output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "quadopt {args:?}: {stderr}");
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The largest distance of `coords` from the plane z = 0.3 x + 0.7 y.
fn off_tilted_plane(coords: &[f64]) -> f64 {
    let norm = (0.3f64 * 0.3 + 0.7 * 0.7 + 1.0).sqrt();
    coords.chunks(3).map(|p| (0.3 * p[0] + 0.7 * p[1] - p[2]).abs() / norm).fold(0.0, f64::max)
}

#[test]
fn a_wobbling_sheet_is_a_surface_in_the_cli() {
    let (coords, faces) = sheet(wobble);
    let dir = temp_dir("cli-wobble");
    let (input, output) = (dir.join("in.obj"), dir.join("out.obj"));
    write_obj(&input, &coords, &faces);
    let (i, o) = (input.to_str().unwrap(), output.to_str().unwrap());
    let report = cli_json(&["optimize", i, "-o", o]);
    assert!(report["output"]["min"].as_f64().unwrap() > report["input"]["min"].as_f64().unwrap());
    let measured = cli_json(&["quality", o, "--reference", i]);
    assert_eq!(measured["surface"], Value::Bool(true), "{measured}");
    let fidelity = &measured["surface_fidelity"];
    let relative = fidelity["max_distance_relative"].as_f64().unwrap();
    assert!(relative <= 1e-9, "the output left the input surface by {relative} mean edges: {fidelity}");
    // Not flattened: the output keeps the wobble.
    let z = read_obj(&output).chunks(3).map(|p| p[2].abs()).fold(0.0, f64::max);
    assert!(z > 0.5e-4, "largest |z| {z}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_wobbling_sheet_is_a_surface_in_the_c_abi() {
    let (coords, faces) = sheet(wobble);
    let p = planarity(&coords, &faces);
    assert_eq!(p.planar, 0, "{p:?}");
    assert!(p.distance > 0.5e-4 && p.tolerance < 1e-11, "{p:?}");
    let (out, report) = optimize_c(&coords, &faces);
    assert_eq!(report.surface, 1);
    assert!(report.output.min > report.input.min);
    assert!(report.max_distance_relative <= 1e-9, "{}", report.max_distance_relative);
    assert!(out.chunks(3).map(|p| p[2].abs()).fold(0.0, f64::max) > 0.5e-4, "flattened");
    // quadopt_quality measures it on its surface too: the run's input.
    let mut q = QuadoptQuality::default();
    // SAFETY: live buffers.
    let s = unsafe {
        quadopt_quality(coords.as_ptr(), 3, coords.len() / 3, faces.as_ptr(), 144, &mut q, null_mut(), 0)
    };
    assert_eq!((s, q), (QuadoptStatus::Ok, report.input));
    // A handle refuses it, pointing at the surface function.
    let mut handle = null_mut();
    // SAFETY: live buffers; the call fails.
    let s = unsafe {
        quadopt_optimizer_create(
            coords.as_ptr(),
            3,
            coords.len() / 3,
            faces.as_ptr(),
            144,
            null(),
            &mut handle,
        )
    };
    assert_eq!((s, handle.is_null()), (QuadoptStatus::NotPlanar, true));
    assert!(last_error().contains("quadopt_optimize_surface()"), "{}", last_error());
}

#[test]
fn a_tilted_planar_grid_is_planar_in_every_interface() {
    let (coords, faces) = sheet(tilted);
    assert_eq!(planarity(&coords, &faces), QuadoptPlanarity { planar: 1, ..Default::default() });
    // The Rust API's files: the plane's frame.
    let data = quadopt::io::MeshData::new(
        coords.chunks(3).map(|p| [p[0], p[1], p[2]]).collect(),
        faces.chunks(4).map(|f| [f[0], f[1], f[2], f[3]]).collect(),
    );
    let planar = quadopt::io::PlanarMesh::new(&data).unwrap();
    assert!(matches!(planar.frame, quadopt::io::PlanarFrame::Tilted { .. }));

    // The C ABI: optimized in its plane, moved vertices written back onto it.
    let (out, report) = optimize_c(&coords, &faces);
    assert_eq!(report.surface, 0);
    assert!(report.output.min > report.input.min + 0.1, "{} -> {}", report.input.min, report.output.min);
    assert!(off_tilted_plane(&out) < 1e-14, "{}", off_tilted_plane(&out));
    // Vertices that did not move (the corners) are not written.
    for v in [0, N as usize, (N * (N + 1)) as usize, ((N + 1) * (N + 1) - 1) as usize] {
        assert_eq!(bits(&out[3 * v..3 * v + 3]), bits(&coords[3 * v..3 * v + 3]), "vertex {v}");
    }
    // A handle takes it, with the one-shot result.
    let mut handle = null_mut();
    // SAFETY: live buffers; the handle is freed once.
    unsafe {
        let n = coords.len() / 3;
        let s = quadopt_optimizer_create(coords.as_ptr(), 3, n, faces.as_ptr(), 144, null(), &mut handle);
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        let mut c = coords.clone();
        let s = quadopt_optimizer_optimize(handle, c.as_mut_ptr(), 3, n, null(), null_mut());
        assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
        assert_eq!(bits(&c), bits(&out));
        quadopt_optimizer_free(handle);
    }
    // quadopt_quality measures it in its plane: the report's input.
    let mut q = QuadoptQuality::default();
    // SAFETY: live buffers.
    let s = unsafe {
        quadopt_quality(coords.as_ptr(), 3, coords.len() / 3, faces.as_ptr(), 144, &mut q, null_mut(), 0)
    };
    assert_eq!((s, q), (QuadoptStatus::Ok, report.input));

    // The CLI: planar too (no surface report), the same bits as the C ABI.
    let dir = temp_dir("cli-tilted");
    let (input, output) = (dir.join("in.obj"), dir.join("out.obj"));
    write_obj(&input, &coords, &faces);
    let json = cli_json(&["optimize", input.to_str().unwrap(), "-o", output.to_str().unwrap()]);
    assert!(json.get("surface").is_none_or(|s| s == &Value::Bool(false)), "{json}");
    assert!(json.get("boundary_fidelity").is_some(), "{json}");
    assert_eq!(bits(&read_obj(&output)), bits(&out), "the CLI and the C ABI differ");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The attack's case: a closed curved mesh given to a reusable handle is not planar (the
/// documented status, with a message pointing at quadopt_optimize_surface()), not closed (a closed mesh in 2D is
/// still `QUADOPT_STATUS_CLOSED_MESH`: `src/ffi/boundary.rs`).
#[test]
fn a_handle_refuses_a_closed_curved_mesh_as_not_planar() {
    let (points, faces) = cube_sphere(3);
    let coords: Vec<f64> = points.iter().flat_map(|p| p.to_array()).collect();
    let faces: Vec<u32> = faces.iter().flatten().copied().collect();
    let (n, f) = (coords.len() / 3, faces.len() / 4);
    let mut handle = 0x10 as *mut QuadoptOptimizer;
    // SAFETY: live buffers; the call fails and leaves `handle` alone.
    let s =
        unsafe { quadopt_optimizer_create(coords.as_ptr(), 3, n, faces.as_ptr(), f, null(), &mut handle) };
    let message = last_error();
    assert_eq!((s, handle as usize), (QuadoptStatus::NotPlanar, 0x10), "{message}");
    assert!(message.starts_with("quadopt_optimizer_create: the mesh is not planar"), "{message}");
    assert!(message.contains("quadopt_optimize_surface()"), "{message}");
    // The one-shot function optimizes it on its surface.
    let (_, report) = optimize_c(&coords, &faces);
    assert_eq!(report.surface, 1);
}

//! The CLI with the `openmesh` feature: `.ply` and `.om` through OpenMesh, `--reader
//! openmesh` for `.obj` / `.off`, and `--version` saying so. (Without the feature this file
//! compiles to nothing; tests/cli.rs covers the default build.)
#![cfg(feature = "openmesh")]

use quadopt::io::{self, MeshData};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn quadopt(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_quadopt")).args(args).output().unwrap()
}

fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("quadopt-omcli-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn sample(name: &str) -> String {
    format!("{}/data/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn version_says_openmesh_is_in() {
    let o = quadopt(&["--version"]);
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stdout).contains("OpenMesh support: PLY, OM"));
}

#[test]
fn om_output_is_the_vtk_output_bit_for_bit_with_the_fixed_flags() {
    let dir = scratch("om");
    let (vtk, om) = (dir.join("out.vtk"), dir.join("out.om"));
    for out in [&vtk, &om] {
        let o = quadopt(&["optimize", &sample("plate_3holes.vtk"), "-o", s(out)]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let want = io::read_mesh(&vtk).unwrap();
    let (got, info) = openmesh_sys::read(&om).unwrap();
    let bits = |p: &[[f64; 3]]| p.iter().map(|q| q.map(f64::to_bits)).collect::<Vec<_>>();
    assert_eq!(bits(&got.points), bits(&want.points));
    assert!(got.faces().zip(&want.quads).all(|(a, b)| a == b));
    assert!(want.fixed.as_ref().unwrap().iter().any(|&f| f));
    assert_eq!(got.fixed, want.fixed);
    assert!(info.has_vertex_status);
    // And read back by the CLI itself.
    let q = quadopt(&["quality", s(&om), "--json"]);
    assert!(q.status.success(), "{}", stderr(&q));
    let v: serde_json::Value = serde_json::from_slice(&q.stdout).unwrap();
    assert_eq!(v["quads"], want.quads.len());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn ply_output_is_float32_and_says_so() {
    let dir = scratch("ply");
    let ply = dir.join("out.ply");
    let o = quadopt(&["optimize", &sample("plate_1hole.vtk"), "-o", s(&ply)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("float32"), "{}", stderr(&o));
    let (got, _) = openmesh_sys::read(&ply).unwrap();
    assert!(got.points.iter().flatten().all(|&c| f64::from(c as f32) == c));
    let q = quadopt(&["quality", s(&ply), "--json"]);
    assert!(q.status.success(), "{}", stderr(&q));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn reader_openmesh_reads_obj_as_openmesh_does() {
    let dir = scratch("reader");
    // A value f32 cannot hold: quadopt's reader keeps it, OpenMesh's rounds it to f32.
    let mut data = MeshData::new(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.1, 1.0, 0.0]],
        vec![[0, 1, 2, 3]],
    );
    let obj = dir.join("q.obj");
    io::write_mesh(&obj, &data).unwrap();
    let (plain, forced) = (dir.join("plain.vtk"), dir.join("forced.vtk"));
    let args = ["--boundary", "fixed", "--max-iter", "1"]; // a lone quad: nothing can move
    let o = quadopt(&[&["optimize", s(&obj), "-o", s(&plain)][..], &args].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let o = quadopt(&[&["--reader", "openmesh", "optimize", s(&obj), "-o", s(&forced)][..], &args].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(io::read_mesh(&plain).unwrap().points[3][0], 0.1);
    data.points[3][0] = f64::from(0.1f32);
    assert_eq!(io::read_mesh(&forced).unwrap().points, data.points);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_ply_files_are_one_line_errors() {
    let dir = scratch("bad");
    let ply = dir.join("dup.ply");
    std::fs::write(
        &ply,
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
         element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n\
         4 0 1 2 3\n4 0 1 2 3\n",
    )
    .unwrap();
    let o = quadopt(&["quality", s(&ply)]);
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(e.contains("dup.ply") && e.contains("face 1") && e.lines().count() == 1, "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

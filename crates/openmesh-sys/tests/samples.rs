//! Every sample mesh, read through openmesh-sys and through quadopt's own readers, gives the
//! same arrays:
//! - `data/*.vtk` (OpenMesh has no VTK reader): quadopt writes each as OBJ and OFF with its
//!   own writers (shortest round-trip decimals); OpenMesh reads those files with the same
//!   vertices, faces and face order as quadopt's readers, and coordinates that are exactly the
//!   correctly rounded `f32` of the file's decimal text (OpenMesh 9 parses OBJ and OFF as
//!   `float`). Written as OM through openmesh-sys, every coordinate and fixed flag comes back
//!   bit-identical.
//! - `cpp_tests/data/*.obj|off` (float-exact coordinates): identical arrays, bit for bit, the
//!   mixed mesh's triangle included (a 3-vertex face in OpenMesh, a face with `NO_VERTEX`
//!   fourth in quadopt).

use openmesh_sys::{Format, MeshArrays, WriteOptions, read_bytes, write_bytes};
use quadopt::io::{self, MeshData};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn files(dir: &str, exts: &[&str]) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| exts.iter().any(|x| e == *x)))
        .collect();
    v.sort();
    assert!(!v.is_empty(), "no {exts:?} files in {dir}");
    v
}

/// quadopt's faces as OpenMesh's: a quad as four vertices, a triangle as three.
fn arrays(d: &MeshData) -> MeshArrays {
    let mut a = MeshArrays::new(d.points.clone(), d.quads.iter().map(quadopt::face::vertices));
    a.fixed = d.fixed.clone();
    a
}

fn bits(points: &[[f64; 3]]) -> Vec<[u64; 3]> {
    points.iter().map(|p| p.map(f64::to_bits)).collect()
}

/// The `f32` values of the numbers in a vertex line (`v x y z` or `x y z`), as OpenMesh parses them.
fn f32_coordinates(text: &str, format: Format, n: usize) -> Vec<[f64; 3]> {
    let lines: Vec<&str> = match format {
        Format::Obj => text.lines().filter(|l| l.starts_with("v ")).map(|l| &l[2..]).collect(),
        // OFF: the header line, the counts line, then the vertices.
        _ => text.lines().filter(|l| !l.trim().is_empty() && !l.starts_with('#')).skip(2).take(n).collect(),
    };
    assert_eq!(lines.len(), n);
    lines
        .iter()
        .map(|l| {
            let v: Vec<f64> =
                l.split_whitespace().take(3).map(|t| f64::from(t.parse::<f32>().unwrap())).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

#[test]
fn vtk_samples_through_obj_and_off_match_quadopts_readers() {
    for path in files("data", &["vtk"]) {
        let data = io::read_mesh(&path).unwrap();
        for (format, qformat) in [(Format::Obj, io::Format::Obj), (Format::Off, io::Format::Off)] {
            let text = io::write_mesh_string(qformat, &data).unwrap();
            let ours = io::read_mesh_str(&text, qformat).unwrap();
            let (theirs, info) = read_bytes(text.as_bytes(), format).unwrap();
            let name = format!("{} as {format}", path.display());
            assert_eq!(theirs.points.len(), ours.points.len(), "{name}");
            assert_eq!(theirs.face_count(), ours.quads.len(), "{name}");
            assert!(
                theirs.faces().zip(&ours.quads).all(|(a, b)| a == quadopt::face::vertices(b)),
                "{name}: faces differ"
            );
            assert_eq!(
                bits(&theirs.points),
                bits(&f32_coordinates(&text, format, ours.points.len())),
                "{name}"
            );
            assert_eq!(info.declared_faces, Some(ours.quads.len() as u64), "{name}");
        }
    }
}

#[test]
fn vtk_samples_round_trip_through_om_bit_for_bit() {
    let mut with_fixed = 0;
    for path in files("data", &["vtk"]) {
        let data = io::read_mesh(&path).unwrap();
        with_fixed += usize::from(data.fixed.is_some());
        let a = arrays(&data);
        let (back, _) =
            read_bytes(&write_bytes(&a, Format::Om, &WriteOptions::default()).unwrap(), Format::Om).unwrap();
        assert_eq!(bits(&back.points), bits(&data.points), "{}", path.display());
        assert_eq!(back.face_indices, a.face_indices, "{}", path.display());
        assert_eq!(back.fixed, data.fixed, "{}", path.display());
    }
    assert!(with_fixed >= 2, "the samples with a fixed array were not seen");
}

#[test]
fn float_exact_samples_give_identical_arrays() {
    let mut triangles = 0;
    for path in files("cpp_tests/data", &["obj", "off"]) {
        let ours = io::read_mesh(&path).unwrap();
        let (theirs, _) = openmesh_sys::read(&path).unwrap();
        assert_eq!(bits(&theirs.points), bits(&ours.points), "{}", path.display());
        assert_eq!(theirs.face_indices, arrays(&ours).face_indices, "{}", path.display());
        assert_eq!(theirs.face_offsets, arrays(&ours).face_offsets, "{}", path.display());
        triangles += theirs.faces().filter(|f| f.len() == 3).count();
    }
    // The mixed meshes' triangles were among them (mixed.obj has one).
    assert!(triangles >= 1);
    let (mixed, _) = openmesh_sys::read(root().join("cpp_tests/data/mixed.obj")).unwrap();
    assert_eq!(mixed.faces().map(<[u32]>::len).collect::<Vec<_>>(), [4, 4, 3]);
}

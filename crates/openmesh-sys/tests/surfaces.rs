//! Meshes on curved surfaces (issue 33): 3D points whose z varies survive OpenMesh's readers
//! and writers, so a curved mesh read, optimized on its surface and written keeps every
//! coordinate: `cpp_tests/data/quarter_cylinder.obj` (a jittered quad grid on a quarter of the
//! cylinder x^2 + y^2 = 4, `f32` coordinates) through OBJ, OFF, PLY (ASCII and binary) and OM.

use glam::DVec3;
use openmesh_sys::{Format, MeshArrays, WriteOptions, read, read_bytes, write_bytes};
use quadopt::surface::{SurfaceMesh, SurfaceOptimizer};

fn fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cpp_tests/data/quarter_cylinder.obj")
}

/// The file's `v` lines parsed exactly (as `f64`).
fn exact_points() -> Vec<[f64; 3]> {
    std::fs::read_to_string(fixture())
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let c: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
            [c[0], c[1], c[2]]
        })
        .collect()
}

fn bits(points: &[[f64; 3]]) -> Vec<[u64; 3]> {
    points.iter().map(|p| p.map(f64::to_bits)).collect()
}

fn faces(m: &MeshArrays) -> Vec<[u32; 4]> {
    m.faces()
        .map(|f| match *f {
            [a, b, c, d] => [a, b, c, d],
            [a, b, c] => [a, b, c, quadopt::face::NO_VERTEX],
            _ => panic!("a face of {} vertices", f.len()),
        })
        .collect()
}

#[test]
fn a_curved_obj_is_read_with_its_z() {
    let (m, _) = read(fixture()).unwrap();
    let exact = exact_points();
    assert_eq!((m.points.len(), m.face_count()), (63, 48));
    assert_eq!(bits(&m.points), bits(&exact), "OpenMesh's coordinates differ from the file's");
    // Curved: the heights span the cylinder, and every vertex is on it (to f32 rounding).
    let (lo, hi) = m.points.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| (lo.min(p[2]), hi.max(p[2])));
    assert_eq!((lo, hi), (0.0, 3.0));
    for p in &m.points {
        assert!((p[0].hypot(p[1]) - 2.0).abs() < 1e-6, "{p:?}");
    }
}

#[test]
fn every_format_keeps_the_f32_coordinates_of_a_curved_mesh() {
    let (m, _) = read(fixture()).unwrap();
    for format in Format::ALL {
        for binary in [false, true] {
            if binary && format != Format::Ply {
                continue;
            }
            let options = WriteOptions { binary, ..WriteOptions::default() };
            let bytes = write_bytes(&m, format, &options).unwrap();
            let (back, _) = read_bytes(&bytes, format).unwrap();
            assert_eq!(bits(&back.points), bits(&m.points), "{format} (binary {binary})");
            assert_eq!(faces(&back), faces(&m), "{format}");
        }
    }
}

#[test]
fn an_optimized_surface_mesh_round_trips_through_om_bit_for_bit() {
    let (m, _) = read(fixture()).unwrap();
    let points: Vec<DVec3> = m.points.iter().map(|p| DVec3::from_array(*p)).collect();
    let mut mesh = SurfaceMesh::new(points, faces(&m), None).unwrap();
    let optimizer = SurfaceOptimizer::new(&mesh, 45.0, &[]).unwrap();
    let report = optimizer.run(&mut mesh, &quadopt::Options::default(), None).unwrap();
    assert!(report.output.min > report.input.min);
    let mut out = m.clone();
    out.points = mesh.points().iter().map(|p| p.to_array()).collect();
    assert_ne!(bits(&out.points), bits(&m.points), "nothing moved");
    // OM keeps every f64 bit, z included.
    let (back, _) =
        read_bytes(&write_bytes(&out, Format::Om, &WriteOptions::default()).unwrap(), Format::Om).unwrap();
    assert_eq!(bits(&back.points), bits(&out.points));
    // PLY keeps them rounded to f32 when asked to, still on the cylinder.
    let ply = write_bytes(&out, Format::Ply, &WriteOptions { binary: true, round_to_f32: true }).unwrap();
    let (back, _) = read_bytes(&ply, Format::Ply).unwrap();
    for (p, q) in back.points.iter().zip(&out.points) {
        for c in 0..3 {
            assert_eq!(p[c], f64::from(q[c] as f32));
        }
        assert!(p[0].hypot(p[1]) - 2.0 < 1e-6);
    }
}

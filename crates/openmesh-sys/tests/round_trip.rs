//! Writing with OpenMesh and reading back: OM keeps every `f64` bit; PLY (ASCII and binary)
//! keeps `f32` coordinates bit for bit and refuses, by default, to round others; the fixed
//! flags survive in both.

use openmesh_sys::{Error, Format, MeshArrays, WriteOptions, read_bytes, write_bytes};

/// A 3 x 2 patch of quads plus a triangle, with awkward `f64` coordinates (none of them an
/// `f32`), some vertices fixed.
fn awkward() -> MeshArrays {
    let mut points = Vec::new();
    for j in 0..3 {
        for i in 0..4 {
            let (x, y) = (i as f64 + 0.1 * (j as f64 + 1.0) / 3.0, j as f64 - 1e-3 / 7.0);
            points.push([x, y, std::f64::consts::PI * 1e-9 * (i + j) as f64]);
        }
    }
    points.push([1.0 / 3.0, 2.0 + 1.0 / 3.0, -0.0]);
    let faces: Vec<Vec<u32>> = vec![
        vec![0, 1, 5, 4],
        vec![1, 2, 6, 5],
        vec![2, 3, 7, 6],
        vec![4, 5, 9, 8],
        vec![5, 6, 10, 9],
        vec![6, 7, 11, 10],
        vec![9, 10, 12],
    ];
    let mut m = MeshArrays::new(points, faces);
    m.fixed = Some((0..13).map(|i| i % 3 == 0).collect());
    m
}

/// The same mesh with every coordinate rounded to `f32`.
fn rounded(m: &MeshArrays) -> MeshArrays {
    let mut r = m.clone();
    for p in &mut r.points {
        for c in p.iter_mut() {
            *c = f64::from(*c as f32);
        }
    }
    r
}

fn bits(m: &MeshArrays) -> Vec<[u64; 3]> {
    m.points.iter().map(|p| p.map(f64::to_bits)).collect()
}

fn round_trip(
    m: &MeshArrays,
    format: Format,
    options: &WriteOptions,
) -> (MeshArrays, openmesh_sys::ReadInfo) {
    let bytes = write_bytes(m, format, options).unwrap();
    read_bytes(&bytes, format).unwrap()
}

#[test]
fn om_keeps_every_bit_and_the_fixed_flags() {
    let m = awkward();
    let (back, info) = round_trip(&m, Format::Om, &WriteOptions::default());
    assert_eq!(bits(&back), bits(&m));
    assert_eq!(back.face_offsets, m.face_offsets);
    assert_eq!(back.face_indices, m.face_indices);
    assert_eq!(back.fixed, m.fixed);
    assert!(info.binary && info.has_fixed_property && info.has_vertex_status);
    assert_eq!((info.declared_vertices, info.declared_faces), (Some(13), Some(7)));
}

#[test]
fn om_without_fixed_flags_reads_none() {
    let mut m = awkward();
    m.fixed = None;
    let (back, info) = round_trip(&m, Format::Om, &WriteOptions::default());
    assert_eq!(back.fixed, None);
    assert!(!info.has_fixed_property);
    assert_eq!(bits(&back), bits(&m));
}

#[test]
fn ply_ascii_and_binary_keep_f32_coordinates_and_the_fixed_flags() {
    let m = rounded(&awkward());
    for binary in [false, true] {
        let options = WriteOptions { binary, ..WriteOptions::default() };
        let bytes = write_bytes(&m, Format::Ply, &options).unwrap();
        let header = String::from_utf8_lossy(&bytes[..200]);
        let expected = if binary { "format binary_little_endian" } else { "format ascii" };
        assert!(header.contains(expected), "{header}");
        assert!(header.contains("property int fixed"), "{header}");
        let (back, info) = read_bytes(&bytes, Format::Ply).unwrap();
        assert_eq!(bits(&back), bits(&m), "binary: {binary}");
        assert_eq!(back.face_offsets, m.face_offsets);
        assert_eq!(back.face_indices, m.face_indices);
        assert_eq!(back.fixed, m.fixed);
        assert_eq!(info.binary, binary);
        assert!(info.has_fixed_property && !info.has_vertex_status);
    }
}

#[test]
fn ply_refuses_to_round_unless_asked() {
    let m = awkward();
    match write_bytes(&m, Format::Ply, &WriteOptions::default()) {
        Err(Error::PrecisionLoss { format: Format::Ply, vertex: 0, axis: 0, value }) => {
            assert_eq!(value, m.points[0][0]);
        }
        other => panic!("expected a precision error, got {other:?}"),
    }
    // With rounding allowed, what comes back is exactly the f32 rounding of every coordinate.
    let options = WriteOptions { round_to_f32: true, binary: true };
    let (back, _) = round_trip(&m, Format::Ply, &options);
    assert_eq!(bits(&back), bits(&rounded(&m)));
    assert_ne!(bits(&back), bits(&m));
}

#[test]
fn obj_and_off_round_trip_f32_coordinates_and_refuse_fixed_flags() {
    let mut m = rounded(&awkward());
    for format in [Format::Obj, Format::Off] {
        assert!(matches!(write_bytes(&m, format, &WriteOptions::default()), Err(Error::Unsupported { .. })));
    }
    m.fixed = None;
    for format in [Format::Obj, Format::Off] {
        let (back, info) = round_trip(&m, format, &WriteOptions::default());
        assert_eq!(bits(&back), bits(&m), "{format}");
        assert_eq!(back.face_indices, m.face_indices, "{format}");
        assert_eq!(back.face_offsets, m.face_offsets, "{format}");
        assert_eq!(back.fixed, None);
        assert_eq!(info.declared_faces, Some(7), "{format}");
    }
}

#[test]
fn fixed_flags_of_any_numeric_ply_type_are_read() {
    let text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
                property int fixed\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
                0 0 0 0\n1 0 0 7\n1 1 0 0\n0 1 0 -1\n4 0 1 2 3\n";
    let (m, info) = read_bytes(text.as_bytes(), Format::Ply).unwrap();
    assert_eq!(m.fixed, Some(vec![false, true, false, true]));
    assert!(info.has_fixed_property);
    assert_eq!(m.face(0), &[0, 1, 2, 3]);
}

#[test]
fn invalid_arrays_are_errors() {
    let m = awkward();
    let mut bad = m.clone();
    bad.face_indices[3] = 99;
    assert!(matches!(
        write_bytes(&bad, Format::Om, &WriteOptions::default()),
        Err(Error::InvalidMesh { .. })
    ));
    let mut bad = m.clone();
    bad.face_offsets.pop();
    assert!(matches!(
        write_bytes(&bad, Format::Om, &WriteOptions::default()),
        Err(Error::InvalidMesh { .. })
    ));
    let mut bad = m.clone();
    bad.fixed = Some(vec![true]);
    assert!(matches!(
        write_bytes(&bad, Format::Om, &WriteOptions::default()),
        Err(Error::InvalidMesh { .. })
    ));
    // The same quad twice: OpenMesh cannot add the second.
    let dup = MeshArrays::new(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
        [[0, 1, 2, 3], [0, 1, 2, 3]],
    );
    match write_bytes(&dup, Format::Om, &WriteOptions::default()) {
        Err(Error::InvalidMesh { message }) => assert!(message.contains("face 1"), "{message}"),
        other => panic!("expected an invalid mesh, got {other:?}"),
    }
    let mut nan = m;
    nan.points[2][1] = f64::NAN;
    assert!(matches!(
        write_bytes(&nan, Format::Om, &WriteOptions::default()),
        Err(Error::InvalidMesh { .. })
    ));
}

#[test]
fn files_round_trip_through_the_path_api() {
    let dir = std::env::temp_dir().join(format!("openmesh-sys-rt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let m = awkward();
    let path = dir.join("mesh.om");
    openmesh_sys::write(&path, &m, &WriteOptions::default()).unwrap();
    let (back, _) = openmesh_sys::read(&path).unwrap();
    assert_eq!(bits(&back), bits(&m));
    assert!(matches!(openmesh_sys::read(dir.join("missing.ply")), Err(Error::File { .. })));
    assert!(matches!(openmesh_sys::read(dir.join("mesh.stl")), Err(Error::UnknownFormat { .. })));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn ascii_ply_uchar_flags_written_as_digits_are_read_as_numbers() {
    // Other tools write `property uchar fixed` as the digits 0 and 1 (OpenMesh reads a char).
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                property uchar fixed\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
                0 0 0 0\n1 0 0 1\n0 1 0 0\n3 0 1 2\n";
    let (m, _) = read_bytes(text.as_bytes(), Format::Ply).unwrap();
    assert_eq!(m.fixed, Some(vec![false, true, false]));
}

//! Bad files are errors, never a panic and never a smaller mesh: truncated data (every prefix
//! of a PLY ASCII, a binary PLY and an OM file), wrong counts, out-of-range and repeated
//! indices, faces OpenMesh cannot add (non-manifold, duplicated), corrupt OM bytes.

use openmesh_sys::{
    DropReason, DroppedFace, Error, Format, MeshArrays, WriteOptions, read_bytes, write_bytes,
};

/// A 2 x 2 grid of unit quads (9 vertices, 4 faces), f32-exact, two vertices fixed.
fn grid() -> MeshArrays {
    let points = (0..9).map(|k| [(k % 3) as f64, (k / 3) as f64 * 0.5, 0.0]).collect();
    let mut m = MeshArrays::new(points, [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]]);
    m.fixed = Some((0..9).map(|k| k == 0 || k == 8).collect());
    m
}

const PLY_HEAD: &str = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n\
                        property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n\
                        0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n";

fn ply(faces: &str) -> Vec<u8> {
    format!("{PLY_HEAD}{faces}").into_bytes()
}

fn dropped(result: Result<(MeshArrays, openmesh_sys::ReadInfo), Error>) -> Vec<DroppedFace> {
    match result {
        Err(Error::Incomplete { dropped, message, .. }) => {
            assert!(message.contains("face"), "{message}");
            dropped
        }
        other => panic!("expected Incomplete, got {other:?}"),
    }
}

#[test]
fn a_valid_file_reads() {
    let (m, info) = read_bytes(&ply("4 0 1 4 3\n4 1 2 5 4\n"), Format::Ply).unwrap();
    assert_eq!(m.face_count(), 2);
    assert_eq!(m.face(1), &[1, 2, 5, 4]);
    assert_eq!((info.declared_vertices, info.declared_faces), (Some(6), Some(2)));
}

#[test]
fn out_of_range_and_repeated_indices_name_the_face() {
    let d = dropped(read_bytes(&ply("4 0 1 4 3\n4 1 2 5 6\n"), Format::Ply));
    assert_eq!(d, [DroppedFace { face: 1, reason: DropReason::InvalidIndex }]);
    let d = dropped(read_bytes(&ply("4 0 1 4 3\n4 1 2 2 4\n"), Format::Ply));
    assert_eq!(d, [DroppedFace { face: 1, reason: DropReason::RepeatedVertex }]);
    let d = dropped(read_bytes(&ply("4 0 1 4 3\n2 1 2\n"), Format::Ply));
    assert_eq!(d, [DroppedFace { face: 1, reason: DropReason::TooFewVertices }]);
}

#[test]
fn faces_openmesh_cannot_add_are_errors_not_copies() {
    // The same quad twice, and a quad using edge 1-4 in the same direction as the first.
    let d = dropped(read_bytes(&ply("4 0 1 4 3\n4 0 1 4 3\n"), Format::Ply));
    assert_eq!(d, [DroppedFace { face: 1, reason: DropReason::NonManifold }]);
    let d = dropped(read_bytes(&ply("4 0 1 4 3\n4 1 4 5 2\n"), Format::Ply));
    assert_eq!(d, [DroppedFace { face: 1, reason: DropReason::NonManifold }]);
    // Three quads on one edge (OBJ, 1-based): the third cannot be added.
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 -1 0\nv 0 -1 0\nv 2 0 0\nv 2 1 0\n\
               f 1 2 3 4\nf 2 1 6 5\nf 1 2 8 7\n";
    let d = dropped(read_bytes(obj.as_bytes(), Format::Obj));
    assert_eq!(d, [DroppedFace { face: 2, reason: DropReason::NonManifold }]);
}

#[test]
fn wrong_counts_are_errors() {
    // Fewer faces than declared, at a line end (OpenMesh's reader stops quietly).
    let r = read_bytes(&ply("4 0 1 4 3\n"), Format::Ply);
    assert!(matches!(r, Err(Error::Read { .. }) | Err(Error::Incomplete { .. })), "{r:?}");
    // Fewer vertices than declared.
    let text = PLY_HEAD.replace("element vertex 6", "element vertex 9") + "4 0 1 4 3\n4 1 2 5 4\n";
    assert!(read_bytes(text.as_bytes(), Format::Ply).is_err());
    // OFF declaring 3 faces, giving 2.
    let off = "OFF\n4 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
    assert!(read_bytes(off.as_bytes(), Format::Off).is_err());
    // A malformed number.
    assert!(matches!(read_bytes(&ply("4 0 1 4 3\n4 1 2 x 4\n"), Format::Ply), Err(Error::Read { .. })));
}

#[test]
fn garbage_and_empty_data_are_errors() {
    for format in Format::ALL {
        for data in [&b""[..], b"\0\0\0\0", b"OM", b"ply\n", b"OFF\n", b"v 1 2", b"\xff\xfe garbage \n\n"] {
            match read_bytes(data, format) {
                Err(_) => {}
                // OBJ and OFF without faces are valid empty meshes; nothing may come out of nothing.
                Ok((m, _)) => assert!(m.face_count() == 0, "{format}: {data:?} gave {m:?}"),
            }
        }
    }
}

/// Every prefix of a file is an error, or (for ASCII cut inside the final newline) the whole mesh.
fn every_prefix_fails_or_is_whole(bytes: &[u8], format: Format, whole: &MeshArrays) {
    for len in 0..bytes.len() {
        match read_bytes(&bytes[..len], format) {
            Err(_) => {}
            Ok((m, _)) => {
                assert_eq!(&m, whole, "{format}: the first {len} of {} bytes gave another mesh", bytes.len())
            }
        }
    }
    assert_eq!(&read_bytes(bytes, format).unwrap().0, whole);
}

#[test]
fn truncated_files_are_errors() {
    let m = grid();
    for (format, binary) in [(Format::Ply, false), (Format::Ply, true), (Format::Om, true)] {
        let bytes = write_bytes(&m, format, &WriteOptions { binary, ..WriteOptions::default() }).unwrap();
        every_prefix_fails_or_is_whole(&bytes, format, &m);
    }
}

#[test]
fn corrupt_om_bytes_never_crash_or_shrink() {
    let m = grid();
    let bytes = write_bytes(&m, Format::Om, &WriteOptions::default()).unwrap();
    // Every byte set to 0x00, 0x7f and 0xff in turn: an error, or a mesh with all the vertices
    // and faces (the byte may be a coordinate or a flag).
    for i in 0..bytes.len() {
        for v in [0x00u8, 0x7f, 0xff] {
            let mut b = bytes.clone();
            b[i] = v;
            if let Ok((got, _)) = read_bytes(&b, Format::Om) {
                assert_eq!(got.points.len(), m.points.len(), "byte {i} = {v:#x}");
                assert_eq!(got.face_count(), m.face_count(), "byte {i} = {v:#x}");
            }
        }
    }
}

#[test]
fn a_list_fixed_property_is_an_error() {
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                property list uchar int fixed\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
                0 0 0 1 1\n1 0 0 1 0\n0 1 0 1 0\n3 0 1 2\n";
    // OpenMesh reads a list property as a list of that name; quadopt's flags must be scalars.
    assert!(read_bytes(text.as_bytes(), Format::Ply).is_err());
}

/// A read error whose message contains `needle`.
fn read_error(data: &[u8], format: Format, needle: &str) {
    match read_bytes(data, format) {
        Err(Error::Read { message }) => {
            assert!(message.contains(needle), "{format}: {message:?} lacks {needle:?}")
        }
        other => panic!("{format}: {:?} gave {other:?}", String::from_utf8_lossy(data)),
    }
}

const PLY_3V: &str =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";

/// OpenMesh's readers loop over counts from the file after a failed read (OFF's counts are not
/// even initialised when missing), pushing stale values: each of these cost minutes and
/// gigabytes, or hung, before the shim's checks. Now each is an error naming the place.
#[test]
fn counts_the_data_cannot_hold_are_errors_not_hangs() {
    for (data, needle) in [
        ("OFF\n", "counts"),
        ("OFF\n3 1", "counts"),
        ("OFF\nx y z\n", "counts"),
        ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n", "face 0: a vertex count larger"),
        ("OFF\n4000000000 4000000000 0\n0 0 0\nx\n", "vertex 1: the coordinate 'x'"),
        ("OFF\n3 1 0\n0 0 0\n1 0 0\n", "vertex 2: the data ends early"),
        ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "face 0: the data ends early"),
    ] {
        read_error(data.as_bytes(), Format::Off, needle);
    }
    for (body, needle) in [
        (
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 x\n",
            "face 0: the vertex index 'x'",
        ),
        (
            "element face 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n2000000000 0 1 2\n",
            "vertex count larger",
        ),
        (
            "element face 4000000000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
            "face 1: the data ends early",
        ),
        (
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 1e39\n",
            "the z value '1e39'",
        ),
        (
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 nan\n",
            "the z value 'nan'",
        ),
    ] {
        read_error(format!("{PLY_3V}{body}").as_bytes(), Format::Ply, needle);
    }
    let huge = PLY_HEAD.replace("element vertex 6", "element vertex 4000000000").replace("4 1 2 5 4\n", "");
    read_error(huge.replace("0 1 0\n", "0 x 0\n").as_bytes(), Format::Ply, "the y value 'x'");
    // Binary: a count of 2^31 - 1 vertex indices, and a vertex count the data cannot hold.
    let binary = |vertices: u32, face: &[u8]| {
        let mut d = format!("ply\nformat binary_little_endian 1.0\nelement vertex {vertices}\nproperty float x\n\
                             property float y\nproperty float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n")
            .into_bytes();
        d.extend_from_slice(&[0u8; 36]);
        d.extend_from_slice(face);
        d
    };
    read_error(&binary(3, &0x7fff_ffffu32.to_le_bytes()), Format::Ply, "face 0: the data ends early");
    read_error(&binary(3, &u32::MAX.to_le_bytes()), Format::Ply, "negative vertex count");
    read_error(&binary(4_000_000_000, &[3, 0, 0, 0]), Format::Ply, "vertex: the data ends early");
    let ok = binary(3, &[3, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0]);
    assert!(matches!(read_bytes(&ok, Format::Ply), Err(Error::Incomplete { .. }) | Ok(_)));
}

/// Header lines OpenMesh would read differently from what they say are refused, not misread.
#[test]
fn ply_headers_openmesh_misreads_are_errors() {
    let tail = "element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
    for (head, needle) in [
        ("ply\nformat ascii 1.0\nproperty float x\n", "a property before any element"),
        ("ply\nformat ascii 1.0\nobj_info made by hand\n", "not a PLY header line"),
        ("ply\nformat ascii 1.0\nelement vertex 3\nproperty list uchar float x\n", "the only list property"),
        ("ply\nformat ascii 1.0\nelement vertex 3\nproperty int x\n", "must be float or double"),
        ("ply\nformat ascii 1.0\nelement vertex 3\nproperty half x\n", "unknown property type 'half'"),
        ("ply\nformat ascii 2.0\n", "expected 'format"),
    ] {
        read_error(format!("{head}{tail}").as_bytes(), Format::Ply, needle);
    }
    let commented = "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
                     property float z\ncomment last\nend_header\n";
    read_error(commented.as_bytes(), Format::Ply, "comment line just before end_header");
    read_error(b"COFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", Format::Off, "must be 'OFF' alone");
}

/// The checks accept what OpenMesh's own writers produce and ordinary variants of it.
#[test]
fn checked_formats_still_read() {
    let crlf = ply("4 0 1 4 3\n4 1 2 5 4\n")
        .iter()
        .flat_map(|&b| if b == b'\n' { vec![b'\r', b'\n'] } else { vec![b] })
        .collect::<Vec<_>>();
    assert_eq!(read_bytes(&crlf, Format::Ply).unwrap().0.face_count(), 2);
    let signs = ply("4 0 1 4 3\n4 1 2 5 4\n");
    let signs = String::from_utf8(signs).unwrap().replace("1 0 0\n", "+1.0e0 -0 .0\n");
    assert_eq!(read_bytes(signs.as_bytes(), Format::Ply).unwrap().0.points[1], [1.0, 0.0, 0.0]);
    let off = "OFF\n4 1 0\n0 0 0 extra\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
    assert_eq!(read_bytes(off.as_bytes(), Format::Off).unwrap().0.face(0), &[0, 1, 2, 3]);
    for binary in [false, true] {
        let bytes =
            write_bytes(&grid(), Format::Ply, &WriteOptions { binary, ..WriteOptions::default() }).unwrap();
        assert_eq!(read_bytes(&bytes, Format::Ply).unwrap().0, grid());
    }
}

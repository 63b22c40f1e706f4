//! VTK XML UnstructuredGrid (`.vtu`): files written by VTK itself (tests/data/vtu, made by
//! tools/make_vtu_fixtures.py) read with the exact points, quads and fixed flags; our files
//! round-trip bit-identical in every encoding; malformed files give one-line errors.

use quadopt::io::{self, Encoding, Format, IoError, MeshData};
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/vtu").join(name)
}

fn bits(points: &[[f64; 3]]) -> Vec<[u64; 3]> {
    points.iter().map(|p| p.map(f64::to_bits)).collect()
}

/// What every fixture holds (tests/data/vtu/expected.txt, written with the fixtures).
fn expected() -> MeshData {
    let text = std::fs::read_to_string(fixture("expected.txt")).unwrap();
    let mut data = MeshData::default();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let mut t = line.split_whitespace();
        match t.next().unwrap() {
            "point" => {
                let c: Vec<f64> = t.map(|x| x.parse().unwrap()).collect();
                data.points.push([c[0], c[1], c[2]]);
            }
            "quad" => {
                let v: Vec<u32> = t.map(|x| x.parse().unwrap()).collect();
                data.quads.push([v[0], v[1], v[2], v[3]]);
            }
            "fixed" => data.fixed = Some(t.map(|x| x == "1").collect()),
            other => panic!("unknown line {other}"),
        }
    }
    assert_eq!((data.points.len(), data.quads.len()), (13, 6));
    data
}

#[test]
fn files_written_by_vtk_read_exactly() {
    let want = expected();
    let cases = [
        ("ascii.vtu", Encoding::Ascii, false),
        ("binary.vtu", Encoding::Binary, false),
        ("binary_zlib.vtu", Encoding::Binary, true),
        ("appended_raw.vtu", Encoding::Appended, false),
        ("appended_base64.vtu", Encoding::Appended, false),
        ("appended_zlib.vtu", Encoding::Appended, true),
        ("appended_zlib_small_blocks.vtu", Encoding::Appended, true),
        ("big_endian_uint32.vtu", Encoding::Appended, false),
    ];
    for (name, encoding, compressed) in cases {
        let got = io::read_mesh(fixture(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(bits(&got.points), bits(&want.points), "{name}");
        assert_eq!(got.quads, want.quads, "{name}");
        assert_eq!(got.fixed, want.fixed, "{name}");
        assert_eq!((got.encoding, got.compressed), (encoding, compressed), "{name}");
        // The cell array in the file is not read: quality is what the tool computes.
        assert_eq!(got.quality, None, "{name}");
    }
    // Float32 points and Int32 connectivity: the points are the float32 roundings.
    let got = io::read_mesh(fixture("float32_int32.vtu")).unwrap();
    let rounded: Vec<[f64; 3]> = want.points.iter().map(|p| p.map(|c| f64::from(c as f32))).collect();
    assert_eq!(bits(&got.points), bits(&rounded));
    assert_eq!(got.quads, want.quads);
    assert_eq!(got.fixed, want.fixed);
}

/// Coordinates that break lossy formatting, and every array the writer writes.
fn awkward_mesh() -> MeshData {
    let points = vec![
        [0.0, -0.0, 1.0 / 3.0],
        [0.1 + 0.2, 1e-300, 1.0 / 3.0],
        [std::f64::consts::PI, 123456789.12345679, 1.0 / 3.0],
        [-2.5e-7, 1e23, 1.0 / 3.0],
        [f64::MIN_POSITIVE, 5e-324, 1.0 / 3.0],
        [1.7976931348623157e308, -1.0, 1.0 / 3.0],
    ];
    MeshData {
        points,
        quads: vec![[0, 1, 2, 3], [3, 2, 5, 0]],
        fixed: Some(vec![true, false, true, false, false, true]),
        corner: Some(vec![true, false, false, false, false, false]),
        quality: Some(vec![-0.25, 1.0 / 3.0]),
        ..MeshData::default()
    }
}

#[test]
fn every_encoding_round_trips_bit_identical() {
    for encoding in [Encoding::Ascii, Encoding::Binary, Encoding::Appended] {
        for compressed in [false, true] {
            let data = MeshData { encoding, compressed, ..awkward_mesh() };
            let bytes = io::write_mesh_bytes(Format::Vtu, &data).unwrap();
            let back = io::read_mesh_bytes(&bytes, Format::Vtu).unwrap();
            let case = format!("{encoding:?} zlib={compressed}");
            assert_eq!(bits(&back.points), bits(&data.points), "{case}");
            assert_eq!(back.quads, data.quads, "{case}");
            assert_eq!(back.fixed, data.fixed, "{case}");
            assert_eq!(back.encoding, encoding, "{case}");
            // Text has nothing to compress.
            assert_eq!(back.compressed, compressed && encoding != Encoding::Ascii, "{case}");
            let text = String::from_utf8_lossy(&bytes);
            assert!(text.contains(r#"Name="scaled_jacobian""#), "{case}");
            assert!(text.contains(r#"Name="corner""#), "{case}");
            assert_eq!(text.contains("vtkZLibDataCompressor"), back.compressed, "{case}");
        }
    }
    // ASCII holds the quality values at round-trip precision.
    let text = io::write_mesh_string(Format::Vtu, &awkward_mesh()).unwrap();
    assert!(text.contains("-0.25 0.3333333333333333"), "{text}");
}

#[test]
fn big_meshes_compress_in_several_blocks_and_round_trip() {
    // 40,000 points: 960 kB of coordinates, 30 zlib blocks of 32 KiB.
    let n = 200u32;
    let points: Vec<[f64; 3]> =
        (0..n * n).map(|i| [f64::from(i % n) * 0.1, f64::from(i / n).sqrt(), 0.0]).collect();
    let quads: Vec<[u32; 4]> = (0..(n - 1) * (n - 1))
        .map(|k| {
            let (i, j) = (k % (n - 1), k / (n - 1));
            let a = j * n + i;
            [a, a + 1, a + n + 1, a + n]
        })
        .collect();
    for encoding in [Encoding::Binary, Encoding::Appended] {
        let data = MeshData { encoding, compressed: true, ..MeshData::new(points.clone(), quads.clone()) };
        let bytes = io::write_mesh_bytes(Format::Vtu, &data).unwrap();
        let back = io::read_mesh_bytes(&bytes, Format::Vtu).unwrap();
        assert_eq!(bits(&back.points), bits(&points));
        assert_eq!(back.quads, quads);
    }
}

fn err(bytes: &[u8]) -> String {
    let e = io::read_mesh_bytes(bytes, Format::Vtu).unwrap_err();
    let msg = e.to_string();
    assert!(!msg.contains('\n'), "one line: {msg}");
    assert!(!matches!(e, IoError::Parse { .. }), "binary formats have no line numbers: {msg}");
    msg
}

fn vtk_file(name: &str) -> Vec<u8> {
    std::fs::read(fixture(name)).unwrap()
}

fn replace(bytes: &[u8], from: &str, to: &str) -> Vec<u8> {
    let at = bytes.windows(from.len()).position(|w| w == from.as_bytes()).unwrap_or_else(|| panic!("{from}"));
    [&bytes[..at], to.as_bytes(), &bytes[at + from.len()..]].concat()
}

/// Where the text of the `Points` DataArray's data starts.
fn points_data_at(text: &str) -> usize {
    let start = text.find(r#"Name="Points""#).unwrap();
    let data_at = start + text[start..].find('>').unwrap() + 1;
    data_at + text[data_at..].find(|c: char| !c.is_whitespace()).unwrap()
}

#[test]
fn malformed_files_give_one_line_errors() {
    // Truncated binary data, in each encoding: an error at every cut, never a panic.
    for name in ["appended_raw.vtu", "appended_zlib.vtu", "binary.vtu", "binary_zlib.vtu", "ascii.vtu"] {
        let bytes = vtk_file(name);
        for end in (0..bytes.len()).step_by(7) {
            if let Ok(m) = io::read_mesh_bytes(&bytes[..end], Format::Vtu) {
                m.check().unwrap();
            }
        }
    }
    let raw = vtk_file("appended_raw.vtu");
    let cut = &raw[..raw.len() - 200];
    assert!(err(cut).contains("(truncated file?)"), "{}", err(cut));

    // A byte order that is neither.
    let m = err(&replace(&raw, "LittleEndian", "MiddleEndian"));
    assert_eq!(m, r#"byte_order="MiddleEndian" (LittleEndian or BigEndian)"#);
    // Big-endian data declared little-endian: the block sizes are nonsense, caught as such.
    let big = vtk_file("big_endian_uint32.vtu");
    let m = err(&replace(&big, "BigEndian", "LittleEndian"));
    assert!(m.contains("bytes where the piece's counts need"), "{m}");

    // Bad base64.
    let b64 = vtk_file("binary.vtu");
    let text = String::from_utf8(b64.clone()).unwrap();
    let data_at = points_data_at(&text);
    let mut broken = b64.clone();
    broken[data_at + 12] = b'*';
    let m = err(&broken);
    assert!(m.contains(r#"DataArray "Points": bad base64"#), "{m}");

    // A compressed header whose first three words end in base64 padding (they decode to 23
    // bytes, not 24): found by the read_vtu fuzz target, once a panic.
    let zb = vtk_file("binary_zlib.vtu");
    let text = String::from_utf8(zb.clone()).unwrap();
    let data_at = points_data_at(&text);
    let mut padded = zb.clone();
    padded[data_at..data_at + 32].copy_from_slice(b"gAAAAAAAAAYAAAAAAAAACwAAAAAAAAA=");
    let m = err(&padded);
    assert!(m.contains(r#"DataArray "Points""#), "{m}");

    // An unknown compressor is named.
    let z = vtk_file("appended_zlib.vtu");
    let m = err(&replace(&z, "vtkZLibDataCompressor", "vtkLZ4DataCompressor"));
    assert_eq!(m, "unsupported: compressor vtkLZ4DataCompressor (vtkZLibDataCompressor is read)");
    // Corrupt zlib data.
    // The last zlib stream starts with 0x78 and a check byte making the pair a multiple of 31.
    let at = z
        .windows(2)
        .rposition(|w| w[0] == 0x78 && (u16::from(w[0]) * 256 + u16::from(w[1])) % 31 == 0)
        .unwrap();
    let mut corrupt = z.clone();
    for b in &mut corrupt[at + 2..at + 12] {
        *b ^= 0x5a;
    }
    let m = err(&corrupt);
    assert!(m.contains("zlib block"), "{m}");

    // Cells that are neither triangles nor quads, cells whose offsets disagree with their type,
    // and indices out of range.
    let ascii = vtk_file("ascii.vtu");
    let text = String::from_utf8(ascii).unwrap();
    let types_at = text.find(r#"Name="types""#).unwrap();
    let line = types_at + text[types_at..].find('\n').unwrap() + 1;
    let nine = line + text[line..].find('9').unwrap();
    let mut polygon = text.clone();
    polygon.replace_range(nine..nine + 1, "7");
    assert_eq!(
        err(polygon.as_bytes()),
        "unsupported: cell 0 is of VTK type 7 (polygon) with 4 vertices; only triangles (type 5) and quads \
         (type 9) are read (cell numbers are 0-based)"
    );
    let mut tri = text.clone();
    tri.replace_range(nine..nine + 1, "5");
    assert_eq!(
        err(tri.as_bytes()),
        "offsets: cell 0 ends at 4 after starting at 0 (a triangle has 3 vertices; cell numbers are 0-based)"
    );
    let conn = text.find(r#"Name="connectivity""#).unwrap();
    let line = conn + text[conn..].find('\n').unwrap() + 1;
    let mut far = text.clone();
    let first = line + far[line..].find('0').unwrap();
    far.replace_range(first..first + 1, "99");
    let m = err(far.as_bytes());
    assert!(m.contains("99") && m.contains("13"), "{m}");
    let offs = text.find(r#"Name="offsets""#).unwrap();
    let line = offs + text[offs..].find('\n').unwrap() + 1;
    let mut off = text.clone();
    let four = line + off[line..].find('4').unwrap();
    off.replace_range(four..four + 1, "3");
    assert_eq!(
        err(off.as_bytes()),
        "offsets: cell 0 ends at 3 after starting at 0 (a quad has 4 vertices; cell numbers are 0-based)"
    );

    // Not VTU at all, or another dataset type.
    assert_eq!(err(b"<html></html>"), "not a VTK XML file (no <VTKFile>)");
    assert_eq!(
        err(br#"<VTKFile type="PolyData"><PolyData/></VTKFile>"#),
        "unsupported: VTK XML PolyData files (UnstructuredGrid is read)"
    );
    let m = err(b"<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece");
    assert!(m.starts_with("bad XML"), "{m}");
}

#[test]
fn errors_from_files_name_the_file() {
    let dir = std::env::temp_dir().join(format!("quadopt-vtu-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("cut.vtu");
    let raw = vtk_file("appended_raw.vtu");
    std::fs::write(&path, &raw[..raw.len() - 200]).unwrap();
    let msg = io::read_mesh(&path).unwrap_err().to_string();
    assert!(msg.starts_with(&format!("{}: DataArray ", path.display())), "{msg}");
    std::fs::remove_dir_all(&dir).unwrap();
}

//! Quad-dominant meshes (quads and triangles) in every file format: written and read back
//! with the same points and faces, in the same order, triangles as triangles; the quality
//! arrays hold one value per face, in the file's face order; triangle-only files read; a face
//! of any other size is an error naming it.

use base64::Engine as _;
use base64::engine::general_purpose::STANDARD as BASE64;
use quadopt::face::{self, NO_VERTEX};
use quadopt::io::{self, Encoding, Format, IoError, MeshData, MshVersion, PlanarMesh};
use std::io::Read as _;

fn bits(points: &[[f64; 3]]) -> Vec<[u64; 3]> {
    points.iter().map(|p| p.map(f64::to_bits)).collect()
}

/// A small mixed mesh: quad, triangle, triangle, quad, triangle (so MSH 4.1 needs four
/// element blocks to keep the order), awkward coordinates, one unused vertex.
fn mixed() -> MeshData {
    let t = 1.0 / 3.0;
    let points = vec![
        [0.0, 0.0, 0.5],
        [1.0 + t, 0.0, 0.5],
        [2.0, 0.1, 0.5],
        [3.0, 0.0, 0.5],
        [0.0, 1.0, 0.5],
        [1.0, 1.0 + t, 0.5],
        [2.0, 1.0, 0.5],
        [3.0, 1.2, 0.5],
        [1.5, 2.5, 0.5],
        [7.0, -0.0, 0.5], // used by no face
    ];
    let faces = vec![
        [0, 1, 5, 4],
        face::triangle(1, 2, 6),
        face::triangle(1, 6, 5),
        [2, 3, 7, 6],
        face::triangle(5, 6, 8),
    ];
    let mut data = MeshData::new(points, faces);
    data.fixed = Some((0..10).map(|v| v % 3 == 0).collect());
    data.corner = Some((0..10).map(|v| v == 4 || v == 8).collect());
    data.quality = Some(PlanarMesh::new(&data).unwrap().mesh.quality_values());
    data
}

/// Verdict's triangle scaled Jacobian (signed: counter-clockwise is positive).
fn verdict_triangle(p: &[[f64; 3]], f: &[u32; 4]) -> f64 {
    let [a, b, c] = [f[0], f[1], f[2]].map(|v| p[v as usize]);
    let e = [[b[0] - a[0], b[1] - a[1]], [c[0] - b[0], c[1] - b[1]], [a[0] - c[0], a[1] - c[1]]];
    let len = e.map(|e| e[0].hypot(e[1]));
    let cross = e[0][0] * (c[1] - a[1]) - e[0][1] * (c[0] - a[0]);
    let max = (len[0] * len[1]).max(len[1] * len[2]).max(len[2] * len[0]);
    cross / max * 2.0 / 3f64.sqrt()
}

#[test]
fn the_mixed_mesh_has_the_triangle_measure_per_face() {
    let data = mixed();
    let quality = data.quality.as_ref().unwrap();
    assert_eq!(quality.len(), 5);
    for (f, &q) in data.quads.iter().zip(quality) {
        if face::is_triangle(f) {
            let want = verdict_triangle(&data.points, f);
            assert!((q - want).abs() < 1e-12, "{f:?}: {q} vs {want}");
        }
    }
    // Every value differs, so a file with the faces or values out of order is caught.
    for i in 0..5 {
        for j in 0..i {
            assert_ne!(quality[i], quality[j]);
        }
    }
}

/// One way to write a file.
#[derive(Clone, Copy, Debug)]
struct Case {
    format: Format,
    msh: Option<MshVersion>,
    encoding: Encoding,
    compressed: bool,
    polydata: bool,
}

fn cases() -> Vec<Case> {
    let case =
        |format, msh, encoding, compressed, polydata| Case { format, msh, encoding, compressed, polydata };
    use Encoding::{Appended, Ascii, Binary};
    vec![
        case(Format::Obj, None, Ascii, false, false),
        case(Format::Off, None, Ascii, false, false),
        case(Format::Vtk, None, Ascii, false, false),
        case(Format::Vtk, None, Ascii, false, true),
        case(Format::Msh, Some(MshVersion::V2_2), Ascii, false, false),
        case(Format::Msh, Some(MshVersion::V4_1), Ascii, false, false),
        case(Format::Msh, Some(MshVersion::V4_1), Binary, false, false),
        case(Format::Vtu, None, Ascii, false, false),
        case(Format::Vtu, None, Binary, false, false),
        case(Format::Vtu, None, Binary, true, false),
        case(Format::Vtu, None, Appended, false, false),
        case(Format::Vtu, None, Appended, true, false),
    ]
}

fn with_case(data: &MeshData, c: Case) -> MeshData {
    MeshData {
        msh_version: c.msh,
        encoding: c.encoding,
        compressed: c.compressed,
        vtk_polydata: c.polydata,
        ..data.clone()
    }
}

/// The text after `start` up to `end`.
fn between<'a>(text: &'a str, start: &str, end: &str) -> &'a str {
    let from = text.find(start).unwrap_or_else(|| panic!("no {start:?} in\n{text}")) + start.len();
    let to = from + text[from..].find(end).unwrap();
    &text[from..to]
}

fn reals(text: &str) -> Vec<f64> {
    text.split_ascii_whitespace().map(|t| t.parse().unwrap()).collect()
}

/// MSH `tag value` lines: checks the tags are 1, 2, ... and returns the values.
fn tagged(text: &str) -> Vec<f64> {
    let mut values = Vec::new();
    for (i, line) in text.lines().filter(|l| !l.is_empty()).enumerate() {
        let (tag, value) = line.split_once(' ').unwrap();
        assert_eq!(tag.parse::<usize>().unwrap(), i + 1, "{line}");
        values.push(value.parse().unwrap());
    }
    values
}

/// The VTU data block at `at` of `bytes` (UInt64 headers, zlib or not), decoded to bytes.
fn vtu_block(header: &[u8], body: &[u8], compressed: bool) -> Vec<u8> {
    let word = |i: usize| u64::from_le_bytes(header[8 * i..8 * i + 8].try_into().unwrap()) as usize;
    if !compressed {
        return body[..word(0)].to_vec();
    }
    let mut out = Vec::new();
    let mut at = 0;
    for b in 0..word(0) {
        let size = word(3 + b);
        flate2::read::ZlibDecoder::new(&body[at..at + size]).read_to_end(&mut out).unwrap();
        at += size;
    }
    out
}

/// The VTU header length in bytes given its first word.
fn vtu_header_len(first: u64, compressed: bool) -> usize {
    if compressed { 8 * (3 + first as usize) } else { 8 }
}

/// The cell array `scaled_jacobian` of a VTU file, in any encoding.
fn vtu_quality(bytes: &[u8], c: Case) -> Vec<f64> {
    let text = String::from_utf8_lossy(bytes);
    let text = &text[text.find(r#"Name="scaled_jacobian""#).unwrap()..];
    let tag = between(text, r#"Name="scaled_jacobian""#, ">");
    let f64s = |b: Vec<u8>| b.chunks_exact(8).map(|c| f64::from_le_bytes(c.try_into().unwrap())).collect();
    match c.encoding {
        Encoding::Ascii => reals(between(text, &format!("{tag}>"), "</DataArray>")),
        Encoding::Binary => {
            let b64 = between(text, &format!("{tag}>"), "</DataArray>").trim();
            let first = BASE64.decode(&b64[..12]).unwrap();
            let first = u64::from_le_bytes(first[..8].try_into().unwrap());
            let len = vtu_header_len(first, c.compressed);
            let split = len.div_ceil(3) * 4;
            let header = BASE64.decode(&b64[..split]).unwrap();
            let body = BASE64.decode(&b64[split..]).unwrap();
            f64s(vtu_block(&header, &body, c.compressed))
        }
        Encoding::Appended => {
            let offset: usize = between(tag, "offset=\"", "\"").parse().unwrap();
            let marker = b"<AppendedData encoding=\"raw\">\n   _";
            let start = bytes.windows(marker.len()).position(|w| w == marker).unwrap() + marker.len();
            let data = &bytes[start + offset..];
            let first = u64::from_le_bytes(data[..8].try_into().unwrap());
            let len = vtu_header_len(first, c.compressed);
            f64s(vtu_block(&data[..len], &data[len..], c.compressed))
        }
    }
}

/// The per-face quality array a file holds (`None` for OBJ and OFF, which have none).
fn written_quality(bytes: &[u8], c: Case, faces: usize) -> Option<Vec<f64>> {
    let text = String::from_utf8_lossy(bytes);
    let msh_header = format!("$ElementData\n1\n\"scaled_jacobian\"\n1\n0.0\n3\n0\n1\n{faces}\n");
    Some(match (c.format, c.encoding) {
        (Format::Obj | Format::Off, _) => return None,
        (Format::Vtk, _) => {
            let header =
                format!("CELL_DATA {faces}\nSCALARS scaled_jacobian double 1\nLOOKUP_TABLE default\n");
            let start = text.find(&header).unwrap() + header.len();
            let values: Vec<&str> = text[start..].split_ascii_whitespace().take(faces).collect();
            reals(&values.join(" "))
        }
        (Format::Msh, Encoding::Ascii) => tagged(between(&text, &msh_header, "$EndElementData")),
        (Format::Msh, _) => {
            let at = bytes.windows(msh_header.len()).position(|w| w == msh_header.as_bytes()).unwrap();
            let entries = &bytes[at + msh_header.len()..][..12 * faces];
            entries
                .chunks_exact(12)
                .enumerate()
                .map(|(i, e)| {
                    assert_eq!(i32::from_le_bytes(e[..4].try_into().unwrap()), i as i32 + 1);
                    f64::from_le_bytes(e[4..].try_into().unwrap())
                })
                .collect()
        }
        (Format::Vtu, _) => vtu_quality(bytes, c),
    })
}

#[test]
fn mixed_meshes_round_trip_in_every_format_and_encoding() {
    let data = mixed();
    let quality = data.quality.clone().unwrap();
    for c in cases() {
        let data = with_case(&data, c);
        let bytes = io::write_mesh_bytes(c.format, &data).unwrap_or_else(|e| panic!("{c:?}: {e}"));
        let back = io::read_mesh_bytes(&bytes, c.format).unwrap_or_else(|e| panic!("{c:?}: {e}"));
        assert_eq!(bits(&back.points), bits(&data.points), "{c:?}");
        assert_eq!(back.quads, data.quads, "{c:?}");
        if matches!(c.format, Format::Obj | Format::Off) {
            assert_eq!(back.fixed, None, "{c:?}");
        } else {
            assert_eq!(back.fixed, data.fixed, "{c:?}");
            assert_eq!((back.encoding, back.compressed), (c.encoding, c.compressed), "{c:?}");
        }
        assert_eq!(back.msh_version, c.msh, "{c:?}");
        assert_eq!(back.vtk_polydata, c.polydata, "{c:?}");
        // One value per face, in the file's face order, bit for bit.
        if let Some(q) = written_quality(&bytes, c, 5) {
            assert_eq!(
                q.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                quality.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                "{c:?}"
            );
        }
        // What was read is the same 2D mesh, with the same quality.
        let planar = PlanarMesh::new(&back).unwrap();
        assert_eq!((planar.mesh.faces().len(), planar.mesh.triangle_count()), (5, 3), "{c:?}");
        assert_eq!(planar.mesh.quality_values(), quality, "{c:?}");
    }
}

#[test]
fn triangles_are_written_as_triangles() {
    let data = mixed();
    let text =
        |c: Case| String::from_utf8(io::write_mesh_bytes(c.format, &with_case(&data, c)).unwrap()).unwrap();
    let all = cases();
    let obj = text(all[0]);
    assert!(obj.contains("f 1 2 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8 7\nf 6 7 9\n"), "{obj}");
    let off = text(all[1]);
    assert!(
        off.contains("10 5 0\n") && off.contains("4 0 1 5 4\n3 1 2 6\n3 1 6 5\n4 2 3 7 6\n3 5 6 8\n"),
        "{off}"
    );
    let vtk = text(all[2]);
    assert!(
        vtk.contains(
            "CELLS 5 22\n4 0 1 5 4\n3 1 2 6\n3 1 6 5\n4 2 3 7 6\n3 5 6 8\nCELL_TYPES 5\n9\n5\n5\n9\n5\n"
        ),
        "{vtk}"
    );
    let poly = text(all[3]);
    assert!(poly.contains("POLYGONS 5 22\n4 0 1 5 4\n3 1 2 6\n") && !poly.contains("CELL_TYPES"), "{poly}");
    let msh2 = text(all[4]);
    assert!(msh2.contains("$Elements\n5\n1 3 2 0 1 1 2 6 5\n2 2 2 0 1 2 3 7\n3 2 2 0 1 2 7 6\n4 3 2 0 1 3 4 8 7\n5 2 2 0 1 6 7 9\n"), "{msh2}");
    // MSH 4.1: one element block per run of one type, so the elements keep their order.
    let msh4 = text(all[5]);
    assert!(
        msh4.contains("$Elements\n4 5 1 5\n2 1 3 1\n1 1 2 6 5\n2 1 2 2\n2 2 3 7\n3 2 7 6\n2 1 3 1\n4 3 4 8 7\n2 1 2 1\n5 6 7 9\n$EndElements"),
        "{msh4}"
    );
    let vtu = text(all[7]);
    assert!(vtu.contains("0 1 5 4 1 2 6 1 6 5 2 3 7 6 5 6 8\n"), "{vtu}");
    assert!(vtu.contains("4 7 10 14 17\n") && vtu.contains("9 5 5 9 5\n"), "{vtu}");
}

#[test]
fn faces_are_written_in_the_handedness_given() {
    let data = mixed();
    // The whole mesh clockwise: kept so.
    let mut cw = data.clone();
    cw.quads = data.quads.iter().map(|&f| face::reversed(f)).collect();
    let planar = PlanarMesh::new(&cw).unwrap();
    assert!(planar.mesh.has_clockwise_component());
    let mut copy = cw.clone();
    planar.write_back(&mut copy);
    assert_eq!(copy.quads, cw.quads);
    assert_eq!(copy.quads[1], [1, 6, 2, NO_VERTEX]);
    for c in cases() {
        let bytes = io::write_mesh_bytes(c.format, &with_case(&copy, c)).unwrap();
        assert_eq!(io::read_mesh_bytes(&bytes, c.format).unwrap().quads, cw.quads, "{c:?}");
    }
    // One triangle against its neighbours: written consistently oriented.
    let mut odd = data.clone();
    odd.quads[2] = face::reversed(odd.quads[2]);
    let planar = PlanarMesh::new(&odd).unwrap();
    assert_eq!(planar.mesh.reoriented(), &[2]);
    planar.write_back(&mut odd);
    assert_eq!(odd.quads, data.quads);
}

/// Two triangles making the unit square.
const TRIANGLES: [[u32; 4]; 2] = [[0, 1, 2, NO_VERTEX], [0, 2, 3, NO_VERTEX]];
const SQUARE: [[f64; 3]; 4] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];

const VTK_HEAD: &str = "# vtk DataFile Version 2.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n\
    0 0 0\n1 0 0\n1 1 0\n0 1 0\n";

fn vtu_ascii(types: &str, offsets: &str, connectivity: &str, cells: usize) -> String {
    format!(
        r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <UnstructuredGrid>
    <Piece NumberOfPoints="4" NumberOfCells="{cells}">
      <Points>
        <DataArray type="Float64" Name="Points" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 1 1 0 0 1 0</DataArray>
      </Points>
      <Cells>
        <DataArray type="Int64" Name="connectivity" format="ascii">{connectivity}</DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">{offsets}</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">{types}</DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
"#
    )
}

#[test]
fn triangle_only_files_read() {
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1/1 3/3/3 4//4\n";
    // Negative indices, and a face before its vertices.
    let obj_relative = "v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\nf 1 3 4\nv 0 1 0\n";
    let off = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3 255 0 0\n";
    let vtk = format!("{VTK_HEAD}CELLS 2 8\n3 0 1 2\n3 0 2 3\nCELL_TYPES 2\n5\n5\n");
    let vtk51 = VTK_HEAD.replace("UNSTRUCTURED_GRID", "POLYDATA")
        + "POLYGONS 3 6\nOFFSETS vtktypeint64\n0 3 6\nCONNECTIVITY vtktypeint64\n0 1 2 0 2 3\n";
    let vtk51_grid = format!(
        "{VTK_HEAD}CELLS 3 6\nOFFSETS vtktypeint64\n0 3 6\nCONNECTIVITY vtktypeint64\n0 1 2 0 2 3\nCELL_TYPES 2\n5\n5\n"
    );
    let nodes2 = "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n";
    let elements2 = "$Elements\n2\n1 2 2 0 1 1 2 3\n2 2 2 0 1 1 3 4\n$EndElements\n";
    let msh2 = format!("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n{nodes2}{elements2}");
    let msh2_elements_first = format!("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n{elements2}{nodes2}");
    let msh4 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n\
        $EndNodes\n$Elements\n1 2 1 2\n2 1 2 2\n1 1 2 3\n2 1 3 4\n$EndElements\n";
    let vtu = vtu_ascii("5 5", "3 6", "0 1 2 0 2 3", 2);
    let files: [(&str, &str, Format); 10] = [
        ("obj", obj, Format::Obj),
        ("obj relative", obj_relative, Format::Obj),
        ("off", off, Format::Off),
        ("vtk", &vtk, Format::Vtk),
        ("vtk 5.1 polydata", &vtk51, Format::Vtk),
        ("vtk 5.1 grid", &vtk51_grid, Format::Vtk),
        ("msh 2.2", &msh2, Format::Msh),
        ("msh 2.2 elements first", &msh2_elements_first, Format::Msh),
        ("msh 4.1", msh4, Format::Msh),
        ("vtu", &vtu, Format::Vtu),
    ];
    for (name, text, format) in files {
        let data = io::read_mesh_str(text, format).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((data.points.as_slice(), data.quads.as_slice()), (&SQUARE[..], &TRIANGLES[..]), "{name}");
        let planar = PlanarMesh::new(&data).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(planar.mesh.triangle_count(), 2, "{name}");
        // And written back (MSH binary included) it reads the same.
        for c in cases().into_iter().filter(|c| c.format == format) {
            let bytes = io::write_mesh_bytes(format, &with_case(&data, c)).unwrap();
            assert_eq!(io::read_mesh_bytes(&bytes, format).unwrap().quads, TRIANGLES, "{name} {c:?}");
        }
    }
}

#[test]
fn mixed_cells_in_the_vtk_offsets_layout_read() {
    let vtk = VTK_HEAD.replace("POINTS 4", "POINTS 5")
        + "2 0.5 0\nCELLS 3 7\nOFFSETS vtktypeint64\n0 4 7\nCONNECTIVITY vtktypeint64\n0 1 2 3\n1 4 2\nCELL_TYPES 2\n9\n5\n";
    let data = io::read_mesh_str(&vtk, Format::Vtk).unwrap();
    assert_eq!(data.quads, vec![[0, 1, 2, 3], face::triangle(1, 4, 2)]);
    // A point index out of range is named by its cell, whatever the sizes before it.
    let far = vtk.replace("1 4 2\n", "1 9 2\n");
    assert_eq!(
        io::read_mesh_str(&far, Format::Vtk).unwrap_err().to_string(),
        "line 16: cell 1 refers to point 9, but there are only 5 points (cell and point numbers are 0-based)"
    );
}

fn read_err(text: &str, format: Format) -> IoError {
    io::read_mesh_str(text, format).unwrap_err()
}

fn non_quad(e: &IoError) -> (usize, usize, &str) {
    match e {
        IoError::NonQuad { line, cell, kind } => (*line, *cell, kind),
        e => panic!("{e:?}"),
    }
}

#[test]
fn five_vertex_faces_are_errors_naming_them() {
    let pentagon = "2 0.5 0\n";
    let points5 = VTK_HEAD.replace("POINTS 4", "POINTS 5") + pentagon;

    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0.5 0\nf 1 2 3\nf 1 2 5 3 4\n";
    let e = read_err(obj, Format::Obj);
    assert_eq!(non_quad(&e), (7, 1, "polygon with 5 vertices"));
    assert_eq!(
        e.to_string(),
        "line 7: cell 1 is a polygon with 5 vertices; only triangles and quads are supported (cell numbers are 0-based)"
    );
    let obj = "v 0 0 0\nv 1 0 0\nf 1 2\n";
    assert_eq!(non_quad(&read_err(obj, Format::Obj)), (3, 0, "face with 2 vertices"));

    let off = "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0.5 0\n3 0 1 2\n5 0 1 4 2 3\n";
    assert_eq!(non_quad(&read_err(off, Format::Off)), (9, 1, "polygon with 5 vertices"));
    let off = "OFF\n3 1 0\n0 0 0\n1 0 0\n1 1 0\n3 0 1\n";
    assert_eq!(read_err(off, Format::Off).to_string(), "line 6: a triangle face needs 3 vertex indices");

    // VTK: a polygon cell, a quad or triangle cell of the wrong size, a POLYDATA polygon, in
    // both layouts.
    let vtk = format!("{points5}CELLS 2 10\n3 0 1 2\n5 0 1 4 2 3\nCELL_TYPES 2\n5\n7\n");
    assert_eq!(non_quad(&read_err(&vtk, Format::Vtk)), (16, 1, "polygon (VTK type 7) with 5 vertices"));
    let vtk = format!("{points5}CELLS 2 10\n3 0 1 2\n5 0 1 4 2 3\nCELL_TYPES 2\n5\n9\n");
    assert_eq!(
        read_err(&vtk, Format::Vtk).to_string(),
        "line 13: quad cell 1 has 5 vertices (cell numbers are 0-based)"
    );
    let vtk = format!("{points5}CELLS 2 9\n4 0 1 4 2\n4 0 2 3 1\nCELL_TYPES 2\n9\n5\n");
    assert_eq!(
        read_err(&vtk, Format::Vtk).to_string(),
        "line 13: triangle cell 1 has 4 vertices (cell numbers are 0-based)"
    );
    let vtk = format!("{points5}CELLS 2 8\n3 0 1 2\n3 0 2 3\nCELL_TYPES 2\n5\n9\n");
    assert_eq!(
        read_err(&vtk, Format::Vtk).to_string(),
        "line 13: quad cell 1 has 3 vertices (cell numbers are 0-based)"
    );
    let poly = points5.replace("UNSTRUCTURED_GRID", "POLYDATA") + "POLYGONS 2 10\n3 0 1 2\n5 0 1 4 2 3\n";
    assert_eq!(non_quad(&read_err(&poly, Format::Vtk)), (13, 1, "polygon with 5 vertices"));
    let poly51 = points5.replace("UNSTRUCTURED_GRID", "POLYDATA")
        + "POLYGONS 3 8\nOFFSETS vtktypeint64\n0 3\n8\nCONNECTIVITY vtktypeint64\n0 1 2 0 1 4 2 3\n";
    assert_eq!(non_quad(&read_err(&poly51, Format::Vtk)), (14, 1, "polygon with 5 vertices"));
    let grid51 = format!(
        "{points5}CELLS 3 8\nOFFSETS vtktypeint64\n0 3\n8\nCONNECTIVITY vtktypeint64\n0 1 2 0 1 4 2 3\nCELL_TYPES 2\n5\n7\n"
    );
    assert_eq!(non_quad(&read_err(&grid51, Format::Vtk)), (19, 1, "polygon (VTK type 7) with 5 vertices"));

    // VTU: a polygon cell (type 7), and a cell whose offsets disagree with its type.
    let vtu = vtu_ascii("5 7", "3 8", "0 1 2 0 1 3 2 3", 2);
    assert_eq!(
        read_err(&vtu, Format::Vtu).to_string(),
        "unsupported: cell 1 is of VTK type 7 (polygon) with 5 vertices; only triangles (type 5) and quads \
         (type 9) are read (cell numbers are 0-based)"
    );
    let vtu = vtu_ascii("5 9", "3 6", "0 1 2 0 2 3", 2);
    assert_eq!(
        read_err(&vtu, Format::Vtu).to_string(),
        "offsets: cell 1 ends at 6 after starting at 3 (a quad has 4 vertices; cell numbers are 0-based)"
    );

    // MSH has no polygon element: an element of another size, or type, is named.
    let head = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 2 0.5 0\n$EndNodes\n";
    let msh = format!("{head}$Elements\n2\n1 2 2 0 1 1 2 3\n2 3 2 0 1 1 2 5 3 4\n$EndElements\n");
    assert_eq!(
        read_err(&msh, Format::Msh).to_string(),
        "line 15: quad element 1 has 5 nodes (element numbers are 0-based)"
    );
    let msh = format!("{head}$Elements\n2\n1 2 2 0 1 1 2 3\n2 2 2 0 1 1 2 5 3\n$EndElements\n");
    assert_eq!(
        read_err(&msh, Format::Msh).to_string(),
        "line 15: triangle element 1 has 4 nodes (element numbers are 0-based)"
    );
    let msh = format!("{head}$Elements\n2\n1 2 2 0 1 1 2 3\n2 9 2 0 1 1 2 3 4 5 1\n$EndElements\n");
    assert_eq!(
        non_quad(&read_err(&msh, Format::Msh)),
        (15, 1, "higher-order triangle (Gmsh element type 9)")
    );
    // Binary: the 3-node triangle block of a written file turned into a 6-node one.
    let mut data = mixed();
    data.encoding = Encoding::Binary;
    let mut bytes = io::write_mesh_bytes(Format::Msh, &data).unwrap();
    let triangle_block = [2i32.to_le_bytes(), 1i32.to_le_bytes(), 2i32.to_le_bytes()].concat();
    let at = bytes.windows(12).position(|w| w == triangle_block.as_slice()).unwrap();
    bytes[at + 8..at + 12].copy_from_slice(&9i32.to_le_bytes());
    assert_eq!(
        io::read_mesh_bytes(&bytes, Format::Msh).unwrap_err().to_string(),
        "unsupported: element 1 has Gmsh element type 9; only triangles (type 2), quads (type 3), points and \
         lines are read (element numbers are 0-based)"
    );
}

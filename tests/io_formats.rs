//! Mesh file formats: round trips (bit-identical coordinates), the hand-written fixtures in
//! tests/data/io, and precise errors on malformed input.

mod common;

use common::grids::Grid;
use quadopt::io::{self, Format, IoError, MeshData, MshVersion, PlanarFrame, PlanarMesh};
use quadopt::{BoundaryMode, Error, Options, optimize};
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/io").join(name)
}

/// A scratch directory unique to one test.
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("quadopt-io-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn bits(points: &[[f64; 3]]) -> Vec<[u64; 3]> {
    points.iter().map(|p| p.map(f64::to_bits)).collect()
}

/// Coordinates chosen to break any lossy formatting: thirds, tiny and huge magnitudes,
/// negative zero, values needing 17 significant digits.
fn awkward_mesh() -> MeshData {
    let points = vec![
        [0.0, -0.0, 1.0 / 3.0],
        [0.1 + 0.2, 1e-300, 1.0 / 3.0],
        [std::f64::consts::PI, 123456789.12345679, 1.0 / 3.0],
        [-2.5e-7, 1e23, 1.0 / 3.0],
        [f64::MIN_POSITIVE, 5e-324, 1.0 / 3.0], // unused by any quad
        [1.7976931348623157e308, -1.0, 1.0 / 3.0],
    ];
    let quads = vec![[0, 1, 2, 3], [3, 2, 5, 0]];
    MeshData {
        points,
        quads,
        fixed: Some(vec![true, false, true, false, false, true]),
        ..MeshData::default()
    }
}

#[test]
fn every_format_round_trips_bit_identical() {
    for format in Format::ALL {
        let mesh = awkward_mesh();
        let text = io::write_mesh_string(format, &mesh).unwrap();
        let back = io::read_mesh_str(&text, format).unwrap();
        assert_eq!(bits(&back.points), bits(&mesh.points), "{format:?}");
        assert_eq!(back.quads, mesh.quads, "{format:?}");
        if matches!(format, Format::Vtk | Format::Msh | Format::Vtu) {
            assert_eq!(back.fixed, mesh.fixed, "{format:?}");
        } else {
            assert_eq!(back.fixed, None, "{format:?} has no fixed flags");
        }
    }
}

#[test]
fn format_details_are_kept() {
    let mut mesh = awkward_mesh();
    mesh.msh_version = Some(MshVersion::V2_2);
    let text = io::write_mesh_string(Format::Msh, &mesh).unwrap();
    assert!(text.starts_with("$MeshFormat\n2.2 0 8\n"), "{text}");
    let back = io::read_mesh_str(&text, Format::Msh).unwrap();
    assert_eq!(back.msh_version, Some(MshVersion::V2_2));
    assert_eq!(bits(&back.points), bits(&mesh.points));
    mesh.msh_version = None;
    assert!(io::write_mesh_string(Format::Msh, &mesh).unwrap().starts_with("$MeshFormat\n4.1 0 8\n"));

    mesh.vtk_polydata = true;
    let text = io::write_mesh_string(Format::Vtk, &mesh).unwrap();
    assert!(text.contains("DATASET POLYDATA\n") && text.contains("POLYGONS 2 10\n"), "{text}");
    let back = io::read_mesh_str(&text, Format::Vtk).unwrap();
    assert!(back.vtk_polydata);
    assert_eq!((back.quads, back.fixed), (mesh.quads, mesh.fixed));
}

#[test]
fn files_round_trip_and_overwrite_atomically() {
    let dir = scratch("files");
    for format in Format::ALL {
        let path = dir.join(format!("mesh.{}", format.extension().to_uppercase()));
        let mesh = awkward_mesh();
        io::write_mesh(&path, &mesh).unwrap();
        io::write_mesh(&path, &mesh).unwrap(); // overwrite in place
        let back = io::read_mesh(&path).unwrap();
        assert_eq!(bits(&back.points), bits(&mesh.points));
    }
    // Only the meshes: no temporary files left behind.
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), Format::ALL.len());
    // A mesh that fails validation is not written at all.
    let bad = MeshData::new(vec![[0.0; 3]; 3], vec![[0, 1, 2, 3]]);
    let path = dir.join("bad.obj");
    assert!(matches!(
        io::write_mesh(&path, &bad),
        Err(IoError::Mesh(Error::IndexOutOfRange { quad: 0, corner: 3, .. }))
    ));
    assert!(!path.exists());
    // An unwritable location fails with the path named, and leaves nothing.
    let err = io::write_mesh(dir.join("no/such/dir/m.obj"), &awkward_mesh()).unwrap_err();
    assert!(
        err.to_string().starts_with("cannot write ") && err.to_string().contains("no/such/dir/m.obj"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The two-square strip every fixture holds, with the unused vertex (9, 9).
fn strip_points(z: f64) -> Vec<[f64; 3]> {
    [(0., 0.), (1., 0.), (2., 0.), (0., 1.), (1., 1.), (2., 1.), (9., 9.)]
        .iter()
        .map(|&(x, y)| [x, y, z])
        .collect()
}

#[test]
fn fixtures_read() {
    let strip = vec![[0, 1, 4, 3], [1, 2, 5, 4]];
    for (name, version) in [("square2x1_v22.msh", MshVersion::V2_2), ("square2x1_v41.msh", MshVersion::V4_1)]
    {
        let m = io::read_mesh(fixture(name)).unwrap();
        assert_eq!((m.points.clone(), m.quads.clone()), (strip_points(0.0), strip.clone()), "{name}");
        assert_eq!(m.msh_version, Some(version));
    }
    for name in ["square2x1.obj", "square2x1.off"] {
        let m = io::read_mesh(fixture(name)).unwrap();
        assert_eq!((m.points, m.quads, m.fixed), (strip_points(0.0), strip.clone(), None), "{name}");
    }
    let m = io::read_mesh(fixture("square2x1_polydata_v51.vtk")).unwrap();
    assert_eq!((m.points, m.quads.clone()), (strip_points(0.0), strip.clone()));
    assert_eq!(m.fixed, Some(vec![true, true, true, true, false, true, false]));
    assert!(m.vtk_polydata);
    let m = io::read_mesh(fixture("square2x1_grid.vtk")).unwrap();
    assert_eq!((m.points, m.quads.clone()), (strip_points(-5.0), strip));
    assert_eq!(m.fixed, Some(vec![true, false, true, true, false, true, true]));
    assert!(!m.vtk_polydata);
}

fn read_err(text: &str, format: Format) -> IoError {
    io::read_mesh_str(text, format).unwrap_err()
}

const VTK_HEAD: &str = "# vtk DataFile Version 2.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 6 float\n\
    0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n";

#[test]
fn non_quad_cells_are_named() {
    // Triangles are read (tests/io_triangles.rs has the rest); other cells are named.
    let vtk = format!("{VTK_HEAD}CELLS 2 9\n4 0 1 4 3\n3 1 2 5\nCELL_TYPES 2\n9\n5\n");
    let m = io::read_mesh_str(&vtk, Format::Vtk).unwrap();
    assert_eq!(m.quads, vec![[0, 1, 4, 3], quadopt::face::triangle(1, 2, 5)]);
    let vtk = format!("{VTK_HEAD}CELLS 2 11\n4 0 1 4 3\n5 1 2 5 4 0\nCELL_TYPES 2\n9\n7\n");
    let e = read_err(&vtk, Format::Vtk);
    assert!(
        matches!(&e, IoError::NonQuad { line: 17, cell: 1, kind } if kind == "polygon (VTK type 7) with 5 vertices"),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "line 17: cell 1 is a polygon (VTK type 7) with 5 vertices; only triangles and quads are supported \
         (cell numbers are 0-based)"
    );
    let vtk = format!("{VTK_HEAD}CELLS 2 8\n4 0 1 4 3\n2 1 2\nCELL_TYPES 2\n9\n3\n");
    assert!(
        matches!(read_err(&vtk, Format::Vtk), IoError::NonQuad { cell: 1, kind, .. } if kind == "line (VTK type 3)")
    );
    let poly = VTK_HEAD.replace("UNSTRUCTURED_GRID", "POLYDATA") + "POLYGONS 2 11\n4 0 1 4 3\n5 1 2 5 4 0\n";
    assert!(
        matches!(read_err(&poly, Format::Vtk), IoError::NonQuad { line: 14, cell: 1, kind } if kind == "polygon with 5 vertices")
    );
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 2 3 4 1\n";
    assert!(
        matches!(read_err(obj, Format::Obj), IoError::NonQuad { line: 6, cell: 1, kind } if kind == "polygon with 5 vertices")
    );
    let off = "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n5 0 1 2 3 0\n";
    assert!(
        matches!(read_err(off, Format::Off), IoError::NonQuad { line: 7, cell: 0, kind } if kind == "polygon with 5 vertices")
    );
    let msh = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n\
        $Elements\n2\n1 1 2 0 1 1 2\n2 4 2 0 1 1 2 3 4\n$EndElements\n";
    assert!(
        matches!(read_err(msh, Format::Msh), IoError::NonQuad { line: 14, cell: 1, kind } if kind == "tetrahedron (Gmsh element type 4)")
    );
}

#[test]
fn out_of_range_indices_are_errors() {
    let vtk = format!("{VTK_HEAD}CELLS 1 5\n4 0 1 9 3\nCELL_TYPES 1\n9\n");
    let e = read_err(&vtk, Format::Vtk);
    assert_eq!(
        e.to_string(),
        "line 13: cell 0 refers to point 9, but there are only 6 points (cell and point numbers are 0-based)"
    );
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 5\n";
    assert_eq!(read_err(obj, Format::Obj).to_string(), "line 5: vertex index 5 is out of range (4 vertices)");
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nf -1 -2 -3 -4\nv 0 1 0\n";
    assert_eq!(
        read_err(obj, Format::Obj).to_string(),
        "line 4: vertex index -4 is out of range (4 vertices)"
    );
    let off = "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 4\n";
    assert_eq!(read_err(off, Format::Off).to_string(), "line 7: vertex index 4 is out of range (4 vertices)");
    let msh = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n\
        $Elements\n1\n7 3 0 1 2 3 5\n$EndElements\n";
    assert_eq!(
        read_err(msh, Format::Msh).to_string(),
        "line 13: element 0 refers to node 5, which does not exist (element numbers are 0-based, node numbers \
         are the file's tags)"
    );
}

#[test]
fn missing_file_and_unknown_extension_name_the_path() {
    let e = io::read_mesh("/nonexistent/dir/mesh.obj").unwrap_err();
    assert!(matches!(&e, IoError::File { action: "read", .. }));
    let msg = e.to_string();
    assert!(msg.starts_with("cannot read /nonexistent/dir/mesh.obj: "), "{msg}");
    assert!(!msg.contains('\n'));
    let e = io::read_mesh(fixture("square2x1.obj").with_extension("stl")).unwrap_err();
    assert!(matches!(e, IoError::UnknownFormat { .. }));
    assert!(
        e.to_string().ends_with(
            "square2x1.stl: unknown mesh format (expected the extension .obj, .off, .vtk, .msh or .vtu)"
        ),
        "{e}"
    );
    assert!(matches!(io::write_mesh("out.stl", &awkward_mesh()), Err(IoError::UnknownFormat { .. })));
    // Errors inside a file name the file and the line.
    let dir = scratch("named");
    let path = dir.join("broken.off");
    std::fs::write(&path, "OFF\n1 0 0\n0 zero 0\n").unwrap();
    let msg = io::read_mesh(&path).unwrap_err().to_string();
    assert_eq!(msg, format!("{}: line 3: expected a coordinate (a number), found 'zero'", path.display()));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn truncated_files_are_errors_and_no_prefix_panics() {
    for format in Format::ALL {
        let text = io::write_mesh_string(format, &awkward_mesh()).unwrap();
        // Cut inside the coordinates: always an error.
        let cut = &text[..text.find("123456789").unwrap()];
        let e = read_err(cut, format);
        assert!(matches!(e, IoError::Parse { .. } | IoError::Malformed(_)), "{format:?}: {e:?}");
        // Every prefix either fails cleanly or reads a mesh whose indices are valid.
        for end in 0..text.len() {
            if let Ok(m) = io::read_mesh_str(&text[..end], format) {
                m.check().unwrap();
            }
        }
    }
    let vtk = format!("{VTK_HEAD}CELLS 2 10\n4 0 1 4 3\n");
    assert_eq!(read_err(&vtk, Format::Vtk).to_string(), "line 13: unexpected end of file (expected a cell)");
    // Forged huge counts fail on the missing data instead of allocating.
    let vtk = "# vtk DataFile Version 2.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 4000000000 float\n0 0 0\n";
    assert!(matches!(read_err(vtk, Format::Vtk), IoError::Parse { line: 6, .. }));
    let off = "OFF\n18446744073709551615 18446744073709551615 0\n";
    assert!(read_err(off, Format::Off).to_string().contains("too many"));
}

#[test]
fn unsupported_variants_are_refused() {
    let bin = "# vtk DataFile Version 2.0\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\n";
    assert!(matches!(read_err(bin, Format::Vtk), IoError::Unsupported(_)));
    // Binary MSH 2.2 is refused by name; a binary 4.1 header without its byte-order check
    // is a malformed file, not an unsupported one; file types other than 0 and 1 are errors.
    let msh = "$MeshFormat\n2.2 1 8\n$EndMeshFormat\n";
    assert!(
        matches!(read_err(msh, Format::Msh), IoError::Unsupported(m) if m.contains("binary MSH version 2.2"))
    );
    let msh = "$MeshFormat\n4.1 1 8\n$EndMeshFormat\n";
    let e = read_err(msh, Format::Msh);
    assert!(matches!(e, IoError::Malformed(_) | IoError::Parse { .. }), "{e:?}");
    assert!(!e.to_string().contains('\n'), "{e}");
    let msh = "$MeshFormat\n4.1 2 8\n$EndMeshFormat\n";
    assert!(read_err(msh, Format::Msh).to_string().contains("file type '2'"));
    let msh = "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n";
    assert!(matches!(read_err(msh, Format::Msh), IoError::Unsupported(m) if m.contains("3.0")));
    let sp = "# vtk DataFile Version 2.0\nt\nASCII\nDATASET STRUCTURED_POINTS\n";
    assert!(matches!(read_err(sp, Format::Vtk), IoError::Unsupported(_)));
}

/// A 4x4 grid of unit squares in the plane through `origin` spanned by `u` and `v`, with the
/// interior vertices jittered and the boundary vertices fixed.
fn tilted_grid(origin: [f64; 3], u: [f64; 3], v: [f64; 3]) -> MeshData {
    let grid = Grid::square(4);
    let mut points = grid.per_vertex(|i, j| {
        let (mut a, mut b) = (i as f64, j as f64);
        if grid.is_interior(i, j) {
            a += 0.3 * ((i * 7 + j * 3) as f64).sin();
            b += 0.3 * ((i * 5 + j * 11) as f64).cos();
        }
        [0, 1, 2].map(|k| origin[k] + a * u[k] + b * v[k])
    });
    let mut fixed = grid.per_vertex(|i, j| grid.on_boundary(i, j));
    points.push([100.0, -3.0, 7.0]); // unused, far off the plane
    fixed.push(false);
    MeshData { points, quads: grid.quads(), fixed: Some(fixed), ..MeshData::default() }
}

#[test]
fn tilted_plane_mesh_is_optimized_in_its_plane() {
    let s = 0.5f64.sqrt();
    let (origin, u, v) = ([1.0, 2.0, 3.0], [s, 0.0, s], [0.0, 1.0, 0.0]);
    let mut data = tilted_grid(origin, u, v);
    let original = data.clone();
    let mut planar = PlanarMesh::new(&data).unwrap();
    assert!(matches!(planar.frame, PlanarFrame::Tilted { .. }));
    let options = Options::default().with_boundary(BoundaryMode::Fixed);
    let report = optimize(&mut planar.mesh, &options).unwrap();
    assert!(report.output.avg > report.input.avg);
    assert_eq!(planar.moved(&data).len(), 9, "exactly the interior vertices moved");
    assert_eq!(planar.write_back(&mut data), 9);
    let normal = [-s, 0.0, s]; // u x v
    for (i, (p, q)) in data.points.iter().zip(&original.points).enumerate() {
        if i == 25 || original.fixed.as_ref().unwrap()[i] {
            assert_eq!(p.map(f64::to_bits), q.map(f64::to_bits), "vertex {i} did not move");
        } else {
            assert_ne!(p, q, "vertex {i}");
            let d: f64 = (0..3).map(|k| (p[k] - origin[k]) * normal[k]).sum();
            assert!(d.abs() < 1e-12, "vertex {i} left the plane by {d}");
        }
    }
}

#[test]
fn axis_aligned_plane_keeps_the_constant_coordinate() {
    let mut data = tilted_grid([0.5, 0.25, -5.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    let mut planar = PlanarMesh::new(&data).unwrap();
    // The unused vertex at z = 7 does not count.
    assert_eq!(planar.frame, PlanarFrame::Axis { axis: 2, value: -5.0 });
    optimize(&mut planar.mesh, &Options::default().with_boundary(BoundaryMode::Fixed)).unwrap();
    planar.write_back(&mut data);
    assert!(data.points[..25].iter().all(|p| p[2] == -5.0));
    assert_eq!(data.points[25], [100.0, -3.0, 7.0]);
    // x = const: the 2D frame is (y, z).
    let data = tilted_grid([2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    let planar = PlanarMesh::new(&data).unwrap();
    assert_eq!(planar.frame, PlanarFrame::Axis { axis: 0, value: 2.0 });
    assert_eq!(planar.frame.to_3d(planar.mesh.points()[7]), data.points[7]);
}

#[test]
fn curved_mesh_is_rejected() {
    // A paraboloid patch: z = 0.05 (x^2 + y^2) over the 4x4 grid.
    let mut data = tilted_grid([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    data.points.pop();
    data.fixed = None;
    for p in &mut data.points {
        p[2] = 0.05 * (p[0] * p[0] + p[1] * p[1]);
    }
    match PlanarMesh::new(&data) {
        Err(IoError::Mesh(Error::NotPlanar { distance, tolerance, .. })) => {
            assert!(distance > 0.1 && tolerance < 1e-3, "{distance} {tolerance}")
        }
        other => panic!("expected NotPlanar, got {other:?}"),
    }
    // The tolerance is rounding's: a tilted plane in doubles is planar, the same plane written
    // with 6 decimals (1e-7 of its size off the plane) is a surface, and so is a sheet whose z
    // wobbles by 1e-4 of its size.
    let tilted = tilted_grid([0.0; 3], [0.6, 0.0, 0.8], [0.0, 1.0, 0.0]);
    assert!(PlanarMesh::new(&tilted).is_ok());
    let mut rounded = tilted.clone();
    for p in &mut rounded.points {
        *p = p.map(|c| format!("{c:.6}").parse().unwrap());
    }
    match PlanarMesh::new(&rounded) {
        Err(IoError::Mesh(Error::NotPlanar { distance, tolerance, .. })) => {
            assert!(distance > 1e-8 && tolerance < 1e-10, "{distance} {tolerance}")
        }
        other => panic!("expected NotPlanar, got {other:?}"),
    }
    let mut wobble = tilted_grid([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    for p in &mut wobble.points[..25] {
        p[2] = 4e-4 * (p[0] * 1.7).sin() * (p[1] * 0.9).cos();
    }
    assert!(matches!(PlanarMesh::new(&wobble), Err(IoError::Mesh(Error::NotPlanar { .. }))));
}

#[test]
fn mutated_fixtures_never_panic() {
    // A deterministic xorshift: flip, delete and duplicate bytes of every fixture; the readers
    // must return (Ok or Err) for every variant, and whatever they accept must be consistent.
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let alphabet = b"0123456789 -.e\n/#$ABCDEFGHIJKLMNOPQRSTUVWXYZ";
    for entry in std::fs::read_dir(fixture("")).unwrap() {
        let path = entry.unwrap().path();
        let format = Format::from_path(&path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        for _ in 0..400 {
            let mut b = bytes.clone();
            for _ in 0..1 + next() % 4 {
                let at = (next() as usize) % b.len();
                match next() % 3 {
                    0 => b[at] = alphabet[(next() as usize) % alphabet.len()],
                    1 => {
                        b.remove(at);
                    }
                    _ => b.insert(at, alphabet[(next() as usize) % alphabet.len()]),
                }
            }
            if let Ok(m) = io::read_mesh_bytes(&b, format) {
                m.check().unwrap();
                let _ = PlanarMesh::new(&m);
            }
        }
    }
}

#[test]
fn a_byte_order_mark_is_skipped_in_every_format() {
    // The reported case: a BOM right before the first `v` used to hide that vertex and shift
    // every index by one.
    let obj = "\u{feff}v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    let m = io::read_mesh_str(obj, Format::Obj).unwrap();
    assert_eq!(m.points, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]);
    assert_eq!(m.quads, [[0, 1, 2, 3]]);
    let dir = scratch("bom");
    for format in Format::ALL {
        let mesh = awkward_mesh();
        let text = io::write_mesh_string(format, &mesh).unwrap();
        let plain = io::read_mesh_str(&text, format).unwrap();
        let with_bom = io::read_mesh_str(&format!("\u{feff}{text}"), format).unwrap();
        assert_eq!(with_bom, plain, "{format:?}");
        // From a file's bytes too.
        let path = dir.join(format!("bom.{}", format.extension()));
        std::fs::write(&path, [b"\xef\xbb\xbf".as_slice(), text.as_bytes()].concat()).unwrap();
        let from_file = io::read_mesh(&path).unwrap();
        assert_eq!(bits(&from_file.points), bits(&mesh.points), "{format:?}");
        assert_eq!(from_file.quads, mesh.quads, "{format:?}");
    }
    // Only one leading BOM is a BOM: a second one makes `\u{feff}v` an unknown statement,
    // and the face then refers to a missing vertex, an error rather than a shifted mesh.
    let twice = format!("\u{feff}{obj}");
    assert!(io::read_mesh_str(&twice, Format::Obj).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn msh_fixed_flags_round_trip_in_both_versions_and_views_are_checked() {
    for version in [MshVersion::V2_2, MshVersion::V4_1] {
        let mut mesh = awkward_mesh();
        mesh.msh_version = Some(version);
        mesh.quality = Some(vec![0.25, -0.5]);
        mesh.corner = Some(vec![false, true, false, false, true, false]);
        let text = io::write_mesh_string(Format::Msh, &mesh).unwrap();
        let back = io::read_mesh_str(&text, Format::Msh).unwrap();
        // `fixed` is read back; the quality and corner views are skipped.
        assert_eq!(back.fixed, mesh.fixed, "{version:?}");
        assert_eq!((back.quality, back.corner), (None, None));
    }
    let mesh = awkward_mesh();
    let text = io::write_mesh_string(Format::Msh, &mesh).unwrap();
    let bad = text.replace("\n6 1\n$EndNodeData", "\n9 1\n$EndNodeData");
    let e = io::read_mesh_str(&bad, Format::Msh).unwrap_err().to_string();
    assert!(e.contains("view \"fixed\" refers to node 9, which does not exist"), "{e}");
    let truncated = &text[..text.find("$EndNodeData").unwrap()];
    assert!(io::read_mesh_str(truncated, Format::Msh).is_err());
    // Arrays of the wrong length are refused before anything is written.
    let mut wrong = awkward_mesh();
    wrong.quality = Some(vec![1.0]);
    let e = io::write_mesh_string(Format::Vtk, &wrong).unwrap_err().to_string();
    assert!(e.contains("1 quality values for 2 quads"), "{e}");
}

//! Mesh files through OpenMesh (cargo feature `openmesh`, crate openmesh-sys): `.ply` and `.om`
//! are always read and written with OpenMesh; `--reader openmesh` also reads `.obj` and `.off`
//! with it (as an OpenMesh-based tool would load them). Every other case goes to quadopt's own
//! readers and writers (`quadopt::io`). Without the feature, `.ply` and `.om` are an error that
//! says how to get them. Faces of three vertices are triangles (`NO_VERTEX` fourth in
//! `MeshData`), written back as three-vertex faces; a face of five or more vertices is an error
//! naming it.

use quadopt::io::{self, MeshData};
use std::path::Path;
use std::sync::OnceLock;

/// Whether OpenMesh support (`.ply`, `.om`, `--reader openmesh`) is compiled in.
pub const ENABLED: bool = cfg!(feature = "openmesh");

/// `optimize --help` on its input: the formats this build reads.
pub const INPUT_HELP: &str = if ENABLED {
    "Input mesh (.obj, .off, .vtk, .msh, .vtu; .ply and .om through OpenMesh)"
} else {
    "Input mesh (.obj, .off, .vtk, .msh, .vtu)"
};

/// Which reader loads `.obj` and `.off` files.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Reader {
    /// quadopt's own parsers for .obj, .off, .vtk, .msh, .vtu; OpenMesh for .ply and .om.
    #[default]
    Auto,
    /// OpenMesh for every format it reads (.ply, .om, .obj, .off).
    Openmesh,
}

/// `--version`: the package version and whether OpenMesh support is compiled in.
pub const VERSION: &str = if cfg!(feature = "openmesh") {
    concat!(env!("CARGO_PKG_VERSION"), " (OpenMesh support: PLY, OM; --reader openmesh)")
} else {
    concat!(env!("CARGO_PKG_VERSION"), " (without OpenMesh support: build with --features openmesh)")
};

static READER: OnceLock<Reader> = OnceLock::new();

/// Records `--reader` (once, from main).
pub fn set_reader(reader: Reader) -> Result<(), String> {
    if reader == Reader::Openmesh && !cfg!(feature = "openmesh") {
        return Err("--reader openmesh: this quadopt was built without OpenMesh support (build with --features openmesh)".into());
    }
    let _ = READER.set(reader);
    Ok(())
}

fn extension(path: &Path) -> String {
    path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).unwrap_or_default()
}

/// Whether OpenMesh handles this file: `.ply`, `.om`, and `.obj`/`.off` when `reading` with
/// `--reader openmesh`.
fn through_openmesh(path: &Path, reading: bool) -> bool {
    match extension(path).as_str() {
        "ply" | "om" => true,
        "obj" | "off" => reading && READER.get() == Some(&Reader::Openmesh),
        _ => false,
    }
}

#[cfg(not(feature = "openmesh"))]
fn without_openmesh(path: &Path) -> String {
    format!(
        "{}: .{} files are read and written through OpenMesh, which this quadopt was built without \
         (build with --features openmesh)",
        path.display(),
        extension(path)
    )
}

/// Reads a mesh file with OpenMesh or quadopt's readers (see the module documentation).
pub fn read_mesh(path: &Path) -> Result<MeshData, String> {
    if !through_openmesh(path, true) {
        return io::read_mesh(path).map_err(|e| e.to_string());
    }
    #[cfg(feature = "openmesh")]
    {
        let (arrays, _) = openmesh_sys::read(path).map_err(|e| e.to_string())?;
        to_mesh_data(&arrays).map_err(|m| format!("{}: {m}", path.display()))
    }
    #[cfg(not(feature = "openmesh"))]
    Err(without_openmesh(path))
}

/// Whether OpenMesh writes `path` (`.ply`, `.om`); other outputs go to quadopt's writers.
pub fn handles_output(path: &Path) -> bool {
    through_openmesh(path, false)
}

/// Checks, before any work, that `path` names a format that can be written.
pub fn check_output(path: &Path) -> Result<(), String> {
    if through_openmesh(path, false) {
        #[cfg(not(feature = "openmesh"))]
        return Err(without_openmesh(path));
        #[cfg(feature = "openmesh")]
        return Ok(());
    }
    io::Format::from_path(path).map(|_| ()).map_err(|e| e.to_string())
}

/// Writes a mesh file with OpenMesh (`.ply`, `.om`) or quadopt's writers; either way the file
/// itself is written by `quadopt::io::write_file` (a securely created temporary file renamed
/// over a regular file, devices and FIFOs in place).
pub fn write_mesh(path: &Path, data: &MeshData) -> Result<(), String> {
    if !through_openmesh(path, false) {
        return io::write_mesh(path, data).map_err(|e| e.to_string());
    }
    #[cfg(feature = "openmesh")]
    {
        data.check().map_err(|e| e.to_string())?;
        let arrays = to_arrays(data);
        // OpenMesh 9 stores PLY coordinates as float32: say so when that rounds anything.
        let rounded = arrays.points.iter().filter(|p| p.iter().any(|&c| f64::from(c as f32) != c)).count();
        let binary = extension(path) == "ply";
        let options = openmesh_sys::WriteOptions { binary, round_to_f32: true };
        let format = openmesh_sys::Format::from_path(path)
            .ok_or_else(|| format!("{}: not a PLY or OM file", path.display()))?;
        let bytes = openmesh_sys::write_bytes(&arrays, format, &options)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        io::write_file(path, &bytes).map_err(|e| e.to_string())?;
        if rounded > 0 && !openmesh_sys::Format::from_path(path).is_some_and(|f| f.keeps_f64()) {
            eprintln!(
                "quadopt: note: {}: PLY through OpenMesh 9 stores float32 coordinates; {rounded} vertices \
                 were rounded (write .om for full precision)",
                path.display()
            );
        }
        Ok(())
    }
    #[cfg(not(feature = "openmesh"))]
    Err(without_openmesh(path))
}

/// OpenMesh's arrays as quadopt's mesh: every face must be a quad or a triangle (a triangle
/// gets [`NO_VERTEX`](quadopt::face::NO_VERTEX) in its fourth slot, as in `quadopt::face`).
#[cfg(feature = "openmesh")]
fn to_mesh_data(a: &openmesh_sys::MeshArrays) -> Result<MeshData, String> {
    let mut quads = Vec::with_capacity(a.face_count());
    for (f, face) in a.faces().enumerate() {
        match *face {
            [v0, v1, v2, v3] => quads.push([v0, v1, v2, v3]),
            [v0, v1, v2] => quads.push(quadopt::face::triangle(v0, v1, v2)),
            _ => {
                return Err(format!(
                    "face {f} has {} vertices; only quads and triangles are supported (face numbers are 0-based)",
                    face.len()
                ));
            }
        }
    }
    let data = MeshData { points: a.points.clone(), quads, fixed: a.fixed.clone(), ..MeshData::default() };
    data.check().map_err(|e| e.to_string())?;
    Ok(data)
}

/// quadopt's mesh as OpenMesh's arrays: a quad as four vertices, a triangle as three.
#[cfg(feature = "openmesh")]
fn to_arrays(data: &MeshData) -> openmesh_sys::MeshArrays {
    let mut a =
        openmesh_sys::MeshArrays::new(data.points.clone(), data.quads.iter().map(quadopt::face::vertices));
    a.fixed = data.fixed.clone();
    a
}

#[cfg(all(test, feature = "openmesh"))]
mod tests {
    use super::*;

    #[test]
    fn quads_convert_both_ways_and_other_faces_are_refused() {
        let mut data = MeshData::new(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [2.0, 0.5, 0.0]],
            vec![[0, 1, 2, 3]],
        );
        data.fixed = Some(vec![true, false, false, true, false]);
        let arrays = to_arrays(&data);
        assert_eq!(arrays.face(0), &[0, 1, 2, 3]);
        assert_eq!(to_mesh_data(&arrays).unwrap(), data);
        let pentagon =
            openmesh_sys::MeshArrays::new(data.points.clone(), [vec![1, 4, 2], vec![0, 1, 4, 2, 3]]);
        assert_eq!(
            to_mesh_data(&pentagon).unwrap_err(),
            "face 1 has 5 vertices; only quads and triangles are supported (face numbers are 0-based)"
        );
    }

    /// Two quads and a triangle (cpp_tests/data/mixed.obj): the triangle becomes a face with
    /// NO_VERTEX fourth, goes back to OpenMesh as a 3-vertex face, and survives PLY and OM.
    #[test]
    fn triangles_convert_both_ways_and_survive_ply_and_om() {
        use quadopt::face::{NO_VERTEX, triangle};
        let points = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [2.0, 1.0, 0.0],
            [1.0, 2.0, 0.0],
        ];
        let arrays = openmesh_sys::MeshArrays::new(
            points.clone(),
            [vec![0, 1, 4, 3], vec![1, 2, 5, 4], vec![3, 4, 6]],
        );
        let data = to_mesh_data(&arrays).unwrap();
        assert_eq!(data.quads, vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 6, NO_VERTEX]]);
        assert_eq!(data.quads[2], triangle(3, 4, 6));
        let back = to_arrays(&data);
        assert_eq!(back, arrays);
        assert_eq!(back.face_offsets, vec![0, 4, 8, 11]);
        for (format, binary) in [
            (openmesh_sys::Format::Ply, false),
            (openmesh_sys::Format::Ply, true),
            (openmesh_sys::Format::Om, false),
        ] {
            let options = openmesh_sys::WriteOptions { binary, round_to_f32: false };
            let bytes = openmesh_sys::write_bytes(&back, format, &options).unwrap();
            let (read, _) = openmesh_sys::read_bytes(&bytes, format).unwrap();
            assert_eq!(to_mesh_data(&read).unwrap().quads, data.quads, "{format} (binary: {binary})");
        }
        // A triangle written with a NO_VERTEX fourth is never passed to OpenMesh as an index.
        assert!(back.face_indices.iter().all(|&v| (v as usize) < points.len()));
    }
}

//! Mesh files as the commands read and write them: `.ply` and `.om` through OpenMesh
//! ([`openmesh_io`]), the rest through `quadopt::io`, and `-o -` on stdout. A file is always
//! written by `quadopt::io`'s atomic output ([`quadopt::io::write_output`]), never here.

use crate::fail::Fail;
use crate::openmesh_io;
use crate::stdout::{is_stdout, stdout_write_error};
use glam::DVec3;
use quadopt::io::{self, Format, MeshData, PlanarMesh};
use quadopt::surface::SurfaceMesh;
use std::path::Path;

/// A mesh read from a file and mapped to 2D.
pub struct Loaded {
    pub data: MeshData,
    pub planar: PlanarMesh,
}

/// A mesh file as the commands read it: planar (optimized in its plane, as ever) or on a
/// curved surface (optimized on that surface).
pub enum Input {
    Planar(Loaded),
    Curved(Curved),
}

/// A mesh on a curved surface.
pub struct Curved {
    pub data: MeshData,
    pub surface: SurfaceMesh,
}

/// Reads `path` (the nodes of the physical groups named in `fix` join the fixed flags) and
/// maps it to 2D; a mesh that is not planar is read as a surface mesh in 3D instead.
pub fn load_input(path: &Path, fix: &[String]) -> Result<Input, Fail> {
    let mut data = openmesh_io::read_mesh(path)?;
    let failed = |e: &dyn std::fmt::Display| Fail::Other(format!("{}: {e}", path.display()));
    fix_physical(&mut data, fix).map_err(|e| failed(&e))?;
    match PlanarMesh::new(&data) {
        Ok(planar) => Ok(Input::Planar(Loaded { data, planar })),
        Err(io::IoError::Mesh(quadopt::Error::NotPlanar { .. })) => {
            let points = data.points.iter().map(|&p| DVec3::from_array(p)).collect();
            let surface =
                SurfaceMesh::new(points, data.quads.clone(), data.fixed.clone()).map_err(|e| failed(&e))?;
            Ok(Input::Curved(Curved { data, surface }))
        }
        Err(e) => Err(failed(&e)),
    }
}

/// The feature edges a user marks for a surface mesh: the pairs of `--feature-edges FILE`
/// (two 0-based vertex numbers per line; `#` starts a comment) and, for each name of
/// `--feature-physical`, every edge of the mesh whose two vertices are nodes of that Gmsh
/// physical curve.
pub fn marked_edges(
    data: &MeshData,
    surface: &SurfaceMesh,
    file: Option<&Path>,
    physical: &[String],
) -> Result<Vec<[u32; 2]>, Fail> {
    let mut edges = Vec::new();
    if let Some(file) = file {
        let text = std::fs::read_to_string(file)
            .map_err(|e| Fail::Other(format!("cannot read the feature edges {}: {e}", file.display())))?;
        for (k, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let bad = || {
                Fail::Other(format!(
                    "{}:{}: expected two vertex numbers, found '{line}'",
                    file.display(),
                    k + 1
                ))
            };
            let numbers: Vec<u32> = line
                .split(|c: char| c.is_whitespace() || c == ',')
                .filter(|t| !t.is_empty())
                .map(|t| t.parse().map_err(|_| bad()))
                .collect::<Result<_, _>>()?;
            match numbers[..] {
                [a, b] => edges.push([a, b]),
                _ => return Err(bad()),
            }
        }
    }
    for name in physical {
        let groups: Vec<&io::PhysicalGroup> =
            data.physical_groups.iter().filter(|g| &g.name == name && g.dim == 1).collect();
        if groups.is_empty() {
            return Err(Fail::Other(format!("--feature-physical {name}: no physical curve of that name")));
        }
        for g in groups {
            let inside = |v: u32| g.nodes.binary_search(&v).is_ok();
            edges.extend(surface.edges().iter().filter(|e| inside(e.a) && inside(e.b)).map(|e| [e.a, e.b]));
        }
    }
    Ok(edges)
}

/// Pins every node of the physical points and curves named `names` (all groups of a name).
fn fix_physical(data: &mut MeshData, names: &[String]) -> Result<(), String> {
    let n = data.points.len();
    for name in names {
        let groups: Vec<&io::PhysicalGroup> =
            data.physical_groups.iter().filter(|g| &g.name == name).collect();
        if groups.is_empty() {
            let mut known: Vec<&str> =
                data.physical_groups.iter().map(|g| g.name.as_str()).filter(|s| !s.is_empty()).collect();
            known.dedup();
            let has = if known.is_empty() {
                "the file has none".to_string()
            } else {
                format!("the file has: {}", known.join(", "))
            };
            return Err(format!("--fix-physical {name}: no physical point or curve of that name ({has})"));
        }
        let nodes: Vec<u32> = groups.iter().flat_map(|g| g.nodes.iter().copied()).collect();
        let fixed = data.fixed.get_or_insert_with(|| vec![false; n]);
        for v in nodes {
            fixed[v as usize] = true;
        }
    }
    Ok(())
}

/// How an output mesh is written; chosen before any work, so that a bad name fails at once.
#[derive(Clone, Copy)]
pub enum MeshWriter {
    /// `.ply` or `.om`, through OpenMesh (`--format` does not apply).
    OpenMesh,
    /// quadopt's writer of this format (to stdout for `-`).
    Format(Format),
}

impl MeshWriter {
    /// OpenMesh's writer for `.ply` and `.om`, else quadopt's in [`output_format`]'s format.
    pub fn for_output(output: &Path, format: Option<Format>, fallback: Option<Format>) -> Result<Self, Fail> {
        if openmesh_io::handles_output(output) {
            openmesh_io::check_output(output)?;
            Ok(MeshWriter::OpenMesh)
        } else {
            Ok(MeshWriter::Format(output_format(output, format, fallback)?))
        }
    }

    /// Writes `data` to `output`.
    pub fn write(self, output: &Path, data: &MeshData) -> Result<(), Fail> {
        match self {
            MeshWriter::OpenMesh => Ok(openmesh_io::write_mesh(output, data)?),
            MeshWriter::Format(format) => write_mesh_output(output, format, data),
        }
    }
}

/// The format to write: `--format`, else the output's extension, else (for stdout) `fallback`.
fn output_format(output: &Path, format: Option<Format>, fallback: Option<Format>) -> Result<Format, Fail> {
    match (format, is_stdout(output), fallback) {
        (Some(f), _, _) => Ok(f),
        (None, true, Some(f)) => Ok(f),
        (None, true, None) => Err(Fail::Usage("writing to stdout (-o -) needs --format".into())),
        // A directory has no extension either: say what it is.
        (None, false, _) if output.is_dir() => {
            Err(Fail::Other(format!("cannot write {}: it is a directory", output.display())))
        }
        (None, false, _) => Ok(Format::from_path(output)?),
    }
}

/// Writes a mesh to `output` (or stdout for `-`), every write checked.
fn write_mesh_output(output: &Path, format: Format, data: &MeshData) -> Result<(), Fail> {
    if !is_stdout(output) {
        return Ok(io::write_mesh_as(output, format, data)?);
    }
    io::write_mesh_to(&mut std::io::stdout().lock(), format, data).map_err(|e| match e {
        io::IoError::Stream(e) => stdout_write_error(e),
        e => Fail::Other(e.to_string()),
    })
}

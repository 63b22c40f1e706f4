//! The sample meshes of `data/` and their jittered copies, shared by tests/samples.rs and
//! tests/quality_floor.rs.

use super::Rng;
use quadopt::io::{self, PlanarMesh};
use quadopt::{DVec2, Mesh};
use quadopt::{Topology, VertexKind};
use std::path::{Path, PathBuf};

/// The planar sample files, sorted by name.
pub fn sample_files() -> Vec<PathBuf> {
    all_sample_files().into_iter().filter(|p| !is_surface_sample(p)).collect()
}

/// The samples on curved surfaces (`*_surface*.vtk`), sorted by name.
pub fn surface_sample_files() -> Vec<PathBuf> {
    all_sample_files().into_iter().filter(|p| is_surface_sample(p)).collect()
}

fn is_surface_sample(p: &Path) -> bool {
    p.file_stem().is_some_and(|s| s.to_string_lossy().contains("_surface"))
}

fn all_sample_files() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| io::Format::from_path(p).is_ok())
        .collect();
    files.sort();
    files
}

/// A sample: its file name, the 2D mesh and whether the file had `fixed` flags.
pub fn load(path: &Path) -> (String, Mesh, bool) {
    let data = io::read_mesh(path).unwrap_or_else(|e| panic!("{e}"));
    let has_fixed = data.fixed.is_some();
    let planar = PlanarMesh::new(&data).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    (name, planar.mesh, has_fixed)
}

/// `mesh` with every movable interior vertex moved by up to `amount` times its shortest
/// incident edge, in a random direction.
pub fn jittered(mesh: &Mesh, topo: &Topology, amount: f64, seed: u64) -> Mesh {
    let mut rng = Rng(seed);
    let mut points = mesh.points().to_vec();
    for (v, point) in points.iter_mut().enumerate() {
        if topo.kind(v) != VertexKind::Interior || mesh.fixed()[v] {
            continue;
        }
        let p = mesh.points()[v];
        let h = topo
            .ring(v)
            .iter()
            .map(|&u| (mesh.points()[u as usize] - p).length())
            .fold(f64::INFINITY, f64::min);
        *point = p + amount * h * DVec2::new(rng.next(), rng.next());
    }
    Mesh::with_faces(points, mesh.quads().to_vec(), Some(mesh.fixed().to_vec())).unwrap()
}

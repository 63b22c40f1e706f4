//! What a written mesh carries besides its geometry, for viewers to colour by.

use quadopt::io::{MeshData, PlanarMesh};
use quadopt::{BoundaryMode, Mesh, Options};

/// Per-vertex corner flags of `mesh` (the corners `options` keep in place).
pub fn corner_flags(mesh: &Mesh, options: &Options) -> Vec<bool> {
    let topo = quadopt::Topology::new(mesh);
    let features = quadopt::Features::new(
        mesh,
        &topo,
        options.feature_angle_deg,
        options.boundary != BoundaryMode::Fixed,
    );
    (0..mesh.points().len()).map(|v| features.is_corner(v)).collect()
}

/// Adds what viewers colour by to `data`: each quad's signed scaled Jacobian at the planar
/// mesh's positions, and the fixed and corner flags.
pub fn annotate(data: &mut MeshData, planar: &PlanarMesh, corners: Vec<bool>) {
    data.quality = Some(planar.mesh.quality_values());
    data.fixed = Some(planar.mesh.fixed().to_vec());
    data.corner = Some(corners);
}

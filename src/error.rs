//! The library's error type. Every variant names the offending item so a caller (or the C
//! ABI's last-error message) can point at it; `ffi` maps each variant to one status code.
//! Vertices, quads and corners are numbered by their position in the caller's arrays, from 0,
//! and every message that numbers them says so (a file's line numbers count from 1).

use thiserror::Error;

/// Everything that can go wrong when building or optimizing a mesh. Field names are the
/// quantities the variant's message describes.
#[allow(missing_docs)]
#[derive(Clone, Debug, Error, PartialEq)]
pub enum Error {
    /// The mesh has no quads at all.
    #[error("the mesh has no quads")]
    NoQuads,
    /// A quad refers to a vertex that does not exist.
    #[error(
        "quad {quad} corner {corner} refers to vertex {index}, but there are only {vertex_count} vertices \
         (quad, corner and vertex numbers are 0-based)"
    )]
    IndexOutOfRange { quad: usize, corner: usize, index: u64, vertex_count: usize },
    /// A quad uses the same vertex twice.
    #[error("quad {quad} uses vertex {vertex} more than once (quad and vertex numbers are 0-based)")]
    RepeatedVertex { quad: usize, vertex: u32 },
    /// An edge is shared by more than two quads.
    #[error(
        "edge ({a}, {b}) is shared by {count} quads (first: quads {first} and {second}); the mesh is non-manifold \
         (vertex and quad numbers are 0-based)"
    )]
    NonManifoldEdge { a: u32, b: u32, count: usize, first: usize, second: usize },
    /// A face has a number of vertices other than three or four.
    #[error(
        "face {face} has {corners} vertices; only triangles and quads are supported (face numbers are 0-based)"
    )]
    UnsupportedFace { face: usize, corners: usize },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate (vertex numbers are 0-based)")]
    NonFiniteCoordinate { vertex: usize },
    /// The quads cannot be oriented consistently (e.g. a Moebius strip).
    #[error(
        "the mesh is not orientable: quad {quad} cannot be oriented consistently with its neighbours \
         (quad numbers are 0-based)"
    )]
    NonOrientable { quad: usize },
    /// The mesh, or a connected part of it (the quads edge-connected to `quad`), has no
    /// boundary edge: a closed surface, which cannot lie flat in a plane without folds, so no
    /// orientation makes all its quads valid.
    #[error("{}", closed_message(*.quad, *.whole_mesh))]
    ClosedMesh { quad: usize, whole_mesh: bool },
    /// The fixed-flag array does not have one entry per vertex.
    #[error("{got} fixed flags were given for {expected} vertices")]
    FixedLengthMismatch { expected: usize, got: usize },
    /// The coordinate array does not match the mesh it is applied to.
    #[error("{got} vertices were given, but the mesh has {expected}")]
    VertexCountMismatch { expected: usize, got: usize },
    /// The mesh given to an optimizer does not have the quads of the one it was built for.
    #[error("the mesh's quads ({got}) are not those the optimizer was built for ({expected})")]
    ConnectivityMismatch { expected: usize, got: usize },
    /// An option is out of its valid range.
    #[error("invalid option {name}: {reason}")]
    InvalidOption { name: &'static str, reason: String },
    /// The vertices do not lie in one plane by the library's planarity rule (`io::PlanarFrame::fit`):
    /// given to a planar-only entry point (a planar `Mesh`, the reusable C handle), a mesh on a
    /// curved surface, which the surface optimizer takes (`surface::SurfaceOptimizer`).
    #[error(
        "the mesh is not planar: vertex {vertex} is {distance:e} away from the best-fit plane (tolerance {tolerance:e}; \
         vertex numbers are 0-based)"
    )]
    NotPlanar { vertex: usize, distance: f64, tolerance: f64 },
    /// An allocation that grows with the input failed (or its size overflowed).
    #[error("out of memory: cannot allocate {bytes} bytes for {what}")]
    OutOfMemory { what: &'static str, bytes: u128 },
    /// Not even one worker thread could start (a thread limit, no memory for a stack).
    #[error("cannot start worker threads: {why}")]
    NoThreads { why: String },
}

fn closed_message(quad: usize, whole_mesh: bool) -> String {
    let why = "a closed surface cannot lie flat in a plane without folds";
    if whole_mesh {
        format!("the mesh is closed (it has no boundary edge): {why}")
    } else {
        format!(
            "the mesh has a closed part (quad {quad} and the quads connected to it have no boundary edge; \
             quad numbers are 0-based): {why}"
        )
    }
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, Error>;

//! Surfaces in 3D: the reference surface that a mesh on a curved surface is kept on
//! (issue 33).
//!
//! [`ReferenceSurface`] is the input surface, triangulated and frozen for a run, with a
//! bounding-volume hierarchy over its triangles and an exact closest-point query
//! ([`ReferenceSurface::closest_point`]), and a local walk over its triangles for a point that
//! moved a little from a known triangle ([`ReferenceSurface::closest_point_near`]). The point-triangle and point-segment routines it is
//! built on are public too: [`closest_point_on_triangle`], [`closest_point_on_segment`].
//!
//! [`SurfaceOptimizer`] runs the planar method on a surface: feature curves cut the input
//! into smooth patches (`patches`), each vertex's star is mapped to its tangent plane
//! (`star`), moved there by the planar kernels (`moves`, the guard's certificates in `slack`)
//! and put back on its patch or along its feature curve (`tracks`); the run's stages are in
//! `optimizer`. docs/reference_surface.md
//! explains the choices (the quad's diagonal, the tree) and gives the measured numbers.

mod bvh;
mod features;
mod mesh;
mod moves;
mod optimizer;
mod patches;
mod reference;
mod report;
mod slack;
mod star;
mod tracks;

pub use features::{
    DEFAULT_FEATURE_ANGLE_DEG, FEATURE_ANGLE_TOLERANCE_DEG, FeatureCurve, FeatureEdgeKind, SurfaceFeatures,
    VertexRole, angle_between_deg,
};
pub use mesh::{NO_FACE, SurfaceComponent, SurfaceEdge, SurfaceMesh, face_vector_area};
pub use optimizer::SurfaceOptimizer;
pub use reference::{
    Closest, NO_TRIANGLE, ReferenceSurface, TriangleRegion, closest_point_on_segment,
    closest_point_on_triangle,
};
pub use report::{SurfaceFidelity, SurfaceMeasure, SurfaceReport};

//! Surfaces in 3D: the reference surface that a mesh on a curved surface is kept on
//! (issue 33).
//!
//! [`ReferenceSurface`] is the input surface, triangulated and frozen for a run, with a
//! bounding-volume hierarchy over its triangles and an exact closest-point query
//! ([`ReferenceSurface::closest_point`]). The point-triangle and point-segment routines it is
//! built on are public too: [`closest_point_on_triangle`], [`closest_point_on_segment`].
//!
//! Nothing in the optimizer uses this module yet; docs/reference_surface.md explains the
//! choices (the quad's diagonal, the tree) and gives the measured numbers.

mod bvh;
mod features;
mod mesh;
mod reference;

pub use features::{
    DEFAULT_FEATURE_ANGLE_DEG, FEATURE_ANGLE_TOLERANCE_DEG, FeatureCurve, FeatureEdgeKind, SurfaceFeatures,
    VertexRole, angle_between_deg,
};
pub use mesh::{NO_FACE, SurfaceComponent, SurfaceEdge, SurfaceMesh, face_vector_area};
pub use reference::{
    Closest, ReferenceSurface, TriangleRegion, closest_point_on_segment, closest_point_on_triangle,
};

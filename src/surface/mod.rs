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
mod reference;

pub use reference::{
    Closest, ReferenceSurface, TriangleRegion, closest_point_on_segment, closest_point_on_triangle,
};

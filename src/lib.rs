//! # quadopt
//!
//! Quality improvement of 2D quadrilateral meshes by vertex repositioning, after Akram, Si and
//! Chen, "An Embedded Polygon Strategy for Quality Improvement of 2D Quadrilateral Meshes with
//! Boundaries" (2021). Connectivity never changes; the scaled Jacobian (Verdict's definition,
//! signed against the mesh's orientation) of the quads is raised while boundaries, corners and
//! fixed vertices are preserved.
//!
//! ```
//! use glam::DVec2;
//! use quadopt::{optimize, BoundaryMode, Options, Mesh};
//!
//! // A 2x2 patch whose centre vertex has been dragged off-centre.
//! let mut points = Vec::new();
//! for j in 0..3 {
//!     for i in 0..3 {
//!         points.push(DVec2::new(i as f64, j as f64));
//!     }
//! }
//! points[4] = DVec2::new(1.6, 1.5);
//! let quads = vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
//! let mut mesh = Mesh::new(points, quads, None).unwrap();
//! let options = Options::default().with_boundary(BoundaryMode::Fixed).with_tau(1e-12);
//! let report = optimize(&mut mesh, &options).unwrap();
//! assert!(report.output.min > report.input.min);
//! assert!((mesh.points()[4] - DVec2::new(1.0, 1.0)).length() < 1e-3);
//! ```
#![deny(unsafe_code)]
#![warn(missing_docs)]

// The public surface is what the README promises: the optimizer's types (re-exported below),
// `io` (files), `quality` (the scaled Jacobian) and `synthetic` (benchmark meshes). Everything
// else is internal; `testing` reaches a few internals for the crate's own integration tests.
pub(crate) mod alloc;
pub(crate) mod error;
pub mod face;
pub(crate) mod features;
/// The C ABI (`include/quadopt.h`): with `pool`, the only modules with `unsafe` code. Hidden
/// from the Rust documentation: Rust callers use the types above; C callers read the header.
#[allow(unsafe_code)]
#[doc(hidden)]
pub mod ffi;
pub mod io;
#[cfg(feature = "json")]
pub mod json;
pub(crate) mod mesh;
pub(crate) mod normalization;
/// The process's worker pool (its `unsafe`: a published pool pointer that is never freed).
#[allow(unsafe_code)]
mod pool;
pub(crate) mod power_of_two;
pub mod quality;
pub mod quality3d;
pub(crate) mod quiet_threads;
mod renumbering;
/// Run-time choice of the vector width (its `unsafe`: calling code compiled for AVX2 once the
/// CPU is known to have it).
mod simd;
pub(crate) mod smooth;
pub mod surface;
pub mod synthetic;
#[cfg(test)]
mod test_meshes;
#[cfg(test)]
mod test_rng;
pub(crate) mod topology;

pub use error::{Error, Result};
pub use features::Features;
pub use glam::{DVec2, DVec3};
pub use mesh::Mesh;
pub use pool::max_threads;

/// The mesh type's name before it took triangles ([`Mesh`]); kept so code written against it
/// compiles unchanged.
pub type QuadMesh = Mesh;
pub use quality::QualityStats;
pub use smooth::{
    BoundaryFidelity, BoundaryMode, Effort, MaxMinGain, Method, Optimizer, Options, Progress, Report,
    StopRule, TangleReason, TangledQuad, optimize,
};
pub use topology::{Topology, VertexKind};

/// Internals that the crate's integration tests (tests/) drive directly: the max-min stage
/// on its own and the exact power-of-two scaling. Not part of the API: may change at any
/// release.
#[doc(hidden)]
pub mod testing {
    pub use crate::power_of_two::scale_by_power_of_two;
    pub use crate::smooth::boundary::BoundaryGeometry;
    pub use crate::smooth::maxmin::{LocalSolver, MaxMinReport, MaxMinSettings, max_min_stage};
}

/// The README's Rust example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

/// The user guide's Rust examples (tests/docs.rs checks that every page with one is here).
#[cfg(doctest)]
#[doc = include_str!("../docs/guide/rust.md")]
struct GuideRustDoctests;

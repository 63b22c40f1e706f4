//! What a run on a curved surface reports.

use crate::quality::{ByFaceKind, QualityStats};
use crate::smooth::effort::Effort;
use crate::smooth::report::MaxMinGain;

/// How far the output is from the input surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceFidelity {
    /// The largest distance of a vertex from the input surface (the union of the patches
    /// around it).
    pub max_distance: f64,
    /// The largest distance of an on-curve vertex from its feature curve's original polyline.
    pub max_feature_distance: f64,
    /// The largest distance of a new edge along a feature curve (a chord between two
    /// consecutive vertices of the curve) from the stretch of the curve's original polyline it
    /// replaces: how far the curves' shape changed, as the planar run's boundary deviation.
    /// `Options::max_boundary_deviation` bounds it relative to each edge's length.
    pub max_curve_deviation: f64,
    /// The input's mean edge length, which the relative distances divide by.
    pub mean_edge: f64,
}

impl SurfaceFidelity {
    /// [`max_distance`](Self::max_distance) over the mean edge.
    pub fn max_distance_relative(&self) -> f64 {
        self.max_distance / self.mean_edge
    }

    /// [`max_feature_distance`](Self::max_feature_distance) over the mean edge.
    pub fn max_feature_distance_relative(&self) -> f64 {
        self.max_feature_distance / self.mean_edge
    }

    /// [`max_curve_deviation`](Self::max_curve_deviation) over the mean edge.
    pub fn max_curve_deviation_relative(&self) -> f64 {
        self.max_curve_deviation / self.mean_edge
    }
}

/// The result of [`super::SurfaceOptimizer::run`].
///
/// Two measures of quality: the signed scaled Jacobian the optimizer ranks by (`input`,
/// `output`: each corner of a face against its patch's normal there, so a face folded over
/// is inverted) and Verdict's 3D scaled Jacobian (`input_verdict`, `output_verdict`: what
/// VTK's vtkMeshQuality prints, corners against the face's own centre normal, blind to folds).
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceReport {
    /// The signed measure of the input.
    pub input: QualityStats,
    /// The signed measure of the output.
    pub output: QualityStats,
    /// Verdict's 3D scaled Jacobian of the input.
    pub input_verdict: QualityStats,
    /// Verdict's 3D scaled Jacobian of the output.
    pub output_verdict: QualityStats,
    /// The signed measure of the input's quads and triangles apart.
    pub input_by_kind: ByFaceKind,
    /// The signed measure of the output's quads and triangles apart.
    pub output_by_kind: ByFaceKind,
    /// Smoothing sweeps done.
    pub iterations: usize,
    /// Untangling sweeps done.
    pub untangle_sweeps: usize,
    /// Whether the progress callback cancelled the run.
    pub cancelled: bool,
    /// The max-min stage's effect, when it ran.
    pub max_min: Option<MaxMinGain>,
    /// Wall time of the run.
    pub seconds: f64,
    /// The preset of the run.
    pub effort: Effort,
    /// Smooth patches between the feature curves.
    pub patches: usize,
    /// Feature curves.
    pub feature_curves: usize,
    /// Feature corners (never moved).
    pub corners: usize,
    /// Vertices allowed to move.
    pub movable: usize,
    /// Distances of the output from the input surface and feature curves.
    pub fidelity: SurfaceFidelity,
    /// The signed value of each face of the output, in face order (what `output` summarizes).
    pub output_values: Vec<f64>,
}

/// The quality of a placement of a mesh against its input surface
/// ([`super::SurfaceOptimizer::measure`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceMeasure {
    /// The signed scaled Jacobian of each face (the optimizer's measure).
    pub values: Vec<f64>,
    /// Their statistics.
    pub signed: QualityStats,
    /// The signed statistics of the quads and of the triangles apart.
    pub by_kind: ByFaceKind,
    /// Verdict's 3D scaled Jacobian of each face.
    pub verdict_values: Vec<f64>,
    /// Their statistics.
    pub verdict: QualityStats,
    /// Distances from the input surface (the whole of it) and from the feature curves.
    pub fidelity: SurfaceFidelity,
}

//! What a run reports: progress after every sweep, and the final report.

use super::effort::Effort;
use super::fidelity::BoundaryFidelity;
use super::options::BoundaryMode;
use super::untangle::TangledQuad;
use crate::quality::{ByFaceKind, QualityStats};

/// Progress of a run, passed to the progress callback after every sweep. Made only by the
/// library (`#[non_exhaustive]`: later versions may add fields).
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub struct Progress {
    /// Sweeps done so far in the current pass (0 while untangling, with NaN energies).
    pub iteration: usize,
    /// The iteration cap.
    pub max_iterations: usize,
    /// Collective energy measured during the last sweep.
    pub energy: f64,
    /// |E_new - E_old| of the last sweep.
    pub energy_change: f64,
    /// Current pass (1-based). A run is one pass since `Auto` chooses per vertex; kept so
    /// callers that display passes keep working.
    pub pass: usize,
    /// Number of passes planned (1).
    pub passes: usize,
}

/// What a run did: the quality before and after, how the run ended, and what it could not fix.
/// Made only by the library (`#[non_exhaustive]`: later versions may add fields).
///
/// ```
/// use quadopt::{optimize, DVec2, Options, Mesh};
///
/// // A 2x2 patch with its centre vertex dragged across an edge: one quad is inverted.
/// let mut points: Vec<DVec2> =
///     (0..9).map(|k| DVec2::new((k % 3) as f64, (k / 3) as f64)).collect();
/// points[4] = DVec2::new(2.2, 1.5);
/// let quads = vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
/// let mut mesh = Mesh::new(points, quads, None)?;
/// assert!(mesh.quality().inverted > 0);
///
/// let report = optimize(&mut mesh, &Options::default())?;
/// assert!(report.input.inverted > 0 && report.output.inverted == 0);
/// assert!(report.output.min > 0.9, "the centre is back near (1, 1)");
/// assert!(report.tangled.is_empty(), "nothing left inverted");
/// assert_eq!(report.output, mesh.quality(), "the report describes the mesh it returns");
/// println!(
///     "min {:.3} -> {:.3} in {} sweeps ({} untangling)",
///     report.input.min, report.output.min, report.iterations, report.untangle_sweeps
/// );
/// # Ok::<(), quadopt::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Report {
    /// Quality before.
    pub input: QualityStats,
    /// Quality after.
    pub output: QualityStats,
    /// Sweeps performed.
    pub iterations: usize,
    /// Untangling sweeps performed.
    pub untangle_sweeps: usize,
    /// Whether the stopping rule was met (false: iteration cap reached or cancelled).
    pub converged: bool,
    /// Whether the progress callback cancelled the run.
    pub cancelled: bool,
    /// Collective energy of the input.
    pub initial_energy: f64,
    /// Collective energy of the output.
    pub final_energy: f64,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// Quads that were reversed to make the orientation consistent.
    pub reoriented_quads: usize,
    /// Boundary vertices detected as corners (never moved).
    pub corners: usize,
    /// Vertices the optimizer was allowed to move.
    pub movable: usize,
    /// Boundary mode used for each boundary loop (in [`crate::topology::Topology::boundary_loops`] order); with
    /// `Auto`, the approach its vertices chose most often.
    pub loop_modes: Vec<BoundaryMode>,
    /// How far the boundary moved from the original.
    pub fidelity: BoundaryFidelity,
    /// Quads still inverted in the output, and why.
    pub tangled: Vec<TangledQuad>,
    /// Quality before and after the max-min stage, when it ran and its result was kept.
    pub max_min: Option<MaxMinGain>,
    /// The preset that ran ([`crate::Options::effort`]).
    pub effort: Effort,
    /// [`Report::input`] per face kind: the quads and the triangles apart.
    pub input_by_kind: ByFaceKind,
    /// [`Report::output`] per face kind.
    pub output_by_kind: ByFaceKind,
}

/// What the max-min stage changed. Made only by the library (`#[non_exhaustive]`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct MaxMinGain {
    /// Quality after the sweeps, when the stage started.
    pub before: QualityStats,
    /// Quality after the stage.
    pub after: QualityStats,
    /// Rounds of the stage.
    pub rounds: usize,
    /// Wall-clock seconds of the stage.
    pub seconds: f64,
}

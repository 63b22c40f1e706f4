//! The stage's public surface: which local solver, every setting of the stage with its
//! defaults (each one's measured reason is in its documentation), and the report. Kept apart
//! from the algorithm so that the knobs and their rationale can be read in one place.

use crate::quality::QualityStats;

/// How an interior vertex's best position is searched.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LocalSolver {
    /// DMO's nested grid: `grid_size` x `grid_size` candidates in a box of half the star's
    /// extent around the vertex, re-centred on the best one and shrunk to two cells,
    /// `grid_levels` times.
    Grid,
    /// Freitag and Plassmann's active-set method: ascend along the minimum-norm element of the
    /// convex hull of the active corners' gradients, with the step predicted from where
    /// another corner becomes active, halved until the star minimum rises.
    ActiveSet,
    /// The nested grid, then the active-set ascent from its best point.
    #[default]
    GridActiveSet,
}

/// Settings of the max-min stage.
#[derive(Clone, Debug, PartialEq)]
pub struct MaxMinSettings {
    /// Interior solver.
    pub solver: LocalSolver,
    /// Candidates per axis of the nested grid (>= 2).
    pub grid_size: usize,
    /// Refinement levels of the nested grid (>= 1).
    pub grid_levels: usize,
    /// Iteration cap of the active-set ascent.
    pub active_set_iterations: usize,
    /// Samples per level of the boundary 1-D search (>= 2).
    pub boundary_samples: usize,
    /// Initial region: the vertices of quads whose scaled Jacobian is below the level (the
    /// minimum over quads with a movable vertex) plus this.
    pub region_delta: f64,
    /// The region's threshold grows (doubling) up to this when the minimum stalls.
    pub max_region_delta: f64,
    /// The region grows only while the grown region has at most this many vertices. Growing
    /// lets the vertices next to a small worst region make room; on a large mesh of even
    /// quality a grown threshold takes in most of the mesh for nothing (measured on a
    /// 186k-quad plate: each growth covered 70-100% of its vertices, cost 1.7 s of a 24 s stage
    /// and raised the level by under 1e-4), so the stage goes on to its escape instead.
    pub max_grown_region: usize,
    /// A round works on at most the worst `max(min_region_quads, region_quads_fraction x
    /// quads)` quads below its threshold: on a large mesh of even quality the threshold
    /// (level + `region_delta`) takes in most of the mesh, and a round costs as much as a sweep
    /// of grid searches (measured on a 186k-quad plate: regions of 100k vertices, 0.1-0.8 s a
    /// round, 7.6 s of rounds; with the cap 1.5 s for the same minimum). Meshes of up to
    /// `min_region_quads` quads are never capped.
    pub min_region_quads: usize,
    /// See `min_region_quads`.
    pub region_quads_fraction: f64,
    /// Positions whose star minimum is within this of the best one found count as equal, and
    /// the highest star average among them is taken (0: the best minimum only).
    pub avg_tolerance: f64,
    /// A round whose gain of the level is below this counts as a stall.
    pub min_gain: f64,
    /// Round cap.
    pub max_rounds: usize,
    /// Which of the two phases runs first. In the max-min phase every star goes to its
    /// highest minimum; in the ranked phase, candidates whose star minimum exceeds the region's
    /// threshold plus `region_delta` are ranked by average (leaving neighbours room). The
    /// stage switches phase once, when the first stalls (measured: max-min first reaches the
    /// higher minimum on the Mesquite and sample meshes).
    pub average_first: bool,
    /// With [`LocalSolver::GridActiveSet`], search with the grid only a vertex's first time
    /// (and after an escape), later with the active set alone from where it is.
    pub warm_start: bool,
    /// Switch phase (see `average_first`) when the first stalls.
    pub switch_phase: bool,
    /// Average sweeps over the region allowed when the max-min rounds stall.
    pub escapes: usize,
    /// Recover the average (escapes and final sweeps) by steps towards the embedded-polygon
    /// target, halved until acceptable, instead of a grid search for the highest average
    /// (measured: a third cheaper, but the average ends up to 0.007 lower).
    pub average_by_smoothing: bool,
    /// The final average recovery keeps each star above min(its value, level + this).
    pub recovery_margin: f64,
    /// Sweeps of the final average recovery over the moved vertices (0: none).
    pub average_sweeps: usize,
    /// The recovery's sweeps may cover (the sum of their regions' vertices) at most
    /// max(`min_recovery_searches`, this times the vertex count): a sweep that would go past
    /// it is not started (the first always is).
    /// Measured on a 186k-quad plate with holes: its 6 recovery sweeps (regions of 130k to
    /// 188k vertices) took 61% of the run for an average of 0.94548 -> 0.94946; the first
    /// two give 0.94864 for a quarter of that time.
    pub recovery_searches_per_vertex: f64,
    /// See `recovery_searches_per_vertex`: 2^18, above the 8 sweeps of every mesh with up to
    /// 32k vertices, whose recovery is cheap (the sample and Mesquite meshes keep all of it).
    pub min_recovery_searches: usize,
    /// The recovery stops after a sweep that raised the mean scaled Jacobian of the quads it
    /// worked on by less than this (measured on a 186k-quad plate: its sweeps 5 to 8 gave
    /// 2.3e-4 of average for 4 of the stage's 18 s; on the sample meshes a sweep gains up
    /// to 4e-3).
    pub average_min_gain: f64,
    /// Move movable boundary vertices (along the original boundary) as well as interior ones.
    pub boundary: bool,
    /// As [`Options::max_boundary_deviation`](crate::smooth::options::Options::max_boundary_deviation):
    /// largest distance between a new boundary edge and the stretch of the original boundary
    /// it replaces, relative to its length.
    pub max_boundary_deviation: Option<f64>,
}

impl Default for MaxMinSettings {
    fn default() -> Self {
        MaxMinSettings {
            solver: LocalSolver::default(),
            grid_size: 8,
            grid_levels: 3,
            active_set_iterations: 30,
            boundary_samples: 16,
            region_delta: 0.05,
            max_region_delta: 0.2,
            max_grown_region: 4096,
            min_region_quads: 1024,
            region_quads_fraction: 0.02,
            avg_tolerance: 0.0,
            min_gain: 1e-4,
            max_rounds: 200,
            average_first: false,
            average_sweeps: 8,
            recovery_searches_per_vertex: 2.0,
            min_recovery_searches: 1 << 18,
            average_min_gain: 1e-4,
            recovery_margin: 0.01,
            average_by_smoothing: false,
            warm_start: false,
            switch_phase: true,
            escapes: 2,
            boundary: true,
            max_boundary_deviation: None,
        }
    }
}

/// What the stage did.
#[derive(Clone, Debug, PartialEq)]
pub struct MaxMinReport {
    /// Quality when the stage started.
    pub before: QualityStats,
    /// Quality when it ended.
    pub after: QualityStats,
    /// Rounds (Gauss-Seidel passes over the region) performed.
    pub rounds: usize,
    /// Vertex moves taken.
    pub moves: usize,
    /// Sweeps of the average recovery performed.
    pub average_sweeps: usize,
    /// Vertices of the largest grown region a round worked on (0: the region never grew; at
    /// most `MaxMinSettings::max_grown_region`).
    pub largest_grown_region: usize,
    /// Global minimum scaled Jacobian before the first round, after every round and after the
    /// average recovery (non-decreasing).
    pub history: Vec<f64>,
    /// Whether the callback cancelled the stage.
    pub cancelled: bool,
    /// Wall-clock seconds.
    pub seconds: f64,
}

//! The optimizer: options, the iteration loop, termination and the report.
//!
//! Every method is a per-vertex update that reads only the previous positions (a Jacobi
//! sweep), so a sweep runs in parallel and gives the same result on any number of threads.
//! Interior vertices are moved by the chosen [`Method`]; boundary vertices by the embedded
//! polygon's boundary rule (Section 3.3) in the chosen [`BoundaryMode`], whatever the method.
//!
//! A run (see [`Optimizer::run`]):
//! 1. untangles inverted quads first ([`untangle`]), when the input has any;
//! 2. sweeps colour class by colour class (vertices of one class share no quad, so a class
//!    moves in parallel and the result does not depend on the thread count), each vertex
//!    taking its method's target through the guard of [`guard`] unless that is turned off;
//! 3. stops on the collective torsion-spring energy of Eq. 1 ([`energy`]): by default when
//!    its change per movable vertex falls below `tau` (independent of mesh size), or with
//!    `tau_absolute` when |E_new - E_old| < tau as in the paper; or at the iteration cap;
//! 4. returns the best iterate seen (the input included), ranked by inverted count, then
//!    minimum scaled Jacobian, then average, among those with no more inverted quads, no quad
//!    inverted that was valid in the input, and a minimum not below the input's.
//!
//! With [`BoundaryMode::Auto`] both boundary approaches are run and the better result kept,
//! refined per boundary loop on small meshes.

pub mod angle_based;
pub mod boundary;
pub mod embedded_polygon;
pub mod energy;
pub mod fidelity;
pub mod guard;
pub mod laplacian;
pub mod untangle;

use crate::error::{Error, Result};
use crate::features::Features;
use crate::mesh::QuadMesh;
use crate::quality::{QualityStats, corners, scaled_jacobian};
use crate::topology::Topology;
use boundary::BoundaryGeometry;
pub use fidelity::BoundaryFidelity;
use glam::DVec2;
use rayon::prelude::*;
use std::str::FromStr;
use std::time::Instant;
pub use untangle::{TangleReason, TangledQuad};

/// How interior vertices are moved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Method {
    /// The embedded polygon method of Akram, Si and Chen (Sections 3.1-3.2).
    #[default]
    EmbeddedPolygon,
    /// Uniform Laplacian: each vertex moves towards the average of its edge-neighbours.
    Laplacian,
    /// Cotangent-weighted Laplacian.
    Cotangent,
    /// Xu and Newman's angle-based smoothing (2005): bisectors at edge and diagonal neighbours.
    AngleBased,
}

impl Method {
    /// Every method, in the order of the paper's comparison.
    pub const ALL: [Method; 4] =
        [Method::AngleBased, Method::Laplacian, Method::Cotangent, Method::EmbeddedPolygon];

    /// The short name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Method::EmbeddedPolygon => "ep",
            Method::Laplacian => "laplace",
            Method::Cotangent => "cotan",
            Method::AngleBased => "angle",
        }
    }
}

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "ep" | "embedded-polygon" => Ok(Method::EmbeddedPolygon),
            "laplace" | "laplacian" => Ok(Method::Laplacian),
            "cotan" | "cotangent" => Ok(Method::Cotangent),
            "angle" | "angle-based" => Ok(Method::AngleBased),
            _ => Err(format!("unknown method '{s}' (expected ep, laplace, cotan or angle)")),
        }
    }
}

/// How boundary vertices are treated (Section 3.3). Corners and fixed vertices never move.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BoundaryMode {
    /// Boundary vertices never move.
    Fixed,
    /// Approach 2: move along the original boundary polyline only.
    Slide,
    /// Approach 1: rotate to bisect, then project back onto the original boundary between the
    /// vertex's two boundary neighbours.
    Snap,
    /// Run both approaches and keep the better result, per boundary loop on small meshes.
    #[default]
    Auto,
}

impl BoundaryMode {
    /// Every mode.
    pub const ALL: [BoundaryMode; 4] =
        [BoundaryMode::Fixed, BoundaryMode::Slide, BoundaryMode::Snap, BoundaryMode::Auto];

    /// The short name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            BoundaryMode::Fixed => "fixed",
            BoundaryMode::Slide => "slide",
            BoundaryMode::Snap => "snap",
            BoundaryMode::Auto => "auto",
        }
    }
}

impl FromStr for BoundaryMode {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "fixed" => Ok(BoundaryMode::Fixed),
            "slide" => Ok(BoundaryMode::Slide),
            "snap" => Ok(BoundaryMode::Snap),
            "auto" => Ok(BoundaryMode::Auto),
            _ => Err(format!("unknown boundary mode '{s}' (expected fixed, slide, snap or auto)")),
        }
    }
}

/// Optimization options.
///
/// The defaults keep the paper's method and parameters (lambda = 1, feature angle 45
/// degrees) and add what makes the result never worse than the input: guarded moves,
/// untangling, the automatic boundary mode and a size-independent stopping rule. Set
/// [`Options::paper`] reproduces the plain method of the paper.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Interior smoothing method.
    pub method: Method,
    /// Boundary treatment.
    pub boundary: BoundaryMode,
    /// Step factor of Eq. 8, in (0, 1].
    pub lambda: f64,
    /// Stopping threshold on the energy change between sweeps (>= 0): per movable vertex by
    /// default, absolute (the paper's tau) when `tau_absolute` is set.
    pub tau: f64,
    /// Compare `tau` with the absolute change of the collective energy, as the paper does;
    /// this depends on mesh size (large meshes may never reach it).
    pub tau_absolute: bool,
    /// Iteration cap (>= 1).
    pub max_iterations: usize,
    /// A boundary vertex whose turning angle differs from 180 degrees by more than this is a
    /// corner and never moves, in degrees within [0, 180].
    pub feature_angle_deg: f64,
    /// Guarded moves: a vertex with a valid star may not lower its star's minimum scaled
    /// Jacobian below min(current, floor), where the floor is the larger of `guard_floor` and
    /// the input's minimum scaled Jacobian (so a valid mesh's worst quad never gets worse).
    pub guard: bool,
    /// The guard's floor, in (0, 1].
    pub guard_floor: f64,
    /// Untangle inverted quads before smoothing.
    pub untangle: bool,
    /// Return the best iterate seen (never worse than the input) instead of the last one.
    pub keep_best: bool,
    /// Largest allowed distance between a new boundary edge and the stretch of the original
    /// boundary it replaces, relative to that edge's length (`None`: unlimited).
    pub max_boundary_deviation: Option<f64>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            method: Method::EmbeddedPolygon,
            boundary: BoundaryMode::Auto,
            lambda: 1.0,
            tau: 1e-7,
            tau_absolute: false,
            max_iterations: 1000,
            feature_angle_deg: 45.0,
            guard: true,
            guard_floor: 0.05,
            untangle: true,
            keep_best: true,
            max_boundary_deviation: None,
        }
    }
}

impl Options {
    /// The paper's plain method: no guard, no untangling, the last iterate, Approach 2 on the
    /// boundary, the absolute energy threshold tau = 1e-4.
    pub fn paper() -> Options {
        Options {
            boundary: BoundaryMode::Slide,
            tau: 1e-4,
            tau_absolute: true,
            guard: false,
            untangle: false,
            keep_best: false,
            ..Options::default()
        }
    }

    /// Checks every option's range, naming the first bad one.
    pub fn validate(&self) -> Result<()> {
        let bad = |name, reason: String| Err(Error::InvalidOption { name, reason });
        if !(self.lambda > 0.0 && self.lambda <= 1.0) {
            return bad("lambda", format!("{} is not in (0, 1]", self.lambda));
        }
        if !(self.tau >= 0.0 && self.tau.is_finite()) {
            return bad("tau", format!("{} is not a finite number >= 0", self.tau));
        }
        if self.max_iterations == 0 {
            return bad("max_iterations", "must be at least 1".into());
        }
        if !(0.0..=180.0).contains(&self.feature_angle_deg) {
            return bad("feature_angle_deg", format!("{} is not in [0, 180]", self.feature_angle_deg));
        }
        if !(self.guard_floor > 0.0 && self.guard_floor <= 1.0) {
            return bad("guard_floor", format!("{} is not in (0, 1]", self.guard_floor));
        }
        if let Some(d) = self.max_boundary_deviation {
            if d.is_nan() || d < 0.0 {
                return bad("max_boundary_deviation", format!("{d} is not a number >= 0"));
            }
        }
        Ok(())
    }
}

/// Progress of a run, passed to the progress callback after every sweep.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Sweeps done so far in the current pass.
    pub iteration: usize,
    /// The iteration cap.
    pub max_iterations: usize,
    /// Collective energy measured during the last sweep.
    pub energy: f64,
    /// |E_new - E_old| of the last sweep.
    pub energy_change: f64,
    /// Current pass (1-based): `Auto` runs several passes.
    pub pass: usize,
    /// Number of passes planned.
    pub passes: usize,
}

/// What a run did.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Quality before.
    pub input: QualityStats,
    /// Quality after.
    pub output: QualityStats,
    /// Sweeps performed (of the pass whose result was kept).
    pub iterations: usize,
    /// Untangling sweeps performed.
    pub untangle_sweeps: usize,
    /// Whether the energy criterion was met (false: iteration cap reached or cancelled).
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
    /// Boundary mode used for each boundary loop (in [`Topology::boundary_loops`] order).
    pub loop_modes: Vec<BoundaryMode>,
    /// How far the boundary moved from the original.
    pub fidelity: BoundaryFidelity,
    /// Quads still inverted in the output, and why.
    pub tangled: Vec<TangledQuad>,
}

/// Optimizes `mesh` in place with `options`. Builds the topology; to optimize many meshes
/// with the same connectivity, build an [`Optimizer`] once instead.
pub fn optimize(mesh: &mut QuadMesh, options: &Options) -> Result<Report> {
    Optimizer::new(mesh).run(mesh, options, None)
}

/// A reusable optimizer: the topology of one connectivity, built once.
#[derive(Clone, Debug)]
pub struct Optimizer {
    topology: Topology,
}

/// Per-vertex result of a sweep.
#[derive(Clone, Copy, Debug, Default)]
struct Update {
    vertex: u32,
    position: DVec2,
    /// Boundary arclength parameter (unused for interior vertices).
    param: f64,
    /// Torsion energy of the vertex before its move.
    energy: f64,
}

/// Result of one pass (one boundary-mode assignment).
struct Pass {
    points: Vec<DVec2>,
    params: Vec<f64>,
    stats: QualityStats,
    iterations: usize,
    untangle_sweeps: usize,
    converged: bool,
    cancelled: bool,
    initial_energy: f64,
    final_energy: f64,
}

/// Minimum differences that count when ranking iterates by minimum scaled Jacobian; closer
/// minima are a tie decided by the average, so a negligible gain of the worst quad does not
/// beat a large gain of the average.
const MIN_TIE: f64 = 1e-3;

/// Whether `candidate` should replace `best`, given the `input` it may never be worse than.
fn improves(candidate: &QualityStats, best: &QualityStats, input: &QualityStats) -> bool {
    if candidate.inverted > input.inverted || candidate.min < input.min {
        return false;
    }
    if candidate.inverted != best.inverted {
        return candidate.inverted < best.inverted;
    }
    if (candidate.min - best.min).abs() > MIN_TIE {
        return candidate.min > best.min;
    }
    candidate.avg > best.avg
}

/// Quality statistics, computed in parallel but summed in a fixed order.
fn stats_of(points: &[DVec2], quads: &[[u32; 4]], scratch: &mut Vec<f64>) -> QualityStats {
    scratch.clear();
    scratch.par_extend(quads.par_iter().map(|q| scaled_jacobian(&corners(points, q))));
    QualityStats::from_values(scratch)
}

impl Optimizer {
    /// Builds the topology of `mesh`.
    pub fn new(mesh: &QuadMesh) -> Optimizer {
        Optimizer { topology: Topology::new(mesh) }
    }

    /// The topology this optimizer works on.
    pub fn topology(&self) -> &Topology {
        &self.topology
    }

    /// Optimizes `mesh` (which must have the connectivity this optimizer was built for). The
    /// optional `progress` callback runs after every sweep; returning `false` cancels, keeping
    /// the best positions reached so far.
    ///
    /// The run works on coordinates normalized to the mesh's bounding box
    /// ([`crate::normalization`]), so its result does not depend on the mesh's units: scaled by
    /// a power of two it is the same bit for bit. Vertices that do not move keep their
    /// coordinates exactly; the report's statistics are those of the coordinates given and
    /// returned.
    pub fn run(
        &self,
        mesh: &mut QuadMesh,
        options: &Options,
        progress: Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> Result<Report> {
        let frame = crate::normalization::Normalization::new(mesh.points(), mesh.quads());
        let original = frame.normalize(mesh.points_mut())?;
        let result = self.run_normalized(mesh, options, progress);
        frame.restore(mesh.points_mut(), &original);
        let mut report = result?;
        if frame.origin() != DVec2::ZERO {
            // Translating rounded the coordinates: report the quality of the actual ones.
            report.input = QualityStats::from_values(&crate::quality::quad_values(&original, mesh.quads()));
            report.output = mesh.quality();
        }
        let fidelity = &mut report.fidelity;
        fidelity.max_deviation = frame.length_to_original(fidelity.max_deviation);
        fidelity.hausdorff = frame.length_to_original(fidelity.hausdorff);
        Ok(report)
    }

    fn run_normalized(
        &self,
        mesh: &mut QuadMesh,
        options: &Options,
        mut progress: Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> Result<Report> {
        options.validate()?;
        let topo = &self.topology;
        if mesh.points().len() != topo.vertex_count() {
            return Err(Error::VertexCountMismatch {
                expected: topo.vertex_count(),
                got: mesh.points().len(),
            });
        }
        let start = Instant::now();
        let input_values = mesh.quality_values();
        let input = QualityStats::from_values(&input_values);
        let features = Features::new(mesh, topo, options.feature_angle_deg, options.boundary);
        let geometry = BoundaryGeometry::new(mesh.points(), topo, &features);
        let loops = topo.loop_count();
        let ctx = RunContext {
            topo,
            features: &features,
            geometry: &geometry,
            options,
            quads: mesh.quads(),
            input,
            input_inverted: input_values.iter().map(|&v| v <= 0.0).collect(),
            floor: options.guard_floor.max(input.min),
        };

        let (pass, loop_modes) = if options.boundary == BoundaryMode::Auto {
            ctx.auto(mesh.points(), &mut progress)
        } else {
            let modes = vec![options.boundary; loops];
            (ctx.pass(mesh.points(), &modes, (1, 1), &mut progress), modes)
        };

        let mean_edge = mean_edge_length(mesh.points(), mesh.quads());
        let fidelity = fidelity::measure(&geometry, &pass.params, mean_edge);
        mesh.points_mut().copy_from_slice(&pass.points);
        Ok(Report {
            input,
            output: pass.stats,
            iterations: pass.iterations,
            untangle_sweeps: pass.untangle_sweeps,
            converged: pass.converged,
            cancelled: pass.cancelled,
            initial_energy: pass.initial_energy,
            final_energy: pass.final_energy,
            seconds: start.elapsed().as_secs_f64(),
            reoriented_quads: mesh.reoriented().len(),
            corners: features.corner_count(),
            movable: features.movable_vertices().len(),
            loop_modes,
            fidelity,
            tangled: untangle::diagnose(mesh.points(), mesh.quads(), topo, &features),
        })
    }
}

/// Mean length of the quad edges (each interior edge counted twice, which does not matter
/// for a scale).
fn mean_edge_length(points: &[DVec2], quads: &[[u32; 4]]) -> f64 {
    let total: f64 = quads
        .iter()
        .map(|q| {
            (0..4).map(|i| (points[q[(i + 1) % 4] as usize] - points[q[i] as usize]).length()).sum::<f64>()
        })
        .sum();
    total / (4 * quads.len()).max(1) as f64
}

/// Everything a pass reads besides the positions.
struct RunContext<'a> {
    topo: &'a Topology,
    features: &'a Features,
    geometry: &'a BoundaryGeometry,
    options: &'a Options,
    quads: &'a [[u32; 4]],
    input: QualityStats,
    /// Per quad: inverted (scaled Jacobian <= 0) in the input.
    input_inverted: Vec<bool>,
    /// The guard's floor for this run.
    floor: f64,
}

/// Loops beyond which `Auto` decides for the whole mesh at once instead of per loop.
const AUTO_MAX_LOOPS: usize = 12;
/// Vertices beyond which `Auto` decides for the whole mesh at once.
const AUTO_MAX_VERTICES: usize = 50_000;

impl RunContext<'_> {
    /// Whether per-quad `values` invert a quad that was valid in the input. Such an iterate is
    /// never returned, so no quad that was valid ends inverted, even while untangling trades
    /// one inversion for another on a mesh that stays tangled.
    fn inverts_a_valid_quad(&self, values: &[f64]) -> bool {
        self.input.inverted > 0 && values.iter().zip(&self.input_inverted).any(|(&v, &was)| v <= 0.0 && !was)
    }

    /// `Auto`: slide and snap for the whole mesh, keep the better; then on small meshes try
    /// switching each loop to the other approach, keeping every switch that improves. Loops
    /// where no vertex may move are reported as fixed and never tried both ways (slide and
    /// snap coincide there), so a mesh whose boundary cannot move costs one pass.
    fn auto(
        &self,
        start: &[DVec2],
        progress: &mut Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> (Pass, Vec<BoundaryMode>) {
        let loops = self.topo.loop_count();
        let movable: Vec<bool> = (0..loops)
            .map(|l| self.topo.boundary_loop(l).iter().any(|&v| self.features.is_movable(v as usize)))
            .collect();
        let with = |mode| -> Vec<BoundaryMode> {
            movable.iter().map(|&m| if m { mode } else { BoundaryMode::Fixed }).collect()
        };
        let toggled: Vec<usize> = (0..loops).filter(|&l| movable[l]).collect();
        if toggled.is_empty() {
            let modes = with(BoundaryMode::Fixed);
            return (self.pass(start, &modes, (1, 1), progress), modes);
        }
        let per_loop =
            toggled.len() > 1 && toggled.len() <= AUTO_MAX_LOOPS && start.len() <= AUTO_MAX_VERTICES;
        let passes = 2 + if per_loop { toggled.len() } else { 0 };
        let (slide, snap) = (with(BoundaryMode::Slide), with(BoundaryMode::Snap));
        let mut best = self.pass(start, &slide, (1, passes), progress);
        let mut best_modes = slide;
        if best.cancelled {
            return (best, best_modes);
        }
        let other = self.pass(start, &snap, (2, passes), progress);
        if improves(&other.stats, &best.stats, &self.input) || other.cancelled {
            (best, best_modes) = (other, snap);
        }
        if per_loop && !best.cancelled {
            for (k, &l) in toggled.iter().enumerate() {
                let mut modes = best_modes.clone();
                modes[l] =
                    if modes[l] == BoundaryMode::Slide { BoundaryMode::Snap } else { BoundaryMode::Slide };
                let p = self.pass(start, &modes, (3 + k, passes), progress);
                let cancelled = p.cancelled;
                if improves(&p.stats, &best.stats, &self.input) {
                    (best, best_modes) = (p, modes);
                }
                if cancelled {
                    best.cancelled = true;
                    break;
                }
            }
        }
        (best, best_modes)
    }

    /// One full optimization from `start` with the given per-loop boundary modes.
    fn pass(
        &self,
        start: &[DVec2],
        loop_modes: &[BoundaryMode],
        (pass, passes): (usize, usize),
        progress: &mut Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> Pass {
        let opts = self.options;
        let mut points = start.to_vec();
        let mut params = self.geometry.initial_params();
        let mut scratch = Vec::with_capacity(self.quads.len());
        let mut untangle_sweeps = 0;
        if opts.untangle && self.input.inverted > 0 {
            untangle_sweeps = untangle::untangle(&mut points, self.quads, self.topo, self.features, 200);
        }
        let mut best_stats = self.input;
        let mut best_points = start.to_vec();
        let mut best_params = params.clone();
        let current = stats_of(&points, self.quads, &mut scratch);
        if !self.inverts_a_valid_quad(&scratch) && improves(&current, &best_stats, &self.input) {
            best_stats = current;
            best_points.copy_from_slice(&points);
        }

        let movable = self.features.movable_vertices().len().max(1) as f64;
        let largest_class =
            (0..self.topo.colour_count()).map(|c| self.topo.colour_class(c).len()).max().unwrap_or(0);
        let mut updates: Vec<Update> = Vec::with_capacity(largest_class);
        let (mut energy_old, mut initial_energy) = (f64::NAN, f64::NAN);
        let (mut iterations, mut converged, mut cancelled) = (0, false, false);
        while iterations < opts.max_iterations {
            let mut energy = 0.0;
            for c in 0..self.topo.colour_count() {
                let class = self.topo.colour_class(c);
                updates.clear();
                {
                    let (pts, prm) = (&points[..], &params[..]);
                    updates.par_extend(
                        class
                            .par_iter()
                            .filter(|&&v| self.features.is_movable(v as usize))
                            .map(|&v| self.update(pts, prm, v as usize, loop_modes)),
                    );
                }
                // Sequential: the same sum whatever the thread count.
                for u in &updates {
                    energy += u.energy;
                    points[u.vertex as usize] = u.position;
                    if let Some(slot) = self.geometry.slot(u.vertex as usize) {
                        params[slot] = u.param;
                    }
                }
            }
            iterations += 1;
            if iterations == 1 {
                initial_energy = energy;
            }
            let stats = stats_of(&points, self.quads, &mut scratch);
            if !self.inverts_a_valid_quad(&scratch) && improves(&stats, &best_stats, &self.input) {
                best_stats = stats;
                best_points.copy_from_slice(&points);
                best_params.copy_from_slice(&params);
            }
            let change = (energy - energy_old).abs();
            energy_old = energy;
            let scaled = if opts.tau_absolute { change } else { change / movable };
            if let Some(cb) = progress.as_mut() {
                let p = Progress {
                    iteration: iterations,
                    max_iterations: opts.max_iterations,
                    energy,
                    energy_change: change,
                    pass,
                    passes,
                };
                if !cb(&p) {
                    cancelled = true;
                    break;
                }
            }
            if scaled < opts.tau {
                converged = true;
                break;
            }
        }
        if !opts.keep_best {
            best_stats = stats_of(&points, self.quads, &mut scratch);
            best_points = points;
            best_params = params;
        }
        let final_energy = self.energy(&best_points);
        Pass {
            points: best_points,
            params: best_params,
            stats: best_stats,
            iterations,
            untangle_sweeps,
            converged,
            cancelled,
            initial_energy: if initial_energy.is_nan() { final_energy } else { initial_energy },
            final_energy,
        }
    }

    /// Collective energy of the movable interior vertices at `points` (boundary vertices
    /// contribute their one angle inside the sweep; here only the interior part is needed
    /// for reporting the result).
    fn energy(&self, points: &[DVec2]) -> f64 {
        self.features
            .movable_vertices()
            .iter()
            .filter(|&&v| !self.features.is_boundary(v as usize))
            .map(|&v| energy::vertex_energy(points, v as usize, self.topo.ring(v as usize)))
            .sum()
    }

    fn update(&self, points: &[DVec2], params: &[f64], v: usize, loop_modes: &[BoundaryMode]) -> Update {
        let opts = self.options;
        let (target, param, energy) = if self.features.is_boundary(v) {
            boundary::update(
                points,
                self.topo,
                self.geometry,
                params,
                v,
                loop_modes,
                opts.lambda,
                opts.max_boundary_deviation,
            )
        } else {
            let ring = self.topo.ring(v);
            let (target, energy) = match opts.method {
                Method::EmbeddedPolygon => embedded_polygon::target(points, v, ring),
                Method::Laplacian => {
                    (laplacian::uniform_target(points, ring), energy::vertex_energy(points, v, ring))
                }
                Method::Cotangent => {
                    (laplacian::cotangent_target(points, v, ring), energy::vertex_energy(points, v, ring))
                }
                Method::AngleBased => (
                    angle_based::target(points, v, self.topo.full_ring(v)),
                    energy::vertex_energy(points, v, ring),
                ),
            };
            let p = points[v];
            let moved = p + opts.lambda * (target - p);
            // Next to coordinates near f64::MAX a target can overflow: then the vertex stays.
            (if moved.is_finite() { moved } else { p }, 0.0, energy)
        };
        if !opts.guard || target == points[v] {
            return Update { vertex: v as u32, position: target, param, energy };
        }
        if self.features.is_boundary(v) {
            // A boundary vertex must stay on the polyline: accept its move or stay.
            let at_target = guard::star_min(points, self.quads, self.topo, v, target);
            let ok = at_target >= self.floor || {
                let current = guard::star_min(points, self.quads, self.topo, v, points[v]);
                at_target >= current || current <= 0.0
            };
            let (position, param) =
                if ok { (target, param) } else { (points[v], current_param(self.geometry, params, v)) };
            return Update { vertex: v as u32, position, param, energy };
        }
        let position = guard::guarded_position(points, self.quads, self.topo, v, target, self.floor);
        Update { vertex: v as u32, position, param, energy }
    }
}

fn current_param(geometry: &BoundaryGeometry, params: &[f64], v: usize) -> f64 {
    geometry.slot(v).map_or(0.0, |s| params[s])
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn grid(nx: u32, ny: u32) -> QuadMesh {
        let mut p = Vec::new();
        for j in 0..=ny {
            for i in 0..=nx {
                p.push(DVec2::new(i as f64, j as f64));
            }
        }
        let mut q = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let a = j * (nx + 1) + i;
                q.push([a, a + 1, a + nx + 2, a + nx + 1]);
            }
        }
        QuadMesh::new(p, q, None).unwrap()
    }

    #[test]
    fn perfect_grid_is_a_fixed_point_of_every_method_and_mode() {
        for method in Method::ALL {
            for boundary in BoundaryMode::ALL {
                let mut m = grid(4, 3);
                let before = m.points().to_vec();
                let r = optimize(&mut m, &Options { method, boundary, ..Options::default() }).unwrap();
                for (a, b) in before.iter().zip(m.points()) {
                    assert!((*a - *b).length() < 1e-12, "{method:?} {boundary:?} moved {a} to {b}");
                }
                assert_eq!(r.output.min, 1.0);
            }
        }
    }

    /// 2x2 grid whose centre (vertex 4) is pinned at (1.5, 1), every vertex fixed but the
    /// bottom-middle one (vertex 1), which sits at (1, 0) between boundary neighbours 0 and 2.
    fn one_free_boundary_vertex() -> QuadMesh {
        let m = grid(2, 2);
        let mut p = m.points().to_vec();
        p[4] = DVec2::new(1.5, 1.0);
        let fixed = (0..9).map(|v| v != 1).collect();
        QuadMesh::new(p, m.quads().to_vec(), Some(fixed)).unwrap()
    }

    fn one_sweep(boundary: BoundaryMode) -> Options {
        Options {
            boundary,
            max_iterations: 1,
            guard: false,
            untangle: false,
            keep_best: false,
            ..Options::default()
        }
    }

    #[test]
    fn slide_puts_the_boundary_vertex_on_the_bisector_in_one_sweep() {
        // Approach 2: v - n1 must bisect the angle at n1 = (1.5, 1) between the boundary
        // neighbours (0, 0) and (2, 0). By the angle bisector theorem the bisector meets the
        // bottom edge at (0,0) + (2,0) |n1 - (0,0)| / (|n1 - (0,0)| + |n1 - (2,0)|).
        let mut m = one_free_boundary_vertex();
        optimize(&mut m, &one_sweep(BoundaryMode::Slide)).unwrap();
        let (l0, l2) = (DVec2::new(1.5, 1.0).length(), DVec2::new(-0.5, 1.0).length());
        let expected = DVec2::new(2.0 * l0 / (l0 + l2), 0.0);
        assert!((m.points()[1] - expected).length() < 1e-12, "{} vs {expected}", m.points()[1]);
        assert_eq!(m.points()[1].y, 0.0);
    }

    #[test]
    fn snap_rotates_onto_the_bisector_then_projects_onto_the_original_boundary() {
        // Approach 1: rotate v about n1 onto the bisector (keeping |v - n1|), then project
        // onto the bottom edge: the x of the rotated point.
        let mut m = one_free_boundary_vertex();
        optimize(&mut m, &one_sweep(BoundaryMode::Snap)).unwrap();
        let n1 = DVec2::new(1.5, 1.0);
        let bisector = ((DVec2::ZERO - n1).normalize() + (DVec2::new(2.0, 0.0) - n1).normalize()).normalize();
        let rotated = n1 + (DVec2::new(1.0, 0.0) - n1).length() * bisector;
        let expected = DVec2::new(rotated.x, 0.0);
        assert!((m.points()[1] - expected).length() < 1e-12, "{} vs {expected}", m.points()[1]);
    }

    #[test]
    fn fixed_boundary_and_corners_never_move() {
        let mut m = one_free_boundary_vertex();
        let before = m.points().to_vec();
        optimize(&mut m, &one_sweep(BoundaryMode::Fixed)).unwrap();
        assert_eq!(m.points(), &before[..]);
        // Corner rule: turning the bottom edge by more than the feature angle pins vertex 1.
        let mut p = before.clone();
        p[1] = DVec2::new(1.0, 0.9); // 2 * atan(0.9) = 84 degrees of turn > 45
        let mut bent = QuadMesh::new(p.clone(), m.quads().to_vec(), Some(m.fixed().to_vec())).unwrap();
        optimize(&mut bent, &one_sweep(BoundaryMode::Slide)).unwrap();
        assert_eq!(bent.points()[1], p[1]);
    }

    #[test]
    fn absolute_tau_depends_on_size_and_per_vertex_tau_does_not() {
        // The same jitter pattern on a small and a large grid: the per-vertex criterion stops
        // both at a similar sweep; the absolute one needs more sweeps on the larger mesh.
        let jitter = |n: u32| {
            let m = grid(n, n);
            let p: Vec<DVec2> = m
                .points()
                .iter()
                .map(|q| {
                    let inside = q.x > 0.0 && q.y > 0.0 && q.x < n as f64 && q.y < n as f64;
                    if inside {
                        *q + 0.2 * DVec2::new((q.x * 7.0 + q.y).sin(), (q.y * 5.0 - q.x).cos())
                    } else {
                        *q
                    }
                })
                .collect();
            QuadMesh::new(p, m.quads().to_vec(), None).unwrap()
        };
        let run = |n: u32, options: &Options| optimize(&mut jitter(n), options).unwrap().iterations;
        let relative = Options { boundary: BoundaryMode::Fixed, tau: 1e-6, ..Options::default() };
        let absolute = Options { tau_absolute: true, tau: 1e-4, ..relative.clone() };
        let (rs, rl) = (run(8, &relative), run(32, &relative));
        let (a_s, a_l) = (run(8, &absolute), run(32, &absolute));
        assert!(a_l > a_s, "absolute tau: {a_s} sweeps on 8x8, {a_l} on 32x32");
        assert!((rl as f64) < 1.5 * rs as f64 + 5.0, "per-vertex tau: {rs} sweeps on 8x8, {rl} on 32x32");
    }
}

//! The optimizer on curved surfaces: the planar run's stages (untangling, guarded sweeps by
//! colour class, the best iterate, a max-min stage), each vertex's computation in its
//! tangent-plane chart ([`super::star`]) and every result put back on the reference surface.

use glam::DVec3;
use rayon::prelude::*;
use std::time::Instant;

use super::features::{SurfaceFeatures, VertexRole};
use super::mesh::SurfaceMesh;
use super::moves::{self, Step, StepRule};
use super::patches::{Patches, corner_vertices};
use super::reference::{NO_TRIANGLE, ReferenceSurface};
use super::report::{SurfaceFidelity, SurfaceMeasure, SurfaceReport};
use super::slack::Slack;
use super::star::{Bound, LocalStar, MAX_PATCHES, Motion, State, Surface};
use super::tracks::Tracks;
use crate::error::{Error, Result};
use crate::face::Face;
use crate::quality::{ByFaceKind, QualityStats};
use crate::smooth::effort::Effort;
use crate::smooth::options::{BoundaryMode, Method, Options, StopRule};
use crate::smooth::ranking::{MIN_TIE, MIN_TIE_BEFORE_MAX_MIN, improves_with_tie};
use crate::smooth::report::Progress;
use crate::smooth::stopping::{self, Stopper};
use crate::topology::{Topology, VertexKind};

/// Classes smaller than this are computed on the calling thread (as in the plane).
const PARALLEL_MIN: usize = 512;

/// Untangling sweeps at most.
const UNTANGLE_SWEEPS: usize = 20;

/// Sweeps for the average after the max-min stage, per preset (they stop at the first that
/// does not rank better).
fn recovery_sweeps(effort: Effort) -> usize {
    match effort {
        Effort::Fast => 0,
        Effort::Balanced => 3,
        Effort::Best => 10,
    }
}

/// Rounds of the max-min stage per preset (`best` stops earlier when a round gains nothing).
fn max_min_rounds(effort: Effort) -> usize {
    match effort {
        Effort::Fast => 0,
        Effort::Balanced => Effort::BALANCED_ROUNDS,
        Effort::Best => 30,
    }
}

/// An optimizer for one surface mesh: its features, patches and reference surface, built
/// once from the input positions.
///
/// ```
/// use glam::DVec3;
/// use quadopt::surface::{SurfaceMesh, SurfaceOptimizer};
/// use quadopt::Options;
///
/// // A 4x4 grid of quads on a cylinder of radius 1 (a quarter turn), one vertex pushed along it.
/// let at = |i: usize, j: usize| {
///     let a = i as f64 * std::f64::consts::FRAC_PI_8;
///     DVec3::new(a.cos(), a.sin(), j as f64 * 0.4)
/// };
/// let mut points: Vec<DVec3> = (0..25).map(|k| at(k % 5, k / 5)).collect();
/// let a = 2.6 * std::f64::consts::FRAC_PI_8;
/// points[12] = DVec3::new(a.cos(), a.sin(), 0.8);
/// let faces = (0..16).map(|k| {
///     let (i, j) = (k % 4, k / 4);
///     let v = (j * 5 + i) as u32;
///     [v, v + 1, v + 6, v + 5]
/// });
/// let mut mesh = SurfaceMesh::new(points, faces.collect(), None)?;
/// let optimizer = SurfaceOptimizer::new(&mesh, 45.0, &[])?;
/// let report = optimizer.run(&mut mesh, &Options::default(), None)?;
/// assert!(report.output.min > report.input.min);
/// // Still on the cylinder: every vertex within rounding of the input surface.
/// assert!(report.fidelity.max_distance < 1e-12);
/// # Ok::<(), quadopt::Error>(())
/// ```
pub struct SurfaceOptimizer {
    faces: Vec<Face>,
    topo: Topology,
    features: SurfaceFeatures,
    patches: Patches,
    tracks: Tracks,
    motion: Vec<Motion>,
    /// The input positions in the optimizer's units: the caller's scaled by `2^-exponent`.
    input_points: Vec<DVec3>,
    /// The caller's input positions when they differ from `input_points` (`exponent != 0`).
    caller_points: Vec<DVec3>,
    /// The power of two the optimizer's units are of the caller's (see [`SurfaceOptimizer::new`]).
    exponent: i32,
    /// The input's mean edge length, in the optimizer's units.
    mean_edge: f64,
}

impl SurfaceOptimizer {
    /// Builds the optimizer of `mesh` at its current positions: sharp edges are those whose
    /// faces' normals differ by more than `feature_angle_deg` (also the turn at which a feature
    /// curve has a corner), and `marked` lists more feature edges as vertex pairs (errors as
    /// [`SurfaceFeatures::detect`]).
    ///
    /// The optimizer works on the mesh scaled by a power of two into the unit box (exact):
    /// normals, squared lengths and areas neither over- nor underflow at any scale, and a mesh
    /// scaled by a power of two gets the very same run. Results go back to the caller's units
    /// exactly, and a vertex that did not move keeps the caller's bits.
    pub fn new(mesh: &SurfaceMesh, feature_angle_deg: f64, marked: &[[u32; 2]]) -> Result<SurfaceOptimizer> {
        let exponent = crate::power_of_two::extent_exponent3(
            mesh.faces()
                .iter()
                .flat_map(|f| crate::face::vertices(f).iter().map(|&v| mesh.points()[v as usize])),
        );
        let scaled;
        let (mesh, caller_points) = if exponent == 0 {
            (mesh, Vec::new())
        } else {
            scaled = mesh.scaled(-exponent)?;
            (&scaled, crate::alloc::try_copy(mesh.points(), "input positions")?)
        };
        let features = SurfaceFeatures::detect(mesh, feature_angle_deg, marked)?;
        let topo = Topology::try_from_faces(mesh.points().len(), mesh.faces())?;
        let patches = Patches::new(mesh, &features)?;
        let tracks = Tracks::new(&features, mesh.points());
        let motion = (0..mesh.points().len())
            .map(|v| {
                if mesh.fixed()[v] {
                    return Motion::Still;
                }
                let kind = topo.kind(v);
                if !matches!(kind, VertexKind::Interior | VertexKind::Boundary) {
                    return Motion::Still;
                }
                let mut patches_here: Vec<u32> =
                    topo.vertex_quads(v).iter().map(|&f| patches.of_face(f as usize)).collect();
                patches_here.sort_unstable();
                patches_here.dedup();
                match features.roles()[v] {
                    VertexRole::Corner => Motion::Still,
                    VertexRole::Free if kind == VertexKind::Interior && patches_here.len() == 1 => {
                        Motion::Free(patches_here[0])
                    }
                    VertexRole::OnCurve(_) if patches_here.len() <= MAX_PATCHES => {
                        tracks.slot(v).map_or(Motion::Still, Motion::Curve)
                    }
                    _ => Motion::Still,
                }
            })
            .collect();
        let mut edge_sum = 0.0;
        for e in mesh.edges() {
            edge_sum += (mesh.points()[e.a as usize] - mesh.points()[e.b as usize]).length();
        }
        let mean_edge = edge_sum / mesh.edges().len().max(1) as f64;
        Ok(SurfaceOptimizer {
            faces: mesh.faces().to_vec(),
            topo,
            features,
            patches,
            tracks,
            motion,
            input_points: mesh.points().to_vec(),
            caller_points,
            exponent,
            mean_edge,
        })
    }

    /// The features found at construction.
    pub fn features(&self) -> &SurfaceFeatures {
        &self.features
    }

    /// Number of smooth patches the feature curves cut the surface into.
    pub fn patch_count(&self) -> usize {
        self.patches.count()
    }

    pub(super) fn surface(&self) -> Surface<'_> {
        self.bounded(&[], None)
    }

    /// The surface whose faces may not fall below `bounds` (one per face) and whose curves'
    /// new edges stay within `curve_tolerance` (`Options::max_boundary_deviation`).
    pub(super) fn bounded<'a>(&'a self, bounds: &'a [Bound], curve_tolerance: Option<f64>) -> Surface<'a> {
        Surface {
            faces: &self.faces,
            topo: &self.topo,
            patches: &self.patches,
            tracks: &self.tracks,
            motion: &self.motion,
            bounds,
            curve_tolerance,
        }
    }

    /// `value` of every face, in parallel on large meshes (the same values either way).
    fn per_face(&self, value: impl Fn(usize) -> f64 + Sync + Send) -> Vec<f64> {
        if self.faces.len() >= 4 * PARALLEL_MIN {
            (0..self.faces.len()).into_par_iter().map(value).collect()
        } else {
            (0..self.faces.len()).map(value).collect()
        }
    }

    /// The signed scaled Jacobian of every face at `state`.
    pub(super) fn values(&self, state: &State) -> Vec<f64> {
        let surface = self.surface();
        self.per_face(|f| surface.face_value(state, f, None))
    }

    /// The signed scaled Jacobian of every face of the input (each corner against its
    /// patch's normal at the input positions): the measure the optimizer ranks by.
    pub fn input_values(&self) -> Vec<f64> {
        self.values(&self.initial_state())
    }

    pub(super) fn initial_state(&self) -> State {
        State {
            points: self.input_points.clone(),
            params: self.tracks.initial_params(),
            hints: self.initial_hints(),
            normals: self.patches.input_corner_normals().to_vec(),
        }
    }

    /// Each free vertex's triangle at the input: one of its patch's reference triangles it is a
    /// corner of, where its first projection walks from.
    fn initial_hints(&self) -> Vec<u32> {
        (0..self.input_points.len())
            .map(|v| match (self.motion[v], self.topo.vertex_quads(v).first()) {
                (Motion::Free(_), Some(&f)) => self.patches.triangle_at(f as usize, v as u32),
                _ => NO_TRIANGLE,
            })
            .collect()
    }

    /// Optimizes `mesh`, which must have the faces and the positions this optimizer was built
    /// for (else [`Error::ConnectivityMismatch`] or [`Error::VertexCountMismatch`]). Vertices
    /// move on the input surface: a vertex on no feature curve within its smooth patch, one on
    /// a feature curve along the curve's original polyline; corners and fixed vertices keep
    /// their coordinates bit for bit. The result is never worse than the input by the signed
    /// measure (inverted faces, then minimum, then average), no face valid in the input ends
    /// inverted, and it is the same on any number of threads. `progress` runs after every
    /// sweep; returning `false` cancels, keeping the best positions so far.
    pub fn run(
        &self,
        mesh: &mut SurfaceMesh,
        options: &Options,
        progress: Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> Result<SurfaceReport> {
        options.validate()?;
        if mesh.points().len() != self.input_points.len() {
            return Err(Error::VertexCountMismatch {
                expected: self.input_points.len(),
                got: mesh.points().len(),
            });
        }
        if mesh.faces() != self.faces.as_slice() {
            return Err(Error::ConnectivityMismatch { expected: self.faces.len(), got: mesh.faces().len() });
        }
        if mesh.points() != self.caller_input() {
            return Err(Error::InvalidOption {
                name: "points",
                reason: "the mesh has moved since its optimizer was built: build a new SurfaceOptimizer"
                    .into(),
            });
        }
        let start = Instant::now();
        let run = if rayon::current_thread_index().is_some() {
            self.run_here(options, progress)
        } else {
            // On quadopt's own pool, the progress callback on the calling thread (as in the plane).
            let wants_progress = progress.is_some();
            let job = |ask: &mut dyn FnMut(Progress) -> bool| {
                let mut forward = |p: &Progress| ask(*p);
                self.run_here(options, if wants_progress { Some(&mut forward) } else { None })
            };
            let mut progress = progress;
            let answer = |p: Progress| progress.as_mut().is_none_or(|f| f(&p));
            crate::pool::run_with_progress(job, answer)
                .map_err(|crate::pool::NoThreads(why)| Error::NoThreads { why })?
        };
        let Run { state, input, input_values, iterations, untangle_sweeps, cancelled, max_min, end } = run;
        // Only moved vertices change: the others keep their bits (they were never written).
        mesh.set_points(&self.to_caller(&state.points)?)?;
        Ok(SurfaceReport {
            input,
            output: QualityStats::from_values(&end.values),
            input_verdict: end.input_verdict,
            output_verdict: end.output_verdict,
            input_by_kind: ByFaceKind::new(&self.faces, &input_values),
            output_by_kind: ByFaceKind::new(&self.faces, &end.values),
            iterations,
            untangle_sweeps,
            cancelled,
            max_min,
            seconds: start.elapsed().as_secs_f64(),
            effort: options.effort,
            patches: self.patches.count(),
            feature_curves: self.features.curves().len(),
            corners: self.features.roles().iter().filter(|r| **r == VertexRole::Corner).count(),
            movable: self.motion.iter().filter(|m| **m != Motion::Still).count(),
            fidelity: self.fidelity_to_caller(end.fidelity),
            output_values: end.values,
        })
    }

    /// The caller's input positions.
    fn caller_input(&self) -> &[DVec3] {
        if self.exponent == 0 { &self.input_points } else { &self.caller_points }
    }

    /// `points`, in the caller's units, in the optimizer's.
    fn to_units(&self, points: &[DVec3]) -> Result<Vec<DVec3>> {
        let mut out = crate::alloc::try_with_capacity(points.len(), "scaled positions")?;
        out.extend(points.iter().map(|&p| crate::power_of_two::scale_point3(p, -self.exponent)));
        Ok(out)
    }

    /// `points`, a placement in the optimizer's units, in the caller's: a vertex at its input
    /// position gets the caller's bits back (its scaled copy may have lost some below the
    /// normal range), a moved one its position scaled back (exact).
    fn to_caller(&self, points: &[DVec3]) -> Result<Vec<DVec3>> {
        if self.exponent == 0 {
            return crate::alloc::try_copy(points, "output positions");
        }
        let mut out = crate::alloc::try_with_capacity(points.len(), "output positions")?;
        out.extend(points.iter().zip(&self.input_points).zip(&self.caller_points).map(
            |((&p, &input), &caller)| {
                if p == input { caller } else { crate::power_of_two::scale_point3(p, self.exponent) }
            },
        ));
        Ok(out)
    }

    /// Distances measured in the optimizer's units, in the caller's (exact).
    fn fidelity_to_caller(&self, f: SurfaceFidelity) -> SurfaceFidelity {
        let back = |d: f64| crate::power_of_two::scale_by_power_of_two(d, self.exponent);
        SurfaceFidelity {
            max_distance: back(f.max_distance),
            max_feature_distance: back(f.max_feature_distance),
            max_curve_deviation: back(f.max_curve_deviation),
            mean_edge: back(f.mean_edge),
        }
    }

    /// What the report measures of a run's result, computed on the run's pool.
    fn measure_end(&self, state: &State) -> EndMeasures {
        // Verdict's values as `quality3d::verdict_values`, per face in parallel.
        let verdict = |points: &[DVec3]| {
            let corners = |f: usize| crate::quality3d::corners(points, &self.faces[f]);
            QualityStats::from_values(
                &self.per_face(|f| crate::quality3d::verdict_scaled_jacobian(&corners(f))),
            )
        };
        EndMeasures {
            values: self.values(state),
            input_verdict: verdict(&self.input_points),
            output_verdict: verdict(&state.points),
            fidelity: self.state_fidelity(state),
        }
    }

    /// How far a run's result is from the input surface and its feature vertices from their
    /// curves: a free vertex's distance from its patch (the query from its last triangle), an
    /// on-curve vertex's from its curve's segments around its arclength (the curve lies on
    /// the surface), so each is an upper bound of the distance it reports.
    fn state_fidelity(&self, state: &State) -> SurfaceFidelity {
        // (distance from the surface, distance from the curve) of one vertex.
        let distances = |v: usize| {
            let p = state.points[v];
            if p == self.input_points[v] {
                return (0.0, 0.0);
            }
            match self.motion[v] {
                Motion::Free(patch) => {
                    let on = self.patches.project(patch, p, state.hints[v]);
                    ((on.point - p).length(), 0.0)
                }
                Motion::Curve(slot) => {
                    let d = self.tracks.track(slot.track).distance_near(p, state.params[v]);
                    (d, d)
                }
                // Never moves.
                Motion::Still => (0.0, 0.0),
            }
        };
        // The largest of each, whatever the order (the maximum of numbers is).
        let larger = |a: (f64, f64), b: (f64, f64)| (a.0.max(b.0), a.1.max(b.1));
        let n = state.points.len();
        let (max_distance, max_feature_distance) = if n >= 4 * PARALLEL_MIN {
            (0..n).into_par_iter().map(distances).reduce(|| (0.0, 0.0), larger)
        } else {
            (0..n).map(distances).fold((0.0, 0.0), larger)
        };
        SurfaceFidelity {
            max_distance,
            max_feature_distance,
            max_curve_deviation: self.curve_deviation(&state.params),
            mean_edge: self.mean_edge,
        }
    }

    /// The quality of `points`, a placement of this optimizer's mesh (another smoother's
    /// output, say), measured against the input surface: the signed values (each corner
    /// against the normal of its face's patch at the corner's closest point), Verdict's 3D
    /// values, and the distances of the vertices from the whole input surface and of the
    /// on-curve vertices from their curves. [`Error::VertexCountMismatch`] if `points` has
    /// another length.
    pub fn measure(&self, caller_points: &[DVec3]) -> Result<SurfaceMeasure> {
        if caller_points.len() != self.input_points.len() {
            return Err(Error::VertexCountMismatch {
                expected: self.input_points.len(),
                got: caller_points.len(),
            });
        }
        let scaled;
        let points = if self.exponent == 0 {
            caller_points
        } else {
            scaled = self.to_units(caller_points)?;
            &scaled
        };
        let mut state = self.initial_state();
        if points != self.input_points.as_slice() {
            state.points = points.to_vec();
            // Each moved vertex projected once per patch around it (a cone's apex is a corner
            // of thousands of faces), its normal there given to its corners. The input's own
            // normal stays, bit for bit, where the vertex has not moved or the corner is
            // measured against its face's own normal.
            let mut normals: Vec<(u32, DVec3)> = Vec::new();
            for (v, &p) in points.iter().enumerate() {
                if p == self.input_points[v] {
                    continue;
                }
                normals.clear();
                for &f in self.topo.vertex_quads(v) {
                    let f = f as usize;
                    let patch = self.patches.of_face(f);
                    for (k, &u) in corner_vertices(&self.faces[f]).iter().enumerate() {
                        if u as usize != v || self.patches.is_own(f, k) {
                            continue;
                        }
                        let normal = match normals.iter().find(|(q, _)| *q == patch) {
                            Some(&(_, n)) => n,
                            None => {
                                let n = self.patches.project(patch, p, NO_TRIANGLE).normal;
                                normals.push((patch, n));
                                n
                            }
                        };
                        state.normals[f][k] = normal;
                    }
                }
            }
        }
        let values = self.values(&state);
        let verdict_values = crate::quality3d::verdict_values(caller_points, &self.faces);
        let whole = ReferenceSurface::new(&self.input_points, &self.faces)?;
        // Each on-curve vertex's arclength: the input's where it has not moved, else that of
        // its closest point on its curve.
        let mut params = self.tracks.initial_params();
        for (v, p) in points.iter().enumerate() {
            if let (Some(slot), true) = (self.tracks.slot(v), *p != self.input_points[v]) {
                params[v] = self.tracks.track(slot.track).closest_param(*p);
            }
        }
        let (mut max_distance, mut max_feature_distance) = (0.0f64, 0.0f64);
        for (v, p) in points.iter().enumerate() {
            if *p == self.input_points[v] || self.topo.vertex_quads(v).is_empty() {
                continue;
            }
            max_distance = max_distance.max(whole.closest_point(*p).distance);
            if let Some(slot) = self.tracks.slot(v) {
                max_feature_distance = max_feature_distance.max(self.tracks.track(slot.track).distance(*p));
            }
        }
        Ok(SurfaceMeasure {
            signed: QualityStats::from_values(&values),
            verdict: QualityStats::from_values(&verdict_values),
            by_kind: ByFaceKind::new(&self.faces, &values),
            values,
            verdict_values,
            fidelity: self.fidelity_to_caller(SurfaceFidelity {
                max_distance,
                max_feature_distance,
                max_curve_deviation: self.curve_deviation(&params),
                mean_edge: self.mean_edge,
            }),
        })
    }

    /// Verdict's value of every face with its corners at `points`.
    fn verdicts(&self, points: &[DVec3]) -> Vec<f64> {
        self.per_face(|f| {
            crate::quality3d::verdict_scaled_jacobian(&crate::quality3d::corners(points, &self.faces[f]))
        })
    }

    /// The run on the current thread's pool.
    fn run_here(&self, options: &Options, mut progress: Option<&mut dyn FnMut(&Progress) -> bool>) -> Run {
        let mut state = self.initial_state();
        let values = self.values(&state);
        let input_verdicts = self.verdicts(&state.points);
        let input = QualityStats::from_values(&values);
        let input_verdict = QualityStats::from_values(&input_verdicts);
        // Every face's bounds in both measures: no move goes below them, and what ends below
        // them after rounding goes back (`restore_below_bounds`).
        let bounds = Bound::of_input(&values, &input_verdicts, options.guard_floor);
        let surface = self.bounded(&bounds, options.max_boundary_deviation);
        let input_both = Both::new(input, input_verdict);
        let rounds = if options.max_min { max_min_rounds(options.effort) } else { 0 };
        let tie = if rounds > 0 { MIN_TIE_BEFORE_MAX_MIN } else { MIN_TIE };
        let mut best = (input_both, state.clone());
        // An iterate is kept when it ranks better in both measures together, keeps every face
        // at or above its bounds, and is not worse than the input in either measure.
        let ranks_better = |candidate: &Both, values: (&[f64], &[f64]), best: &Both, tie: f64| {
            candidate.not_worse_than(&input_both)
                && within(values.0, values.1, &bounds)
                && improves_with_tie(&candidate.ranked, &best.ranked, &input_both.ranked, tie)
        };
        let consider = |state: &State, best: &mut (Both, State), tie: f64| -> bool {
            let values = self.values(state);
            let verdicts = self.verdicts(&state.points);
            let both = Both::of(&values, &verdicts);
            if ranks_better(&both, (&values, &verdicts), &best.0, tie) {
                *best = (both, state.clone());
                return true;
            }
            false
        };
        let mut cancelled = false;
        let sweep_cap = options.sweep_cap();
        let mut report = |iteration: usize, energy: f64, energy_change: f64| {
            let p =
                Progress { iteration, max_iterations: sweep_cap, energy, energy_change, pass: 1, passes: 1 };
            progress.as_mut().is_none_or(|cb| cb(&p))
        };
        // With `BoundaryMode::Fixed`, vertices on feature curves never move (in every stage).
        let curves_move = options.boundary != BoundaryMode::Fixed;
        let may_move =
            |surface: &Surface, v: usize| curves_move || !matches!(surface.motion[v], Motion::Curve(_));

        // 1. Untangling.
        let mut untangle_sweeps = 0;
        if options.untangle && (input.inverted > 0 || input_verdict.inverted > 0) {
            let mut lowest = input.inverted + input_verdict.inverted;
            let mut stale = 0;
            while untangle_sweeps < UNTANGLE_SWEEPS {
                untangle_sweeps += 1;
                let (moved, _) = self.sweep(&surface, &mut state, None, |surface, state, v, star, _| {
                    let to = if may_move(surface, v) {
                        moves::untangle_move(surface, state, v, star)
                    } else {
                        None
                    };
                    Step::uncertified(to, 0.0)
                });
                consider(&state, &mut best, tie);
                let inverted = QualityStats::from_values(&self.values(&state)).inverted
                    + QualityStats::from_values(&self.verdicts(&state.points)).inverted;
                if !report(0, f64::NAN, f64::NAN) {
                    cancelled = true;
                    break;
                }
                if inverted == 0 || moved == 0 {
                    break;
                }
                if inverted < lowest {
                    (lowest, stale) = (inverted, 0);
                } else {
                    stale += 1;
                    if stale >= 3 {
                        break;
                    }
                }
            }
        }

        // 2. Guarded sweeps, stopped by the planar run's rules ([`Stopper`]; the energy is the
        // embedded polygon's, summed over the vertices' charts).
        let floor = options.guard_floor.max(input.min);
        let with_laplacian = options.method == Method::EmbeddedPolygon && options.effort != Effort::Fast;
        let rule = StepRule {
            method: options.method,
            lambda: options.lambda,
            guard: options.guard,
            floor,
            with_laplacian,
        };
        let movable = self.motion.iter().filter(|m| **m != Motion::Still).count();
        let mut stopper = Stopper::new(options, movable);
        // The input's values again unless untangling moved something.
        let start_values = if untangle_sweeps == 0 { values.clone() } else { self.values(&state) };
        stopper.start(&QualityStats::from_values(&start_values), &best.0.signed);
        // The guard's first test by certificate where it can (src/surface/slack.rs).
        let mut slack = options.guard.then(|| Slack::new(&surface, &state, &start_values, floor));
        let stale_limit = options.effort.stale_sweeps().filter(|_| options.stop == StopRule::Quality);
        let (mut iterations, mut stale) = (0, 0);
        while !cancelled && iterations < sweep_cap {
            iterations += 1;
            let (moved, energy) =
                self.sweep(&surface, &mut state, slack.as_mut(), |surface, state, v, star, slack| {
                    if !may_move(surface, v) {
                        return Step::uncertified(None, 0.0);
                    }
                    moves::smoothing_move(surface, state, v, &rule, star, slack)
                });
            let kept_before = best.0.ranked;
            let (values, verdicts) = match slack.as_mut() {
                Some(slack) => slack.values_and_reset(&surface, &state, floor),
                None => (self.values(&state), self.verdicts(&state.points)),
            };
            let stats = QualityStats::from_values(&values);
            let both = Both::of(&values, &verdicts);
            if ranks_better(&both, (&values, &verdicts), &best.0, tie) {
                best.0 = both;
                best.1.clone_from(&state);
            }
            stale = if stopping::same(&kept_before, &best.0.ranked) { stale + 1 } else { 0 };
            let kept = if options.keep_best { best.0.signed } else { stats };
            let verdict = stopper.after_sweep(&stats, &kept, energy);
            if !report(iterations, energy, verdict.energy_change) {
                cancelled = true;
            }
            if verdict.stop
                || (moved == 0 && options.stop == StopRule::Quality)
                || stale_limit.is_some_and(|limit| stale >= limit)
            {
                break;
            }
        }
        if options.keep_best {
            state = best.1;
        }

        // 3. The max-min stage, from the kept iterate; each round kept only if it ranks better.
        // A minimum within the ranking's tie threshold of a perfect face has nothing to gain
        // (the plane's rule).
        let mut max_min = None;
        let kept_min = if options.keep_best {
            best.0.signed.min
        } else {
            QualityStats::from_values(&self.values(&state)).min
        };
        if rounds > 0 && !cancelled && kept_min < 1.0 - MIN_TIE {
            let t = Instant::now();
            let before = best.0.signed;
            let mut done = 0;
            let values = self.values(&state);
            let verdicts = self.verdicts(&state.points);
            let mut current = (Both::of(&values, &verdicts), state.clone());
            for _ in 0..rounds {
                // The worst faces in either measure.
                let verdicts = self.verdicts(&current.1.points);
                let values: Vec<f64> =
                    self.values(&current.1).iter().zip(&verdicts).map(|(&s, &v)| s.min(v)).collect();
                let mut trial = current.1.clone();
                let moved = self.max_min_round(&surface, &mut trial, &values, curves_move, &mut || {
                    report(iterations, f64::NAN, f64::NAN)
                });
                done += 1;
                let stopped = moved.is_none();
                let gained = moved.unwrap_or(1) > 0 && consider(&trial, &mut current, MIN_TIE.min(1e-9));
                if stopped || !report(iterations, f64::NAN, f64::NAN) {
                    cancelled = true;
                    break;
                }
                if !gained {
                    break;
                }
            }
            if current.0.signed != before || !options.keep_best {
                state = current.1;
            }
            max_min = Some(crate::smooth::report::MaxMinGain {
                before,
                after: QualityStats::from_values(&self.values(&state)),
                rounds: done,
                seconds: t.elapsed().as_secs_f64(),
            });
        }
        // 4. Sweeps for the average with the floor at the minimum reached, so the stage's
        // minimum is kept; each kept only if it ranks better (docs/surfaces.md).
        if max_min.is_some() && !cancelled {
            let values = self.values(&state);
            let verdicts = self.verdicts(&state.points);
            let mut kept = (Both::of(&values, &verdicts), state.clone());
            let rule = StepRule { floor: kept.0.signed.min.max(options.guard_floor), ..rule };
            for _ in 0..recovery_sweeps(options.effort) {
                let mut trial = kept.1.clone();
                self.sweep(&surface, &mut trial, None, |surface, state, v, star, _| {
                    if !may_move(surface, v) {
                        return Step::uncertified(None, 0.0);
                    }
                    moves::smoothing_move(surface, state, v, &rule, star, None)
                });
                if !consider(&trial, &mut kept, MIN_TIE) || !report(iterations, f64::NAN, f64::NAN) {
                    break;
                }
            }
            state = kept.1;
        }
        self.restore_below_bounds(&mut state, &bounds, options.max_boundary_deviation);
        let end = self.measure_end(&state);
        Run { state, input, input_values: values, iterations, untangle_sweeps, cancelled, max_min, end }
    }

    /// The largest distance of a new edge along a curve from the stretch it replaces, the
    /// curves' vertices at arclengths `params` ([`SurfaceFidelity::max_curve_deviation`]).
    fn curve_deviation(&self, params: &[f64]) -> f64 {
        self.tracks
            .edges(params)
            .map(|(t, _, s0, s1)| t.chord_deviation(s0, s1).new_to_original)
            .fold(0.0, f64::max)
    }

    /// Puts back at their input positions the moved vertices of every face below its bound in
    /// either measure, and with a curve tolerance those of every curve edge beyond it (or
    /// whose ends passed each other), round after round until none is (at worst the input,
    /// where every face is at its input value and every curve edge on its curve): the
    /// guarantee, whatever path the run took (no guard, the rounding of a projection).
    fn restore_below_bounds(
        &self,
        state: &mut State,
        bounds: &[Bound],
        curve_tolerance: Option<f64>,
    ) -> usize {
        let initial = self.initial_state();
        let surface = self.surface();
        let mut restored = 0;
        // Vertex v back at its input (its position, arclength, hint and the normals of its
        // corners), returning what it replaced; `put` undoes it with that.
        type Saved = (DVec3, f64, u32, Vec<(usize, usize, DVec3)>);
        let swap = |state: &mut State, v: usize, to: &Saved| -> Saved {
            let was = (state.points[v], state.params[v], state.hints[v], {
                let mut corners = Vec::new();
                for &g in self.topo.vertex_quads(v) {
                    let g = g as usize;
                    for (k, &u) in corner_vertices(&self.faces[g]).iter().enumerate() {
                        if u as usize == v {
                            corners.push((g, k, state.normals[g][k]));
                        }
                    }
                }
                corners
            });
            (state.points[v], state.params[v], state.hints[v]) = (to.0, to.1, to.2);
            for &(g, k, n) in &to.3 {
                state.normals[g][k] = n;
            }
            was
        };
        let input_of = |v: usize| -> Saved {
            let mut corners = Vec::new();
            for &g in self.topo.vertex_quads(v) {
                let g = g as usize;
                for (k, &u) in corner_vertices(&self.faces[g]).iter().enumerate() {
                    if u as usize == v {
                        corners.push((g, k, initial.normals[g][k]));
                    }
                }
            }
            (initial.points[v], initial.params[v], initial.hints[v], corners)
        };
        let restore = |state: &mut State, v: usize| {
            if state.points[v] == initial.points[v] {
                return false;
            }
            swap(state, v, &input_of(v));
            true
        };
        let within = |state: &State, f: usize| {
            surface.face_value(state, f, None) >= bounds[f].signed
                && surface.face_verdict(state, f, None) >= bounds[f].verdict
        };
        loop {
            let values = self.values(state);
            let verdicts = self.verdicts(&state.points);
            let mut changed = false;
            for (f, b) in bounds.iter().enumerate() {
                if values[f] >= b.signed && verdicts[f] >= b.verdict || within(state, f) {
                    continue;
                }
                // One vertex back, the first that mends the face without putting another face
                // of its star below (the rest of the run's progress stays), else all of them.
                let single = crate::face::vertices(&self.faces[f]).iter().map(|&v| v as usize).find(|&v| {
                    if state.points[v] == initial.points[v] {
                        return false;
                    }
                    let was = swap(state, v, &input_of(v));
                    let mended = self.topo.vertex_quads(v).iter().all(|&g| within(state, g as usize));
                    swap(state, v, &was);
                    mended
                });
                if let Some(v) = single {
                    restore(state, v);
                    restored += 1;
                    changed = true;
                    continue;
                }
                for &v in crate::face::vertices(&self.faces[f]) {
                    if restore(state, v as usize) {
                        restored += 1;
                        changed = true;
                    }
                }
            }
            if let Some(tol) = curve_tolerance {
                // The ends of every edge beyond the tolerance (by the curve order, through the
                // curves' vertex lists).
                let beyond: Vec<[u32; 2]> = self.tracks.beyond(&state.params, tol);
                for v in beyond.into_iter().flatten() {
                    if restore(state, v as usize) {
                        restored += 1;
                        changed = true;
                    }
                }
            }
            if !changed {
                return restored;
            }
        }
    }

    /// One sweep, colour class by colour class: each class's moves computed from the same
    /// positions (in parallel when large), then applied in order, so the result does not
    /// depend on the thread count. `step` gives a vertex's move and its energy before it.
    /// Returns how many vertices moved and the sum of the energies (in a fixed order).
    fn sweep(
        &self,
        surface: &Surface,
        state: &mut State,
        mut slack: Option<&mut Slack>,
        step: impl Fn(&Surface, &State, usize, &mut LocalStar, Option<&Slack>) -> Step + Sync,
    ) -> (usize, f64) {
        let (mut moved, mut energy) = (0, 0.0);
        let mut moves: Vec<(u32, Step)> = Vec::new();
        for c in 0..self.topo.colour_count() {
            let class = self.topo.colour_class(c);
            let certificates = slack.as_deref();
            // The move, and what the certificates record of it, computed in parallel; only
            // writing them is left to the ordered loop below.
            let compute = |star: &mut LocalStar, &v: &u32| {
                let mut s = step(surface, state, v as usize, star, certificates);
                if let (Some(to), Some(slack), None) = (&s.to, certificates, &s.certified) {
                    s.certified = Some(slack.displacement(surface, state, v as usize, to));
                }
                (v, s)
            };
            // One buffer for every class (a fresh one per class cost page faults).
            if class.len() >= PARALLEL_MIN {
                class.par_iter().map_init(LocalStar::default, compute).collect_into_vec(&mut moves);
            } else {
                let mut star = LocalStar::default();
                moves.clear();
                moves.extend(class.iter().map(|v| compute(&mut star, v)));
            }
            for (v, s) in &moves {
                energy += s.energy;
                if let Some(p) = &s.to {
                    surface.apply(state, *v as usize, p);
                    if let (Some(slack), Some(d)) = (slack.as_deref_mut(), s.certified) {
                        slack.record(*v as usize, d);
                    }
                    moved += 1;
                }
            }
        }
        (moved, energy)
    }

    /// One round of the max-min stage: the movable vertices of the worst faces (the lowest
    /// 2%, at least 4, and every inverted one), one after the other in vertex order, each to
    /// the best place its search finds. `go_on` is asked every [`ROUND_PROGRESS`] vertices;
    /// `None` when it said stop (the vertices done so far keep their moves).
    fn max_min_round(
        &self,
        surface: &Surface,
        state: &mut State,
        values: &[f64],
        curves_move: bool,
        go_on: &mut dyn FnMut() -> bool,
    ) -> Option<usize> {
        let mut sorted: Vec<f64> = values.to_vec();
        sorted.sort_unstable_by(f64::total_cmp);
        let k = (values.len() / 50).max(4).min(values.len());
        let threshold = sorted[k - 1].max(0.0);
        let mut vertices: Vec<u32> = Vec::new();
        for (f, &value) in values.iter().enumerate() {
            if value <= threshold {
                vertices.extend(crate::face::vertices(&self.faces[f]).iter().filter(|&&v| match self.motion
                    [v as usize]
                {
                    Motion::Still => false,
                    Motion::Curve(_) => curves_move,
                    Motion::Free(_) => true,
                }));
            }
        }
        vertices.sort_unstable();
        vertices.dedup();
        let mut star = LocalStar::default();
        let mut moved = 0;
        for (i, &v) in vertices.iter().enumerate() {
            if i > 0 && i % ROUND_PROGRESS == 0 && !go_on() {
                return None;
            }
            if let Some(p) = moves::max_min_move(surface, state, v as usize, &mut star) {
                surface.apply(state, v as usize, &p);
                moved += 1;
            }
        }
        Some(moved)
    }
}

/// Vertices of a max-min round between two progress reports (a round on a large mesh moves
/// thousands, each searched with up to 96 star scores).
const ROUND_PROGRESS: usize = 256;

/// An iterate's statistics in both measures, and the one they are ranked by: the inverted
/// faces of both, the lower minimum, the mean of the averages.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Both {
    signed: QualityStats,
    verdict: QualityStats,
    ranked: QualityStats,
}

impl Both {
    fn new(signed: QualityStats, verdict: QualityStats) -> Both {
        let ranked = QualityStats {
            min: signed.min.min(verdict.min),
            avg: 0.5 * (signed.avg + verdict.avg),
            max: signed.max.max(verdict.max),
            inverted: signed.inverted + verdict.inverted,
        };
        Both { signed, verdict, ranked }
    }

    fn of(signed: &[f64], verdict: &[f64]) -> Both {
        Both::new(QualityStats::from_values(signed), QualityStats::from_values(verdict))
    }

    /// No more inverted faces and no lower minimum than `input` in either measure.
    fn not_worse_than(&self, input: &Both) -> bool {
        let ok = |a: &QualityStats, b: &QualityStats| a.inverted <= b.inverted && a.min >= b.min;
        ok(&self.signed, &input.signed) && ok(&self.verdict, &input.verdict)
    }
}

/// Whether every face is at or above its bounds.
fn within(signed: &[f64], verdict: &[f64], bounds: &[Bound]) -> bool {
    bounds.iter().zip(signed.iter().zip(verdict)).all(|(b, (&s, &v))| s >= b.signed && v >= b.verdict)
}

/// What a run leaves.
struct Run {
    state: State,
    input: QualityStats,
    /// The signed value of each face of the input.
    input_values: Vec<f64>,
    iterations: usize,
    untangle_sweeps: usize,
    cancelled: bool,
    max_min: Option<crate::smooth::report::MaxMinGain>,
    end: EndMeasures,
}

/// The report's measures of a run's result.
struct EndMeasures {
    /// The signed value of each face.
    values: Vec<f64>,
    input_verdict: QualityStats,
    output_verdict: QualityStats,
    fidelity: SurfaceFidelity,
}

//! The optimizer: [`Optimizer::run`] ties the parts of a run together.
//!
//! A run:
//! 1. classifies the vertices ([`Features`]) and records the original boundary
//!    ([`boundary::BoundaryGeometry`]);
//! 2. untangles inverted quads first ([`untangle`]), when the input has any;
//! 3. sweeps colour class by colour class ([`sweep`]), each vertex taking its method's target
//!    through the guard of [`guard`]; boundary vertices follow the embedded polygon's
//!    boundary rule (Section 3.3) in the chosen [`BoundaryMode`] (`Auto` takes, per vertex and
//!    in one pass, the better of slide's and snap's candidates: [`auto`]);
//! 4. stops by the [`StopRule`]: by default [`StopRule::Quality`], when the quality the user
//!    gets (inverted count, minimum, average) stops improving; [`StopRule::Energy`] when the
//!    energy of Eq. 1 changes by less than `tau` per movable vertex;
//! 5. runs the max-min stage ([`maxmin`]) on the worst quads, as far as the [`Effort`] preset
//!    says (none for `Fast`), unless `max_min` is off;
//! 6. returns the best iterate seen (the input included), ranked by [`ranking`]: inverted
//!    count, then minimum scaled Jacobian, then average, among those with no more inverted
//!    quads, no quad inverted that was valid in the input, and a minimum not below the
//!    input's.

pub mod angle_based;
mod auto;
pub mod boundary;
pub mod effort;
pub mod embedded_polygon;
pub mod energy;
pub mod fidelity;
pub mod guard;
pub mod laplacian;
pub mod maxmin;
pub mod options;
pub mod ranking;
pub mod report;
pub(crate) mod stopping;
pub(crate) mod sweep;
pub mod untangle;

use crate::error::{Error, Result};
use crate::features::Features;
use crate::mesh::Mesh;
use crate::normalization::Normalization;
use crate::quality::{ByFaceKind, QualityStats};
use crate::renumbering::Renumbering;
use crate::topology::Topology;
use boundary::BoundaryGeometry;
pub use effort::Effort;
pub use fidelity::BoundaryFidelity;
use glam::DVec2;
pub use options::{BoundaryMode, Method, Options, StopRule};
use rayon::prelude::*;
pub use report::{MaxMinGain, Progress, Report};
use std::time::Instant;
use sweep::RunContext;
pub use untangle::{TangleReason, TangledQuad};

/// Optimizes `mesh` in place with `options`. Builds the topology; to optimize many meshes
/// with the same connectivity, build an [`Optimizer`] once instead.
pub fn optimize(mesh: &mut Mesh, options: &Options) -> Result<Report> {
    Optimizer::new(mesh).run(mesh, options, None)
}

/// A reusable optimizer: the topology of one connectivity, built once.
///
/// A large mesh is worked on in an order of its own, chosen for memory locality
/// (along a Hilbert curve); results come back in the caller's numbering.
///
/// ```
/// use quadopt::{DVec2, Optimizer, Options, Mesh};
///
/// // One connectivity (a 2x2 patch), two placements of its centre vertex.
/// let grid: Vec<DVec2> = (0..9).map(|k| DVec2::new((k % 3) as f64, (k / 3) as f64)).collect();
/// let quads = vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
/// let mut mesh = Mesh::new(grid.clone(), quads, None)?;
/// let optimizer = Optimizer::new(&mesh); // the topology, built once
///
/// let options = Options::default();
/// for centre in [DVec2::new(1.6, 1.5), DVec2::new(0.5, 0.7)] {
///     let mut points = grid.clone();
///     points[4] = centre;
///     mesh.set_points(&points)?;
///     // A progress callback after every sweep; returning false would cancel the run.
///     let mut sweeps = 0;
///     let mut progress = |_: &quadopt::Progress| {
///         sweeps += 1;
///         true
///     };
///     let report = optimizer.run(&mut mesh, &options, Some(&mut progress))?;
///     assert!(report.output.min > report.input.min && !report.cancelled);
///     assert!((mesh.points()[4] - DVec2::new(1.0, 1.0)).length() < 0.1);
///     assert!(sweeps >= 1);
/// }
/// # Ok::<(), quadopt::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct Optimizer {
    /// The topology, in the internal numbering when there is one.
    topology: Topology,
    renumbering: Option<Renumbering>,
    /// The quad count and a fingerprint of the quads it was built for: a run on other quads
    /// is an error, not an index out of range.
    quad_count: usize,
    fingerprint: u64,
}

/// A 64-bit FNV-1a hash of the quads' vertex indices.
fn fingerprint(quads: &[[u32; 4]]) -> u64 {
    quads
        .iter()
        .flatten()
        .fold(0xcbf2_9ce4_8422_2325, |h, &v| (h ^ u64::from(v)).wrapping_mul(0x0100_0000_01b3))
}

impl Optimizer {
    /// Builds the topology of `mesh`.
    pub fn new(mesh: &Mesh) -> Optimizer {
        // The order is only for speed: without the memory for it the mesh keeps its own.
        let (quad_count, fingerprint) = (mesh.quads().len(), fingerprint(mesh.quads()));
        if let Ok(Some(renumbering)) = Renumbering::new(mesh) {
            if let Ok(internal) = renumbering.internal(mesh) {
                let topology = Topology::new(&internal);
                return Optimizer { topology, renumbering: Some(renumbering), quad_count, fingerprint };
            }
        }
        Optimizer { topology: Topology::new(mesh), renumbering: None, quad_count, fingerprint }
    }

    /// Optimizes `mesh`, which must have the quads this optimizer was built for (else
    /// [`Error::VertexCountMismatch`] or [`Error::ConnectivityMismatch`], the mesh untouched).
    /// The optional `progress` callback runs after every sweep; returning `false` cancels,
    /// keeping the best positions reached so far.
    ///
    /// The run works on coordinates normalized to the mesh's bounding box
    /// (`src/normalization.rs`), so its result does not depend on the mesh's units: scaled by
    /// a power of two it is the same bit for bit. Vertices that do not move keep their
    /// coordinates exactly; the report's statistics are those of the coordinates given and
    /// returned.
    ///
    /// Threads: called inside a rayon pool (`ThreadPool::install`), the run uses that pool;
    /// otherwise quadopt's own pool, one per process (`RAYON_NUM_THREADS` threads, else one per
    /// core), never rayon's global pool, so that a process forked after a run can run again
    /// (its pool is rebuilt there). The result is the same on any number of threads. When no
    /// worker thread can start at all, the run fails with [`Error::NoThreads`].
    pub fn run(
        &self,
        mesh: &mut Mesh,
        options: &Options,
        progress: Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> Result<Report> {
        if mesh.points().len() != self.topology.vertex_count() {
            return Err(Error::VertexCountMismatch {
                expected: self.topology.vertex_count(),
                got: mesh.points().len(),
            });
        }
        if mesh.quads().len() != self.quad_count || fingerprint(mesh.quads()) != self.fingerprint {
            return Err(Error::ConnectivityMismatch { expected: self.quad_count, got: mesh.quads().len() });
        }
        // Per-kind statistics: with triangles, measured apart before and after the run.
        let triangles = mesh.quads().iter().any(crate::face::is_triangle);
        let input_by_kind = if triangles { Some(mesh.quality_by_face_kind()) } else { None };
        let mut report = self.run_in_numbering(mesh, options, progress)?;
        report.input_by_kind = input_by_kind.unwrap_or(ByFaceKind::quads_only(self.quad_count, report.input));
        report.output_by_kind = if triangles {
            mesh.quality_by_face_kind()
        } else {
            ByFaceKind::quads_only(self.quad_count, report.output)
        };
        Ok(report)
    }

    /// [`Optimizer::run`] after its checks: in the internal numbering if there is one.
    fn run_in_numbering(
        &self,
        mesh: &mut Mesh,
        options: &Options,
        progress: Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> Result<Report> {
        if let Some(renumbering) = &self.renumbering {
            // On an error the caller's mesh is left as it was: only the copy has moved.
            let mut internal = renumbering.internal(mesh)?;
            let mut report = self.run_on_pool(&mut internal, options, progress)?;
            // The statistics as the caller's order sums them (the average differs in its
            // last bits), so that they are the quality of the mesh given and returned.
            report.input = mesh.quality();
            renumbering.write_back(&internal, mesh);
            report.output = mesh.quality();
            for t in &mut report.tangled {
                t.quad = renumbering.quad(t.quad);
            }
            return Ok(report);
        }
        self.run_on_pool(mesh, options, progress)
    }

    /// [`Optimizer::run`] on a mesh in the internal numbering.
    fn run_on_pool(
        &self,
        mesh: &mut Mesh,
        options: &Options,
        progress: Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> Result<Report> {
        if rayon::current_thread_index().is_some() {
            // Inside the caller's rayon pool (`ThreadPool::install`): its threads do the work.
            return self.run_here(mesh, options, progress);
        }
        // Otherwise on quadopt's own pool, never rayon's global one: the global pool's workers
        // do not exist in a process forked after it started, and every later call there would
        // block; quadopt's pool is rebuilt in the child. The progress callback stays on the
        // calling thread.
        let wants_progress = progress.is_some();
        let job = |ask: &mut dyn FnMut(Progress) -> bool| {
            let mut forward = |p: &Progress| ask(*p);
            self.run_here(mesh, options, if wants_progress { Some(&mut forward) } else { None })
        };
        let mut progress = progress;
        let answer = |p: Progress| progress.as_mut().is_none_or(|f| f(&p));
        crate::pool::run_with_progress(job, answer)
            .map_err(|crate::pool::NoThreads(why)| Error::NoThreads { why })?
    }

    /// [`Optimizer::run`] on the current thread and pool.
    ///
    /// The run works on coordinates rounded to a grid ([`Normalization`]), which makes it the
    /// same for every rescaled copy of a mesh. Fixed and unmoved vertices come back with their
    /// own coordinates, so a quad the run left within the grid's rounding of degenerate can
    /// change sign in the output. Then the mesh is run again without the grid (the run of the
    /// releases before it), so that what the report diagnoses is what the output has.
    fn run_here(
        &self,
        mesh: &mut Mesh,
        options: &Options,
        mut progress: Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> Result<Report> {
        let frame = Normalization::new(mesh.points(), mesh.quads());
        let ask = progress.as_mut().map(|p| &mut **p as &mut dyn FnMut(&Progress) -> bool);
        let (report, consistent) = self.run_in_frame(&frame, mesh, options, ask)?;
        if consistent || frame.is_exact() {
            return Ok(report);
        }
        self.run_in_frame(&frame.without_grid(), mesh, options, progress).map(|(report, _)| report)
    }

    /// One run in `frame`; says whether the result holds on the actual coordinates: every
    /// quad has the sign class in the output that it had at the end of the run on the
    /// normalized ones, and a tangled input is not returned worse than it came. On `false`
    /// the mesh is left as it was given.
    fn run_in_frame(
        &self,
        frame: &Normalization,
        mesh: &mut Mesh,
        options: &Options,
        progress: Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> Result<(Report, bool)> {
        let (points, quads) = mesh.points_mut_and_quads();
        let normalized = frame.normalize(points, quads)?;
        let (result, mut on_boundary) = match self.run_normalized(mesh, options, progress) {
            Ok((report, on_boundary)) => (Ok(report), on_boundary),
            Err(e) => (Err(e), Vec::new()),
        };
        let classes = if frame.is_exact() {
            Ok(Vec::new())
        } else {
            try_values(mesh.points(), mesh.quads()).map(|values| sign_classes(&values))
        };
        // Moved boundary vertices lie on the normalized (grid-rounded) polyline: evaluated at
        // the same place on the original one, they stay on the original boundary exactly.
        on_boundary.retain(|b| !frame.unmoved(mesh.points()[b.vertex], &normalized, b.vertex));
        frame.restore(mesh.points_mut(), &normalized);
        let original = normalized.original();
        // On an error the mesh goes back as it was given.
        let (mut report, classes) = match (result, classes) {
            (Ok(report), Ok(classes)) => (report, classes),
            (Err(e), _) | (_, Err(e)) => {
                mesh.points_mut().copy_from_slice(original);
                return Err(e);
            }
        };
        for b in on_boundary {
            let (p0, p1) = (original[b.from], original[b.to]);
            mesh.points_mut()[b.vertex] = if b.t == 0.0 { p0 } else { p0 + (p1 - p0) * b.t };
        }
        // The output's values: the sign check's, then the restore's, then the report's.
        let mut values = match try_values(mesh.points(), mesh.quads()) {
            Ok(values) if classes.is_empty() || sign_classes(&values) == classes => values,
            disagree_or_error => {
                mesh.points_mut().copy_from_slice(original);
                return disagree_or_error.map(|_| (report, false));
            }
        };
        // Normalizing rounded the coordinates: report the quality of the actual ones.
        let input_values = crate::quality::quad_values(original, mesh.quads());
        report.input = QualityStats::from_values(&input_values);
        // The guarantee, per quad and on the actual coordinates (the grid's rounding, a
        // max-min move, a cell below one ulp of its coordinates): no quad ends below
        // min(its input value, floor); the vertices of one that does go back where they were,
        // until none does. Measured on Mesquite's tfi_chevron24x24, whose worst quads the run
        // ties, this keeps an average of 0.83 that returning the input loses (0.71).
        let floor = options.guard_floor.max(report.input.min);
        let restored =
            restore_below_bounds(mesh, original, &self.topology, &input_values, floor, &mut values);
        report.output = QualityStats::from_values(&values);
        let (input, output) = (&report.input, &report.output);
        // Only a tie on the minimum that the average decides for the input is left to lose:
        // the input is then the better result.
        if input.better_than_with_tie(output, ranking::MIN_TIE) {
            mesh.points_mut().copy_from_slice(original);
            if report.input.inverted > 0 && !frame.is_exact() {
                return Ok((report, false));
            }
            report.output = report.input;
        } else if restored > 0 && report.output.inverted > 0 {
            // The diagnosis describes the output as returned.
            let features = Features::new(
                mesh,
                &self.topology,
                options.feature_angle_deg,
                options.boundary != BoundaryMode::Fixed,
            );
            report.tangled = untangle::diagnose(mesh.points(), mesh.quads(), &self.topology, &features);
        }
        let fidelity = &mut report.fidelity;
        fidelity.max_deviation = frame.length_to_original(fidelity.max_deviation);
        fidelity.hausdorff = frame.length_to_original(fidelity.hausdorff);
        Ok((report, true))
    }

    /// The run on normalized coordinates; also says where each movable boundary vertex ends
    /// on the boundary polyline.
    fn run_normalized(
        &self,
        mesh: &mut Mesh,
        options: &Options,
        mut progress: Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> Result<(Report, Vec<OnPolyline>)> {
        options.validate()?;
        // `Optimizer::run` has checked the mesh against the topology.
        let topo = &self.topology;
        let start = Instant::now();
        // Only the statistics and the inverted flags outlive this: the values are 8 bytes a
        // quad that the sweeps would otherwise hold for nothing.
        let (input, input_inverted) = {
            let input_values = mesh.quality_values();
            let inverted: Vec<bool> = input_values.iter().map(|&v| v <= 0.0).collect();
            (QualityStats::from_values(&input_values), inverted)
        };
        let boundary_moves = options.boundary != BoundaryMode::Fixed;
        let features = Features::new(mesh, topo, options.feature_angle_deg, boundary_moves);
        let geometry = BoundaryGeometry::new(mesh.points(), topo, &features);
        let ctx = RunContext {
            topo,
            features: &features,
            geometry: &geometry,
            options,
            quads: mesh.quads(),
            input,
            input_inverted,
            floor: options.guard_floor.max(input.min),
        };
        let (mut pass, loop_modes) = if options.boundary == BoundaryMode::Auto {
            ctx.auto(mesh.points(), &mut progress)
        } else {
            let modes = vec![options.boundary; topo.loop_count()];
            (ctx.pass(mesh.points(), &modes, (1, 1), &mut progress), modes)
        };
        // A minimum within the ranking's tie threshold of a perfect quad has nothing to gain
        // (measured: on a 10k-quad grid at 0.9998 the stage costs 70% of the run for 1e-4).
        let max_min = if options.max_min_settings().is_some()
            && !pass.cancelled
            && pass.stats.min < 1.0 - ranking::MIN_TIE
        {
            ctx.max_min_stage(&mut pass, &mut progress)
        } else {
            None
        };

        // Once, for the kept pass: it costs as much as the targets of a sweep.
        let final_energy = ctx.energy(&pass.points);
        let mean_edge = mean_edge_length(mesh.points(), mesh.quads());
        let fidelity = fidelity::measure(&geometry, &pass.params, mean_edge);
        mesh.points_mut().copy_from_slice(&pass.points);
        let mut on_boundary = crate::alloc::try_with_capacity(pass.params.len(), "boundary positions")?;
        on_boundary.extend((0..topo.vertex_count()).filter_map(|v| {
            let (from, to, t) = geometry.on_polyline(v, &pass.params)?;
            Some(OnPolyline { vertex: v, from, to, t })
        }));
        let report = Report {
            input,
            output: pass.stats,
            iterations: pass.iterations,
            untangle_sweeps: pass.untangle_sweeps,
            converged: pass.converged,
            cancelled: pass.cancelled,
            initial_energy: pass.initial_energy.unwrap_or(final_energy),
            final_energy,
            seconds: start.elapsed().as_secs_f64(),
            reoriented_quads: mesh.reoriented().len(),
            corners: features.corner_count(),
            movable: features.movable_vertices().len(),
            loop_modes,
            fidelity,
            // The statistics already say whether there is anything to diagnose.
            max_min,
            effort: options.effort,
            // Set by `Optimizer::run`, which sees the caller's mesh.
            input_by_kind: ByFaceKind::quads_only(0, input),
            output_by_kind: ByFaceKind::quads_only(0, pass.stats),
            tangled: if pass.stats.inverted == 0 {
                Vec::new()
            } else {
                untangle::diagnose(mesh.points(), mesh.quads(), topo, &features)
            },
        };
        Ok((report, on_boundary))
    }
}

/// Where a movable boundary vertex ends on the boundary polyline: the fraction `t` of the way
/// along the segment from vertex `from` to vertex `to`.
#[derive(Debug)]
struct OnPolyline {
    vertex: usize,
    from: usize,
    to: usize,
    t: f64,
}

/// Puts back at their `original` positions moved vertices of every quad below min(its input
/// value, `floor`) (`input_values`): one, where that mends the quad and leaves no quad of its
/// star below, else all of them, and then those of every quad this leaves below, until none is
/// (at worst the input, where every quad has its input value). `values` are the quads' values
/// at the mesh's positions, before and after. Returns how many vertices went back.
fn restore_below_bounds(
    mesh: &mut Mesh,
    original: &[DVec2],
    topo: &Topology,
    input_values: &[f64],
    floor: f64,
    values: &mut [f64],
) -> usize {
    let (points, quads) = mesh.points_mut_and_quads();
    let bound = |f: usize| input_values[f].min(floor);
    let below = |points: &[DVec2], f: usize| {
        let value = crate::quality::scaled_jacobian(&crate::quality::corners(points, &quads[f]));
        !(value >= bound(f))
    };
    let mut pending: Vec<usize> = (0..quads.len())
        .into_par_iter()
        .with_min_len(crate::quality::PARALLEL_CHUNK)
        .filter(|&f| !(values[f] >= bound(f)))
        .collect();
    if pending.is_empty() {
        return 0;
    }
    let mut restored = 0;
    while let Some(f) = pending.pop() {
        if !below(points, f) {
            continue;
        }
        // One vertex back, the first that mends the quad without putting another quad of its
        // star below: the rest of the run's progress stays (restoring every moved vertex of a
        // quad leaves its neighbours half restored, and that cascaded to the whole input).
        let single = crate::face::vertices(&quads[f]).iter().map(|&v| v as usize).find(|&v| {
            if points[v] == original[v] {
                return false;
            }
            let kept = points[v];
            points[v] = original[v];
            let mended = topo.vertex_quads(v).iter().all(|&g| !below(points, g as usize));
            points[v] = kept;
            mended
        });
        if let Some(v) = single {
            points[v] = original[v];
            restored += 1;
            continue;
        }
        for &v in crate::face::vertices(&quads[f]) {
            let v = v as usize;
            if points[v] != original[v] {
                points[v] = original[v];
                restored += 1;
                pending.extend(topo.vertex_quads(v).iter().map(|&g| g as usize));
            }
        }
    }
    crate::quality::values_into(points, quads, values);
    restored
}

/// Per-quad scaled Jacobians, or [`Error::OutOfMemory`].
fn try_values(points: &[DVec2], quads: &[[u32; 4]]) -> Result<Vec<f64>> {
    let mut values = crate::alloc::try_filled(quads.len(), 0.0, "quad values")?;
    crate::quality::values_into(points, quads, &mut values);
    Ok(values)
}

/// Per quad, whether its scaled Jacobian (`values`) is positive, zero or negative (NaN: none),
/// as [`crate::quality::sign_class`] says.
fn sign_classes(values: &[f64]) -> Vec<Option<std::cmp::Ordering>> {
    values.iter().map(|v| v.partial_cmp(&0.0)).collect()
}

/// Mean length of the face edges (each interior edge counted twice, which does not matter
/// for a scale).
fn mean_edge_length(points: &[DVec2], quads: &[[u32; 4]]) -> f64 {
    let chunk_sum = |chunk: &[[u32; 4]]| {
        let (mut total, mut count) = (0.0, 0usize);
        for q in chunk {
            let n = crate::face::corner_count(q);
            total += (0..n)
                .map(|i| (points[q[(i + 1) % n] as usize] - points[q[i] as usize]).length())
                .sum::<f64>();
            count += n;
        }
        (total, count)
    };
    // Chunk sums in parallel, added in order: the same bits on any thread count.
    let sums: Vec<(f64, usize)> = quads.par_chunks(crate::quality::PARALLEL_CHUNK).map(chunk_sum).collect();
    let (total, count) = sums.iter().fold((0.0, 0), |(t, c), &(dt, dc)| (t + dt, c + dc));
    total / count.max(1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::test_meshes::grid;

    /// [`restore_below_bounds`] from the mesh's values, checking the values it leaves.
    fn restore(m: &mut Mesh, original: &[DVec2], topo: &Topology, input_values: &[f64], floor: f64) -> usize {
        let mut values = m.quality_values();
        let restored = restore_below_bounds(m, original, topo, input_values, floor, &mut values);
        assert_eq!(values, m.quality_values());
        restored
    }

    #[test]
    fn quads_below_their_bounds_get_their_vertices_back_until_none_is() {
        // 4x4 unit grid (vertex j * 5 + i at (i, j)), floor 0.9995: interior vertex 6 moved
        // (its quads fall to about 0.9992), boundary vertex 1 moved along the boundary (its
        // quads to about 0.9987), interior vertex 18, far from both, moved a little (its quads
        // stay above 0.99999).
        let mut m = grid(4, 4);
        let topo = Topology::new(&m);
        let original = m.points().to_vec();
        let input_values = m.quality_values();
        let moved = [(6, DVec2::new(1.04, 1.0)), (1, DVec2::new(1.05, 0.0)), (18, DVec2::new(3.0, 3.001))];
        for (v, p) in moved {
            m.points_mut()[v] = p;
        }
        let restored = restore(&mut m, &original, &topo, &input_values, 0.9995);
        assert_eq!(restored, 2);
        for (v, &was) in original.iter().enumerate() {
            let want = if v == 18 { DVec2::new(3.0, 3.001) } else { was };
            assert_eq!(m.points()[v], want, "vertex {v}");
        }
        // Two moved vertices of the quads below: putting back the one that broke them is
        // enough, and the other keeps its move.
        let mut two = grid(4, 4);
        let moved = [(6, DVec2::new(1.3, 1.2)), (7, DVec2::new(2.0, 1.002))];
        for (v, p) in moved {
            two.points_mut()[v] = p;
        }
        assert!(two.quality_values().iter().zip(&input_values).any(|(q, i)| *q < i.min(0.99)));
        assert_eq!(restore(&mut two, &original, &topo, &input_values, 0.99), 1);
        assert_eq!((two.points()[6], two.points()[7]), (original[6], DVec2::new(2.0, 1.002)));
        // Every quad at or above min(input, floor): nothing changes.
        let before = m.points().to_vec();
        assert_eq!(restore(&mut m, &original, &topo, &input_values, 0.9995), 0);
        assert_eq!(m.points(), &before[..]);
        // A chain: restoring one vertex leaves its neighbour's quad below, which goes back too.
        let mut m = grid(4, 1);
        let topo = Topology::new(&m);
        let original = m.points().to_vec();
        let input_values = m.quality_values();
        // Vertices 1, 2 and 3 (bottom row) slid together: fine alone, 6 then breaks.
        for v in 1..4 {
            m.points_mut()[v] = original[v] + DVec2::new(0.3, 0.0);
        }
        restore(&mut m, &original, &topo, &input_values, 0.99);
        for (f, &value) in m.quality_values().iter().enumerate() {
            assert!(value >= input_values[f].min(0.99), "quad {f}: {value}");
        }
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

    #[test]
    fn the_quality_rule_stops_at_a_sweep_that_moved_nothing_and_the_energy_rule_does_not() {
        // A perfect grid is a fixed point: the first sweep moves no vertex, so the quality rule
        // (the default) stops there; the energy rule with tau = 0 runs to the cap.
        let mut m = grid(4, 3);
        let r = optimize(&mut m, &Options::default()).unwrap();
        assert_eq!((r.iterations, r.converged), (1, true));
        let energy = Options { stop: StopRule::Energy, tau: 0.0, max_iterations: 30, ..Options::default() };
        let r = optimize(&mut grid(4, 3), &energy).unwrap();
        assert_eq!((r.iterations, r.converged), (30, false));
    }

    /// 2x2 grid whose centre (vertex 4) is pinned at (1.5, 1), every vertex fixed but the
    /// bottom-middle one (vertex 1), which sits at (1, 0) between boundary neighbours 0 and 2.
    fn one_free_boundary_vertex() -> Mesh {
        let m = grid(2, 2);
        let mut p = m.points().to_vec();
        p[4] = DVec2::new(1.5, 1.0);
        let fixed = (0..9).map(|v| v != 1).collect();
        Mesh::new(p, m.quads().to_vec(), Some(fixed)).unwrap()
    }

    fn one_sweep(boundary: BoundaryMode) -> Options {
        Options {
            boundary,
            max_iterations: 1,
            guard: false,
            untangle: false,
            keep_best: false,
            max_min: false,
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
        let mut bent = Mesh::new(p.clone(), m.quads().to_vec(), Some(m.fixed().to_vec())).unwrap();
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
            Mesh::new(p, m.quads().to_vec(), None).unwrap()
        };
        let run = |n: u32, options: &Options| optimize(&mut jitter(n), options).unwrap().iterations;
        let relative = Options {
            boundary: BoundaryMode::Fixed,
            stop: StopRule::Energy,
            tau: 1e-6,
            ..Options::default()
        };
        let absolute = Options { tau_absolute: true, tau: 1e-4, ..relative.clone() };
        let (rs, rl) = (run(8, &relative), run(32, &relative));
        let (a_s, a_l) = (run(8, &absolute), run(32, &absolute));
        assert!(a_l > a_s, "absolute tau: {a_s} sweeps on 8x8, {a_l} on 32x32");
        assert!((rl as f64) < 1.5 * rs as f64 + 5.0, "per-vertex tau: {rs} sweeps on 8x8, {rl} on 32x32");
    }
}

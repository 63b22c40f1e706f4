//! The sweep loop of a run: untangling, then sweeps colour class by colour class until the
//! stopping rule says done, keeping the best iterate.
//!
//! Vertices of one colour class share no quad, so a class is computed in parallel from the
//! current positions and applied in a fixed order: the result does not depend on the thread
//! count. Each vertex takes its method's target through the guard of [`guard`] unless that is
//! turned off. A pass has one boundary mode per loop; [`super::auto`] chooses them.

use super::boundary::{self, BoundaryGeometry, BoundaryMove};
use super::embedded_polygon::Target;
use super::maxmin::{self, MaxMinSettings};
use super::options::{BoundaryMode, Method, Options, StopRule};
use super::ranking::{MIN_TIE, MIN_TIE_BEFORE_MAX_MIN, improves, improves_with_tie, stats_of};
use super::report::{MaxMinGain, Progress};
use super::stopping::{self, Stopper};
use super::{angle_based, embedded_polygon, energy, guard, laplacian, untangle};
use crate::features::Features;
use crate::quality::QualityStats;
use crate::topology::Topology;
use glam::DVec2;
use rayon::prelude::*;

/// Classes smaller than this are computed on the calling thread: waking the pool costs more
/// than it saves (the result is the same either way, as a class is applied in order).
const PARALLEL_MIN: usize = 2048;

/// Vertices of a colour class handed out together to a parallel task.
const CHUNK: usize = 256;

/// How much better snap's star must be for one-pass `Auto` to take it over slide's. Where the
/// two candidates (nearly) coincide, on straight stretches, their stars differ by rounding
/// only; a strict comparison would then pick by rounding, and the run would not be the same
/// after a scaling or a translation of the mesh.
const AUTO_TIE: f64 = 1e-9;

/// Per-vertex result of a sweep.
#[derive(Clone, Copy, Debug, Default)]
struct Update {
    vertex: u32,
    position: DVec2,
    /// Boundary arclength parameter (unused for interior vertices).
    param: f64,
    /// Torsion energy of the vertex before its move.
    energy: f64,
    /// How far it moved ([`guard::move_length`]; 0 without the guard).
    moved: f32,
    /// An interior vertex the guard kept where it was although its target differs: stuck
    /// until something in its star moves ([`Since::still_stuck`]).
    stuck: bool,
}

impl Update {
    /// The place of a vertex that does not move.
    const NONE: Update =
        Update { vertex: u32::MAX, position: DVec2::ZERO, param: 0.0, energy: 0.0, moved: 0.0, stuck: false };
}

/// Result of a pass.
pub struct Pass {
    pub points: Vec<DVec2>,
    pub params: Vec<f64>,
    pub stats: QualityStats,
    pub iterations: usize,
    pub untangle_sweeps: usize,
    pub converged: bool,
    pub cancelled: bool,
    /// Collective energy measured during the first sweep (`None` without sweeps).
    pub initial_energy: Option<f64>,
}

/// Everything a pass reads besides the positions.
pub struct RunContext<'a> {
    pub topo: &'a Topology,
    pub features: &'a Features,
    pub geometry: &'a BoundaryGeometry,
    pub options: &'a Options,
    pub quads: &'a [[u32; 4]],
    pub input: QualityStats,
    /// Per quad: inverted (scaled Jacobian <= 0) in the input.
    pub input_inverted: Vec<bool>,
    /// The guard's floor for this run.
    pub floor: f64,
}

impl RunContext<'_> {
    /// Whether per-quad `values` invert a quad that was valid in the input. Such an iterate is
    /// never returned, so no quad that was valid ends inverted, even while untangling trades
    /// one inversion for another on a mesh that stays tangled.
    pub fn inverts_a_valid_quad(&self, values: &[f64]) -> bool {
        self.input.inverted > 0 && values.iter().zip(&self.input_inverted).any(|(&v, &was)| v <= 0.0 && !was)
    }

    /// One full optimization from `start` with the given per-loop boundary modes (slide, snap
    /// or fixed), reported as pass `pass` of `passes`.
    pub fn pass(
        &self,
        start: &[DVec2],
        loop_modes: &[BoundaryMode],
        (pass, passes): (usize, usize),
        progress: &mut Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> Pass {
        let opts = self.options;
        let mut points = start.to_vec();
        let mut params = self.geometry.initial_params();
        let mut values = Vec::with_capacity(self.quads.len());
        let (mut untangle_sweeps, mut cancelled) = (0, false);
        if opts.untangle && self.input.inverted > 0 {
            // Untangling reports iteration 0 (no smoothing sweep done yet) and no energy.
            let p = Progress {
                iteration: 0,
                max_iterations: opts.sweep_cap(),
                energy: f64::NAN,
                energy_change: f64::NAN,
                pass,
                passes,
            };
            let mut keep_going = || progress.as_mut().is_none_or(|cb| cb(&p));
            let u =
                untangle::untangle(&mut points, self.quads, self.topo, self.features, 200, &mut keep_going);
            (untangle_sweeps, cancelled) = (u.sweeps, u.cancelled);
        }
        let mut best_stats = self.input;
        let mut best_points = start.to_vec();
        let mut best_params = params.clone();
        // With the guard, each sweep starts from the slack of every quad at its start and
        // records how far each vertex moved during it: most guard checks are then certain
        // without evaluating the star (see guard::certainly_at_least).
        let mut slack = Vec::new();
        let mut moved = if opts.guard { vec![0.0f32; points.len()] } else { Vec::new() };
        // With the guard, the class step at which each vertex last moved, and at which each
        // stuck vertex was found stuck (`NOT_STUCK` otherwise): a stuck vertex whose star has
        // not moved since would be stuck again, and is not evaluated again (the guard's
        // search for a way out is most of a sweep's time on a converged mesh).
        let (mut last_move, mut stuck) = if opts.guard {
            (vec![0u32; points.len()], vec![NOT_STUCK; points.len()])
        } else {
            (Vec::new(), Vec::new())
        };
        let mut step = 0u32;
        let measure = |points: &[DVec2], values: &mut Vec<f64>, slack: &mut Vec<f32>| {
            if opts.guard {
                guard::stats_and_slack(points, self.quads, self.floor, values, slack)
            } else {
                stats_of(points, self.quads, values)
            }
        };
        let current = measure(&points, &mut values, &mut slack);
        if !self.inverts_a_valid_quad(&values) && improves(&current, &best_stats, &self.input) {
            best_stats = current;
            best_points.copy_from_slice(&points);
        }

        // The stage that follows sets the minimum: keep the sweeps for their average.
        let tie = if opts.max_min_settings().is_some() { MIN_TIE_BEFORE_MAX_MIN } else { MIN_TIE };
        let mut stopper = Stopper::new(opts, self.features.movable_vertices().len());
        stopper.start(&current, &best_stats);
        let largest_class =
            (0..self.topo.colour_count()).map(|c| self.topo.colour_class(c).len()).max().unwrap_or(0);
        let mut updates: Vec<Update> = Vec::with_capacity(largest_class);
        let mut initial_energy = f64::NAN;
        let (mut iterations, mut converged) = (0, false);
        // Sweeps in a row that left the kept iterate as it was (see Effort::stale_sweeps).
        let (stale_limit, mut stale) =
            (opts.effort.stale_sweeps().filter(|_| opts.stop == StopRule::Quality), 0);
        let sweep_cap = opts.sweep_cap();
        while iterations < sweep_cap && !cancelled {
            let mut energy = 0.0;
            let mut any_moved = false;
            moved.fill(0.0);
            for c in 0..self.topo.colour_count() {
                let class = self.topo.colour_class(c);
                step += 1;
                // One update per class member, written in place (no per-chunk buffers).
                updates.clear();
                updates.resize(class.len(), Update::NONE);
                {
                    let (pts, prm) = (&points[..], &params[..]);
                    let since = opts.guard.then_some(Since {
                        slack: &slack,
                        moved: &moved,
                        last_move: &last_move,
                        stuck: &stuck,
                    });
                    let chunk_updates = |chunk: &[u32], out: &mut [Update]| {
                        chunk_updates_widest(self, pts, prm, chunk, loop_modes, since, out);
                    };
                    if class.len() >= PARALLEL_MIN {
                        class
                            .par_chunks(CHUNK)
                            .zip(updates.par_chunks_mut(CHUNK))
                            .for_each(|(chunk, out)| chunk_updates(chunk, out));
                    } else {
                        chunk_updates(class, &mut updates);
                    }
                }
                // Sequential: the same sum whatever the thread count.
                for u in updates.iter().filter(|u| u.vertex != Update::NONE.vertex) {
                    let v = u.vertex as usize;
                    energy += u.energy;
                    let moves = points[v] != u.position;
                    any_moved |= moves;
                    points[v] = u.position;
                    if opts.guard {
                        moved[v] = u.moved;
                        if moves {
                            last_move[v] = step;
                        }
                        stuck[v] = if u.stuck { step } else { NOT_STUCK };
                    }
                    if let Some(slot) = self.geometry.slot(u.vertex as usize) {
                        params[slot] = u.param;
                    }
                }
            }
            iterations += 1;
            if iterations == 1 {
                initial_energy = energy;
            }
            let stats = measure(&points, &mut values, &mut slack);
            let kept_before = best_stats;
            if !self.inverts_a_valid_quad(&values) && improves_with_tie(&stats, &best_stats, &self.input, tie)
            {
                best_stats = stats;
                best_points.copy_from_slice(&points);
                best_params.copy_from_slice(&params);
            }
            stale = if stopping::same(&kept_before, &best_stats) { stale + 1 } else { 0 };
            let kept = if opts.keep_best { best_stats } else { stats };
            let verdict = stopper.after_sweep(&stats, &kept, energy);
            if let Some(cb) = progress.as_mut() {
                let p = Progress {
                    iteration: iterations,
                    max_iterations: opts.sweep_cap(),
                    energy,
                    energy_change: verdict.energy_change,
                    pass,
                    passes,
                };
                if !cb(&p) {
                    cancelled = true;
                    break;
                }
            }
            // Under the quality rule a sweep that moved nothing ends the run: every later sweep
            // would repeat it. (The energy rule is the paper's: tau = 0 runs to the cap.)
            if verdict.stop
                || (!any_moved && opts.stop == StopRule::Quality)
                || stale_limit.is_some_and(|limit| stale >= limit)
            {
                converged = true;
                break;
            }
        }
        if !opts.keep_best {
            best_stats = stats_of(&points, self.quads, &mut values);
            best_points = points;
            best_params = params;
        }
        Pass {
            points: best_points,
            params: best_params,
            stats: best_stats,
            iterations,
            untangle_sweeps,
            converged,
            cancelled,
            initial_energy: (!initial_energy.is_nan()).then_some(initial_energy),
        }
    }

    /// The max-min stage on the kept pass: its result replaces the pass's when the ranking
    /// takes it (the stage never lowers the minimum, but may trade average for it).
    ///
    /// When the average falls too far, the stage is tried once more without its escapes (the
    /// average moves that unlock a stalled minimum are what costs the average): on Mesquite's
    /// unstrquad the full stage's result is rejected and the pass keeps 0.570, the stage
    /// without escapes is taken at 0.701.
    pub fn max_min_stage(
        &self,
        pass: &mut Pass,
        progress: &mut Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> Option<MaxMinGain> {
        let settings = self.options.max_min_settings()?;
        let full_recovery = MaxMinSettings::default().average_sweeps;
        let tries = if settings.escapes > 0 {
            vec![settings.clone(), MaxMinSettings { escapes: 0, ..settings }]
        } else if settings.average_sweeps < full_recovery {
            // A short stage (balanced's) whose rounds cost more average than its one recovery
            // sweep gives back: tried again with the full recovery.
            vec![settings.clone(), MaxMinSettings { average_sweeps: full_recovery, ..settings }]
        } else {
            vec![settings]
        };
        let (mut rounds, mut seconds) = (0, 0.0);
        for settings in &tries {
            let (points, params, after, report, keep) = self.max_min_attempt(pass, settings, progress);
            rounds += report.rounds;
            seconds += report.seconds;
            if keep {
                let gain = MaxMinGain { before: pass.stats, after, rounds, seconds };
                (pass.points, pass.params, pass.stats) = (points, params, after);
                return Some(gain);
            }
            if pass.cancelled || report.cancelled {
                break;
            }
        }
        None
    }

    /// One run of the max-min stage from the kept pass with `settings`: its positions,
    /// parameters, quality, report, and whether the pass takes it.
    fn max_min_attempt(
        &self,
        pass: &mut Pass,
        settings: &MaxMinSettings,
        progress: &mut Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> (Vec<DVec2>, Vec<f64>, QualityStats, maxmin::MaxMinReport, bool) {
        let (mut points, mut params) = (pass.points.clone(), pass.params.clone());
        let sweeps = pass.iterations;
        let max_iterations = self.options.sweep_cap();
        let mut cancelled = false;
        let mut on_round = |round: usize, _min: f64| {
            let Some(cb) = progress.as_mut() else { return true };
            // Rounds continue the sweep count of the pass, without an energy.
            let p = Progress {
                iteration: sweeps + round,
                max_iterations,
                energy: f64::NAN,
                energy_change: f64::NAN,
                pass: 1,
                passes: 1,
            };
            cancelled = !cb(&p);
            !cancelled
        };
        let report = maxmin::max_min_stage(
            &mut points,
            &mut params,
            self.quads,
            self.topo,
            self.features,
            self.geometry,
            settings,
            Some(&mut on_round),
        );
        let mut values = Vec::with_capacity(self.quads.len());
        let after = stats_of(&points, self.quads, &mut values);
        // The average may fall by the ranking's tie threshold at most: the stage is for the
        // worst quad, not a trade of the average for it. A rise of the minimum smaller than
        // the ranking's tie counts too (near-perfect meshes gain that much).
        let min_rose = after.inverted <= pass.stats.inverted && after.min > pass.stats.min;
        let keep = !self.inverts_a_valid_quad(&values)
            && after.avg >= pass.stats.avg - MIN_TIE
            && (after == pass.stats || min_rose || improves(&after, &pass.stats, &self.input));
        pass.cancelled |= cancelled;
        (points, params, after, report, keep)
    }

    /// Collective energy of the movable interior vertices at `points` (boundary vertices
    /// contribute their one angle inside the sweep; here only the interior part is needed
    /// for reporting the result).
    pub fn energy(&self, points: &[DVec2]) -> f64 {
        // Chunk sums in parallel, added in order: the same bits on any thread count.
        let sums: Vec<f64> = self
            .features
            .movable_vertices()
            .par_chunks(crate::quality::PARALLEL_CHUNK)
            .map(|chunk| interior_energy(self.features, self.topo, points, chunk))
            .collect();
        sums.iter().sum()
    }

    /// The updates of the vertices of `chunk` (part of a colour class) into `out` (as long as
    /// `chunk`, filled with [`Update::NONE`]), in order; vertices that may not move keep
    /// `Update::NONE`. Under the embedded polygon method, interior vertices of valence 4 take
    /// their targets [`embedded_polygon::BATCH`] at a time (the same bits as one by one).
    ///
    /// Called through [`chunk_updates_widest`], which compiles it for AVX2 where the CPU has
    /// it ([`crate::simd`]: four lanes where SSE2 has two, the same bits).
    #[inline(always)]
    fn chunk_updates(
        &self,
        points: &[DVec2],
        params: &[f64],
        chunk: &[u32],
        loop_modes: &[BoundaryMode],
        since: Option<Since>,
        out: &mut [Update],
    ) {
        const BATCH: usize = embedded_polygon::BATCH;
        let batching = self.options.method == Method::EmbeddedPolygon;
        // Batched vertices wait until their batch is full: (place in `out`, vertex).
        let (mut queue, mut queued) = ([(0usize, 0usize); BATCH], 0);
        for (place, &v) in chunk.iter().enumerate() {
            let v = v as usize;
            if !self.features.is_movable(v) {
                continue;
            }
            if !(batching && !self.features.is_boundary(v) && self.topo.ring(v).len() == 4) {
                out[place] = self.update(points, params, v, loop_modes, since, None);
                continue;
            }
            queue[queued] = (place, v);
            queued += 1;
            if queued == BATCH {
                let vertices = queue.map(|(_, v)| v);
                let rings = vertices.map(|v| self.topo.ring(v).try_into().expect("valence 4"));
                let targets = embedded_polygon::targets_of_four(points, vertices, rings);
                for (&(place, v), target) in queue.iter().zip(targets) {
                    out[place] = self.update(points, params, v, loop_modes, since, Some(target));
                }
                queued = 0;
            }
        }
        for &(place, v) in &queue[..queued] {
            out[place] = self.update(points, params, v, loop_modes, since, None);
        }
    }

    /// Vertex `v`'s update; `target` is its interior target when already computed.
    #[inline(always)]
    fn update(
        &self,
        points: &[DVec2],
        params: &[f64],
        v: usize,
        loop_modes: &[BoundaryMode],
        since: Option<Since>,
        target: Option<Target>,
    ) -> Update {
        let mut update = if self.features.is_boundary(v) {
            self.boundary_update(points, params, v, loop_modes, since)
        } else {
            self.interior_update(points, v, since, target)
        };
        if since.is_some() {
            update.moved = guard::move_length(points[v], update.position);
        }
        update
    }

    /// An interior vertex: its method's target (unless given), through the guard.
    #[inline(always)]
    fn interior_update(
        &self,
        points: &[DVec2],
        v: usize,
        since: Option<Since>,
        target: Option<Target>,
    ) -> Update {
        let opts = self.options;
        let ring = self.topo.ring(v);
        let with_energy = |point| Target { point, energy: energy::vertex_energy(points, v, ring) };
        let Target { point: target, energy } = match (target, opts.method) {
            (Some(computed), _) => computed,
            (None, Method::EmbeddedPolygon) => embedded_polygon::target(points, v, ring),
            (None, Method::Laplacian) => with_energy(laplacian::uniform_target(points, ring)),
            (None, Method::Cotangent) => with_energy(laplacian::cotangent_target(points, v, ring)),
            (None, Method::AngleBased) => {
                let mut full_ring = Vec::with_capacity(2 * ring.len());
                self.topo.full_ring_into(self.quads, v, &mut full_ring);
                with_energy(angle_based::target(points, v, &full_ring))
            }
        };
        let p = points[v];
        let moved = p + opts.lambda * (target - p);
        // Next to coordinates near f64::MAX a target can overflow: then the vertex stays.
        let target = if moved.is_finite() { moved } else { p };
        let (position, stuck) =
            if opts.guard && target != p && !self.certainly_at_least(points, v, target, since) {
                if since.is_some_and(|s| s.still_stuck(self.quads, self.topo, v)) {
                    (p, true)
                } else {
                    let position =
                        guard::guarded_position(points, self.quads, self.topo, v, target, self.floor);
                    (position, position == p)
                }
            } else {
                (target, false)
            };
        Update { vertex: v as u32, position, param: 0.0, energy, moved: 0.0, stuck }
    }

    /// Whether moving `v` to `target` certainly keeps its star at or above the guard's floor,
    /// from the sweep's slack (false without one).
    #[inline(always)]
    fn certainly_at_least(&self, points: &[DVec2], v: usize, target: DVec2, since: Option<Since>) -> bool {
        since.is_some_and(|s| {
            guard::certainly_at_least(points, self.quads, self.topo, v, target, s.slack, s.moved)
        })
    }

    /// A boundary vertex: its loop's approach's candidate, accepted whole or not at all, since
    /// it must stay on the polyline.
    fn boundary_update(
        &self,
        points: &[DVec2],
        params: &[f64],
        v: usize,
        loop_modes: &[BoundaryMode],
        since: Option<Since>,
    ) -> Update {
        let opts = self.options;
        let p = points[v];
        let stay = |energy| Update {
            vertex: v as u32,
            position: p,
            param: current_param(self.geometry, params, v),
            energy,
            moved: 0.0,
            stuck: false,
        };
        let Some(l) = self.geometry.loop_of(v) else { return stay(0.0) };
        let (step, at_target) = if loop_modes[l] == BoundaryMode::Auto {
            let auto = self.auto_candidate(points, params, v);
            (auto.step, auto.star_min)
        } else {
            (self.boundary_candidate(points, params, v, loop_modes[l]), None)
        };
        let BoundaryMove { position: target, param, energy } = step;
        let take = Update { vertex: v as u32, position: target, param, energy, moved: 0.0, stuck: false };
        if !opts.guard
            || target == p
            || (at_target.is_none() && self.certainly_at_least(points, v, target, since))
        {
            return take;
        }
        let at_target =
            at_target.unwrap_or_else(|| guard::star_min(points, self.quads, self.topo, v, target));
        let ok = at_target >= self.floor || {
            // Face by face, as the interior's guard (guard::StarValues::kept_at).
            let here = guard::StarValues::at(points, self.quads, self.topo, v, p);
            here.min() <= 0.0 || here.kept_at(points, self.quads, self.topo, v, target, self.floor)
        };
        if ok { take } else { stay(energy) }
    }

    /// Boundary vertex `v`'s candidate in `mode`.
    fn boundary_candidate(
        &self,
        points: &[DVec2],
        params: &[f64],
        v: usize,
        mode: BoundaryMode,
    ) -> BoundaryMove {
        let opts = self.options;
        boundary::update(
            points,
            self.topo,
            self.geometry,
            params,
            v,
            mode,
            opts.lambda,
            opts.max_boundary_deviation,
        )
    }

    /// One-pass `Auto` for boundary vertex `v`: slide's and snap's candidates, the better kept
    /// (when both keep the star at or above the guard's floor, by the star's average; else by
    /// its minimum), with the approach taken and the star's minimum there (when it moves).
    pub(crate) fn auto_candidate(&self, points: &[DVec2], params: &[f64], v: usize) -> AutoCandidate {
        let slide = self.boundary_candidate(points, params, v, BoundaryMode::Slide);
        let snap = self.boundary_candidate(points, params, v, BoundaryMode::Snap);
        let p = points[v];
        let pick = |step, mode, star_min| AutoCandidate { step, mode, star_min };
        if slide.position == snap.position || snap.position == p {
            return pick(slide, BoundaryMode::Slide, None);
        }
        if slide.position == p {
            return pick(snap, BoundaryMode::Snap, None);
        }
        let q_slide = guard::star_quality(points, self.quads, self.topo, v, slide.position);
        let q_snap = guard::star_quality(points, self.quads, self.topo, v, snap.position);
        let snap_wins = if q_snap.min.min(q_slide.min) >= self.floor {
            q_snap.avg > q_slide.avg + AUTO_TIE
        } else {
            q_snap.min > q_slide.min + AUTO_TIE
        };
        if snap_wins {
            pick(snap, BoundaryMode::Snap, Some(q_snap.min))
        } else {
            pick(slide, BoundaryMode::Slide, Some(q_slide.min))
        }
    }
}

crate::simd::avx2_twin! {
    /// The collective energy of the interior vertices of `chunk`, summed in order.
    fn interior_energy(features: &Features, topo: &Topology, points: &[DVec2], chunk: &[u32]) -> f64 {
        const BATCH: usize = embedded_polygon::BATCH;
        // Each interior vertex's energy in chunk order, valence-4 ones four at a time (the same
        // bits as one by one), then summed in that order.
        let interior: Vec<usize> =
            chunk.iter().map(|&v| v as usize).filter(|&v| !features.is_boundary(v)).collect();
        let mut energies = vec![0.0; interior.len()];
        let (mut queue, mut queued) = ([0usize; BATCH], 0);
        for (place, &v) in interior.iter().enumerate() {
            if topo.ring(v).len() != 4 {
                energies[place] = energy::vertex_energy(points, v, topo.ring(v));
                continue;
            }
            queue[queued] = place;
            queued += 1;
            if queued == BATCH {
                let vertices = queue.map(|place| interior[place]);
                let rings = vertices.map(|v| topo.ring(v).try_into().expect("valence 4"));
                let four = embedded_polygon::energies_of_four(points, vertices, rings);
                for ((&place, v), e) in queue.iter().zip(vertices).zip(four) {
                    energies[place] = e.unwrap_or_else(|| energy::vertex_energy(points, v, topo.ring(v)));
                }
                queued = 0;
            }
        }
        for &place in &queue[..queued] {
            let v = interior[place];
            energies[place] = energy::vertex_energy(points, v, topo.ring(v));
        }
        energies.iter().sum()
    }
}

crate::simd::avx2_twin! {
    /// [`RunContext::chunk_updates`], compiled for AVX2 where the CPU has it (the sweep's entry).
    fn chunk_updates_widest(
        ctx: &RunContext,
        points: &[DVec2],
        params: &[f64],
        chunk: &[u32],
        loop_modes: &[BoundaryMode],
        since: Option<Since>,
        out: &mut [Update],
    ) {
        ctx.chunk_updates(points, params, chunk, loop_modes, since, out)
    }
}

/// One-pass `Auto`'s choice for a boundary vertex.
pub(crate) struct AutoCandidate {
    /// The move of the approach taken.
    pub step: BoundaryMove,
    /// Slide or snap.
    pub mode: BoundaryMode,
    /// The vertex's star's minimum scaled Jacobian at `step`, when it was computed (both
    /// approaches moved the vertex and were compared).
    pub star_min: Option<f64>,
}

/// What a sweep's guard knows since the sweep started: the slack of every quad then
/// ([`guard::stats_and_slack`]) and how far each vertex has moved since ([`guard::move_length`]).
#[derive(Clone, Copy)]
struct Since<'a> {
    slack: &'a [f32],
    moved: &'a [f32],
    /// Per vertex: the class step at which it last moved in this pass.
    last_move: &'a [u32],
    /// Per vertex: the class step at which the guard found it stuck, or [`NOT_STUCK`].
    stuck: &'a [u32],
}

/// [`Since::stuck`] of a vertex that was not stuck at its last update.
const NOT_STUCK: u32 = u32::MAX;

impl Since<'_> {
    /// Whether interior vertex `v` was stuck at its last update and no vertex of its star has
    /// moved since: its target and the guard's verdict depend on those positions only, so it
    /// would be stuck again.
    fn still_stuck(&self, quads: &[[u32; 4]], topo: &Topology, v: usize) -> bool {
        let at = self.stuck[v];
        at != NOT_STUCK
            && topo.vertex_quads(v).iter().all(|&q| {
                crate::face::vertices(&quads[q as usize]).iter().all(|&u| self.last_move[u as usize] < at)
            })
    }
}

fn current_param(geometry: &BoundaryGeometry, params: &[f64], v: usize) -> f64 {
    geometry.slot(v).map_or(0.0, |s| params[s])
}

//! The local solvers: where one vertex should go. Interior vertices by the nested grid, the
//! active-set ascent or both; boundary vertices by a nested 1-D search along their original
//! boundary; and the [`Objective`] that says what a search maximizes and which candidate is
//! taken. Separate from the stage driver, which only asks each vertex for its move. The
//! [`Context`] the searches read is defined here, so the driver imports from this file and
//! never the other way round.

use super::settings::{LocalSolver, MaxMinSettings};
use super::star::{REJECTED, Star, Value};
use crate::features::Features;
use crate::smooth::boundary::BoundaryGeometry;
use crate::topology::Topology;
use glam::DVec2;

/// Keep at least this fraction of the neighbour-to-neighbour arclength between a boundary
/// vertex and each of its boundary neighbours (as the boundary sweeps do).
const BOUNDARY_MARGIN: f64 = 0.05;

/// A move must raise its star's minimum (or, recovering the average, its average) by more
/// than this: gains at roundoff level are not worth a move (perfect meshes would otherwise
/// shuffle vertices by 1e-16 forever).
pub(super) const MIN_RISE: f64 = 1e-9;

/// Step halvings towards the smoothing target when recovering the average.
const AVERAGE_HALVINGS: usize = 8;

/// Step halvings of the active-set line search before the step counts as failed.
const ACTIVE_SET_HALVINGS: usize = 12;

/// What every sweep reads.
pub(super) struct Context<'a> {
    pub(super) quads: &'a [[u32; 4]],
    pub(super) topo: &'a Topology,
    pub(super) features: &'a Features,
    pub(super) geometry: &'a BoundaryGeometry,
    pub(super) settings: &'a MaxMinSettings,
    /// [`edge_floors`](super::star::edge_floors) at the stage's start.
    pub(super) edge_floors: &'a [f64],
}

impl Context<'_> {
    /// Whether the stage may move `v`.
    pub(super) fn eligible(&self, v: usize) -> bool {
        self.features.is_movable(v)
            && (!self.features.is_boundary(v) || (self.settings.boundary && self.geometry.slot(v).is_some()))
    }
}

/// Candidate positions seen by a local search, and the choice among them.
struct Candidates<T> {
    seen: Vec<(T, Value)>,
    best: Value,
}

impl<T: Copy> Candidates<T> {
    fn new() -> Self {
        Candidates { seen: Vec::new(), best: REJECTED }
    }

    fn add(&mut self, at: T, value: Value) {
        if value.min > self.best.min {
            self.best = value;
        }
        self.seen.push((at, value));
    }

    /// The highest-average candidate that strictly raises `current` and whose minimum is
    /// within `tolerance` of the best one or at least `enough`.
    fn choose(&self, current: f64, tolerance: f64, enough: f64) -> Option<(T, Value)> {
        let level = (self.best.min - tolerance).min(enough);
        let mut chosen: Option<(T, Value)> = None;
        for &(at, value) in &self.seen {
            if value.min > current + MIN_RISE && value.min >= level {
                let better = chosen
                    .is_none_or(|(_, c)| value.avg > c.avg || (value.avg == c.avg && value.min > c.min));
                if better {
                    chosen = Some((at, value));
                }
            }
        }
        chosen
    }
}

/// Minimum-norm point of the convex hull of `g` (a handful of 2D points): the steepest
/// ascent direction of min_i (f_i + g_i . d), zero when the origin is in the hull.
fn min_norm_in_hull(g: &[DVec2]) -> DVec2 {
    // The min-norm point c satisfies g_i . c >= |c|^2 for every i; it is a point of g or the
    // projection of the origin onto a segment between two of them, unless it is the origin.
    let optimal = |c: DVec2| {
        let c2 = c.length_squared();
        g.iter().all(|gi| gi.dot(c) >= c2 - 1e-12 * c2.max(1e-300))
    };
    let mut best: Option<DVec2> = None;
    let mut consider = |c: DVec2| {
        if best.is_none_or(|b| c.length_squared() < b.length_squared()) && optimal(c) {
            best = Some(c);
        }
    };
    for (i, &a) in g.iter().enumerate() {
        consider(a);
        for &b in &g[i + 1..] {
            let d = b - a;
            let d2 = d.length_squared();
            if d2 > 0.0 {
                let t = (-a.dot(d) / d2).clamp(0.0, 1.0);
                consider(a + t * d);
            }
        }
    }
    best.unwrap_or(DVec2::ZERO)
}

/// Freitag and Plassmann's active-set ascent from `start`; every accepted iterate is added
/// to `seen`. `scale` bounds the length of one step.
fn active_set(star: &Star, start: DVec2, iterations: usize, scale: f64, seen: &mut Candidates<DVec2>) {
    let mut x = start;
    let mut m = star.value(x).min;
    if !m.is_finite() {
        return;
    }
    let mut functions = Vec::with_capacity(star.quads.len() * 4);
    let mut active = Vec::with_capacity(16);
    // The active set's tolerance: large at first so the step follows the ridge of nearly
    // equal corners, shrunk when it gives no ascent, until the smallest one fails too.
    let mut eps = 1e-3;
    let mut it = 0;
    while it < iterations {
        star.corner_functions(x, &mut functions);
        let fmin = functions.iter().map(|f| f.0).fold(f64::INFINITY, f64::min);
        active.clear();
        active.extend(functions.iter().filter(|f| f.0 <= fmin + eps).map(|f| f.1));
        let d = min_norm_in_hull(&active);
        let d2 = d.length_squared();
        let mut moved = false;
        if d2 * scale * scale > 1e-24 {
            // Where a non-active corner, decreasing slower than the active ones rise, meets
            // them on the linearization.
            let mut alpha = scale / d2.sqrt();
            for &(f, g) in &functions {
                let rate = g.dot(d);
                if f > fmin + eps && rate < d2 {
                    alpha = alpha.min((f - fmin) / (d2 - rate));
                }
            }
            for _ in 0..ACTIVE_SET_HALVINGS {
                let y = x + alpha * d;
                let value = star.value(y);
                if value.min > m {
                    x = y;
                    m = value.min;
                    seen.add(y, value);
                    moved = true;
                    break;
                }
                alpha *= 0.5;
            }
        }
        it += 1;
        if !moved {
            if eps <= 1e-11 {
                break;
            }
            eps *= 1e-4;
        }
    }
}

/// Nested grid search (DMO) around `start` for the highest `score`; every candidate is added
/// to `seen`. Returns the best point.
///
/// `bar(centre score)` is a star minimum below which a candidate can neither become the centre
/// nor be chosen: such candidates are evaluated only until a quad falls below it (the result
/// is the same as with full evaluations, for a fraction of the work).
fn grid_search(
    star: &Star,
    start: DVec2,
    extent: DVec2,
    settings: &MaxMinSettings,
    score: impl Fn(Value) -> f64,
    bar: impl Fn(f64) -> f64,
    seen: &mut Candidates<DVec2>,
) -> DVec2 {
    let n = settings.grid_size.max(2);
    let affine = 1.0 / (n - 1) as f64;
    let mut centre = start;
    let mut centre_min = score(star.value(start));
    let mut scale = 0.5;
    let (mut positions, mut values) = (Vec::with_capacity(n * n), Vec::with_capacity(n * n));
    for _ in 0..settings.grid_levels.max(1) {
        let (lo, hi) = (centre - scale * extent, centre + scale * extent);
        let mut level_best = (f64::NEG_INFINITY, centre);
        let bar = bar(centre_min);
        positions.clear();
        positions.extend((0..n * n).map(|ij| {
            let t = DVec2::new((ij / n) as f64 * affine, (ij % n) as f64 * affine);
            lo + (hi - lo) * t
        }));
        star.values_above(&positions, bar, &mut values);
        for (&p, &value) in positions.iter().zip(&values) {
            seen.add(p, value);
            if score(value) > level_best.0 {
                level_best = (score(value), p);
            }
        }
        if level_best.0 > centre_min {
            (centre_min, centre) = level_best;
        }
        scale *= 2.0 * affine;
    }
    centre
}

/// What a move of one vertex aims at.
#[derive(Clone, Copy, Debug)]
pub(super) enum Objective {
    /// Strictly raise the star's minimum; candidates at least `enough` are ranked by average.
    MaxMin { enough: f64 },
    /// Strictly raise the star's average, keeping its minimum at least min(current, floor).
    Average { floor: f64 },
}

impl Objective {
    /// The bar a candidate's star minimum must clear, given the star's current value.
    fn floor(self, current: Value) -> f64 {
        match self {
            Objective::MaxMin { .. } => current.min,
            Objective::Average { floor } => current.min.min(floor),
        }
    }

    /// What the searches maximize.
    fn score(self, current: Value) -> impl Fn(Value) -> f64 {
        let floor = self.floor(current);
        move |value: Value| match self {
            Objective::MaxMin { .. } => value.min,
            Objective::Average { .. } => {
                if value.min >= floor {
                    value.avg
                } else {
                    f64::NEG_INFINITY
                }
            }
        }
    }

    /// A star minimum below which a candidate is of no use to a search whose centre scores
    /// `centre` (it cannot score above it, see [`Objective::score`]) and cannot be chosen (see
    /// [`Objective::choose`] and [`Candidates::choose`]): the bound of [`grid_search`].
    fn prune_bar(self, current: Value, tolerance: f64) -> impl Fn(f64) -> f64 {
        move |centre: f64| match self {
            // The score is the minimum, and a choice needs a minimum above current + MIN_RISE
            // and at least min(best - tolerance, enough), best >= centre.
            Objective::MaxMin { enough } => {
                let chosen_at_least = (current.min + MIN_RISE).max((centre - tolerance).min(enough));
                centre.min(chosen_at_least)
            }
            // Below the floor the score is -inf and nothing is chosen.
            Objective::Average { .. } => self.floor(current),
        }
    }

    /// The candidate taken, if any improves on `current`.
    fn choose<T: Copy>(self, seen: &Candidates<T>, current: Value, tolerance: f64) -> Option<T> {
        let current_min = if current.min.is_finite() { current.min } else { f64::NEG_INFINITY };
        match self {
            Objective::MaxMin { enough } => seen.choose(current_min, tolerance, enough).map(|(at, _)| at),
            Objective::Average { .. } => {
                let floor = self.floor(current);
                let mut chosen: Option<(T, f64)> = None;
                for &(at, value) in &seen.seen {
                    if value.min >= floor
                        && value.avg > current.avg + MIN_RISE
                        && chosen.is_none_or(|(_, a)| value.avg > a)
                    {
                        chosen = Some((at, value.avg));
                    }
                }
                chosen.map(|(at, _)| at)
            }
        }
    }
}

/// The best position for interior vertex `v` under `objective`, if one improves its star.
pub(super) fn interior_move(
    points: &[DVec2],
    ctx: &Context,
    v: usize,
    solver: LocalSolver,
    objective: Objective,
) -> Option<DVec2> {
    let (settings, topo) = (ctx.settings, ctx.topo);
    let star = Star::new(points, ctx.quads, topo, ctx.edge_floors, v);
    let p = points[v];
    let current = star.value(p);
    // Extent of the star: the largest offsets to the ring's vertices, per axis (as DMO).
    let mut extent = DVec2::ZERO;
    for u in topo.star_vertices(ctx.quads, v) {
        extent = extent.max((points[u as usize] - p).abs());
    }
    if !(extent.x > 0.0 || extent.y > 0.0) || !extent.is_finite() {
        return None;
    }
    let mut seen = Candidates::new();
    seen.add(p, current);
    let scale = 0.5 * extent.max_element();
    let score = objective.score(current);
    let bar = objective.prune_bar(current, settings.avg_tolerance);
    match (solver, objective) {
        (_, Objective::Average { .. }) if settings.average_by_smoothing => {
            // The embedded-polygon target is where the sweeps put the vertex for the average:
            // the longest step back towards it that keeps the star above the floor.
            let target = crate::smooth::embedded_polygon::target(points, v, topo.ring(v)).point;
            let mut step = target - p;
            if step.is_finite() {
                for _ in 0..=AVERAGE_HALVINGS {
                    let at = p + step;
                    let value = star.value(at);
                    seen.add(at, value);
                    if score(value) > f64::NEG_INFINITY && value.avg > current.avg {
                        break;
                    }
                    step *= 0.5;
                }
            }
        }
        (LocalSolver::Grid, _) | (_, Objective::Average { .. }) => {
            grid_search(&star, p, extent, settings, score, bar, &mut seen);
        }
        (LocalSolver::ActiveSet, _) => active_set(&star, p, settings.active_set_iterations, scale, &mut seen),
        (LocalSolver::GridActiveSet, _) => {
            let from = grid_search(&star, p, extent, settings, score, bar, &mut seen);
            active_set(&star, from, settings.active_set_iterations, scale, &mut seen);
        }
    }
    objective.choose(&seen, current, settings.avg_tolerance)
}

/// The best arclength for movable boundary vertex `v` on its original loop under
/// `objective`, if one improves its star: a nested 1-D search between its boundary
/// neighbours.
pub(super) fn boundary_move(
    points: &[DVec2],
    params: &[f64],
    ctx: &Context,
    v: usize,
    objective: Objective,
) -> Option<(DVec2, f64)> {
    let (geometry, settings) = (ctx.geometry, ctx.settings);
    let slot = geometry.slot(v)?;
    let l = geometry.slot_loop(slot);
    let (a, b) = geometry.loop_slots(l);
    let count = b - a;
    let len = geometry.loop_length(l);
    if count < 3 || !(len > 0.0 && len.is_finite()) {
        return None;
    }
    let k = slot - a;
    let s_prev = params[a + (k + count - 1) % count];
    let mut s_next = params[a + (k + 1) % count];
    while s_next <= s_prev {
        s_next += len;
    }
    let margin = BOUNDARY_MARGIN * (s_next - s_prev);
    let (lo, hi) = (s_prev + margin, s_next - margin);
    if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let star = Star::new(points, ctx.quads, ctx.topo, ctx.edge_floors, v);
    let current = star.value(points[v]);
    let score = objective.score(current);
    let mut seen: Candidates<f64> = Candidates::new();
    // Honour the shape tolerance as the boundary sweeps do: both new boundary edges within
    // tol x their length of the original stretch they replace.
    let within_tolerance = |t: f64| {
        settings.max_boundary_deviation.is_none_or(|tol| {
            [(s_prev, t), (t, s_next)].iter().all(|&(a, b)| {
                geometry.chord_deviation(l, a, b).largest()
                    <= tol * (geometry.eval(l, b) - geometry.eval(l, a)).length()
            })
        })
    };
    let n = settings.boundary_samples.max(2);
    let (mut from, mut to) = (lo, hi);
    let (mut positions, mut values) = (Vec::with_capacity(n), Vec::with_capacity(n));
    // Refine until the spacing is at roundoff level of the loop's length.
    for _ in 0..40 {
        let step = (to - from) / (n - 1) as f64;
        let mut level_best = (f64::NEG_INFINITY, from);
        geometry.eval_many(l, (0..n).map(|i| from + step * i as f64), &mut positions);
        star.values_above(&positions, f64::NEG_INFINITY, &mut values);
        for (i, &value) in values.iter().enumerate() {
            let s = from + step * i as f64;
            let value = if within_tolerance(s) { value } else { REJECTED };
            seen.add(s, value);
            if score(value) > level_best.0 {
                level_best = (score(value), s);
            }
        }
        if step <= 1e-13 * len {
            break;
        }
        let s = level_best.1;
        (from, to) = ((s - step).max(lo), (s + step).min(hi));
    }
    let s = objective.choose(&seen, current, settings.avg_tolerance)?.rem_euclid(len);
    Some((geometry.eval(l, s), s))
}

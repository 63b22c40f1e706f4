//! One vertex's move on the surface: the smoothing step through the guard, the untangling
//! step and the max-min search, each computed in the vertex's tangent-plane chart (or along
//! its feature curve) and judged on the surface.

use glam::DVec2;

use super::slack::{Displacement, Slack};
use super::star::{Chart, LocalStar, Motion, Placed, Score, State, Surface};
use super::tracks::Slot;
use crate::smooth::options::Method;
use crate::smooth::{angle_based, embedded_polygon, laplacian};

/// Halvings of a step the guard tries before giving up on its direction (as in the plane).
const MAX_HALVINGS: usize = 8;

/// A star whose minimum is at least this has nothing left to gain.
const PERFECT: f64 = 1.0 - 1e-9;

/// Positions along a curve the 1-D searches sample between the vertex's two neighbours.
const CURVE_SAMPLES: usize = 16;

/// Steps of the max-min stage's pattern search in a chart before it stops.
const SEARCH_EVALUATIONS: usize = 96;

/// What the smoothing step needs besides the star.
#[derive(Clone, Copy, Debug)]
pub struct StepRule {
    pub method: Method,
    pub lambda: f64,
    pub guard: bool,
    /// The guard's floor: a move may lower its star's minimum to at most min(current, floor).
    pub floor: f64,
    /// With the embedded polygon: also try the Laplacian's target and take, per vertex, the
    /// candidate that leaves the star better (docs/surfaces.md: the embedded polygon alone leaves
    /// the average lower on surfaces with fillets).
    pub with_laplacian: bool,
}

/// A vertex's step in a sweep: where it moves (if it does), the energy before it, and what
/// the certificates record of the move when one took it (else the sweep computes that).
pub struct Step {
    pub to: Option<Placed>,
    pub energy: f64,
    pub certified: Option<Displacement>,
}

impl Step {
    /// A step from a guarded move and the energy.
    pub fn new(to: Option<(Placed, Option<Displacement>)>, energy: f64) -> Step {
        match to {
            Some((to, certified)) => Step { to: Some(to), energy, certified },
            None => Step { to: None, energy, certified: None },
        }
    }

    /// A step to `to` (or none) that no certificate took.
    pub fn uncertified(to: Option<Placed>, energy: f64) -> Step {
        Step { to, energy, certified: None }
    }
}

/// Whether `candidate` passes the guard from `current`: no more faces below their bounds, no
/// more inverted faces and a minimum of at least min(current minimum, floor); from a tangled
/// star, not worse.
fn guard_accepts(candidate: &Score, current: &Score, floor: f64) -> bool {
    if candidate.below > current.below {
        return false;
    }
    if current.inverted > 0 || current.min <= 0.0 {
        return !current.better_than(candidate);
    }
    candidate.inverted == 0 && candidate.min >= current.min.min(floor)
}

/// Whether `score` is acceptable whatever the current star: no face inverted or below its
/// bound, and a minimum at or above the floor.
fn above_floor(score: &Score, floor: f64) -> bool {
    score.below == 0 && score.inverted == 0 && score.min >= floor
}

/// The chart of free vertex `v` and its star in it.
fn chart_of(surface: &Surface, state: &State, v: usize, star: &mut LocalStar) -> (Chart, Placed) {
    let here = surface.current(state, v);
    let chart = Chart::new(here.point, here.normal_for(u32::MAX));
    star.build(surface, state, v, &chart);
    (chart, here)
}

/// The smoothing move of `v`, if it moves: its method's target in its chart (or the middle of
/// its interval along its curve), the lambda step, then the guard (its first test by
/// `slack`'s certificate where that holds).
pub fn smoothing_move(
    surface: &Surface,
    state: &State,
    v: usize,
    rule: &StepRule,
    star: &mut LocalStar,
    slack: Option<&Slack>,
) -> Step {
    if let Motion::Free(_) = surface.motion[v] {
        let (chart, here) = chart_of(surface, state, v, star);
        // The torsion energy of the vertex's embedded polygon in its chart (Eq. 1).
        let ep = embedded_polygon::target(&star.points, 0, &star.ring);
        let target = match rule.method {
            Method::EmbeddedPolygon => ep.point,
            Method::Laplacian => laplacian::uniform_target(&star.points, &star.ring),
            Method::Cotangent => laplacian::cotangent_target(&star.points, 0, &star.ring),
            Method::AngleBased => {
                star.build_full_ring(surface, v);
                angle_based::target(&star.points, 0, &star.full_ring)
            }
        };
        if !rule.with_laplacian {
            return Step::new(
                free_move(surface, state, v, rule, star, (chart, here), target, slack),
                ep.energy,
            );
        }
        // Both targets compared in the chart, then only the one preferred there projected and
        // guarded on the surface; the other only if the guard finds no step towards it.
        let lap = laplacian::uniform_target(&star.points, &star.ring);
        let (a, b) = chart_scores(star, target * rule.lambda, lap * rule.lambda);
        let above = |s: &Score| s.inverted == 0 && s.min >= rule.floor;
        let lap_first = if above(&a) && above(&b) { b.sum > a.sum } else { b.better_than(&a) };
        let (first, second) = if lap_first { (lap, target) } else { (target, lap) };
        let chosen = free_move(surface, state, v, rule, star, (chart, here), first, slack)
            .or_else(|| free_move(surface, state, v, rule, star, (chart, here), second, slack));
        return Step::new(chosen, ep.energy);
    }
    Step::new(curve_or_still_move(surface, state, v, rule, slack), 0.0)
}

/// The guarded step of free vertex `v` towards chart position `target`, with what the
/// certificates record of it when one took it.
fn free_move(
    surface: &Surface,
    state: &State,
    v: usize,
    rule: &StepRule,
    star: &LocalStar,
    (chart, here): (Chart, Placed),
    target: DVec2,
    slack: Option<&Slack>,
) -> Option<(Placed, Option<Displacement>)> {
    match surface.motion[v] {
        Motion::Still | Motion::Curve(_) => None,
        Motion::Free(patch) => {
            let step = target * rule.lambda;
            if !step.is_finite() || step == DVec2::ZERO {
                return None;
            }
            let place = |x: DVec2| surface.place_free(patch, chart.lift(x), here.hint);
            if !rule.guard {
                return Some((place(step), None));
            }
            // A target at or above the floor is acceptable whatever the current star (as in the
            // plane), so the current star is scored only when needed.
            let first = place(step);
            if let Some(d) = slack.and_then(|s| s.certify(surface, state, v, &first)) {
                return moved(first, &here).map(|p| (p, Some(d)));
            }
            let scored = |p: Placed| moved(p, &here).map(|p| (p, None));
            let first_score = surface.star_score_at(state, v, star, &first);
            if above_floor(&first_score, rule.floor) {
                return scored(first);
            }
            let current = surface.star_score(state, v, None);
            if guard_accepts(&first_score, &current, rule.floor) {
                return scored(first);
            }
            let mut s = step;
            for _ in 0..MAX_HALVINGS {
                s *= 0.5;
                let candidate = place(s);
                let score = surface.star_score_at(state, v, star, &candidate);
                if guard_accepts(&score, &current, rule.floor) {
                    return scored(candidate);
                }
            }
            if current.min >= PERFECT {
                return None;
            }
            // Stuck: the direction that raises the star's smallest corner in the chart, the
            // longest step along it that makes the star strictly better on the surface.
            untangling_move(surface, state, v, star, (&chart, &here), &current).map(|p| (p, None))
        }
    }
}

/// The guarded step of on-curve vertex `v` towards the middle of its interval, with what the
/// certificates record of it when one took it.
fn curve_or_still_move(
    surface: &Surface,
    state: &State,
    v: usize,
    rule: &StepRule,
    slack: Option<&Slack>,
) -> Option<(Placed, Option<Displacement>)> {
    match surface.motion[v] {
        Motion::Still | Motion::Free(_) => None,
        Motion::Curve(slot) => {
            let (lo, hi) = surface.tracks.interval(slot, &state.params);
            let s0 = state.params[v];
            let target = 0.5 * lo + 0.5 * hi;
            let mut step = (target - s0) * rule.lambda;
            // The curve tolerance first: the longest of the step and its halvings it allows.
            let mut halvings = 0;
            while !surface.curve_allows(state, slot, s0 + step) {
                if halvings == MAX_HALVINGS {
                    return None;
                }
                step *= 0.5;
                halvings += 1;
            }
            if !step.is_finite() || step == 0.0 {
                return None;
            }
            if !rule.guard {
                return Some((surface.place_on_curve(v, slot, s0 + step), None));
            }
            let here = surface.current(state, v);
            let first = surface.place_on_curve(v, slot, s0 + step);
            if let Some(d) = slack.and_then(|s| s.certify(surface, state, v, &first)) {
                return moved(first, &here).map(|p| (p, Some(d)));
            }
            let scored = |p: Placed| moved(p, &here).map(|p| (p, None));
            let first_score = surface.star_score(state, v, Some(&first));
            if above_floor(&first_score, rule.floor) {
                return scored(first);
            }
            let current = surface.star_score(state, v, None);
            if guard_accepts(&first_score, &current, rule.floor) {
                return scored(first);
            }
            let mut d = step;
            for _ in halvings..MAX_HALVINGS {
                d *= 0.5;
                let candidate = surface.place_on_curve(v, slot, s0 + d);
                if guard_accepts(&surface.star_score(state, v, Some(&candidate)), &current, rule.floor) {
                    return scored(candidate);
                }
            }
            None
        }
    }
}

/// `candidate` unless it is where the vertex already is.
fn moved(candidate: Placed, here: &Placed) -> Option<Placed> {
    (candidate.point != here.point).then_some(candidate)
}

/// The scores of `star` in its chart with its vertex at `x` and at `y`: each face's smallest
/// corner value `cross(a, b) / (|a| |b|)` (Verdict's triangle factor for a triangle), what
/// does not depend on the vertex computed once. Only their order is used, to choose which
/// target to project, so they are not Verdict's values to the bit (no rescaling, no
/// short-edge cut-off); a degenerate corner counts as 0.
fn chart_scores(star: &LocalStar, x: DVec2, y: DVec2) -> (Score, Score) {
    // cross(a, b) / sqrt(a2 b2), with a2 and b2 the squared lengths of a and b.
    let corner = |a: DVec2, b: DVec2, a2: f64, b2: f64| {
        let l = (a2 * b2).sqrt();
        if l > 0.0 { a.perp_dot(b) / l } else { 0.0 }
    };
    let (mut sx, mut sy) = (Score::EMPTY, Score::EMPTY);
    for face in &star.faces {
        let triangle = crate::face::is_triangle(face);
        let n = if triangle { 3 } else { 4 };
        let Some(k) = face[..n].iter().position(|&u| u == 0) else { continue };
        // Corner k + i (i < n), wrapped without a division.
        let at = |i: usize| star.points[face[if k + i >= n { k + i - n } else { k + i }] as usize];
        // The vertex's neighbours in the face: the next corner and the previous one.
        let (next, prev) = (at(1), at(n - 1));
        // Per candidate: its own corner and the two next to it, whose other edges are fixed.
        let (to_next, to_prev) =
            if triangle { (prev - next, next - prev) } else { (at(2) - next, at(2) - prev) };
        let (l_next, l_prev) = (to_next.length_squared(), to_prev.length_squared());
        let fixed = if triangle {
            f64::INFINITY
        } else {
            // The corner opposite the vertex: both its edges fixed.
            let (a, b) = (prev - at(2), next - at(2));
            corner(a, b, a.length_squared(), b.length_squared())
        };
        let value = |z: DVec2| {
            let (a, b) = (next - z, prev - z);
            let (a2, b2) = (a.length_squared(), b.length_squared());
            let own = corner(a, b, a2, b2);
            let at_next = corner(to_next, -a, l_next, a2);
            let at_prev = corner(-b, to_prev, b2, l_prev);
            let min = own.min(at_next).min(at_prev).min(fixed);
            if triangle { (min * (2.0 / 3.0f64.sqrt())).min(1.0) } else { min }
        };
        sx.add(value(x));
        sy.add(value(y));
    }
    (sx, sy)
}

/// The untangling move of free vertex `v` from its chart: the local linear program of the
/// plane ([`crate::smooth::untangle`]) on the charted star, then the longest of the full step
/// and its halvings that leaves the star strictly better on the surface.
fn untangling_move(
    surface: &Surface,
    state: &State,
    v: usize,
    star: &LocalStar,
    (chart, here): (&Chart, &Placed),
    current: &Score,
) -> Option<Placed> {
    let Motion::Free(patch) = surface.motion[v] else { return None };
    let target = crate::smooth::untangle::untangle_star(&star.points, &star.faces, 0)?;
    let mut s = target;
    for _ in 0..=MAX_HALVINGS {
        let candidate = surface.place_free(patch, chart.lift(s), here.hint);
        let score = surface.star_score_at(state, v, star, &candidate);
        if score.better_than(current) {
            return moved(candidate, here);
        }
        s *= 0.5;
    }
    None
}

/// A move of `v` that makes its tangled star better, if it finds one: the untangling program
/// in its chart for a free vertex, the best of the samples along its curve for an on-curve one.
pub fn untangle_move(surface: &Surface, state: &State, v: usize, star: &mut LocalStar) -> Option<Placed> {
    let current = surface.star_score(state, v, None);
    if current.inverted == 0 && current.min > 0.0 {
        return None;
    }
    match surface.motion[v] {
        Motion::Still => None,
        Motion::Free(_) => {
            let (chart, here) = chart_of(surface, state, v, star);
            untangling_move(surface, state, v, star, (&chart, &here), &current)
        }
        Motion::Curve(slot) => curve_search(surface, state, v, slot, &current),
    }
}

/// The best position of on-curve `v` among samples of its interval, refined twice around the
/// best, if it beats `current`.
fn curve_search(surface: &Surface, state: &State, v: usize, slot: Slot, current: &Score) -> Option<Placed> {
    let (mut lo, mut hi) = surface.tracks.interval(slot, &state.params);
    let mut best: Option<(Score, Placed)> = None;
    for _ in 0..3 {
        let h = (hi - lo) / (CURVE_SAMPLES + 1) as f64;
        if h.is_nan() || h <= 0.0 {
            break;
        }
        let mut centre = None;
        for k in 1..=CURVE_SAMPLES {
            let s = lo + h * k as f64;
            if !surface.curve_allows(state, slot, s) {
                continue;
            }
            let candidate = surface.place_on_curve(v, slot, s);
            let score = surface.star_score(state, v, Some(&candidate));
            if best.as_ref().is_none_or(|(b, _)| score.better_than(b)) {
                best = Some((score, candidate));
                centre = Some(candidate.param);
            }
        }
        // Refine around the best sample (or the best so far, if this level found nothing).
        let c = centre.or(best.as_ref().map(|(_, p)| p.param)).unwrap_or(0.5 * lo + 0.5 * hi);
        (lo, hi) = (c - h, c + h);
    }
    let (score, placed) = best?;
    let here = surface.current(state, v);
    if score.better_than(current) { moved(placed, &here) } else { None }
}

/// The max-min stage's move of `v`: the position that makes its star best (fewest inverted
/// faces, highest minimum, highest sum), by a pattern search in its chart (eight directions,
/// the step halved when none helps) or by sampling along its curve; `None` if none beats
/// where it is.
pub fn max_min_move(surface: &Surface, state: &State, v: usize, star: &mut LocalStar) -> Option<Placed> {
    let current = surface.star_score(state, v, None);
    match surface.motion[v] {
        Motion::Still => None,
        Motion::Curve(slot) => curve_search(surface, state, v, slot, &current),
        Motion::Free(patch) => {
            let (chart, here) = chart_of(surface, state, v, star);
            // Start at a fifth of the shortest distance to a ring neighbour in the chart.
            let nearest =
                star.ring.iter().map(|&u| star.points[u as usize].length()).fold(f64::INFINITY, f64::min);
            let mut h = 0.2 * nearest;
            if !(h > 0.0 && h.is_finite()) {
                return None;
            }
            let stop = h * 1e-4;
            let (mut x, mut best, mut best_score) = (DVec2::ZERO, None, current);
            let mut evaluations = 0;
            const DIRECTIONS: [DVec2; 8] = [
                DVec2::new(1.0, 0.0),
                DVec2::new(std::f64::consts::FRAC_1_SQRT_2, std::f64::consts::FRAC_1_SQRT_2),
                DVec2::new(0.0, 1.0),
                DVec2::new(-std::f64::consts::FRAC_1_SQRT_2, std::f64::consts::FRAC_1_SQRT_2),
                DVec2::new(-1.0, 0.0),
                DVec2::new(-std::f64::consts::FRAC_1_SQRT_2, -std::f64::consts::FRAC_1_SQRT_2),
                DVec2::new(0.0, -1.0),
                DVec2::new(std::f64::consts::FRAC_1_SQRT_2, -std::f64::consts::FRAC_1_SQRT_2),
            ];
            while h > stop && evaluations < SEARCH_EVALUATIONS {
                let mut improved = None;
                for d in DIRECTIONS {
                    let y = x + d * h;
                    let candidate = surface.place_free(patch, chart.lift(y), here.hint);
                    evaluations += 1;
                    let score = surface.star_score_at(state, v, star, &candidate);
                    if score.better_than(&best_score) {
                        best_score = score;
                        improved = Some((y, candidate));
                    }
                }
                match improved {
                    Some((y, candidate)) => {
                        x = y;
                        best = Some(candidate);
                    }
                    None => h *= 0.5,
                }
            }
            best.and_then(|b| moved(b, &here))
        }
    }
}

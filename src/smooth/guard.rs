//! Guarded moves: a vertex whose star (its incident quads) is valid may not move to a place
//! that lowers any quad of its star below min(that quad's current value, floor). (A rule on
//! the star's minimum alone let a star holding one bad quad lower its other quads to that
//! quad's value.)
//!
//! The paper's method ignores where v may go without folding its star, so on graded and
//! anisotropic meshes it can lower the minimum quality or create inversions (docs/method.md,
//! "Guarded moves and the best iterate"). Vertices in a tangled star are not guarded, so
//! untangling is never blocked.

use crate::face::{fourth_corner, is_triangle};
use crate::quality::{QualityStats, corners, scaled_jacobian, scaled_jacobian_below};
use crate::topology::Topology;
use glam::DVec2;
use rayon::prelude::*;

/// A star whose minimum is at least this is perfect up to rounding: the guard does not look
/// for a way to raise it.
const PERFECT: f64 = 1.0 - 1e-9;

/// Step halvings tried before a guarded vertex stays where it is.
const MAX_HALVINGS: usize = 8;

/// The corners of each quad around `v`, with `v` placed at `at`.
fn star_quads<'a>(
    points: &'a [DVec2],
    quads: &'a [[u32; 4]],
    topo: &'a Topology,
    v: usize,
    at: DVec2,
) -> impl Iterator<Item = [DVec2; 4]> + 'a {
    topo.vertex_quads(v).iter().map(move |&qi| {
        let q = &quads[qi as usize];
        let mut c = corners(points, q);
        for (k, &u) in q.iter().enumerate() {
            if u as usize == v {
                c[k] = at;
            }
        }
        // A triangle's fourth corner repeats its third (see `corners`).
        if is_triangle(q) {
            c[3] = c[2];
        }
        c
    })
}

/// Minimum scaled Jacobian of the quads around `v` with `v` placed at `at`.
pub fn star_min(points: &[DVec2], quads: &[[u32; 4]], topo: &Topology, v: usize, at: DVec2) -> f64 {
    star_quads(points, quads, topo, v, at).map(|c| scaled_jacobian(&c)).fold(f64::INFINITY, f64::min)
}

/// Whether every quad around `v` with `v` placed at `at` is at or above `floor`: the answer of
/// `star_min(..) >= floor` (a NaN value passes in both), stopping at the first quad below.
pub fn star_at_least(
    points: &[DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    v: usize,
    at: DVec2,
    floor: f64,
) -> bool {
    !star_quads(points, quads, topo, v, at).any(|c| scaled_jacobian_below(&c, floor))
        && f64::INFINITY >= floor
}

/// The quality of a vertex's star (the quads around it) at one position of the vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StarQuality {
    /// The smallest scaled Jacobian of the star's quads (infinity for a vertex in no quad).
    pub min: f64,
    /// The mean scaled Jacobian of the star's quads (0 for a vertex in no quad).
    pub avg: f64,
}

/// The [`StarQuality`] of the quads around `v` with `v` placed at `at`.
pub fn star_quality(
    points: &[DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    v: usize,
    at: DVec2,
) -> StarQuality {
    let (mut min, mut sum) = (f64::INFINITY, 0.0);
    for c in star_quads(points, quads, topo, v, at) {
        let sj = scaled_jacobian(&c);
        min = min.min(sj);
        sum += sj;
    }
    StarQuality { min, avg: sum / topo.vertex_quads(v).len().max(1) as f64 }
}

/// Absolute margin of [`quad_slack`] for the rounding of the scaled Jacobians it compares
/// (1e-15 relative): far above it, far below any quality difference that matters.
const SLACK_MARGIN: f64 = 1e-9;

/// How far each vertex of a quad may move (every one of them at once) before the quad's
/// scaled Jacobian can fall below `floor`, given its value `value` and its corners `c`: a
/// length that is not more than that, 0 (or less) when the quad is at or below the floor.
///
/// Moving an edge's two ends by at most D each turns the edge by at most asin(2D / l) <=
/// pi D / l (l its length, 2D < l); a corner's angle then changes by at most 2 pi D / L (L
/// the quad's shortest edge) and its value, the sine of that angle, by at most as much. So
/// with D < (value - floor) L / (2 pi) the quad stays above the floor; its edges stay longer
/// than L (1 - 1/pi), far from Verdict's degenerate-edge cut-off when L is not tiny next to
/// the longest edge. A margin of 1e-9 covers the rounding of the scaled Jacobians. The
/// result is rounded down to an f32 (half the memory).
#[inline(always)]
pub fn quad_slack(c: &[DVec2; 4], value: f64, floor: f64) -> f32 {
    let squared = [c[1] - c[0], c[2] - c[1], c[3] - c[2], c[0] - c[3]].map(DVec2::length_squared);
    let shortest = squared[0].min(squared[1]).min(squared[2]).min(squared[3]);
    let longest = squared[0].max(squared[1]).max(squared[2]).max(squared[3]);
    let slack = (value - floor - SLACK_MARGIN) * shortest.sqrt() / std::f64::consts::TAU;
    // No bound for a quad at or below the floor, a NaN (value or corner), or an edge shorter
    // than 1e-12 of the longest, which could come near the cut-off (2.2e-15 of the quad's
    // bounding-box diagonal).
    slack_f32(slack, shortest >= 1e-24 * longest)
}

/// [`quad_slack`] for a triangle with corners `c[0..3]`: the same bound on each corner's
/// angle, whose sine Verdict scales by 2/sqrt(3), so the value moves up to 2/sqrt(3) times
/// as fast.
#[inline]
pub fn triangle_slack(c: &[DVec2; 4], value: f64, floor: f64) -> f32 {
    let squared = [c[1] - c[0], c[2] - c[1], c[0] - c[2]].map(DVec2::length_squared);
    let shortest = squared[0].min(squared[1]).min(squared[2]);
    let longest = squared[0].max(squared[1]).max(squared[2]);
    let per_turn = std::f64::consts::TAU * 2.0 / 3.0_f64.sqrt();
    let slack = (value - floor - SLACK_MARGIN) * shortest.sqrt() / per_turn;
    slack_f32(slack, shortest >= 1e-24 * longest)
}

/// A slack rounded down to an f32, 0 unless it is positive and `bounded`.
#[inline(always)]
fn slack_f32(slack: f64, bounded: bool) -> f32 {
    if bounded && slack > 0.0 {
        // Positive: one step down in the bits is the next smaller f32 (f32::MAX from infinity).
        let rounded = slack as f32;
        if f64::from(rounded) <= slack { rounded } else { f32::from_bits(rounded.to_bits() - 1) }
    } else {
        0.0
    }
}

/// The slack of face `q` with corners `c` ([`quad_slack`] or [`triangle_slack`]).
#[inline(always)]
pub fn face_slack(q: &[u32; 4], c: &[DVec2; 4], value: f64, floor: f64) -> f32 {
    if is_triangle(q) { triangle_slack(c, value, floor) } else { quad_slack(c, value, floor) }
}

/// The length of a move rounded up to an f32, to compare with [`quad_slack`]. (A length
/// whose square underflows, below 1e-154, comes out 0: still below any positive slack.)
#[inline(always)]
pub fn move_length(from: DVec2, to: DVec2) -> f32 {
    let length = (to - from).length();
    let rounded = length as f32;
    // Non-negative (or NaN, which stays NaN): one step up in the bits is the next larger f32.
    if f64::from(rounded) >= length { rounded } else { f32::from_bits(rounded.to_bits() + 1) }
}

/// Quads below which [`stats_and_slack`] runs on the calling thread.
const PARALLEL_MIN: usize = 4096;

/// Per-quad scaled Jacobians into `values` and [`quad_slack`]s for `floor` into `slack`
/// (parallel), and their statistics (summed in a fixed order, the same on any thread count):
/// what the ranking needs after a sweep and what lets the next sweep skip most guard checks.
pub fn stats_and_slack(
    points: &[DVec2],
    quads: &[[u32; 4]],
    floor: f64,
    values: &mut Vec<f64>,
    slack: &mut Vec<f32>,
) -> QualityStats {
    values.clear();
    values.resize(quads.len(), 0.0);
    slack.clear();
    slack.resize(quads.len(), 0.0);
    if quads.len() >= PARALLEL_MIN {
        quads
            .par_chunks(PARALLEL_MIN)
            .zip(values.par_chunks_mut(PARALLEL_MIN).zip(slack.par_chunks_mut(PARALLEL_MIN)))
            .for_each(|(quads, (values, slack))| measure_into(points, quads, floor, values, slack));
    } else {
        measure_into(points, quads, floor, values, slack);
    }
    QualityStats::from_values(values)
}

crate::simd::avx2_twin! {
    /// The values and slacks of `quads` into `values` and `slack` (as long), compiled for AVX2
    /// where the CPU has it ([`crate::simd`]: the same bits).
    fn measure_into(points: &[DVec2], quads: &[[u32; 4]], floor: f64, values: &mut [f64], slack: &mut [f32]) {
        for ((q, value), s) in quads.iter().zip(values.iter_mut()).zip(slack.iter_mut()) {
            let c = corners(points, q);
            *value = crate::quality::scaled_jacobian_inline(&c);
            *s = face_slack(q, &c, *value, floor);
        }
    }
}

/// Whether moving `v` to `target` certainly keeps every quad around it at or above the floor
/// that `slack` was computed for ([`stats_and_slack`]), given how far each vertex has moved
/// since (`moved`, [`move_length`]): then [`star_at_least`] would say so too, and need not
/// run. `false` means only "not certain". `v` must be a vertex with a ring (interior or
/// boundary, not non-manifold), not moved yet in this sweep (`moved[v]` is 0, so reading it
/// with the other corners of its quads changes nothing).
#[inline(always)]
pub fn certainly_at_least(
    points: &[DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    v: usize,
    target: DVec2,
    slack: &[f32],
    moved: &[f32],
) -> bool {
    // A plain comparison (one instruction; f32::max's NaN rule takes three), each quad's
    // corners reduced as a tree: the chain of dependent maxima is what this costs.
    let larger = |a: f32, b: f32| if a > b { a } else { b };
    let star = topo.vertex_quads(v);
    let most = star.iter().fold(move_length(points[v], target), |most, &qi| {
        let q = &quads[qi as usize];
        let [a, b, c, d] = [q[0], q[1], q[2], fourth_corner(q)].map(|u| moved[u as usize]);
        larger(most, larger(larger(a, b), larger(c, d)))
    });
    star.iter().all(|&qi| most < slack[qi as usize])
}

/// The position actually taken by `v` when it wants to go to `target`: the target itself if
/// the star is tangled or stays acceptable, else the longest acceptable step among
/// 1/2, 1/4, ... of the way.
///
/// When no step towards the target is acceptable, the smoothing direction is making the
/// star's worst quad worse, and a guarded vertex would stay stuck there for good (measured:
/// freshly untangled meshes stuck at a minimum near 0). It then tries the direction that
/// raises the star's smallest corner area ([`super::untangle`]'s local program) and takes
/// the longest step along it that strictly improves the star's minimum; else it stays.
pub fn guarded_position(
    points: &[DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    v: usize,
    target: DVec2,
    floor: f64,
) -> DVec2 {
    let p = points[v];
    if target == p {
        return p;
    }
    // A target at or above the floor is acceptable whatever the current value (the bar is
    // min(current, floor)), so the current star is only evaluated when needed.
    if star_at_least(points, quads, topo, v, target, floor) {
        return target;
    }
    let here = StarValues::at(points, quads, topo, v, p);
    let current = here.min();
    if current <= 0.0 {
        return target;
    }
    if let Some(q) = longest_step(p, target, |at| here.kept_at(points, quads, topo, v, at, floor)) {
        return q;
    }
    if current >= PERFECT {
        // Nothing left to gain: every quad of the star is a rectangle up to rounding.
        return p;
    }
    super::untangle::untangle_vertex(points, quads, topo, v)
        .and_then(|t| {
            longest_step(p, t, |at| {
                star_min(points, quads, topo, v, at) > current
                    && here.kept_at(points, quads, topo, v, at, floor)
            })
        })
        .unwrap_or(p)
}

/// The first of p + d, p + d/2, p + d/4, ... (d = target - p) that `accept` takes.
fn longest_step(p: DVec2, target: DVec2, accept: impl Fn(DVec2) -> bool) -> Option<DVec2> {
    let mut step = target - p;
    for _ in 0..=MAX_HALVINGS {
        let candidate = p + step;
        if accept(candidate) {
            return Some(candidate);
        }
        step *= 0.5;
    }
    None
}

/// The scaled Jacobians of a vertex's star at one position (in `Topology::vertex_quads`
/// order), to test a move against face by face: the per-face rule of the guard.
pub struct StarValues {
    values: Vec<f64>,
}

impl StarValues {
    /// The values of the quads around `v` with `v` at `at`.
    pub fn at(points: &[DVec2], quads: &[[u32; 4]], topo: &Topology, v: usize, at: DVec2) -> StarValues {
        StarValues { values: star_quads(points, quads, topo, v, at).map(|c| scaled_jacobian(&c)).collect() }
    }

    /// The smallest (infinity for no quad).
    pub fn min(&self) -> f64 {
        self.values.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// Whether every quad around `v` with `v` at `at` is at or above min(its value here,
    /// `floor`): no quad falls below the floor, and none already below it falls further. A
    /// star with one bad quad no longer lets its other quads fall to that quad's value.
    pub fn kept_at(
        &self,
        points: &[DVec2],
        quads: &[[u32; 4]],
        topo: &Topology,
        v: usize,
        at: DVec2,
        floor: f64,
    ) -> bool {
        star_quads(points, quads, topo, v, at)
            .zip(&self.values)
            .all(|(c, &here)| !scaled_jacobian_below(&c, here.min(floor)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Mesh;

    /// 2x2 unit squares; vertex 4 is the centre.
    fn grid_2x2() -> (Mesh, Topology) {
        let mut p = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                p.push(DVec2::new(i as f64, j as f64));
            }
        }
        let m = Mesh::new(p, vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]], None).unwrap();
        let t = Topology::new(&m);
        (m, t)
    }

    #[test]
    fn a_bad_quad_in_the_star_does_not_let_the_others_fall_to_its_value() {
        // The centre's star: quad 0 poor (corner 0 dragged towards the centre), the
        // others squares. Targets for the centre along the diagonal towards corner 8: each
        // keeps the star's minimum at quad 0's value (the old rule's bar) while the far quad
        // sinks below the floor; the guard must not take one.
        let (mut m, t) = grid_2x2();
        m.points_mut()[0] = DVec2::new(0.45, 0.45);
        let floor = 0.5;
        let here = StarValues::at(m.points(), m.quads(), &t, 4, m.points()[4]);
        let bad = here.min();
        assert!(bad > 0.0 && bad < 0.3, "{bad}");
        let mut tested = 0;
        for k in 1..40 {
            let target = DVec2::new(1.0, 1.0) + DVec2::splat(0.02 * f64::from(k));
            let values = StarValues::at(m.points(), m.quads(), &t, 4, target);
            let far = values.values[3];
            if !(values.min() >= bad && far < floor) {
                continue;
            }
            tested += 1;
            let at = guarded_position(m.points(), m.quads(), &t, 4, target, floor);
            assert_ne!(at, target, "target {target}: the far quad at {far}");
            assert!(here.kept_at(m.points(), m.quads(), &t, 4, at, floor), "{at}");
        }
        assert!(tested >= 3, "{tested}");
    }

    #[test]
    fn star_at_least_answers_as_star_min_does() {
        let (m, t) = grid_2x2();
        let mut rnd = crate::test_rng::xorshift(0x2545_f491_4f6c_dd1d);
        let (mut yes, mut no) = (0, 0);
        for k in 0..20_000 {
            // The centre anywhere around its star (folded stars included), floors across [-1, 1]
            // and NaN.
            let at = DVec2::new(1.0 + 1.5 * rnd(), 1.0 + 1.5 * rnd());
            let floor = if k % 100 == 0 { f64::NAN } else { rnd() };
            let want = star_min(m.points(), m.quads(), &t, 4, at) >= floor;
            assert_eq!(star_at_least(m.points(), m.quads(), &t, 4, at, floor), want, "{at} {floor}");
            if want { yes += 1 } else { no += 1 }
        }
        assert!(yes > 1000 && no > 1000, "{yes} {no}");
    }

    #[test]
    fn no_move_within_the_slack_takes_a_quad_below_the_floor() {
        let mut rnd = crate::test_rng::xorshift(0x9e37_79b9_7f4a_7c15);
        let (mut checked, mut beyond_fails) = (0, 0);
        for _ in 0..20_000 {
            // A random quad around the unit square (some skewed, some folded).
            let c =
                [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y].map(|p| p + 0.45 * DVec2::new(rnd(), rnd()));
            let value = scaled_jacobian(&c);
            let floor = 0.05 + 0.9 * (0.5 + 0.5 * rnd());
            let slack = f64::from(quad_slack(&c, value, floor));
            if slack <= 0.0 {
                assert!(value <= floor + SLACK_MARGIN || value.is_nan(), "{value} {floor}");
                continue;
            }
            // Every corner moved by up to the slack (the worst directions are the likeliest
            // ones to break a wrong bound: each corner at full length, random direction).
            let moved = |scale: f64, rnd: &mut dyn FnMut() -> f64| {
                c.map(|p| p + scale * slack * DVec2::from_angle(std::f64::consts::PI * rnd()))
            };
            for _ in 0..8 {
                let q = moved(1.0 - 1e-12, &mut rnd);
                assert!(scaled_jacobian(&q) >= floor, "{c:?} -> {q:?}: floor {floor}");
                checked += 1;
                // The bound is not far from tight: ten times as far often breaks it.
                beyond_fails += usize::from(scaled_jacobian(&moved(10.0, &mut rnd)) < floor);
            }
        }
        assert!(checked > 20_000 && beyond_fails > 1000, "{checked} {beyond_fails}");
    }

    #[test]
    fn a_certain_move_is_one_star_at_least_accepts() {
        let (m, t) = grid_2x2();
        let mut rnd = crate::test_rng::xorshift(0x2545_f491_4f6c_dd1d);
        let mut certain = 0;
        for _ in 0..20_000 {
            // The slack at a random start, then the ring moved (as earlier colour classes
            // would) and a random target for the centre.
            let start: Vec<DVec2> = m.points().iter().map(|&p| p + 0.3 * DVec2::new(rnd(), rnd())).collect();
            let floor = 0.05 + 0.5 * (0.5 + 0.5 * rnd());
            let (mut values, mut slack) = (Vec::new(), Vec::new());
            stats_and_slack(&start, m.quads(), floor, &mut values, &mut slack);
            let step = 0.02 * (0.5 + 0.5 * rnd());
            let mut points = start.clone();
            let mut moved = vec![0.0f32; points.len()];
            for u in (0..points.len()).filter(|&u| u != 4) {
                points[u] += step * DVec2::new(rnd(), rnd());
                moved[u] = move_length(start[u], points[u]);
            }
            let target = points[4] + step * DVec2::new(rnd(), rnd());
            if certainly_at_least(&points, m.quads(), &t, 4, target, &slack, &moved) {
                assert!(star_at_least(&points, m.quads(), &t, 4, target, floor));
                certain += 1;
            }
        }
        assert!(certain > 2000, "{certain}");
    }

    #[test]
    fn lengths_round_up_and_slack_down() {
        for x in [1e-150, 1e-40, 0.1, 1.0 / 3.0, 7.0, 1e39] {
            let d = move_length(DVec2::ZERO, DVec2::new(x, 0.0));
            assert!(f64::from(d) >= x, "{x}");
        }
        let square = [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
        let s = quad_slack(&square, 1.0, 0.3);
        assert!(f64::from(s) <= 0.7 / std::f64::consts::TAU && s > 0.11, "{s}");
        assert_eq!(quad_slack(&square, 0.3, 0.3), 0.0);
        assert_eq!(quad_slack(&square, f64::NAN, 0.3), 0.0);
        let sliver = [DVec2::ZERO, DVec2::X, DVec2::new(1.0, 1e-13), DVec2::new(0.0, 1e-13)];
        assert_eq!(quad_slack(&sliver, 1.0, 0.3), 0.0);
    }

    #[test]
    fn guarded_move_never_folds_a_valid_star() {
        // 2x2 grid, centre vertex 4; a target far outside its star would fold it.
        let (m, t) = grid_2x2();
        let target = DVec2::new(5.0, 1.0);
        let got = guarded_position(m.points(), m.quads(), &t, 4, target, 0.05);
        assert!(star_min(m.points(), m.quads(), &t, 4, got) >= 0.05);
        assert!(got.x > 1.0 && got.x < 2.0, "took a partial step: {got}");
        // An acceptable target is taken as is.
        let ok = DVec2::new(1.1, 1.0);
        assert_eq!(guarded_position(m.points(), m.quads(), &t, 4, ok, 0.05), ok);
    }
}

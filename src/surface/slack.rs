//! Slack certificates on the surface: how far a face's corners may move, and their normals
//! turn, before its signed scaled Jacobian can fall to the guard's floor. A sweep takes a
//! move that certainly stays above the floor without scoring its star, as the plane does
//! (`smooth::guard::certainly_at_least`); the decision is the one the score would give, so
//! the result is the same bit for bit.
//!
//! The bound. A corner's value is `n . (u_(i-1) x u_i)` with `n` its unit reference normal
//! and `u` the unit edge directions. Moving an edge's ends by at most `D` each turns it by at
//! most `pi D / l` (`l` its length, `2D < l`), so `|u' - u| <= pi D / L` (`L` the face's
//! shortest edge); a normal that turns to `n'` adds `|n' - n|`, as `|u x u| <= 1`. So with
//! every corner moved by at most `D` and every normal by at most `N`, the value falls by at
//! most `2 pi D / L + N`; while that is below the value's height above the floor, the face
//! stays above it (and above zero: the budget is measured from `max(floor, 0)`). The edges
//! stay longer than `L (1 - 1/pi)`, far from the degenerate-edge cut-off. A margin of 1e-9
//! covers the rounding of the values and of the bound. Triangles get no certificate.
//!
//! Verdict's value has the same form with `n` the face's unit centre normal
//! `w / |w|`, `w = A x B` (`A = e0 - e2`, `B = e1 - e3`), which turns as the corners move: each of
//! `A`, `B` changes by at most `4 D`, so `|w' - w| <= 4 D (|A| + |B|) + 16 D^2` and the unit
//! normal turns by at most twice that over `|w|`. A certified move has `2 pi D / L` below a
//! budget under 2, so `D < L / pi` and `16 D^2 < 16 D L / pi`: Verdict's value falls by at most
//! `D (2 pi / L + (8 (|A| + |B|) + 32 L / pi) / |w|)`, certified against the larger of the
//! face's Verdict bound and `max(floor, 0)` (the star's score takes each face's lower measure). A face whose `w` is small next to `|A| |B|` (nearly parallel diagonals) gets none.

use glam::DVec3;
use rayon::prelude::*;

use super::patches::corner_vertices;
use super::star::{Placed, State, Surface};
use crate::face::is_triangle;

/// Faces from which the budgets are computed in parallel.
const PARALLEL_MIN: usize = 2048;

/// Absolute margin for the rounding of the scaled Jacobians and of the bound (as the plane's).
const MARGIN: f64 = 1e-9;

/// Per-face budgets from one state, and how far each vertex has moved since.
pub struct Slack {
    /// Per face: its budgets, in both measures.
    budget: Vec<Budget>,
    /// Per vertex: how far it has moved since, and how far its normals have turned (the
    /// largest over its faces), rounded up.
    moved: Vec<f32>,
    turned: Vec<f32>,
}

/// A face's budgets: in the signed measure, its value's height above `max(floor, 0)` (and its
/// bound) less the margin, rounded down to an f32 (0: no certificate), and `2 pi` over its
/// shortest edge, rounded up; in Verdict's, its height above its Verdict bound less the
/// margin, and the rate per unit of displacement at which the value can fall, rounded up.
#[derive(Clone, Copy, Debug, Default)]
struct Budget {
    signed: f32,
    per_length: f32,
    verdict: f32,
    verdict_per_length: f32,
}

/// Face `f`'s budgets at `state` (its signed value `value`) above `base` (the signed measure)
/// and its Verdict bound (its Verdict value `verdict` when known, so a sweep's pass computes
/// it once); none for a triangle or a face near the degenerate-edge cut-off.
fn face_budget(
    surface: &Surface,
    state: &State,
    f: usize,
    value: f64,
    verdict: Option<f64>,
    base: f64,
) -> Budget {
    let face = &surface.faces[f];
    if is_triangle(face) {
        return Budget::default();
    }
    let q = corner_vertices(face).map(|u| state.points[u as usize]);
    let squared = [q[1] - q[0], q[2] - q[1], q[3] - q[2], q[0] - q[3]].map(DVec3::length_squared);
    let shortest = squared[0].min(squared[1]).min(squared[2]).min(squared[3]);
    let longest = squared[0].max(squared[1]).max(squared[2]).max(squared[3]);
    // No bound near the degenerate-edge cut-off (the plane's rule).
    if !(shortest >= 1e-24 * longest && shortest > 0.0) {
        return Budget::default();
    }
    let l = shortest.sqrt();
    let mut budget = Budget {
        signed: 0.0,
        per_length: up(std::f64::consts::TAU / l),
        verdict: 0.0,
        verdict_per_length: 0.0,
    };
    let Some(bound) = surface.bounds.get(f) else {
        budget.signed = down(value - base - MARGIN);
        return budget;
    };
    budget.signed = down(value - base.max(bound.signed) - MARGIN);
    let (a, b) = (q[1] - q[0] - (q[3] - q[2]), q[2] - q[1] - (q[0] - q[3]));
    let (la, lb) = (a.length(), b.length());
    let w = a.cross(b).length();
    if w >= 1e-3 * la * lb && w > 0.0 {
        let verdict = verdict.unwrap_or_else(|| crate::quality3d::verdict_scaled_jacobian(&q));
        let rate = std::f64::consts::TAU / l + (8.0 * (la + lb) + 32.0 * l / std::f64::consts::PI) / w;
        budget.verdict = down(verdict - base.max(bound.verdict) - MARGIN);
        budget.verdict_per_length = up(rate);
    }
    budget
}

/// How far a vertex has moved and its normals turned since the budgets' state, rounded up.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Displacement {
    moved: f32,
    turned: f32,
}

/// The larger of `a` and `b`, NaN if `b` is (so a NaN fails the certificate).
fn larger(a: f64, b: f64) -> f64 {
    if b > a || b.is_nan() { b } else { a }
}

/// `x >= 0` rounded up to an f32 (NaN stays NaN, which fails every comparison).
fn up(x: f64) -> f32 {
    let r = x as f32;
    if f64::from(r) >= x || r.is_nan() { r } else { f32::from_bits(r.to_bits() + 1) }
}

/// `x > 0` rounded down to an f32; 0 for anything else.
fn down(x: f64) -> f32 {
    if !(x > 0.0) {
        return 0.0;
    }
    let r = x as f32;
    if f64::from(r) <= x { r } else { f32::from_bits(r.to_bits() - 1) }
}

impl Slack {
    /// The budgets of every face at `state`, whose signed values are `values`, for the
    /// guard's floor `floor`.
    pub fn new(surface: &Surface, state: &State, values: &[f64], floor: f64) -> Slack {
        let mut slack = Slack { budget: Vec::new(), moved: Vec::new(), turned: Vec::new() };
        slack.reset(surface, state, values, floor);
        slack
    }

    /// Recomputes the budgets at `state` (the start of the next sweep), whose signed values
    /// are `values`.
    pub fn reset(&mut self, surface: &Surface, state: &State, values: &[f64], floor: f64) {
        let base = floor.max(0.0);
        let budget = |(f, &value): (usize, &f64)| face_budget(surface, state, f, value, None, base);
        // Once per sweep over every face: in parallel on large meshes (as the values are).
        if surface.faces.len() >= PARALLEL_MIN {
            values.par_iter().enumerate().map(budget).collect_into_vec(&mut self.budget);
        } else {
            self.budget.clear();
            self.budget.extend(values.iter().enumerate().map(budget));
        }
        self.clear_moves(state.points.len());
    }

    /// The signed and Verdict values of every face at `state`, with the budgets recomputed
    /// there as by [`reset`](Self::reset): one pass over the faces where a sweep needs all.
    pub fn values_and_reset(&mut self, surface: &Surface, state: &State, floor: f64) -> (Vec<f64>, Vec<f64>) {
        let base = floor.max(0.0);
        let all = |f: usize| {
            let value = surface.face_value(state, f, None);
            let verdict = surface.face_verdict(state, f, None);
            ((value, verdict), face_budget(surface, state, f, value, Some(verdict), base))
        };
        let mut values: Vec<(f64, f64)> = Vec::new();
        if surface.faces.len() >= PARALLEL_MIN {
            (0..surface.faces.len()).into_par_iter().map(all).unzip_into_vecs(&mut values, &mut self.budget);
        } else {
            self.budget.clear();
            values.reserve(surface.faces.len());
            for f in 0..surface.faces.len() {
                let (value, budget) = all(f);
                values.push(value);
                self.budget.push(budget);
            }
        }
        self.clear_moves(state.points.len());
        values.into_iter().unzip()
    }

    /// Every vertex at rest since the budgets' state.
    fn clear_moves(&mut self, vertices: usize) {
        self.moved.clear();
        self.moved.resize(vertices, 0.0);
        self.turned.clear();
        self.turned.resize(vertices, 0.0);
    }

    /// How far `v` at `at` is from where it was at the last reset, and how far its normals
    /// have turned (the largest over its faces), both rounded up: what [`record`](Self::record)
    /// takes once the move is applied. `state` has `v` where it is before this move: the
    /// distance from there is added to what is recorded already (a sweep moves a vertex once
    /// between resets, so there it is the distance itself). It reads nothing another vertex's
    /// move writes, so a sweep computes it with the move, in parallel.
    pub fn displacement(&self, surface: &Surface, state: &State, v: usize, at: &Placed) -> Displacement {
        let mut turned = 0.0f64;
        for &f in surface.topo.vertex_quads(v) {
            let f = f as usize;
            let normal = at.normal_for(surface.patches.of_face(f));
            for (k, &u) in corner_vertices(&surface.faces[f]).iter().enumerate() {
                if u as usize == v && !surface.patches.is_own(f, k) {
                    turned = larger(turned, (normal - state.normals[f][k]).length());
                }
            }
        }
        let moved = (at.point - state.points[v]).length();
        Displacement {
            moved: up(f64::from(self.moved[v]) + moved),
            turned: up(f64::from(self.turned[v]) + turned),
        }
    }

    /// Records that `v` has moved by `d` ([`displacement`](Self::displacement)).
    pub fn record(&mut self, v: usize, d: Displacement) {
        self.moved[v] = d.moved;
        self.turned[v] = d.turned;
    }

    /// Whether `v` at `at` certainly leaves every face of its star above the floor with no
    /// face inverted (what the guard's first test would find by scoring the star): if so, the
    /// move's [`displacement`](Self::displacement), which it has computed on the way; `None`
    /// means only "not certain". `state` has `v` where it is before this move.
    pub fn certify(&self, surface: &Surface, state: &State, v: usize, at: &Placed) -> Option<Displacement> {
        let moved = up(f64::from(self.moved[v]) + (at.point - state.points[v]).length());
        let (own, own_turn) = (f64::from(moved), f64::from(self.turned[v]));
        // The largest turn of v's own normals, over its faces.
        let mut turn = 0.0f64;
        for &f in surface.topo.vertex_quads(v) {
            let f = f as usize;
            let budget = self.budget[f];
            let bounded = !surface.bounds.is_empty();
            if budget.signed <= 0.0 || (bounded && budget.verdict <= 0.0) {
                return None;
            }
            let (mut d, mut n) = (own, 0.0f64);
            for (k, &u) in corner_vertices(&surface.faces[f]).iter().enumerate() {
                let u = u as usize;
                if u == v {
                    let normal = at.normal_for(surface.patches.of_face(f));
                    // A corner measured against its face's own normal keeps it.
                    let t = if surface.patches.is_own(f, k) {
                        0.0
                    } else {
                        (normal - state.normals[f][k]).length()
                    };
                    turn = larger(turn, t);
                    n = larger(n, own_turn + t);
                } else {
                    d = larger(d, f64::from(self.moved[u]));
                    n = larger(n, f64::from(self.turned[u]));
                }
            }
            if !(d * f64::from(budget.per_length) + n < f64::from(budget.signed)) {
                return None;
            }
            if bounded && !(d * f64::from(budget.verdict_per_length) < f64::from(budget.verdict)) {
                return None;
            }
        }
        Some(Displacement { moved, turned: up(own_turn + turn) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::star::Motion;
    use crate::surface::{SurfaceMesh, SurfaceOptimizer};

    /// A quarter cylinder of 30 x 20 quads, its inner vertices moved along it at random.
    fn cylinder(rnd: &mut impl FnMut() -> f64) -> SurfaceMesh {
        let (nu, nv) = (30, 20);
        let mut points = Vec::new();
        for j in 0..=nv {
            for i in 0..=nu {
                let inner = i > 0 && i < nu && j > 0 && j < nv;
                let (du, dv) = if inner { (0.15 * rnd(), 0.15 * rnd()) } else { (0.0, 0.0) };
                let a = (i as f64 + du) / nu as f64 * std::f64::consts::FRAC_PI_2;
                points.push(DVec3::new(a.cos(), a.sin(), (j as f64 + dv) / nv as f64));
            }
        }
        let id = |i: usize, j: usize| (j * (nu + 1) + i) as u32;
        let faces = (0..nv)
            .flat_map(|j| (0..nu).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]))
            .collect();
        SurfaceMesh::new(points, faces, None).unwrap()
    }

    #[test]
    fn a_certified_move_keeps_every_face_of_its_star_above_the_floor() {
        let mut rnd = crate::test_rng::xorshift(0x51ac_c0de_u64);
        let mesh = cylinder(&mut rnd);
        let optimizer = SurfaceOptimizer::new(&mesh, 45.0, &[]).unwrap();
        let surface = optimizer.surface();
        let (mut certified, mut tried) = (0, 0);
        for floor in [0.0, 0.3, 0.6] {
            let mut state = optimizer.initial_state();
            let values = optimizer.values(&state);
            let mut slack = Slack::new(&surface, &state, &values, floor);
            // Rounds of moves without a reset: later certificates count the moves before them.
            for round in 0..4 {
                for v in 0..state.points.len() {
                    let Motion::Free(patch) = surface.motion[v] else { continue };
                    let here = surface.current(&state, v);
                    let size = [1e-4, 1e-3, 5e-3, 2e-2][(v + round) % 4];
                    let step = DVec3::new(rnd(), rnd(), rnd()) * size;
                    let candidate = surface.place_free(patch, here.point + step, here.hint);
                    tried += 1;
                    if let Some(d) = slack.certify(&surface, &state, v, &candidate) {
                        certified += 1;
                        // What the certificate records is the move's displacement, bit for bit.
                        assert_eq!(d, slack.displacement(&surface, &state, v, &candidate));
                        let score = surface.star_score(&state, v, Some(&candidate));
                        assert!(score.inverted == 0 && score.min >= floor, "{v} {score:?} floor {floor}");
                    }
                    // Move a third of the vertices, whatever that does to their stars.
                    if (v + round) % 3 == 0 {
                        let d = slack.displacement(&surface, &state, v, &candidate);
                        surface.apply(&mut state, v, &candidate);
                        slack.record(v, d);
                    }
                }
            }
        }
        // The certificate holds for a good part of the small moves (else this tests nothing).
        assert!(certified * 8 > tried, "{certified} of {tried}");
    }
}

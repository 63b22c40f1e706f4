//! Untangling: remove inverted quads by moving movable interior vertices, before smoothing.
//!
//! Each corner value of a quad (the cross product of its two edges at that corner, twice a
//! signed corner area) is *linear* in the position of any one vertex. So for one vertex v,
//! "maximize the smallest corner value of the star" is a linear program in (x, y, t), as in
//! Freitag and Plassmann's local untangling: maximize t subject to g_k . v + c_k >= t for
//! every corner that depends on v, and v inside the bounding box of its neighbours. In 2D the
//! program has at most a few dozen constraints, so it is solved exactly by visiting the
//! vertices of the feasible polytope. Sweeps run colour class by colour class (vertices of
//! one class share no quad), so every accepted move improves its star exactly.

use crate::features::Features;
use crate::quality::{corners, scaled_jacobian};
use crate::topology::{Topology, VertexKind};
use glam::DVec2;
use rayon::prelude::*;

/// Why a quad is still inverted after untangling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TangleReason {
    /// All four of its vertices are fixed, corners or boundary vertices that may not move.
    AllVerticesFixed,
    /// Its inverted corner is a reflex angle formed by three vertices that may not move (for
    /// example a concave boundary corner inside a single quad, the paper's mazewheel case):
    /// no placement of the movable vertices can fix it.
    ForcedByFixedVertices,
    /// The quad is the only quad at a fixed boundary vertex whose boundary angle is 180
    /// degrees or more (a straight or concave stretch of boundary folded into one quad): its
    /// neighbours can only slide along the boundary, so the angle cannot shrink.
    BoundaryAngle,
    /// The local untangler found no valid placement (one may still exist).
    NotResolved,
}

impl TangleReason {
    /// Short description.
    pub fn describe(self) -> &'static str {
        match self {
            TangleReason::AllVerticesFixed => "all four vertices are fixed",
            TangleReason::ForcedByFixedVertices => "a reflex corner is formed by three fixed vertices",
            TangleReason::BoundaryAngle => {
                "it spans a boundary angle of 180 degrees or more at a vertex of one quad"
            }
            TangleReason::NotResolved => "the local untangler found no valid placement",
        }
    }
}

/// A quad that is still inverted, and why.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TangledQuad {
    /// Quad index.
    pub quad: u32,
    /// Why it could not be fixed.
    pub reason: TangleReason,
}

/// A linear function of v: g . v + c.
#[derive(Clone, Copy, Debug)]
struct Linear {
    g: DVec2,
    c: f64,
}

impl Linear {
    /// v -> cross(u, v - w).
    fn cross_from(u: DVec2, w: DVec2) -> Linear {
        Linear { g: DVec2::new(-u.y, u.x), c: -u.perp_dot(w) }
    }
    fn negated(self) -> Linear {
        Linear { g: -self.g, c: -self.c }
    }
    fn at(&self, v: DVec2) -> f64 {
        self.g.dot(v) + self.c
    }
}

/// The corner values of the star of `v` that depend on v's position, as linear functions.
fn star_corners(points: &[DVec2], quads: &[[u32; 4]], topo: &Topology, v: usize, out: &mut Vec<Linear>) {
    out.clear();
    for &qi in topo.vertex_quads(v) {
        let q = &quads[qi as usize];
        let i = q.iter().position(|&u| u as usize == v).unwrap_or(0);
        let a = points[q[(i + 1) % 4] as usize];
        let d = points[q[(i + 2) % 4] as usize];
        let b = points[q[(i + 3) % 4] as usize];
        // Corner at v: cross(a - v, b - v) = cross(a - b, v - b) ... written as cross(b - a, v - a) negated? Use the
        // expansion cross(a - v, b - v) = cross(a, b) + v.x (a.y - b.y) + v.y (b.x - a.x).
        out.push(Linear { g: DVec2::new(a.y - b.y, b.x - a.x), c: a.perp_dot(b) });
        // Corner at a (prev v, next d): cross(d - a, v - a).
        out.push(Linear::cross_from(d - a, a));
        // Corner at b (prev d, next v): cross(v - b, d - b) = -cross(d - b, v - b).
        out.push(Linear::cross_from(d - b, b).negated());
    }
}

/// Constraint rows a . (x, y, t) <= b of the program: t - g . v <= c for each f, then the four
/// sides of the box.
fn program_rows(f: &[Linear], lo: DVec2, hi: DVec2) -> Vec<([f64; 3], f64)> {
    let mut rows: Vec<([f64; 3], f64)> = f.iter().map(|l| ([-l.g.x, -l.g.y, 1.0], l.c)).collect();
    rows.push(([1.0, 0.0, 0.0], hi.x));
    rows.push(([-1.0, 0.0, 0.0], -lo.x));
    rows.push(([0.0, 1.0, 0.0], hi.y));
    rows.push(([0.0, -1.0, 0.0], -lo.y));
    rows
}

/// Pivots after which [`max_min`] gives up on the simplex (it needs a handful in practice).
const MAX_PIVOTS: usize = 200;

/// Position maximizing the smallest of `f` inside the box [lo, hi], and that smallest value.
///
/// A primal simplex walking the vertices of the 3-variable program (active-set form: three
/// tight rows define the vertex; drop the one with a negative multiplier, move along the edge
/// the other two keep, stop at the first row that becomes tight), with Bland's rule against
/// cycling. It starts from the box corner `lo` with t at the smallest f there, so each pivot
/// costs one 3x3 solve and one pass over the rows instead of the O(m^4) of visiting every
/// vertex.
fn max_min(f: &[Linear], lo: DVec2, hi: DVec2) -> Option<(DVec2, f64)> {
    if f.is_empty() || !(lo.is_finite() && hi.is_finite()) || lo.cmpgt(hi).any() {
        return None;
    }
    let rows = program_rows(f, lo, hi);
    let m = f.len();
    let scale = f.iter().map(|l| l.c.abs() + l.g.length() * (hi - lo).length()).fold(1e-300, f64::max);
    let tol = 1e-12 * scale;
    let dot = |a: &[f64; 3], z: &[f64; 3]| a[0] * z[0] + a[1] * z[1] + a[2] * z[2];
    let l1 = |a: &[f64; 3]| a[0].abs() + a[1].abs() + a[2].abs();
    // Start: v = lo (tight: x >= lo.x, y >= lo.y), t = min f(lo) (tight: its row).
    let (first, t0) = f
        .iter()
        .enumerate()
        .map(|(i, l)| (i, l.at(lo)))
        .fold((0, f64::INFINITY), |best, (i, t)| if t < best.1 { (i, t) } else { best });
    let mut z = [lo.x, lo.y, t0];
    let mut active = [first, m + 1, m + 3];
    for _ in 0..MAX_PIVOTS {
        let a = [rows[active[0]].0, rows[active[1]].0, rows[active[2]].0];
        let Some(inv) = inverse3(a) else { break };
        // Multipliers of the tight rows: A^T lambda = (0, 0, 1), so lambda_k = inv[2][k].
        let lambda = [inv[2][0], inv[2][1], inv[2][2]];
        // Bland: among negative multipliers, the row of smallest index leaves.
        let leave = (0..3).filter(|&k| lambda[k] < -1e-14).min_by_key(|&k| active[k]);
        let Some(k) = leave else {
            return Some((DVec2::new(z[0], z[1]), z[2]));
        };
        // Edge direction d with A d = -e_k: minus column k of the inverse.
        let d = [-inv[0][k], -inv[1][k], -inv[2][k]];
        let mut enter: Option<(usize, f64)> = None;
        for (r, (row, b)) in rows.iter().enumerate() {
            if active.contains(&r) {
                continue;
            }
            let rate = dot(row, &d);
            if rate <= 1e-14 * l1(row) * l1(&d) {
                continue;
            }
            let step = ((b - dot(row, &z)) / rate).max(0.0);
            if enter.is_none_or(|(_, s)| step < s - tol * 1e-3) {
                enter = Some((r, step));
            }
        }
        let (r, step) = enter?;
        for (zi, di) in z.iter_mut().zip(d) {
            *zi += step * di;
        }
        active[k] = r;
    }
    max_min_exhaustive(f, lo, hi)
}

/// Inverse of a 3x3 matrix; `None` if (nearly) singular.
fn inverse3(a: [[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let c = |r0: usize, c0: usize, r1: usize, c1: usize| a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0];
    let cof = [
        [c(1, 1, 2, 2), -c(1, 0, 2, 2), c(1, 0, 2, 1)],
        [-c(0, 1, 2, 2), c(0, 0, 2, 2), -c(0, 0, 2, 1)],
        [c(0, 1, 1, 2), -c(0, 0, 1, 2), c(0, 0, 1, 1)],
    ];
    let det = a[0][0] * cof[0][0] + a[0][1] * cof[0][1] + a[0][2] * cof[0][2];
    let norm: f64 = a.iter().flatten().map(|x| x.abs()).fold(0.0, f64::max);
    // Written so that a NaN determinant is rejected too.
    let regular = det.abs() > 1e-12 * norm.powi(3);
    if !regular {
        return None;
    }
    // inverse = adjugate / det, adjugate = transposed cofactors.
    let mut inv = [[0.0; 3]; 3];
    for (r, row) in inv.iter_mut().enumerate() {
        for (col, x) in row.iter_mut().enumerate() {
            *x = cof[col][r] / det;
        }
    }
    Some(inv)
}

/// [`max_min`] by visiting every vertex of the arrangement (O(m^4) for m constraints): the
/// reference the simplex is tested against, and its fallback should it ever fail to finish.
fn max_min_exhaustive(f: &[Linear], lo: DVec2, hi: DVec2) -> Option<(DVec2, f64)> {
    let rows = program_rows(f, lo, hi);
    let scale = f.iter().map(|l| l.c.abs() + l.g.length() * (hi - lo).length()).fold(1e-300, f64::max);
    let tol = 1e-9 * scale;
    let mut best: Option<(DVec2, f64)> = None;
    let n = rows.len();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let Some(x) = solve3([rows[i].0, rows[j].0, rows[k].0], [rows[i].1, rows[j].1, rows[k].1])
                else {
                    continue;
                };
                if rows.iter().all(|(a, b)| a[0] * x[0] + a[1] * x[1] + a[2] * x[2] <= b + tol)
                    && best.is_none_or(|(_, t)| x[2] > t)
                {
                    best = Some((DVec2::new(x[0], x[1]), x[2]));
                }
            }
        }
    }
    best
}

/// Solves a 3x3 linear system by Cramer's rule; `None` if (nearly) singular.
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    let norm: f64 = a.iter().flatten().map(|x| x.abs()).fold(0.0, f64::max);
    if d.abs() <= 1e-12 * norm.powi(3) {
        return None;
    }
    let mut x = [0.0; 3];
    for (c, xc) in x.iter_mut().enumerate() {
        let mut m = a;
        for r in 0..3 {
            m[r][c] = b[r];
        }
        *xc = det(m) / d;
    }
    Some(x)
}

/// Whether the star of `v` has a non-positive corner value.
fn star_is_tangled(points: &[DVec2], quads: &[[u32; 4]], topo: &Topology, v: usize) -> bool {
    topo.vertex_quads(v).iter().any(|&q| scaled_jacobian(&corners(points, &quads[q as usize])) <= 0.0)
}

/// One untangling move of `v`, or `None` if it cannot raise its star's smallest corner value.
pub(crate) fn untangle_vertex(
    points: &[DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    v: usize,
) -> Option<DVec2> {
    let mut f = Vec::with_capacity(24);
    star_corners(points, quads, topo, v, &mut f);
    let p = points[v];
    let current = f.iter().map(|l| l.at(p)).fold(f64::INFINITY, f64::min);
    // Search box: the bounding box of the neighbours, shrunk by 10% towards its centre so an
    // optimum on the box (when the star cannot be fully untangled from here) never lands
    // exactly on a neighbour's coordinates and degenerates an edge.
    let (mut lo, mut hi) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
    for &u in topo.full_ring(v) {
        lo = lo.min(points[u as usize]);
        hi = hi.max(points[u as usize]);
    }
    let (centre, half) = ((lo + hi) * 0.5, (hi - lo) * 0.45);
    let (best, value) = max_min(&f, centre - half, centre + half)?;
    (value > current && best.is_finite()).then_some(best)
}

/// Untangles in place; returns the number of sweeps done. Only movable interior vertices move.
pub fn untangle(
    points: &mut [DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    features: &Features,
    max_sweeps: usize,
) -> usize {
    let mut moves: Vec<(u32, DVec2)> = Vec::new();
    for sweep in 0..max_sweeps {
        let mut moved = false;
        for c in 0..topo.colour_count() {
            let class = topo.colour_class(c);
            let snapshot: &[DVec2] = points;
            moves.clear();
            moves.par_extend(class.par_iter().filter_map(|&v| {
                let vu = v as usize;
                if !features.is_movable(vu) || topo.kind(vu) != VertexKind::Interior {
                    return None;
                }
                if !star_is_tangled(snapshot, quads, topo, vu) {
                    return None;
                }
                untangle_vertex(snapshot, quads, topo, vu).map(|p| (v, p))
            }));
            for &(v, p) in &moves {
                points[v as usize] = p;
            }
            moved |= !moves.is_empty();
        }
        let inverted = quads.iter().any(|q| scaled_jacobian(&corners(points, q)) <= 0.0);
        if !moved || !inverted {
            return sweep + 1;
        }
    }
    max_sweeps
}

/// Explains every quad that is still inverted at `points`.
pub fn diagnose(
    points: &[DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    features: &Features,
) -> Vec<TangledQuad> {
    let mut out = Vec::new();
    for (qi, q) in quads.iter().enumerate() {
        let c = corners(points, q);
        if scaled_jacobian(&c) > 0.0 {
            continue;
        }
        let fixed = |k: usize| !features.is_movable(q[k % 4] as usize);
        let reason = if (0..4).all(fixed) {
            TangleReason::AllVerticesFixed
        } else if (0..4).any(|k| {
            let (prev, p, next) = (c[(k + 3) % 4], c[k], c[(k + 1) % 4]);
            fixed(k + 3) && fixed(k) && fixed(k + 1) && (next - p).perp_dot(prev - p) <= 0.0
        }) {
            TangleReason::ForcedByFixedVertices
        } else if (0..4).any(|k| {
            let v = q[k] as usize;
            let (prev, p, next) = (c[(k + 3) % 4], c[k], c[(k + 1) % 4]);
            fixed(k)
                && topo.kind(v) == VertexKind::Boundary
                && topo.quad_count(v) == 1
                && (next - p).perp_dot(prev - p) <= 0.0
        }) {
            TangleReason::BoundaryAngle
        } else {
            TangleReason::NotResolved
        };
        out.push(TangledQuad { quad: qi as u32, reason });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_corner_values_match_direct_cross_products() {
        let points =
            vec![DVec2::new(0.3, 0.4), DVec2::new(2.0, 0.1), DVec2::new(2.2, 1.9), DVec2::new(-0.1, 2.0)];
        let quads = vec![[0u32, 1, 2, 3]];
        let m = crate::QuadMesh::new(points.clone(), quads.clone(), None).unwrap();
        let t = Topology::new(&m);
        let mut f = Vec::new();
        star_corners(&points, &quads, &t, 0, &mut f);
        let v = DVec2::new(0.7, -0.2);
        let (a, d, b) = (points[1], points[2], points[3]);
        let direct = [(a - v).perp_dot(b - v), (d - a).perp_dot(v - a), (v - b).perp_dot(d - b)];
        for (l, e) in f.iter().zip(direct) {
            assert!((l.at(v) - e).abs() < 1e-12, "{} vs {e}", l.at(v));
        }
    }

    #[test]
    fn max_min_of_two_lines_is_their_crossing() {
        // f1 = x, f2 = 1 - x on [0, 1]^2: the best smallest value is 0.5 at x = 0.5.
        let f = [Linear { g: DVec2::X, c: 0.0 }, Linear { g: -DVec2::X, c: 1.0 }];
        let (v, t) = max_min(&f, DVec2::ZERO, DVec2::ONE).unwrap();
        assert!((t - 0.5).abs() < 1e-12 && (v.x - 0.5).abs() < 1e-12);
    }

    #[test]
    fn simplex_matches_the_exhaustive_search_on_random_programs() {
        // Deterministic pseudo-random programs like a star's: 4 to 24 corner functions.
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        };
        for case in 0..2000 {
            let m = 4 + case % 21;
            let f: Vec<Linear> =
                (0..m).map(|_| Linear { g: DVec2::new(rnd(), rnd()) * 3.0, c: rnd() * 2.0 }).collect();
            let (lo, hi) = (DVec2::new(rnd(), rnd()) - 1.5, DVec2::new(rnd(), rnd()) + 1.5);
            let (v, t) = max_min(&f, lo, hi).unwrap();
            let (_, t_ref) = max_min_exhaustive(&f, lo, hi).unwrap();
            assert!((t - t_ref).abs() <= 1e-9 * (1.0 + t_ref.abs()), "case {case}: {t} vs {t_ref}");
            // The point is feasible and attains the value.
            assert!(v.cmpge(lo - 1e-12).all() && v.cmple(hi + 1e-12).all(), "case {case}: {v} outside");
            let at = f.iter().map(|l| l.at(v)).fold(f64::INFINITY, f64::min);
            assert!((at - t).abs() <= 1e-9 * (1.0 + t.abs()), "case {case}: value {at} vs {t}");
        }
    }
}

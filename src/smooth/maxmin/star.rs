//! The star of a vertex (its incident quads) evaluated at candidate positions: the minimum and
//! average scaled Jacobian a move would give, the edge floors no move may cross, and the fast
//! and batched evaluations every search spends its time in. Separate from the searches, which
//! only ask it for values, because its arithmetic must stay bit-identical across its paths.

use crate::face::{corner_count, is_triangle};
use crate::quality::{corners, scaled_jacobian};
use crate::topology::Topology;
use glam::DVec2;
use rayon::prelude::*;

/// No move of the stage may shorten an edge below this fraction of the longest edge its quad
/// had when the stage began, nor below [`SHORTEST_EDGE_KEPT`] of its quad's shortest edge
/// then. The scaled Jacobian does not see aspect ratio: without this floor the stage
/// collapsed quads into slivers that score well (an edge 3e-15 of its quad's on Mesquite's
/// horse20x10, 1e-5 on hole_in_square), useless to a solver and meaningless once the
/// coordinates are rounded.
const SHORTEST_EDGE_FRACTION: f64 = 0.1;

/// See [`SHORTEST_EDGE_FRACTION`]: how much of a quad's already short edge a move may take.
const SHORTEST_EDGE_KEPT: f64 = 0.5;

/// Per quad, the squared length no edge at a moving vertex may fall below during the stage
/// (see [`SHORTEST_EDGE_FRACTION`]).
pub(super) fn edge_floors(points: &[DVec2], quads: &[[u32; 4]]) -> Vec<f64> {
    let mut floors = Vec::with_capacity(quads.len());
    floors.par_extend(quads.par_iter().map(|q| {
        let (c, n) = (corners(points, q), corner_count(q));
        let squared = |i: usize| (c[(i + 1) % n] - c[i]).length_squared();
        let longest = (0..n).map(squared).fold(0.0, f64::max);
        let shortest = (0..n).map(squared).fold(f64::INFINITY, f64::min);
        (SHORTEST_EDGE_FRACTION * SHORTEST_EDGE_FRACTION * longest)
            .min(SHORTEST_EDGE_KEPT * SHORTEST_EDGE_KEPT * shortest)
    }));
    floors
}

/// The quads around one vertex, with the vertex's corner index in each.
pub(super) struct Star {
    pub(super) quads: Vec<([DVec2; 4], usize)>,
    /// Whether each face is a triangle (its fourth corner repeats its third).
    triangle: Vec<bool>,
    /// Whether each quad is valid (scaled Jacobian > 0) at the current position.
    valid: Vec<bool>,
    /// Per quad, what does not depend on the moving corner.
    fixed_part: Vec<FixedPart>,
    /// Per quad, the squared length below which neither edge at the moving corner may fall
    /// ([`edge_floors`]).
    shortest_squared: Vec<f64>,
}

/// The corners and edges of a star quad that stay put while its corner at the vertex moves:
/// with them a candidate costs two square roots instead of four.
#[derive(Clone, Copy, Debug)]
struct FixedPart {
    prev: DVec2,
    next: DVec2,
    opposite: DVec2,
    /// |opposite - next| and |prev - opposite|.
    next_len: f64,
    prev_len: f64,
    /// Scaled Jacobian at the opposite corner.
    opposite_value: f64,
    /// False when the fixed corners are degenerate: always use the full evaluation.
    usable: bool,
}

/// Below this the fast evaluation defers to [`scaled_jacobian`], whose degenerate-edge and
/// sign rules then decide (validity is judged exactly as in the statistics).
const FAST_FLOOR: f64 = 1e-6;

/// Positions [`Star::values_above`] evaluates together.
const LANES: usize = 4;

impl FixedPart {
    fn new(c: &[DVec2; 4], k: usize, triangle: bool) -> FixedPart {
        if triangle {
            // Only the edges to the moving corner's neighbours (for the edge floor): a
            // triangle is always evaluated in full.
            let (prev, next) = (c[(k + 2) % 3], c[(k + 1) % 3]);
            let (next_len, prev_len, opposite_value) = (0.0, 0.0, 0.0);
            return FixedPart {
                prev,
                next,
                opposite: next,
                next_len,
                prev_len,
                opposite_value,
                usable: false,
            };
        }
        let (prev, next, opposite) = (c[(k + 3) % 4], c[(k + 1) % 4], c[(k + 2) % 4]);
        let (next_len, prev_len) = ((opposite - next).length(), (prev - opposite).length());
        let (a, b) = (prev - opposite, next - opposite);
        let opposite_value = a.perp_dot(b) / (prev_len * next_len);
        let usable = next_len > 0.0 && prev_len > 0.0 && opposite_value.is_finite();
        FixedPart { prev, next, opposite, next_len, prev_len, opposite_value, usable }
    }

    /// The quad's scaled Jacobian with its moving corner at `x`, or `None` when it is near
    /// degenerate or inverted (then the caller evaluates it in full).
    #[cfg(test)]
    fn value(&self, x: DVec2) -> Option<f64> {
        let edges = MovingEdges::new(self.next, self.prev, x);
        self.value_from(&edges)
    }

    /// `FixedPart::value` from the moving corner's two edges, already computed.
    #[inline]
    fn value_from(&self, edges: &MovingEdges) -> Option<f64> {
        if !self.usable {
            return None;
        }
        let (u, w) = (edges.to_next, edges.to_prev);
        let (lu, lw) = (edges.next_squared.sqrt(), edges.prev_squared.sqrt());
        let at_x = u.perp_dot(w) / (lu * lw);
        let at_next = (self.opposite - self.next).perp_dot(-u) / (self.next_len * lu);
        let at_prev = (-w).perp_dot(self.opposite - self.prev) / (lw * self.prev_len);
        let m = at_x.min(at_next).min(at_prev).min(self.opposite_value);
        // NaN (a zero edge) fails this test too.
        (m >= FAST_FLOOR).then_some(m)
    }

    /// For `LANES` positions of the moving corner: the squared lengths of its edges to the
    /// next and the previous corner, and the quad's fast value (unchecked: the caller applies
    /// `value_from`'s tests). The same operations in the same order as `MovingEdges::new`
    /// and `value_from`, lane by lane, so the same bits.
    #[inline]
    fn lanes(&self, x: &[f64; LANES], y: &[f64; LANES]) -> ([f64; LANES], [f64; LANES], [f64; LANES]) {
        let (mut next_squared, mut prev_squared, mut fast) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
        let (d_next, d_prev) = (self.opposite - self.next, self.opposite - self.prev);
        for l in 0..LANES {
            let (ux, uy) = (self.next.x - x[l], self.next.y - y[l]);
            let (wx, wy) = (self.prev.x - x[l], self.prev.y - y[l]);
            let (ns, ps) = ((ux * ux) + (uy * uy), (wx * wx) + (wy * wy));
            let (lu, lw) = (ns.sqrt(), ps.sqrt());
            let at_x = ((ux * wy) - (uy * wx)) / (lu * lw);
            let at_next = ((d_next.x * -uy) - (d_next.y * -ux)) / (self.next_len * lu);
            let at_prev = ((-wx * d_prev.y) - (-wy * d_prev.x)) / (lw * self.prev_len);
            next_squared[l] = ns;
            prev_squared[l] = ps;
            fast[l] = at_x.min(at_next).min(at_prev).min(self.opposite_value);
        }
        (next_squared, prev_squared, fast)
    }
}

/// Star minimum and average at one position; `min` is -inf when a valid quad would invert.
#[derive(Clone, Copy, Debug)]
pub(super) struct Value {
    pub(super) min: f64,
    pub(super) avg: f64,
}

/// The value of a position that may not be taken.
pub(super) const REJECTED: Value = Value { min: f64::NEG_INFINITY, avg: f64::NEG_INFINITY };

impl Star {
    pub(super) fn new(
        points: &[DVec2],
        quads: &[[u32; 4]],
        topo: &Topology,
        edge_floors: &[f64],
        v: usize,
    ) -> Star {
        let triangle: Vec<bool> =
            topo.vertex_quads(v).iter().map(|&qi| is_triangle(&quads[qi as usize])).collect();
        let quads: Vec<([DVec2; 4], usize)> = topo
            .vertex_quads(v)
            .iter()
            .map(|&qi| {
                let q = &quads[qi as usize];
                (corners(points, q), q.iter().position(|&u| u as usize == v).unwrap_or(0))
            })
            .collect();
        let valid = quads.iter().map(|(c, _)| scaled_jacobian(c) > 0.0).collect();
        let fixed_part: Vec<FixedPart> =
            quads.iter().zip(&triangle).map(|((c, k), &t)| FixedPart::new(c, *k, t)).collect();
        // Never above the current lengths, so that staying put is always allowed.
        let shortest_squared = topo
            .vertex_quads(v)
            .iter()
            .zip(&quads)
            .zip(&fixed_part)
            .map(|((&qi, (c, k)), part)| {
                let now = MovingEdges::new(part.next, part.prev, c[*k]);
                edge_floors.get(qi as usize).map_or(0.0, |&f| f.min(now.next_squared).min(now.prev_squared))
            })
            .collect();
        Star { quads, triangle, valid, fixed_part, shortest_squared }
    }

    /// The corners of face `i` with the moving corner at `at`.
    #[inline]
    fn moved(&self, i: usize, at: DVec2) -> [DVec2; 4] {
        let (mut c, k) = self.quads[i];
        c[k] = at;
        // A triangle's fourth corner repeats its third.
        if self.triangle[i] {
            c[3] = c[2];
        }
        c
    }

    pub(super) fn value(&self, at: DVec2) -> Value {
        self.value_above(at, f64::NEG_INFINITY)
    }

    /// As [`Star::value`], but once a quad falls below `bar` the rest are skipped: the result
    /// then has that partial minimum (at least the true one, still below `bar`) and an average
    /// of -inf. For a candidate that cannot be taken, whatever its true value.
    fn value_above(&self, at: DVec2, bar: f64) -> Value {
        let (mut min, mut sum) = (f64::INFINITY, 0.0);
        let quads = self.valid.iter().zip(&self.fixed_part).zip(&self.shortest_squared).enumerate();
        for (i, ((&valid, part), &shortest)) in quads {
            let edges = MovingEdges::new(part.next, part.prev, at);
            if edges.next_squared < shortest || edges.prev_squared < shortest {
                return REJECTED;
            }
            let q = part.value_from(&edges).unwrap_or_else(|| scaled_jacobian(&self.moved(i, at)));
            if valid && q <= 0.0 {
                return REJECTED;
            }
            min = min.min(q);
            sum += q;
            if min < bar {
                return Value { min, avg: f64::NEG_INFINITY };
            }
        }
        if !at.is_finite() || min.is_nan() {
            return REJECTED;
        }
        Value { min, avg: sum / self.quads.len().max(1) as f64 }
    }

    /// [`Star::value_above`] of every position of `at`, into `out` (same length): the same
    /// values bit for bit, computed [`LANES`] positions at a time. The square roots and
    /// divisions of the quads' fast values are evaluated for all lanes together (the compiler
    /// vectorizes them; IEEE operations round the same in any lane), then each lane replays
    /// `value_above`'s sequential rules (rejections, fallbacks, the early exit) on them. A
    /// group stops at the first quad after which every lane is decided, so most of the early
    /// exits' saving is kept.
    pub(super) fn values_above(&self, at: &[DVec2], bar: f64, out: &mut Vec<Value>) {
        out.clear();
        for group in at.chunks(LANES) {
            // A short last group repeats its last position in the unused lanes.
            let lane = |l: usize| group[l.min(group.len() - 1)];
            let (x, y): ([f64; LANES], [f64; LANES]) =
                (std::array::from_fn(|l| lane(l).x), std::array::from_fn(|l| lane(l).y));
            let mut min = [f64::INFINITY; LANES];
            let mut sum = [0.0; LANES];
            let mut result: [Option<Value>; LANES] = [None; LANES];
            let mut open = group.len();
            let quads = self.valid.iter().zip(&self.fixed_part).zip(&self.shortest_squared).enumerate();
            for (i, ((&valid, part), &shortest)) in quads {
                let lanes = part.lanes(&x, &y);
                for l in 0..group.len() {
                    if result[l].is_some() {
                        continue;
                    }
                    let (next_squared, prev_squared, fast) = (lanes.0[l], lanes.1[l], lanes.2[l]);
                    if next_squared < shortest || prev_squared < shortest {
                        (result[l], open) = (Some(REJECTED), open - 1);
                        continue;
                    }
                    // As `FixedPart::value_from`; NaN fails the test too.
                    let q = if part.usable && fast >= FAST_FLOOR {
                        fast
                    } else {
                        scaled_jacobian(&self.moved(i, group[l]))
                    };
                    if valid && q <= 0.0 {
                        (result[l], open) = (Some(REJECTED), open - 1);
                        continue;
                    }
                    min[l] = min[l].min(q);
                    sum[l] += q;
                    if min[l] < bar {
                        (result[l], open) = (Some(Value { min: min[l], avg: f64::NEG_INFINITY }), open - 1);
                    }
                }
                if open == 0 {
                    break;
                }
            }
            for (l, &p) in group.iter().enumerate() {
                out.push(result[l].unwrap_or_else(|| {
                    if !p.is_finite() || min[l].is_nan() {
                        REJECTED
                    } else {
                        Value { min: min[l], avg: sum[l] / self.quads.len().max(1) as f64 }
                    }
                }));
            }
        }
    }

    /// Every corner's scaled Jacobian at `at` and its gradient with respect to `at` (a
    /// triangle's three corners scaled by 2/sqrt(3), as Verdict's triangle measure).
    pub(super) fn corner_functions(&self, at: DVec2, out: &mut Vec<(f64, DVec2)>) {
        out.clear();
        for (f, &(_, k)) in self.quads.iter().enumerate() {
            let c = self.moved(f, at);
            let (n, scale) = if self.triangle[f] { (3, 2.0 / 3.0_f64.sqrt()) } else { (4, 1.0) };
            for i in 0..n {
                let (prev, p, next) = (c[(i + n - 1) % n], c[i], c[(i + 1) % n]);
                let (u, w) = (next - p, prev - p);
                let (lu, lw) = (u.length_squared(), w.length_squared());
                if lu == 0.0 || lw == 0.0 {
                    out.push((0.0, DVec2::ZERO));
                    continue;
                }
                let norm = (lu * lw).sqrt();
                let value = u.perp_dot(w) / norm;
                let cos = u.dot(w) / norm;
                // J = sin(angle from u to w): d/dw = cos perp(w)/|w|^2, d/du = -cos perp(u)/|u|^2.
                let d_prev = cos * w.perp() / lw;
                let d_next = -cos * u.perp() / lu;
                let grad = if i == k {
                    -(d_prev + d_next)
                } else if (i + n - 1) % n == k {
                    d_prev
                } else if (i + 1) % n == k {
                    d_next
                } else {
                    DVec2::ZERO
                };
                out.push((scale * value, scale * grad));
            }
        }
    }
}

/// The two edges at a quad's moving corner placed at `x`: to the next corner and to the
/// previous one, and their squared lengths (shared by the edge floor and the quality).
struct MovingEdges {
    to_next: DVec2,
    to_prev: DVec2,
    next_squared: f64,
    prev_squared: f64,
}

impl MovingEdges {
    #[inline]
    fn new(next: DVec2, prev: DVec2, x: DVec2) -> MovingEdges {
        let (to_next, to_prev) = (next - x, prev - x);
        MovingEdges {
            to_next,
            to_prev,
            next_squared: to_next.length_squared(),
            prev_squared: to_prev.length_squared(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_star_value_matches_the_scaled_jacobian() {
        // Random convex-ish quads and moving corners: the fast evaluation agrees with
        // scaled_jacobian to roundoff, or defers to it.
        let mut rnd = crate::test_rng::xorshift(0x2545_f491_4f6c_dd1du64);
        let mut next = || 0.5 * rnd();
        let mut fast = 0;
        for _ in 0..20_000 {
            let base =
                [DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(0.0, 1.0)];
            let c = base.map(|p| p + 0.6 * DVec2::new(next(), next()));
            let k = ((next() + 0.5) * 4.0) as usize % 4;
            let x = base[k] + 0.8 * DVec2::new(next(), next());
            let part = FixedPart::new(&c, k, false);
            let mut moved = c;
            moved[k] = x;
            let exact = scaled_jacobian(&moved);
            if let Some(v) = part.value(x) {
                fast += 1;
                assert!((v - exact).abs() < 1e-14, "{v} vs {exact}");
            }
        }
        assert!(fast > 5_000, "the fast path was taken only {fast} times");
    }

    #[test]
    fn batched_star_values_are_those_of_value_above_bit_for_bit() {
        // Stars of 1 to 7 random quads around a corner (some near degenerate, inverted or
        // below an edge floor), positions in groups of every length, bars that stop the
        // evaluation early or never.
        let mut rnd = crate::test_rng::xorshift(0x5851_f42d_4c95_7f2du64);
        let (mut at, mut out) = (Vec::new(), Vec::new());
        let (mut early, mut rejected, mut complete) = (0, 0, 0);
        for round in 0..3_000 {
            let centre = DVec2::new(rnd(), rnd());
            let count = 1 + round % 7;
            let quads: Vec<([DVec2; 4], usize)> = (0..count)
                .map(|i| {
                    let k = i % 4;
                    let mut c = [DVec2::ZERO; 4];
                    for (j, p) in c.iter_mut().enumerate() {
                        *p = centre + DVec2::new(rnd(), rnd()) * if j == (k + 2) % 4 { 2.0 } else { 1.0 };
                    }
                    if round % 11 == 0 {
                        c[(k + 1) % 4] = c[(k + 2) % 4]; // a degenerate fixed edge
                    }
                    c[k] = centre;
                    (c, k)
                })
                .collect();
            let star = Star {
                triangle: vec![false; quads.len()],
                valid: quads.iter().map(|(c, _)| scaled_jacobian(c) > 0.0).collect(),
                fixed_part: quads.iter().map(|(c, k)| FixedPart::new(c, *k, false)).collect(),
                shortest_squared: (0..count)
                    .map(|i| if i % 3 == 2 { 0.05 * rnd().abs() } else { 0.0 })
                    .collect(),
                quads,
            };
            at.clear();
            at.extend((0..1 + round % 9).map(|_| centre + 0.3 * DVec2::new(rnd(), rnd())));
            if round % 13 == 0 {
                at.push(DVec2::new(f64::NAN, 0.0));
            }
            let bar = [f64::NEG_INFINITY, -0.5, 0.0, 0.2, 0.6, 1.0][round % 6];
            star.values_above(&at, bar, &mut out);
            assert_eq!(out.len(), at.len());
            for (&p, got) in at.iter().zip(&out) {
                let want = star.value_above(p, bar);
                assert_eq!(got.min.to_bits(), want.min.to_bits(), "min at {p} bar {bar}");
                assert_eq!(got.avg.to_bits(), want.avg.to_bits(), "avg at {p} bar {bar}");
                match (want.min == f64::NEG_INFINITY, want.avg == f64::NEG_INFINITY) {
                    (true, _) => rejected += 1,
                    (false, true) => early += 1,
                    _ => complete += 1,
                }
            }
        }
        assert!(early > 1_000 && rejected > 300 && complete > 1_000, "{early} {rejected} {complete}");
    }
}

//! Boundary optimization (Section 3.3) on the ORIGINAL boundary.
//!
//! A movable boundary vertex v has two incident quads, so its half embedded polygon (ring
//! n0, n1, n2: next along the loop, the interior neighbour, previous along the loop) has one
//! full interior angle, at n1. Both approaches aim at making v - n1 bisect that angle:
//!
//! - Slide (Approach 2). Eq. 9 as printed oscillates (vertices jump 0.2-0.7 edge lengths per
//!   sweep) and, applied along the current edges, shrinks curved boundaries. Instead v is a
//!   point of the original boundary polyline, parametrized by arclength s, and we solve
//!   "v(s) - n1 lies on the bisector" between the arclengths of its two boundary neighbours,
//!   where the bisecting rotation changes sign: in closed form, as the crossing of the
//!   bisector ray from n1 with the polyline (the rotation's sign is that of a cross product
//!   linear along each segment), with a bracketed root-find where the crossing is not clean.
//!   The root-find, an atan2 per iterate and a segment search per point, was half of a fast
//!   run's time on data/mazewheel.vtk (3.8 ms; 2.1 ms with the crossing).
//! - Snap (Approach 1). v is rotated about n1 onto the bisector (Eq. 5), then projected back
//!   onto the original polyline, but only onto the stretch between its two boundary
//!   neighbours: snapping to the globally nearest boundary point reproduces the paper's
//!   Figure 4 failure (vertices snapped across a hole).
//!
//! Positions of moving boundary vertices are always evaluated from their arclength on the
//! original polyline, so they stay on it up to roundoff.

use super::embedded_polygon::{bisect, bisecting_rotation, bisector_direction};
use super::options::BoundaryMode;
use crate::features::Features;
use crate::topology::Topology;
use glam::DVec2;
use std::cell::Cell;

/// Keep at least this fraction of the neighbour-to-neighbour arclength between a vertex and
/// each of its boundary neighbours, so boundary edges never collapse.
const MARGIN: f64 = 0.05;

/// The original boundary polylines, parametrized by arclength.
#[derive(Clone, Debug)]
pub struct BoundaryGeometry {
    /// Per loop slot (the concatenated loops of the topology): original position.
    origin: Vec<DVec2>,
    /// Per loop slot: arclength from the loop's first vertex.
    arclength: Vec<f64>,
    /// Loop of each slot.
    slot_loop: Vec<u32>,
    /// Per loop: first slot, and total length.
    loop_start: Vec<u32>,
    loop_length: Vec<f64>,
    /// Per vertex: its slot if it is a movable boundary vertex, else u32::MAX.
    slot_of: Vec<u32>,
    /// Per slot: its vertex.
    slot_vertex: Vec<u32>,
}

impl BoundaryGeometry {
    /// Records the boundary loops of `topo` at `points`.
    pub fn new(points: &[DVec2], topo: &Topology, features: &Features) -> BoundaryGeometry {
        let mut g = BoundaryGeometry {
            origin: Vec::new(),
            arclength: Vec::new(),
            slot_loop: Vec::new(),
            loop_start: Vec::new(),
            loop_length: Vec::new(),
            slot_of: vec![u32::MAX; topo.vertex_count()],
            slot_vertex: Vec::new(),
        };
        for (li, lp) in topo.boundary_loops().enumerate() {
            g.loop_start.push(g.origin.len() as u32);
            let mut s = 0.0;
            for (k, &v) in lp.iter().enumerate() {
                let slot = g.origin.len() as u32;
                if k > 0 {
                    s += (points[v as usize] - points[lp[k - 1] as usize]).length();
                }
                g.origin.push(points[v as usize]);
                g.slot_vertex.push(v);
                g.arclength.push(s);
                g.slot_loop.push(li as u32);
                if features.is_movable(v as usize) && features.is_boundary(v as usize) {
                    g.slot_of[v as usize] = slot;
                }
            }
            s += (points[lp[0] as usize] - points[lp[lp.len() - 1] as usize]).length();
            g.loop_length.push(s);
        }
        g.loop_start.push(g.origin.len() as u32);
        g
    }

    /// Initial slot parameters (the original arclengths).
    pub fn initial_params(&self) -> Vec<f64> {
        self.arclength.clone()
    }

    /// Loop of movable boundary vertex `v`.
    pub fn loop_of(&self, v: usize) -> Option<usize> {
        self.slot(v).map(|s| self.slot_loop(s))
    }

    /// Slot of movable boundary vertex `v`.
    pub fn slot(&self, v: usize) -> Option<usize> {
        let s = self.slot_of[v];
        (s != u32::MAX).then_some(s as usize)
    }

    /// Slot range of loop `l`.
    pub(crate) fn loop_slots(&self, l: usize) -> (usize, usize) {
        (self.loop_start[l] as usize, self.loop_start[l + 1] as usize)
    }

    /// Number of loops.
    pub fn loop_count(&self) -> usize {
        self.loop_length.len()
    }

    /// Original length of loop `l`.
    pub fn loop_length(&self, l: usize) -> f64 {
        self.loop_length[l]
    }

    /// Loop of slot `slot`.
    pub fn slot_loop(&self, slot: usize) -> usize {
        self.slot_loop[slot] as usize
    }

    /// Calls `f` with every original vertex of loop `l` whose arclength lies strictly between
    /// the unwrapped arclengths `s0 < s1` (at most one turn).
    fn for_each_vertex_between(&self, l: usize, s0: f64, s1: f64, mut f: impl FnMut(DVec2)) {
        let (a, b) = self.loop_slots(l);
        let len = self.loop_length[l];
        let count = b - a;
        let base = s0 - s0.rem_euclid(len);
        let start = self.arclength[a..b].partition_point(|&c| c <= s0.rem_euclid(len));
        for k in 0..count {
            let i = (start + k) % count;
            let s = base + self.arclength[a + i] + if start + k >= count { len } else { 0.0 };
            if s >= s1 {
                break;
            }
            if s > s0 {
                f(self.origin[a + i]);
            }
        }
    }

    /// Point of loop `l` at arclength `s` (taken modulo the loop length).
    pub fn eval(&self, l: usize, s: f64) -> DVec2 {
        self.point_on(self.segment_at(l, s))
    }

    /// [`BoundaryGeometry::eval`], trying first the segment at index `hint` of the loop
    /// (updated to the one found): the same point, without a search when successive
    /// arclengths fall on one segment (a root finder's iterates, a walk along the loop).
    fn eval_near(&self, l: usize, s: f64, hint: &Cell<usize>) -> DVec2 {
        let mut i = hint.get();
        let point = self.point_on(self.segment_near(l, s, &mut i));
        hint.set(i);
        point
    }

    /// The point a fraction `t` of the way along the segment between two slots' original
    /// positions (as [`BoundaryGeometry::segment_at`] gives them).
    fn point_on(&self, (p0, p1, t): (usize, usize, f64)) -> DVec2 {
        let (p0, p1) = (self.origin[p0], self.origin[p1]);
        if t == 0.0 {
            return p0;
        }
        p0 + (p1 - p0) * t
    }

    /// The segment of loop `l` holding arclength `s` (modulo the loop length): its two end
    /// slots and the fraction `t` in [0, 1] of the way from the first to the second
    /// (0 on a degenerate segment).
    fn segment_at(&self, l: usize, s: f64) -> (usize, usize, f64) {
        let mut no_hint = usize::MAX;
        self.segment_near(l, s, &mut no_hint)
    }

    /// [`BoundaryGeometry::eval`] at every arclength of `s` on loop `l`, into `out`. Nearby
    /// arclengths (a search's samples) mostly fall on the segment of the one before, which is
    /// then checked first instead of searched for: the same points.
    pub fn eval_many(&self, l: usize, s: impl Iterator<Item = f64>, out: &mut Vec<DVec2>) {
        out.clear();
        let mut hint = usize::MAX;
        out.extend(s.map(|s| self.point_on(self.segment_near(l, s, &mut hint))));
    }

    /// [`BoundaryGeometry::segment_at`], trying first the segment at index `hint` of the loop
    /// (updated to the one found).
    fn segment_near(&self, l: usize, s: f64, hint: &mut usize) -> (usize, usize, f64) {
        let (a, b) = self.loop_slots(l);
        let len = self.loop_length[l];
        let s = s.rem_euclid(len);
        let cum = &self.arclength[a..b];
        // Last slot whose arclength is <= s (on sorted arclengths, the hint is that slot
        // exactly when its arclength is <= s and the next one's is > s).
        let fits = |i: usize| i < cum.len() && cum[i] <= s && cum.get(i + 1).is_none_or(|&c| c > s);
        let i = if fits(*hint) { *hint } else { cum.partition_point(|&c| c <= s).saturating_sub(1) };
        *hint = i;
        let (next, end) = if i + 1 < cum.len() { (a + i + 1, cum[i + 1]) } else { (a, len) };
        let seg = end - cum[i];
        let t = if seg > 0.0 { ((s - cum[i]) / seg).clamp(0.0, 1.0) } else { 0.0 };
        (a + i, next, t)
    }

    /// Where movable boundary vertex `v` (at slot parameters `params`) lies on the boundary,
    /// as the two vertices of its segment and the fraction of the way from the first to the
    /// second, so that it can be evaluated on the same polyline in other coordinates.
    pub fn on_polyline(&self, v: usize, params: &[f64]) -> Option<(usize, usize, f64)> {
        let slot = self.slot(v)?;
        let (a, b, t) = self.segment_at(self.slot_loop(slot), params[slot]);
        Some((self.slot_vertex[a] as usize, self.slot_vertex[b] as usize, t))
    }

    /// The segments of loop `l` from the one holding the unwrapped arclength `lo` on, once
    /// round the loop (and the first one again), with their unwrapped arclengths.
    fn segments_from(&self, l: usize, lo: f64) -> impl Iterator<Item = Segment> + '_ {
        let (a, b) = self.loop_slots(l);
        let len = self.loop_length[l];
        let count = b - a;
        let start = self.arclength[a..b].partition_point(|&c| c <= lo.rem_euclid(len)).saturating_sub(1);
        let first_base = lo - lo.rem_euclid(len); // unwrapped arclength of the loop's start
        (0..=count).map(move |k| {
            let i = (start + k) % count;
            // The loop's start is passed once the walk wraps to slot 0.
            let base = if start + k >= count { first_base + len } else { first_base };
            let s0 = base + self.arclength[a + i];
            let s1 = base + if i + 1 < count { self.arclength[a + i + 1] } else { len };
            Segment { s0, s1, p0: self.origin[a + i], p1: self.origin[a + (i + 1) % count] }
        })
    }

    /// Arclength of the point nearest `q` on loop `l` within the unwrapped range [lo, hi].
    fn project(&self, l: usize, q: DVec2, lo: f64, hi: f64) -> f64 {
        let mut best = (f64::INFINITY, lo);
        let hint = Cell::new(usize::MAX);
        for Segment { s0, s1, p0, p1 } in self.segments_from(l, lo).take_while(|g| g.s0 <= hi) {
            let d = p1 - p0;
            let t = if d.length_squared() > 0.0 {
                ((q - p0).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let s = (s0 + t * (s1 - s0)).clamp(lo, hi);
            let dist = (self.eval_near(l, s, &hint) - q).length_squared();
            if dist < best.0 {
                best = (dist, s);
            }
        }
        best.1
    }

    /// The arclength in the unwrapped range [lo, hi] of loop `l` where the ray from `origin`
    /// along `direction` crosses the polyline from its left (the cross product of the
    /// point's offset from `origin` with `direction` positive at lo, negative at hi):
    /// `None` unless it is positive at lo and negative at hi and a crossing lies ahead of
    /// `origin`. The cross product is linear along each segment, so each crossing is exact
    /// up to rounding.
    fn ray_crossing(&self, l: usize, origin: DVec2, direction: DVec2, lo: f64, hi: f64) -> Option<f64> {
        let side = |s: f64| (self.eval(l, s) - origin).perp_dot(direction);
        if !(side(lo) > 0.0 && side(hi) < 0.0) {
            return None;
        }
        for Segment { s0, s1, p0, p1 } in self.segments_from(l, lo).take_while(|g| g.s0 < hi) {
            let (g0, g1) = ((p0 - origin).perp_dot(direction), (p1 - origin).perp_dot(direction));
            if g0 > 0.0 && g1 <= 0.0 && s1 > s0 {
                let t = g0 / (g0 - g1);
                let s = s0 + t * (s1 - s0);
                let ahead = (p0 + (p1 - p0) * t - origin).dot(direction) > 0.0;
                if ahead && s > lo && s < hi {
                    return Some(s);
                }
            }
        }
        None
    }

    /// How far the chord of loop `l` from arclength `s0` to `s1` (unwrapped, s0 <= s1) is
    /// from the stretch of the original polyline it replaces: the original vertices in
    /// between against the chord, and sample points of the chord against that stretch.
    pub fn chord_deviation(&self, l: usize, s0: f64, s1: f64) -> ChordDeviation {
        let (a, b) = (self.eval(l, s0), self.eval(l, s1));
        // The original polyline between s0 and s1: its vertices strictly inside, plus the ends.
        let mut stretch: [DVec2; 34] = [DVec2::ZERO; 34];
        let mut count = 0;
        stretch[count] = a;
        count += 1;
        let mut overflow = false;
        self.for_each_vertex_between(l, s0, s1, |p| {
            if count < stretch.len() - 1 {
                stretch[count] = p;
                count += 1;
            } else {
                overflow = true;
            }
        });
        stretch[count] = b;
        count += 1;
        let stretch = &stretch[..count];
        let original_to_new = stretch.iter().map(|&p| point_segment_distance(p, a, b)).fold(0.0, f64::max);
        let mut new_to_original: f64 = 0.0;
        if stretch.len() > 2 || overflow {
            for k in 1..CHORD_SAMPLES {
                let q = a + (b - a) * (k as f64 / CHORD_SAMPLES as f64);
                let d = stretch
                    .windows(2)
                    .map(|w| point_segment_distance(q, w[0], w[1]))
                    .fold(f64::INFINITY, f64::min);
                new_to_original = new_to_original.max(d);
            }
        }
        ChordDeviation { new_to_original, original_to_new }
    }
}

/// Sample points per chord for the new -> original direction of
/// [`BoundaryGeometry::chord_deviation`].
const CHORD_SAMPLES: usize = 8;

/// How far a new boundary edge (a chord between two consecutive boundary vertices) is from
/// the stretch of the original polyline it replaces, one way and the other; both are upper
/// bounds of the one-sided Hausdorff distances.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChordDeviation {
    /// The largest distance of the chord's sample points from the original stretch.
    pub new_to_original: f64,
    /// The largest distance of the original stretch's vertices (its ends included) from the
    /// chord.
    pub original_to_new: f64,
}

impl ChordDeviation {
    /// The larger of the two directions: the chord's deviation for a shape tolerance.
    pub fn largest(self) -> f64 {
        self.new_to_original.max(self.original_to_new)
    }
}

/// Distance from `p` to segment `a`-`b`.
fn point_segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let d = b - a;
    let t =
        if d.length_squared() > 0.0 { ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
    (a + d * t - p).length()
}

/// A root of `f` in [a, b] given f(a) > 0 > f(b), by the Illinois variant of regula falsi:
/// the bracket always holds a sign change, and it converges superlinearly where plain
/// bisection needs about 45 halvings for the same tolerance.
fn bracketed_root(f: impl Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    let (mut x0, mut x1) = (a, b);
    let (mut f0, mut f1) = (f(a), f(b));
    if !(f0 > 0.0 && f1 < 0.0) {
        // No sign change (degenerate angle): fall back to the midpoint.
        return 0.5 * (a + b);
    }
    let mut side = 0i8;
    for _ in 0..100 {
        if x1 - x0 <= tol {
            break;
        }
        let mut x = (x0 * f1 - x1 * f0) / (f1 - f0);
        if !(x > x0 && x < x1) {
            x = 0.5 * (x0 + x1);
        }
        let fx = f(x);
        if fx == 0.0 {
            return x;
        }
        if fx > 0.0 {
            (x0, f0) = (x, fx);
            if side == 1 {
                f1 *= 0.5;
            }
            side = 1;
        } else {
            (x1, f1) = (x, fx);
            if side == -1 {
                f0 *= 0.5;
            }
            side = -1;
        }
    }
    0.5 * (x0 + x1)
}

/// One segment of a boundary loop, with the unwrapped arclengths of its ends.
struct Segment {
    s0: f64,
    s1: f64,
    p0: DVec2,
    p1: DVec2,
}

/// A boundary vertex's candidate move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryMove {
    /// Where the vertex goes (on the original boundary polyline).
    pub position: DVec2,
    /// Its arclength parameter there, along its loop.
    pub param: f64,
    /// Its torsion energy (1/2 theta^2 of its one interior angle) at the old positions.
    pub energy: f64,
}

impl BoundaryMove {
    fn new(position: DVec2, param: f64, energy: f64) -> BoundaryMove {
        BoundaryMove { position, param, energy }
    }
}

/// One boundary update of movable boundary vertex `v` by approach `mode` (slide or snap; fixed
/// and auto leave it in place).
#[allow(clippy::too_many_arguments)]
pub fn update(
    points: &[DVec2],
    topo: &Topology,
    geometry: &BoundaryGeometry,
    params: &[f64],
    v: usize,
    mode: BoundaryMode,
    lambda: f64,
    max_deviation: Option<f64>,
) -> BoundaryMove {
    let p = points[v];
    let Some(slot) = geometry.slot(v) else { return BoundaryMove::new(p, 0.0, 0.0) };
    let s = params[slot];
    let ring = topo.ring(v);
    if ring.len() != 3 {
        return BoundaryMove::new(p, s, 0.0);
    }
    let (n0, n1, n2) = (points[ring[0] as usize], points[ring[1] as usize], points[ring[2] as usize]);
    let Some((theta, rotated)) = bisect(p, n1, n0, n2) else { return BoundaryMove::new(p, s, 0.0) };
    let energy = 0.5 * theta * theta;

    // Unwrapped arclength range between the boundary neighbours (previous slot .. next slot).
    let l = geometry.slot_loop[slot] as usize;
    let (a, b) = geometry.loop_slots(l);
    let count = b - a;
    let len = geometry.loop_length[l];
    if len <= 0.0 || !len.is_finite() {
        // A loop of zero length (one vertex, or all vertices at one point: the unwrapping
        // below would never end) or of overflowing length (its arclengths are meaningless).
        return BoundaryMove::new(p, s, energy);
    }
    let k = slot - a;
    let prev_slot = a + (k + count - 1) % count;
    let next_slot = a + (k + 1) % count;
    let s_prev = params[prev_slot];
    let mut s_next = params[next_slot];
    while s_next <= s_prev {
        s_next += len;
    }
    let mut s_cur = s;
    while s_cur < s_prev {
        s_cur += len;
    }
    let margin = MARGIN * (s_next - s_prev);
    let (lo, hi) = (s_prev + margin, s_next - margin);
    if lo >= hi || lo.is_nan() || hi.is_nan() {
        // NaN on either side would make `clamp` below panic.
        return BoundaryMove::new(p, s, energy);
    }

    let target = match mode {
        BoundaryMode::Fixed | BoundaryMode::Auto => return BoundaryMove::new(p, s, energy),
        BoundaryMode::Slide => {
            // f(s_prev) > 0 > f(s_next): at s_prev v sits on n2 (the previous boundary vertex)
            // and must turn counter-clockwise onto the bisector, at s_next it sits on n0 and
            // must turn clockwise. Bisection finds the sign change.
            // Where the bisector ray from n1 crosses the polyline: in closed form, segment by
            // segment (the rotation's sign is that of a cross product linear along a
            // segment); the root finder only where the crossing is not a clean one.
            let crossing = bisector_direction(n1, n0, n2)
                .and_then(|bis| geometry.ray_crossing(l, n1, bis, s_prev, s_next));
            crossing.unwrap_or_else(|| {
                let hint = Cell::new(usize::MAX);
                let f =
                    |t: f64| bisecting_rotation(geometry.eval_near(l, t, &hint), n1, n0, n2).unwrap_or(0.0);
                bracketed_root(f, s_prev, s_next, 1e-13 * len)
            })
        }
        BoundaryMode::Snap => geometry.project(l, rotated, lo, hi),
    };
    if target.is_nan() {
        return BoundaryMove::new(p, s, energy);
    }
    let target = target.clamp(lo, hi);
    let mut s_new = (s_cur + lambda * (target - s_cur)).clamp(lo, hi);
    if let Some(tol) = max_deviation {
        // Honour the shape tolerance: both new edges must stay within tol x their length of
        // the original stretch they replace; otherwise shorten the step.
        let within = |t: f64| {
            [(s_prev, t), (t, s_next)].iter().all(|&(a, b)| {
                geometry.chord_deviation(l, a, b).largest()
                    <= tol * (geometry.eval(l, b) - geometry.eval(l, a)).length()
            })
        };
        let mut step = s_new - s_cur;
        let mut accepted = false;
        for _ in 0..8 {
            if within(s_cur + step) {
                accepted = true;
                break;
            }
            step *= 0.5;
        }
        s_new = if accepted { s_cur + step } else { s_cur };
    }
    let s_new = s_new.rem_euclid(len);
    BoundaryMove::new(geometry.eval(l, s_new), s_new, energy)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Mesh;

    #[test]
    fn point_segment_distances() {
        let (a, b) = (DVec2::ZERO, DVec2::new(2.0, 0.0));
        assert_eq!(point_segment_distance(DVec2::new(1.0, 0.5), a, b), 0.5);
        assert_eq!(point_segment_distance(DVec2::new(3.0, 0.0), a, b), 1.0);
    }

    #[test]
    fn bracketed_root_finds_the_sign_change() {
        let r = bracketed_root(|x| 2.0 - x * x, 0.0, 3.0, 1e-14);
        assert!((r - 2f64.sqrt()).abs() < 1e-12, "{r}");
        // A jump (as the wrapped angle has) is still bracketed.
        let r = bracketed_root(|x| if x < 1.25 { 1.0 } else { -1.0 }, 0.0, 2.0, 1e-12);
        assert!((r - 1.25).abs() < 1e-11, "{r}");
    }

    #[test]
    fn the_ray_crossing_is_the_root_the_root_finder_finds() {
        // A 6x4 grid with its boundary jittered: one loop of 20 vertices, no two segments in line.
        let grid = crate::test_meshes::grid(6, 4);
        let mut rnd = crate::test_rng::xorshift(0x2545_f491_4f6c_dd1d);
        let points: Vec<DVec2> = grid
            .points()
            .iter()
            .map(|&p| {
                let inside = p.x > 0.0 && p.y > 0.0 && p.x < 6.0 && p.y < 4.0;
                if inside { p } else { p + 0.2 * DVec2::new(rnd(), rnd()) }
            })
            .collect();
        let mesh = Mesh::new(points, grid.quads().to_vec(), None).unwrap();
        let topo = Topology::new(&mesh);
        let features = Features::new(&mesh, &topo, 180.0, true);
        let geometry = BoundaryGeometry::new(mesh.points(), &topo, &features);
        let len = geometry.loop_length(0);
        let (mut found, mut refused) = (0, 0);
        for _ in 0..5_000 {
            let origin = DVec2::new(3.0 + 2.5 * rnd(), 2.0 + 1.5 * rnd());
            let direction = DVec2::from_angle(std::f64::consts::PI * rnd());
            let lo = 2.0 * len * rnd().abs();
            let hi = lo + len * (0.05 + 0.3 * rnd().abs());
            let rotation = |s: f64| {
                let a = geometry.eval(0, s) - origin;
                a.perp_dot(direction).atan2(a.dot(direction))
            };
            let Some(s) = geometry.ray_crossing(0, origin, direction, lo, hi) else {
                // Refused only where the root finder's bracket does not hold.
                let (a, b) = (rotation(lo), rotation(hi));
                let crossing_ahead = a > 0.0 && b < 0.0 && a < 1.5 && b > -1.5;
                refused += 1;
                assert!(!crossing_ahead || (a - b).abs() > 1.0, "refused a clean crossing in [{lo}, {hi}]");
                continue;
            };
            found += 1;
            assert!(s > lo && s < hi);
            let a = geometry.eval(0, s) - origin;
            assert!(a.dot(direction) > 0.0, "the crossing is behind the origin");
            assert!(
                a.perp_dot(direction).abs() <= 1e-12 * a.length(),
                "{} off the ray",
                a.perp_dot(direction)
            );
            // Where the rotation changes sign only once, the root finder finds the same point.
            let samples: Vec<f64> = (0..=64).map(|i| rotation(lo + (hi - lo) * i as f64 / 64.0)).collect();
            if samples.windows(2).filter(|w| (w[0] > 0.0) != (w[1] > 0.0)).count() == 1 {
                let root = bracketed_root(rotation, lo, hi, 1e-13 * len);
                assert!((root - s).abs() <= 1e-9 * len, "crossing {s}, root {root}");
            }
        }
        assert!(found > 500 && refused > 500, "{found} crossings, {refused} refused: the test sees both");
    }

    #[test]
    fn eval_many_gives_the_points_of_eval() {
        // A 5x3 grid: one loop of 16 boundary vertices (the corners included).
        let mesh = crate::test_meshes::grid(5, 3);
        let topo = Topology::new(&mesh);
        let features = Features::new(&mesh, &topo, 30.0, true);
        let geometry = BoundaryGeometry::new(mesh.points(), &topo, &features);
        let len = geometry.loop_length(0);
        let mut rnd = crate::test_rng::xorshift(0x9e37_79b9_7f4a_7c15);
        let mut out = Vec::new();
        for _ in 0..2_000 {
            // Increasing runs (a search's samples), across the loop's start and beyond it.
            let from = 3.0 * len * rnd();
            let step = len * 0.2 * rnd().abs();
            let samples: Vec<f64> = (0..16).map(|i| from + step * i as f64).collect();
            geometry.eval_many(0, samples.iter().copied(), &mut out);
            for (&s, p) in samples.iter().zip(&out) {
                let e = geometry.eval(0, s);
                assert_eq!((p.x.to_bits(), p.y.to_bits()), (e.x.to_bits(), e.y.to_bits()), "at {s}");
            }
        }
        // Exactly on the vertices, where the hint must move on.
        let at_vertices: Vec<f64> = geometry.arclength[..16].to_vec();
        geometry.eval_many(0, at_vertices.iter().copied(), &mut out);
        for (&s, p) in at_vertices.iter().zip(&out) {
            assert_eq!(*p, geometry.eval(0, s));
        }
    }
}

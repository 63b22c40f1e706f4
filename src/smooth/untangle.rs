//! Untangling: remove inverted quads by moving movable interior vertices, before smoothing.
//!
//! Each corner value of a quad (the cross product of its two edges at that corner, twice a
//! signed corner area) is *linear* in the position of any one vertex. So for one vertex v,
//! "maximize the smallest corner value of the star" is a linear program in (x, y, t), as in
//! Freitag and Plassmann's local untangling: maximize t subject to g_k . v + c_k >= t for
//! every corner that depends on v, and v inside the bounding box of its neighbours. The
//! program has three variables and three constraints per incident quad; it is set up at unit
//! size in the frame of the vertex's search box and solved by Seidel's randomized incremental
//! algorithm, in work linear in the vertex's quad count whatever its fan or scale. Sweeps run
//! colour class by colour class (vertices of one class share no quad), so every accepted move
//! improves its star exactly, and the caller is asked regularly whether to go on.

use crate::face;
use crate::features::Features;
use crate::quality::{corners, scaled_jacobian};
use crate::topology::{Topology, VertexKind};
use glam::DVec2;
use rayon::prelude::*;
use std::time::{Duration, Instant};

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

/// A similarity u = (p - origin) / scale: a vertex's problem is set up in the frame of its
/// search box, where cross products of local vectors lose no digits to large coordinates.
#[derive(Clone, Copy, Debug)]
struct Frame {
    origin: DVec2,
    scale: f64,
}

impl Frame {
    fn local(&self, p: DVec2) -> DVec2 {
        (p - self.origin) / self.scale
    }
    fn global(&self, u: DVec2) -> DVec2 {
        self.origin + u * self.scale
    }
}

/// The corner values of the star of `v` that depend on v's position, as linear functions of
/// v's position in `frame`.
fn star_corners(
    points: &[DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    v: usize,
    frame: Frame,
    out: &mut Vec<Linear>,
) {
    star_face_corners(points, topo.vertex_quads(v).iter().map(|&qi| &quads[qi as usize]), v, frame, out);
}

/// [`star_corners`] of the faces `star` around `v`, given as faces rather than looked up.
fn star_face_corners<'a>(
    points: &[DVec2],
    star: impl Iterator<Item = &'a [u32; 4]>,
    v: usize,
    frame: Frame,
    out: &mut Vec<Linear>,
) {
    out.clear();
    for q in star {
        let (next, diag, prev) = face::after(q, face::position(q, v as u32).unwrap_or(0));
        let a = frame.local(points[next as usize]);
        let b = frame.local(points[prev as usize]);
        // Corner at v: cross(a - v, b - v) = cross(a, b) + v.x (a.y - b.y) + v.y (b.x - a.x).
        out.push(Linear { g: DVec2::new(a.y - b.y, b.x - a.x), c: a.perp_dot(b) });
        // A triangle's three corners have the same cross product (twice its area): one row.
        if diag == face::NO_VERTEX {
            continue;
        }
        let d = frame.local(points[diag as usize]);
        // Corner at a (prev v, next d): cross(d - a, v - a).
        out.push(Linear::cross_from(d - a, a));
        // Corner at b (prev d, next v): cross(v - b, d - b) = -cross(d - b, v - b).
        out.push(Linear::cross_from(d - b, b).negated());
    }
}

/// Tolerance of the normalized program (box of half-size at most 1 centred at the origin,
/// values of at most 1 on it): a constraint within this much of holding is taken as holding.
const TOL: f64 = 1e-12;

/// Work (constraint evaluations) allowed per constraint before the solver gives up. The
/// randomized incremental solver needs about ten per constraint on average, so the budget is
/// practically never reached; it makes the worst case linear too (giving up means no move).
const WORK_PER_ROW: usize = 200;

/// Evaluations between two calls of the solver's `go_on` (well under a millisecond).
const WORK_PER_CHECK: usize = 1 << 16;

/// One constraint t <= a . u + b of the normalized program.
#[derive(Clone, Copy, Debug)]
struct Row {
    a: DVec2,
    b: f64,
}

/// [`max_min_interruptible`] never interrupted.
#[cfg(test)]
fn max_min(f: &[Linear], lo: DVec2, hi: DVec2) -> Option<(DVec2, f64)> {
    max_min_interruptible(f, lo, hi, &mut || true)
}

/// Position maximizing the smallest of `f` inside the box [lo, hi], and that smallest value
/// (evaluated at the position returned).
///
/// This is the linear program "maximize t subject to t <= f_k(v), v in the box" in (x, y, t),
/// solved by Seidel's randomized incremental algorithm: the constraints are added in a fixed
/// pseudo-random order; while the optimum so far satisfies the next one it stays, otherwise
/// the new optimum lies on that constraint's plane, which is a 2D program over the earlier
/// constraints, solved the same way down to 1D. Expected work is about ten evaluations per
/// constraint, bounded by [`WORK_PER_ROW`]. The program is first moved to the box's centre
/// and scaled to unit size, values to unit size too, so the tolerances are relative and the
/// result does not depend on the coordinates' scale.
///
/// `go_on` is called every [`WORK_PER_CHECK`] evaluations; the solver gives up (`None`) once
/// it returns false.
fn max_min_interruptible(
    f: &[Linear],
    lo: DVec2,
    hi: DVec2,
    go_on: &mut dyn FnMut() -> bool,
) -> Option<(DVec2, f64)> {
    if f.is_empty() || !(lo.is_finite() && hi.is_finite()) || lo.cmpgt(hi).any() {
        return None;
    }
    let value_at = |v: DVec2| f.iter().map(|l| l.at(v)).fold(f64::INFINITY, f64::min);
    let finite = |(v, t): (DVec2, f64)| (v.is_finite() && t.is_finite()).then_some((v, t));
    // Halved before subtracting, so a box spanning most of the f64 range does not overflow.
    let (centre, half) = (lo * 0.5 + hi * 0.5, hi * 0.5 - lo * 0.5);
    let size = half.max_element();
    if size == 0.0 {
        return finite((centre, value_at(centre)));
    }
    // v = centre + size * u with u in [-w, w], max(w) = 1; rows scaled so values are <= 1.
    let w = half / size;
    let mut rows: Vec<Row> = f.iter().map(|l| Row { a: l.g * size, b: l.at(centre) }).collect();
    let peak = |r: &Row| r.b.abs() + r.a.abs().dot(w);
    let unit = rows.iter().map(peak).fold(0.0, f64::max);
    if !unit.is_finite() {
        return None;
    }
    if unit == 0.0 {
        return finite((centre, value_at(centre)));
    }
    for r in &mut rows {
        *r = Row { a: r.a / unit, b: r.b / unit };
    }
    // No position does better than the smallest of the rows' maxima over the box.
    let t_max = rows.iter().map(|r| r.b + r.a.abs().dot(w)).fold(f64::INFINITY, f64::min);
    let mut program =
        Program { order: shuffled(rows.len()), rows, w, t_max, work: WORK_PER_ROW * (f.len() + 4), go_on };
    let u = program.solve()?.clamp(-w, w);
    let v = (centre + size * u).clamp(lo, hi);
    finite((v, value_at(v)))
}

/// 0..n in a pseudo-random order that is the same on every run (SplitMix64, Fisher-Yates),
/// so results never depend on timing or thread count.
fn shuffled(n: usize) -> Vec<u32> {
    let mut order: Vec<u32> = (0..n as u32).collect();
    let mut state = 0x9E37_79B9_7F4A_7C15u64 ^ n as u64;
    for i in (1..n).rev() {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        order.swap(i, (z % (i as u64 + 1)) as usize);
    }
    order
}

/// The normalized program of `max_min`: maximize t subject to t <= a . u + b for every row,
/// t <= t_max and |u| <= w componentwise. Ties are broken towards larger x, then larger y.
struct Program<'a> {
    rows: Vec<Row>,
    order: Vec<u32>,
    w: DVec2,
    t_max: f64,
    /// Constraint evaluations left.
    work: usize,
    /// Asked every [`WORK_PER_CHECK`] evaluations whether to go on.
    go_on: &'a mut dyn FnMut() -> bool,
}

impl Program<'_> {
    fn spend(&mut self, amount: usize) -> Option<()> {
        let left = self.work.checked_sub(amount)?;
        if left / WORK_PER_CHECK != self.work / WORK_PER_CHECK && !(self.go_on)() {
            return None;
        }
        self.work = left;
        Some(())
    }

    /// The optimal u, or `None` if the work budget ran out.
    fn solve(&mut self) -> Option<DVec2> {
        // Optimum of the box and t <= t_max alone.
        let (mut u, mut t) = (self.w, self.t_max);
        for i in 0..self.order.len() {
            self.spend(1)?;
            let r = self.rows[self.order[i] as usize];
            if t <= r.a.dot(u) + r.b + TOL {
                continue;
            }
            u = self.on_plane(r, i)?;
            t = r.a.dot(u) + r.b;
        }
        Some(u)
    }

    /// Optimum on the plane t = r.a . u + r.b under the box, t <= t_max and the first `count`
    /// rows of the order: maximize r.a . u over the half-planes of [`Program::half_plane`].
    fn on_plane(&mut self, r: Row, count: usize) -> Option<DVec2> {
        let w = self.w;
        // The box corner furthest along r.a (ties: +x, +y).
        let mut u = DVec2::new(if r.a.x >= 0.0 { w.x } else { -w.x }, if r.a.y >= 0.0 { w.y } else { -w.y });
        for i in 0..=count {
            self.spend(1)?;
            let (n, c) = self.half_plane(r, i);
            if n.dot(u) <= c + TOL {
                continue;
            }
            self.spend(i + 4)?;
            // In exact arithmetic the line is never empty here; rounding on (nearly) parallel
            // planes can make it so, and then the point stays.
            if let Some(p) = self.on_line(r, n, c, i) {
                u = p;
            }
        }
        Some(u)
    }

    /// Half-plane `i` (n . u <= c) of the program on the plane of `r`: 0 is t <= t_max, i > 0
    /// the row order[i - 1].
    fn half_plane(&self, r: Row, i: usize) -> (DVec2, f64) {
        if i == 0 {
            (r.a, self.t_max - r.b)
        } else {
            let q = self.rows[self.order[i - 1] as usize];
            (r.a - q.a, q.b - r.b)
        }
    }

    /// Optimum of the plane program of `r` on the line n . u = c, under the box and the
    /// half-planes 0..count; `None` if the line is degenerate.
    fn on_line(&self, r: Row, n: DVec2, c: f64, count: usize) -> Option<DVec2> {
        let nn = n.length_squared();
        if nn.is_nan() || nn <= 1e-300 {
            return None;
        }
        let d = n.perp() / nn.sqrt();
        let p = n * (c / nn);
        // u = p + s d with s in [lo, hi].
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        let mut clip = |e: DVec2, bound: f64| {
            let rate = e.dot(d);
            let s = (bound - e.dot(p)) / rate;
            if rate > 0.0 {
                hi = hi.min(s);
            } else if rate < 0.0 {
                lo = lo.max(s);
            }
        };
        let w = self.w;
        clip(DVec2::X, w.x);
        clip(-DVec2::X, w.x);
        clip(DVec2::Y, w.y);
        clip(-DVec2::Y, w.y);
        for j in 0..count {
            let (e, bound) = self.half_plane(r, j);
            clip(e, bound);
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return None;
        }
        // Direction of improvement along d: the objective r.a, then +x, then +y.
        let slope = r.a.dot(d);
        let up = if slope.abs() > 1e-12 * r.a.length() {
            slope > 0.0
        } else if d.x.abs() > 1e-12 {
            d.x > 0.0
        } else {
            d.y > 0.0
        };
        let s = if lo > hi {
            0.5 * (lo + hi)
        } else if up {
            hi
        } else {
            lo
        };
        Some(p + s * d)
    }
}

/// One untangling move of `v`, or `None` if it cannot raise its star's smallest corner value.
pub(crate) fn untangle_vertex(
    points: &[DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    v: usize,
) -> Option<DVec2> {
    untangle_vertex_interruptible(points, quads, topo, v, &mut || true)
}

/// [`untangle_vertex`] on a star given as its faces (`star`, each holding `v`, indices into
/// `points`): for a vertex whose star lives in a chart of its own (a surface's tangent plane).
pub(crate) fn untangle_star(points: &[DVec2], star: &[[u32; 4]], v: usize) -> Option<DVec2> {
    let vertices = star.iter().flat_map(|q| face::vertices(q).iter().copied()).filter(|&u| u as usize != v);
    let mut f = Vec::with_capacity(3 * star.len());
    let frame = search_frame(points, vertices)?;
    star_face_corners(points, star.iter(), v, frame.0, &mut f);
    solve_star(points[v], &f, frame, &mut || true)
}

/// The search box of a vertex's move (the bounding box of its star's other vertices, shrunk by
/// 10% towards its centre so an optimum on the box, when the star cannot be fully untangled
/// from here, never lands exactly on a neighbour's coordinates and degenerates an edge), as
/// the frame of its program and the box's half-size in that frame.
fn search_frame(points: &[DVec2], star: impl Iterator<Item = u32>) -> Option<(Frame, DVec2)> {
    let (mut lo, mut hi) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
    for u in star {
        lo = lo.min(points[u as usize]);
        hi = hi.max(points[u as usize]);
    }
    let (centre, half) = (lo * 0.5 + hi * 0.5, (hi * 0.5 - lo * 0.5) * 0.9);
    let scale = half.max_element();
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    Some((Frame { origin: centre, scale }, half / scale))
}

/// The move maximizing the smallest of the star's corner functions `f` (set up in `frame`)
/// from `p`, if it raises that smallest value.
fn solve_star(
    p: DVec2,
    f: &[Linear],
    (frame, w): (Frame, DVec2),
    go_on: &mut dyn FnMut() -> bool,
) -> Option<DVec2> {
    let p = frame.local(p);
    let current = f.iter().map(|l| l.at(p)).fold(f64::INFINITY, f64::min);
    let (best, value) = max_min_interruptible(f, -w, w, go_on)?;
    let moved = frame.global(best);
    (value > current && moved.is_finite()).then_some(moved)
}

/// [`untangle_vertex`], its solver asking `go_on` regularly whether to go on (`None` once it
/// says no).
fn untangle_vertex_interruptible(
    points: &[DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    v: usize,
    go_on: &mut dyn FnMut() -> bool,
) -> Option<DVec2> {
    let frame = search_frame(points, topo.star_vertices(quads, v))?;
    let mut f = Vec::with_capacity(3 * topo.quad_count(v));
    star_corners(points, quads, topo, v, frame.0, &mut f);
    solve_star(points[v], &f, frame, go_on)
}

/// What [`untangle`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Untangled {
    /// Sweeps done (the last one possibly cut short by a cancel).
    pub sweeps: usize,
    /// Whether `keep_going` returned false.
    pub cancelled: bool,
}

/// Least time between two calls of `keep_going` inside a sweep.
const CHECK_INTERVAL: Duration = Duration::from_millis(20);

/// Incident quads of the vertices solved between two looks at the clock: small enough for a
/// cancel to take effect quickly, large enough to keep every thread busy.
const CHUNK_QUADS: usize = 1 << 14;

/// Sweeps without a new lowest count of inverted quads after which untangling stops: each
/// sweep raises every tangled star's smallest corner, but where the mesh cannot be untangled
/// (a folded surface flattened onto a plane) the count only grows. Measured: on Mesquite's
/// tangled meshes the count falls in the first five sweeps or not at all; on
/// copy-morph-for-ricoh (13,678 quads, a flattened 3D surface) it rose from 5,429 to 6,800
/// over the 200 sweeps of the cap, 1.5 s for nothing.
const STALL_SWEEPS: usize = 20;

/// Untangles in place, sweeping at most `max_sweeps` times, and stopping after
/// [`STALL_SWEEPS`] sweeps without a new lowest count of inverted quads; only movable interior
/// vertices move. `keep_going` is called on the calling thread after every sweep and, inside a sweep,
/// every [`CHECK_INTERVAL`] or so: between chunks of about [`CHUNK_QUADS`] quads, and during
/// the solve of a vertex with more quads than that. Once it returns false untangling stops,
/// keeping the moves done so far (each of which raised its star's smallest corner value).
pub fn untangle(
    points: &mut [DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    features: &Features,
    max_sweeps: usize,
    keep_going: &mut dyn FnMut() -> bool,
) -> Untangled {
    untangle_checking_every(points, quads, topo, features, max_sweeps, keep_going, CHECK_INTERVAL)
}

/// [`untangle`], calling `keep_going` inside a sweep once `interval` has passed.
fn untangle_checking_every(
    points: &mut [DVec2],
    quads: &[[u32; 4]],
    topo: &Topology,
    features: &Features,
    max_sweeps: usize,
    keep_going: &mut dyn FnMut() -> bool,
    interval: Duration,
) -> Untangled {
    let mut moves: Vec<(u32, DVec2)> = Vec::new();
    let mut last_call = Instant::now();
    // Per quad, whether it is inverted (scaled Jacobian <= 0) at the current positions: measured
    // once, then again only for the quads of moved vertices. A vertex's star is tangled when one
    // of its quads is, so most vertices are passed over by a look at their quads' flags.
    let mut inverted_quad: Vec<bool> = {
        let values = crate::quality::quad_values(points, quads);
        values.iter().map(|&value| value <= 0.0).collect()
    };
    let apply = |points: &mut [DVec2], moves: &[(u32, DVec2)], inverted_quad: &mut [bool]| {
        for &(v, p) in moves {
            points[v as usize] = p;
        }
        for &(v, _) in moves {
            for &q in topo.vertex_quads(v as usize) {
                inverted_quad[q as usize] = scaled_jacobian(&corners(points, &quads[q as usize])) <= 0.0;
            }
        }
    };
    let (mut fewest, mut stalled) = (usize::MAX, 0);
    for sweep in 0..max_sweeps {
        let mut moved = false;
        for c in 0..topo.colour_count() {
            let mut rest = topo.colour_class(c);
            moves.clear();
            while !rest.is_empty() {
                let (chunk, tail) = rest.split_at(chunk_len(topo, rest));
                rest = tail;
                // No vertex of a class is in another's star, so the moves of a class can be
                // found in parallel from the same positions and applied afterwards.
                let snapshot: &[DVec2] = points;
                let flags: &[bool] = &inverted_quad;
                // Whether the star of `v` has an inverted quad, from the flags.
                let wanted = |v: u32| {
                    let vu = v as usize;
                    features.is_movable(vu)
                        && topo.kind(vu) == VertexKind::Interior
                        && topo.vertex_quads(vu).iter().any(|&q| flags[q as usize])
                };
                let mut cancelled = false;
                if chunk.len() == 1 && topo.quad_count(chunk[0] as usize) >= CHUNK_QUADS {
                    // One large star: solved on this thread, so the caller can be asked during
                    // the solve.
                    let v = chunk[0];
                    let mut go_on = || {
                        if last_call.elapsed() < interval {
                            return true;
                        }
                        last_call = Instant::now();
                        cancelled = !keep_going();
                        !cancelled
                    };
                    if wanted(v) {
                        let found =
                            untangle_vertex_interruptible(snapshot, quads, topo, v as usize, &mut go_on);
                        moves.extend(found.map(|p| (v, p)));
                    }
                } else {
                    moves.par_extend(
                        chunk.par_iter().filter(|&&v| wanted(v)).filter_map(|&v| {
                            untangle_vertex(snapshot, quads, topo, v as usize).map(|p| (v, p))
                        }),
                    );
                }
                if !cancelled && !rest.is_empty() && last_call.elapsed() >= interval {
                    last_call = Instant::now();
                    cancelled = !keep_going();
                }
                if cancelled {
                    apply(points, &moves, &mut inverted_quad);
                    return Untangled { sweeps: sweep + 1, cancelled: true };
                }
            }
            apply(points, &moves, &mut inverted_quad);
            moved |= !moves.is_empty();
        }
        let inverted = inverted_quad.iter().filter(|&&b| b).count();
        (fewest, stalled) = if inverted < fewest { (inverted, 0) } else { (fewest, stalled + 1) };
        last_call = Instant::now();
        if !keep_going() {
            return Untangled { sweeps: sweep + 1, cancelled: true };
        }
        if !moved || inverted == 0 || stalled >= STALL_SWEEPS {
            return Untangled { sweeps: sweep + 1, cancelled: false };
        }
    }
    Untangled { sweeps: max_sweeps, cancelled: false }
}

/// Length of the prefix of `class` whose stars hold about [`CHUNK_QUADS`] quads (at least one
/// vertex).
fn chunk_len(topo: &Topology, class: &[u32]) -> usize {
    let mut quads = 0;
    for (i, &v) in class.iter().enumerate() {
        quads += topo.quad_count(v as usize);
        if quads >= CHUNK_QUADS {
            return i + 1;
        }
    }
    class.len()
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
        let n = face::corner_count(q);
        let fixed = |k: usize| !features.is_movable(q[k % n] as usize);
        let reason = if (0..n).all(fixed) {
            TangleReason::AllVerticesFixed
        } else if (0..n).any(|k| {
            let (prev, p, next) = (c[(k + n - 1) % n], c[k], c[(k + 1) % n]);
            fixed(k + n - 1) && fixed(k) && fixed(k + 1) && (next - p).perp_dot(prev - p) <= 0.0
        }) {
            TangleReason::ForcedByFixedVertices
        } else if (0..n).any(|k| {
            let v = q[k] as usize;
            let (prev, p, next) = (c[(k + n - 1) % n], c[k], c[(k + 1) % n]);
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
    use std::f64::consts::TAU;

    /// Constraint rows a . (x, y, t) <= b of the program: t - g . v <= c for each f, then the
    /// four sides of the box.
    fn program_rows(f: &[Linear], lo: DVec2, hi: DVec2) -> Vec<([f64; 3], f64)> {
        let mut rows: Vec<([f64; 3], f64)> = f.iter().map(|l| ([-l.g.x, -l.g.y, 1.0], l.c)).collect();
        rows.push(([1.0, 0.0, 0.0], hi.x));
        rows.push(([-1.0, 0.0, 0.0], -lo.x));
        rows.push(([0.0, 1.0, 0.0], hi.y));
        rows.push(([0.0, -1.0, 0.0], -lo.y));
        rows
    }

    /// [`max_min`] by visiting every vertex of the arrangement (O(m^4) for m constraints): the
    /// reference the solver is tested against.
    fn max_min_exhaustive(f: &[Linear], lo: DVec2, hi: DVec2) -> Option<(DVec2, f64)> {
        let rows = program_rows(f, lo, hi);
        let scale = f.iter().map(|l| l.c.abs() + l.g.length() * (hi - lo).length()).fold(1e-300, f64::max);
        let tol = 1e-9 * scale;
        let mut best: Option<(DVec2, f64)> = None;
        let n = rows.len();
        for i in 0..n {
            for j in i + 1..n {
                for k in j + 1..n {
                    let Some(x) =
                        solve3([rows[i].0, rows[j].0, rows[k].0], [rows[i].1, rows[j].1, rows[k].1])
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
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
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

    use crate::test_rng::xorshift;

    const IDENTITY: Frame = Frame { origin: DVec2::ZERO, scale: 1.0 };

    #[test]
    fn linear_corner_values_match_direct_cross_products() {
        let points =
            vec![DVec2::new(0.3, 0.4), DVec2::new(2.0, 0.1), DVec2::new(2.2, 1.9), DVec2::new(-0.1, 2.0)];
        let quads = vec![[0u32, 1, 2, 3]];
        let m = crate::Mesh::new(points.clone(), quads.clone(), None).unwrap();
        let t = Topology::new(&m);
        let mut f = Vec::new();
        star_corners(&points, &quads, &t, 0, IDENTITY, &mut f);
        let v = DVec2::new(0.7, -0.2);
        let (a, d, b) = (points[1], points[2], points[3]);
        let direct = [(a - v).perp_dot(b - v), (d - a).perp_dot(v - a), (v - b).perp_dot(d - b)];
        for (l, e) in f.iter().zip(direct) {
            assert!((l.at(v) - e).abs() < 1e-12, "{} vs {e}", l.at(v));
        }
        // In a frame scaled by s the same corners are the values divided by s^2.
        let frame = Frame { origin: DVec2::new(1.0, -3.0), scale: 4.0 };
        star_corners(&points, &quads, &t, 0, frame, &mut f);
        for (l, e) in f.iter().zip(direct) {
            assert!((l.at(frame.local(v)) * 16.0 - e).abs() < 1e-12, "{} vs {e}", l.at(frame.local(v)));
        }
    }

    /// Smallest corner value (cross product) of the quads at `v`.
    fn star_min_corner(points: &[DVec2], quads: &[[u32; 4]], topo: &Topology, v: usize) -> f64 {
        let mut f = Vec::new();
        star_corners(points, quads, topo, v, IDENTITY, &mut f);
        f.iter().map(|l| l.at(points[v])).fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn a_cancel_inside_a_sweep_keeps_the_moves_of_the_chunks_done() {
        // A tangled grid of 90k quads: each colour class spans several chunks.
        let mesh =
            crate::synthetic::Synthetic { nx: 300, ny: 300, holes: 0, jitter: 0.45, ..Default::default() }
                .generate();
        let topo = Topology::new(&mesh);
        let features = Features::new(&mesh, &topo, 45.0, false);
        let quads = mesh.quads();
        let first_chunk = chunk_len(&topo, topo.colour_class(0));
        assert!(first_chunk < topo.colour_class(0).len());
        // Without a cancel: called after every chunk but the last of each class, and after
        // every sweep.
        let mut points = mesh.points().to_vec();
        let mut calls = 0;
        let done = untangle_checking_every(
            &mut points,
            quads,
            &topo,
            &features,
            1,
            &mut || {
                calls += 1;
                true
            },
            Duration::ZERO,
        );
        let chunks: usize = (0..topo.colour_count())
            .map(|c| {
                let (mut rest, mut count) = (topo.colour_class(c), 0);
                while !rest.is_empty() {
                    rest = &rest[chunk_len(&topo, rest)..];
                    count += 1;
                }
                count - 1
            })
            .sum();
        assert_eq!((done, calls), (Untangled { sweeps: 1, cancelled: false }, chunks + 1));
        // Cancelled at the first call, after the first chunk: only that chunk's vertices
        // moved, each raising its star's smallest corner.
        let mut points = mesh.points().to_vec();
        let done =
            untangle_checking_every(&mut points, quads, &topo, &features, 10, &mut || false, Duration::ZERO);
        assert_eq!(done, Untangled { sweeps: 1, cancelled: true });
        let chunk = &topo.colour_class(0)[..first_chunk];
        let mut moved = 0;
        for v in 0..points.len() {
            if points[v] == mesh.points()[v] {
                continue;
            }
            moved += 1;
            assert!(chunk.contains(&(v as u32)), "vertex {v} moved outside the first chunk");
            let (before, after) =
                (star_min_corner(mesh.points(), quads, &topo, v), star_min_corner(&points, quads, &topo, v));
            assert!(after > before, "vertex {v}: {before} -> {after}");
        }
        assert!(moved > 0);
    }

    #[test]
    fn the_solve_of_a_large_star_can_be_cancelled() {
        // A fan of 30k quads (more than a chunk) around vertex 0, its centre pushed outside.
        let n = 30_000u32;
        let mut points = vec![DVec2::new(2.0, 0.3)];
        for i in 0..n {
            let (a, d) = (TAU * i as f64 / n as f64, TAU * (i as f64 + 0.5) / n as f64);
            points.push(DVec2::new(a.cos(), a.sin()));
            points.push(DVec2::new(d.cos(), d.sin()) * 1.5);
        }
        let quads = (0..n).map(|i| [0, 1 + 2 * i, 2 + 2 * i, 1 + 2 * ((i + 1) % n)]).collect();
        let mesh = crate::Mesh::new(points, quads, None).unwrap();
        let topo = Topology::new(&mesh);
        let features = Features::new(&mesh, &topo, 45.0, false);
        assert!(topo.quad_count(0) > CHUNK_QUADS && features.is_movable(0));
        assert_eq!(topo.colour_class(0), &[0]);
        // Asked regularly and never stopped: untangled in one sweep.
        let mut points = mesh.points().to_vec();
        let mut calls = 0;
        let mut count = || {
            calls += 1;
            true
        };
        let done = untangle_checking_every(
            &mut points,
            mesh.quads(),
            &topo,
            &features,
            5,
            &mut count,
            Duration::ZERO,
        );
        assert_eq!(done, Untangled { sweeps: 1, cancelled: false });
        assert!(calls > 1, "{calls} calls");
        assert!(mesh.quads().iter().all(|q| scaled_jacobian(&corners(&points, q)) > 0.0));
        // The centre is alone in the first colour class, so without a look at the clock inside
        // its solve the first call would come after its move. Stopped there: nothing moved.
        let mut points = mesh.points().to_vec();
        let done = untangle_checking_every(
            &mut points,
            mesh.quads(),
            &topo,
            &features,
            5,
            &mut || false,
            Duration::ZERO,
        );
        assert_eq!(done, Untangled { sweeps: 1, cancelled: true });
        assert_eq!(points, mesh.points());
    }

    #[test]
    fn max_min_of_two_lines_is_their_crossing() {
        // f1 = x, f2 = 1 - x on [0, 1]^2: the best smallest value is 0.5 at x = 0.5.
        let f = [Linear { g: DVec2::X, c: 0.0 }, Linear { g: -DVec2::X, c: 1.0 }];
        let (v, t) = max_min(&f, DVec2::ZERO, DVec2::ONE).unwrap();
        assert!((t - 0.5).abs() < 1e-12 && (v.x - 0.5).abs() < 1e-12);
    }

    #[test]
    fn solver_matches_the_exhaustive_search_on_random_programs() {
        // Deterministic pseudo-random programs like a star's: 4 to 24 corner functions.
        let mut rnd = xorshift(0x2545_F491_4F6C_DD1D);
        for case in 0..2000 {
            let m = 4 + case % 21;
            let f: Vec<Linear> =
                (0..m).map(|_| Linear { g: DVec2::new(rnd(), rnd()) * 3.0, c: rnd() * 2.0 }).collect();
            let (lo, hi) = (DVec2::new(rnd(), rnd()) - 1.5, DVec2::new(rnd(), rnd()) + 1.5);
            let (v, t) = max_min(&f, lo, hi).unwrap();
            let (_, t_ref) = max_min_exhaustive(&f, lo, hi).unwrap();
            assert!((t - t_ref).abs() <= 1e-9 * (1.0 + t_ref.abs()), "case {case}: {t} vs {t_ref}");
            // The point is feasible and attains the value.
            assert!(v.cmpge(lo).all() && v.cmple(hi).all(), "case {case}: {v} outside");
            let at = f.iter().map(|l| l.at(v)).fold(f64::INFINITY, f64::min);
            assert_eq!(at, t, "case {case}");
        }
    }

    #[test]
    fn solver_matches_the_exhaustive_search_on_degenerate_programs() {
        // Repeated and parallel constraints, flat boxes and constant rows: the cases where
        // ties and parallel planes meet.
        let mut rnd = xorshift(0x9E37_79B9_7F4A_7C15);
        for case in 0..500 {
            let m = 3 + case % 10;
            let mut f: Vec<Linear> = (0..m)
                .map(|_| {
                    let g = DVec2::new((rnd() * 2.0).round(), (rnd() * 2.0).round());
                    Linear { g, c: (rnd() * 4.0).round() / 2.0 }
                })
                .collect();
            f.extend_from_within(..m / 2);
            let lo = DVec2::new(-1.0, -1.0);
            let hi = if case % 3 == 0 { DVec2::new(1.0, -1.0) } else { DVec2::ONE };
            let (v, t) = max_min(&f, lo, hi).unwrap();
            let (_, t_ref) = max_min_exhaustive(&f, lo, hi).unwrap();
            assert!((t - t_ref).abs() <= 1e-9 * (1.0 + t_ref.abs()), "case {case}: {t} vs {t_ref}");
            assert!(v.cmpge(lo).all() && v.cmple(hi).all(), "case {case}: {v} outside");
        }
    }

    #[test]
    fn solver_does_not_depend_on_the_scale_or_position_of_the_program() {
        // The same random programs with v = o + s u: the optimum moves with the frame and the
        // value scales with s^2, to within rounding relative to the scale.
        let mut rnd = xorshift(0xD1B5_4A32_D192_ED03);
        for case in 0..300 {
            let m = 4 + case % 40;
            let f: Vec<Linear> = (0..m).map(|_| Linear { g: DVec2::new(rnd(), rnd()), c: rnd() }).collect();
            let (_, t1) = max_min(&f, -DVec2::ONE, DVec2::ONE).unwrap();
            for (s, o) in [(1e-7, DVec2::new(3e-7, -1e-7)), (1e5, DVec2::new(2e5, 7e5)), (1e12, DVec2::ZERO)]
            {
                // f(u) = g . u + c with u = (v - o) / s, times s^2: g s . v + (c s^2 - g s . o).
                let fs: Vec<Linear> =
                    f.iter().map(|l| Linear { g: l.g * s, c: l.c * s * s - (l.g * s).dot(o) }).collect();
                let (vs, ts) = max_min(&fs, o - s, o + s).unwrap();
                assert!(
                    (ts / (s * s) - t1).abs() <= 1e-6 * (1.0 + t1.abs()),
                    "case {case} s {s}: {ts} vs {t1}"
                );
                assert!(vs.cmpge(o - s).all() && vs.cmple(o + s).all(), "case {case} s {s}: {vs} outside");
            }
        }
    }

    #[test]
    fn a_fan_of_thousands_of_nearly_parallel_constraints_is_solved() {
        // f_k(u) = 1 - n_k . u for unit normals n_k all round the circle, plus as many copies
        // shifted down by a hair: the smallest is largest (1 - 1e-9) at the origin only.
        let m = 6000;
        let mut f = Vec::new();
        for k in 0..m {
            let a = std::f64::consts::TAU * k as f64 / m as f64;
            let n = DVec2::new(a.cos(), a.sin());
            f.push(Linear { g: -n, c: 1.0 });
            f.push(Linear { g: -n, c: 1.0 - 1e-9 });
        }
        let (v, t) = max_min(&f, DVec2::new(-3.0, -2.0), DVec2::new(1.0, 4.0)).unwrap();
        assert!(v.length() < 1e-6, "{v}");
        assert!((t - (1.0 - 1e-9)).abs() < 1e-9, "{t}");
    }
}

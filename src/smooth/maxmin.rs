//! The max-min stage: raises the worst quad as far as moving single vertices can.
//!
//! The embedded-polygon fixed point is not a max-min optimum, and the guard only keeps each
//! star above a floor, so after the sweeps the worst quad can usually still be improved. This
//! stage works on the vertices of the worst quads (those within `region_delta` of the current
//! global minimum) and moves each to a position that maximizes the minimum scaled Jacobian of
//! its star (its incident quads), Gauss-Seidel, colour class by colour class:
//!
//! - interior vertices by a local max-min solver ([`LocalSolver`]): a DMO-style nested grid
//!   search (Zint and Grosso, IMR 2018), Freitag and Plassmann's active-set ascent (2000), or
//!   the grid followed by the active-set polish;
//! - movable boundary vertices by a nested 1-D search along their ORIGINAL polyline between
//!   the arclengths of their two boundary neighbours, so they stay on the original boundary.
//!
//! A max-min move is taken only when the star's minimum strictly rises (by more than
//! roundoff) and no quad of the star that is valid becomes inverted, so the global minimum
//! never falls. Among the positions evaluated whose star minimum is within `avg_tolerance` of
//! the best one, the one with the highest star average is taken.
//!
//! A class is evaluated in parallel (its vertices share no quad, so each reads only positions
//! no other one changes) and applied in order: the result does not depend on the thread count.
//! Quads none of whose vertices may move are left out of the region's reference minimum (the
//! "level"), so a fixed worst quad does not stall the stage.
//!
//! Rounds repeat while the level rises by at least `min_gain`. When it stalls, in order: the
//! region grows (the threshold doubles up to `max_region_delta`, while the grown region has at
//! most `max_grown_region` vertices); a round takes at most the worst `min_region_quads` or
//! `region_quads_fraction` of the quads, so that on a large mesh it works on the worst region
//! only; an "escape" moves the region
//! by average instead, each star kept above min(its value, level + `region_delta`), which
//! unlocks the greedy equilibrium (at most `escapes` times); the phase switches once (see
//! [`MaxMinSettings::average_first`]); then the stage ends. Last, `average_sweeps` sweeps over
//! the moved vertices give back average the same way, so the stage does not trade the average
//! for the minimum (measured: the average rises on every sample mesh). The vertices its sweeps
//! cover are capped at `recovery_searches_per_vertex` times the vertex count (at least
//! `min_recovery_searches`): on a large mesh its region grows to the whole mesh, and its later
//! sweeps were most of the run's time for a few 1e-4 of average.
//!
//! A vertex whose max-min search failed is skipped until something in its star moves (the
//! search would fail again), so the late rounds cost little.

use super::boundary::BoundaryGeometry;
use crate::features::Features;
use crate::quality::{QualityStats, corners, scaled_jacobian};
use crate::topology::Topology;
use glam::DVec2;
use rayon::prelude::*;
use std::time::Instant;

/// Keep at least this fraction of the neighbour-to-neighbour arclength between a boundary
/// vertex and each of its boundary neighbours (as the boundary sweeps do).
const BOUNDARY_MARGIN: f64 = 0.05;

/// A move must raise its star's minimum (or, recovering the average, its average) by more
/// than this: gains at roundoff level are not worth a move (perfect meshes would otherwise
/// shuffle vertices by 1e-16 forever).
const MIN_RISE: f64 = 1e-9;

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
fn edge_floors(points: &[DVec2], quads: &[[u32; 4]]) -> Vec<f64> {
    let mut floors = Vec::with_capacity(quads.len());
    floors.par_extend(quads.par_iter().map(|q| {
        let c = corners(points, q);
        let squared = |i: usize| (c[(i + 1) % 4] - c[i]).length_squared();
        let longest = (0..4).map(squared).fold(0.0, f64::max);
        let shortest = (0..4).map(squared).fold(f64::INFINITY, f64::min);
        (SHORTEST_EDGE_FRACTION * SHORTEST_EDGE_FRACTION * longest)
            .min(SHORTEST_EDGE_KEPT * SHORTEST_EDGE_KEPT * shortest)
    }));
    floors
}

/// Classes with fewer region vertices than this are solved on the calling thread.
const PARALLEL_MIN: usize = 32;

/// Step halvings towards the smoothing target when recovering the average.
const AVERAGE_HALVINGS: usize = 8;

/// Step halvings of the active-set line search before the step counts as failed.
const ACTIVE_SET_HALVINGS: usize = 12;

/// How an interior vertex's best position is searched.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LocalSolver {
    /// DMO's nested grid: `grid_size` x `grid_size` candidates in a box of half the star's
    /// extent around the vertex, re-centred on the best one and shrunk to two cells,
    /// `grid_levels` times.
    Grid,
    /// Freitag and Plassmann's active-set method: ascend along the minimum-norm element of the
    /// convex hull of the active corners' gradients, with the step predicted from where
    /// another corner becomes active, halved until the star minimum rises.
    ActiveSet,
    /// The nested grid, then the active-set ascent from its best point.
    #[default]
    GridActiveSet,
}

/// Settings of the max-min stage.
#[derive(Clone, Debug, PartialEq)]
pub struct MaxMinSettings {
    /// Interior solver.
    pub solver: LocalSolver,
    /// Candidates per axis of the nested grid (>= 2).
    pub grid_size: usize,
    /// Refinement levels of the nested grid (>= 1).
    pub grid_levels: usize,
    /// Iteration cap of the active-set ascent.
    pub active_set_iterations: usize,
    /// Samples per level of the boundary 1-D search (>= 2).
    pub boundary_samples: usize,
    /// Initial region: the vertices of quads whose scaled Jacobian is below the level (the
    /// minimum over quads with a movable vertex) plus this.
    pub region_delta: f64,
    /// The region's threshold grows (doubling) up to this when the minimum stalls.
    pub max_region_delta: f64,
    /// The region grows only while the grown region has at most this many vertices. Growing
    /// lets the vertices next to a small worst region make room; on a large mesh of even
    /// quality a grown threshold takes in most of the mesh for nothing (measured on a
    /// 186k-quad plate: each growth covered 70-100% of its vertices, cost 1.7 s of a 24 s stage
    /// and raised the level by under 1e-4), so the stage goes on to its escape instead.
    pub max_grown_region: usize,
    /// A round works on at most the worst `max(min_region_quads, region_quads_fraction x
    /// quads)` quads below its threshold: on a large mesh of even quality the threshold
    /// (level + `region_delta`) takes in most of the mesh, and a round costs as much as a sweep
    /// of grid searches (measured on a 186k-quad plate: regions of 100k vertices, 0.1-0.8 s a
    /// round, 7.6 s of rounds; with the cap 1.5 s for the same minimum). Meshes of up to
    /// `min_region_quads` quads are never capped.
    pub min_region_quads: usize,
    /// See `min_region_quads`.
    pub region_quads_fraction: f64,
    /// Positions whose star minimum is within this of the best one found count as equal, and
    /// the highest star average among them is taken (0: the best minimum only).
    pub avg_tolerance: f64,
    /// A round whose gain of the level is below this counts as a stall.
    pub min_gain: f64,
    /// Round cap.
    pub max_rounds: usize,
    /// Which of the two phases runs first. In the max-min phase every star goes to its
    /// highest minimum; in the ranked phase, candidates whose star minimum exceeds the region's
    /// threshold plus `region_delta` are ranked by average (leaving neighbours room). The
    /// stage switches phase once, when the first stalls (measured: max-min first reaches the
    /// higher minimum on the Mesquite and sample meshes).
    pub average_first: bool,
    /// With [`LocalSolver::GridActiveSet`], search with the grid only a vertex's first time
    /// (and after an escape), later with the active set alone from where it is.
    pub warm_start: bool,
    /// Switch phase (see `average_first`) when the first stalls.
    pub switch_phase: bool,
    /// Average sweeps over the region allowed when the max-min rounds stall.
    pub escapes: usize,
    /// Recover the average (escapes and final sweeps) by steps towards the embedded-polygon
    /// target, halved until acceptable, instead of a grid search for the highest average
    /// (measured: a third cheaper, but the average ends up to 0.007 lower).
    pub average_by_smoothing: bool,
    /// The final average recovery keeps each star above min(its value, level + this).
    pub recovery_margin: f64,
    /// Sweeps of the final average recovery over the moved vertices (0: none).
    pub average_sweeps: usize,
    /// The recovery's sweeps may cover (the sum of their regions' vertices) at most
    /// max(`min_recovery_searches`, this times the vertex count): a sweep that would go past
    /// it is not started (the first always is).
    /// Measured on a 186k-quad plate with holes: its 6 recovery sweeps (regions of 130k to
    /// 188k vertices) took 61% of the run for an average of 0.94548 -> 0.94946; the first
    /// two give 0.94864 for a quarter of that time.
    pub recovery_searches_per_vertex: f64,
    /// See `recovery_searches_per_vertex`: 2^18, above the 8 sweeps of every mesh with up to
    /// 32k vertices, whose recovery is cheap (the sample and Mesquite meshes keep all of it).
    pub min_recovery_searches: usize,
    /// The recovery stops after a sweep that raised the mean scaled Jacobian of the quads it
    /// worked on by less than this (measured on a 186k-quad plate: its sweeps 5 to 8 gave
    /// 2.3e-4 of average for 4 of the stage's 18 s; on the sample meshes a sweep gains up
    /// to 4e-3).
    pub average_min_gain: f64,
    /// Move movable boundary vertices (along the original boundary) as well as interior ones.
    pub boundary: bool,
    /// As [`super::Options::max_boundary_deviation`]: largest distance between a new boundary
    /// edge and the stretch of the original boundary it replaces, relative to its length.
    pub max_boundary_deviation: Option<f64>,
}

impl Default for MaxMinSettings {
    fn default() -> Self {
        MaxMinSettings {
            solver: LocalSolver::default(),
            grid_size: 8,
            grid_levels: 3,
            active_set_iterations: 30,
            boundary_samples: 16,
            region_delta: 0.05,
            max_region_delta: 0.2,
            max_grown_region: 4096,
            min_region_quads: 1024,
            region_quads_fraction: 0.02,
            avg_tolerance: 0.0,
            min_gain: 1e-4,
            max_rounds: 200,
            average_first: false,
            average_sweeps: 8,
            recovery_searches_per_vertex: 2.0,
            min_recovery_searches: 1 << 18,
            average_min_gain: 1e-4,
            recovery_margin: 0.01,
            average_by_smoothing: false,
            warm_start: false,
            switch_phase: true,
            escapes: 2,
            boundary: true,
            max_boundary_deviation: None,
        }
    }
}

/// What the stage did.
#[derive(Clone, Debug, PartialEq)]
pub struct MaxMinReport {
    /// Quality when the stage started.
    pub before: QualityStats,
    /// Quality when it ended.
    pub after: QualityStats,
    /// Rounds (Gauss-Seidel passes over the region) performed.
    pub rounds: usize,
    /// Vertex moves taken.
    pub moves: usize,
    /// Sweeps of the average recovery performed.
    pub average_sweeps: usize,
    /// Vertices of the largest grown region a round worked on (0: the region never grew; at
    /// most `MaxMinSettings::max_grown_region`).
    pub largest_grown_region: usize,
    /// Global minimum scaled Jacobian before the first round, after every round and after the
    /// average recovery (non-decreasing).
    pub history: Vec<f64>,
    /// Whether the callback cancelled the stage.
    pub cancelled: bool,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// The quads around one vertex, with the vertex's corner index in each.
struct Star {
    quads: Vec<([DVec2; 4], usize)>,
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
    fn new(c: &[DVec2; 4], k: usize) -> FixedPart {
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
struct Value {
    min: f64,
    avg: f64,
}

/// The value of a position that may not be taken.
const REJECTED: Value = Value { min: f64::NEG_INFINITY, avg: f64::NEG_INFINITY };

impl Star {
    fn new(points: &[DVec2], quads: &[[u32; 4]], topo: &Topology, edge_floors: &[f64], v: usize) -> Star {
        let quads: Vec<([DVec2; 4], usize)> = topo
            .vertex_quads(v)
            .iter()
            .map(|&qi| {
                let q = &quads[qi as usize];
                (corners(points, q), q.iter().position(|&u| u as usize == v).unwrap_or(0))
            })
            .collect();
        let valid = quads.iter().map(|(c, _)| scaled_jacobian(c) > 0.0).collect();
        let fixed_part: Vec<FixedPart> = quads.iter().map(|(c, k)| FixedPart::new(c, *k)).collect();
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
        Star { quads, valid, fixed_part, shortest_squared }
    }

    fn value(&self, at: DVec2) -> Value {
        self.value_above(at, f64::NEG_INFINITY)
    }

    /// As [`Star::value`], but once a quad falls below `bar` the rest are skipped: the result
    /// then has that partial minimum (at least the true one, still below `bar`) and an average
    /// of -inf. For a candidate that cannot be taken, whatever its true value.
    fn value_above(&self, at: DVec2, bar: f64) -> Value {
        let (mut min, mut sum) = (f64::INFINITY, 0.0);
        let quads = self.quads.iter().zip(&self.valid).zip(&self.fixed_part).zip(&self.shortest_squared);
        for ((((c, k), &valid), part), &shortest) in quads {
            let edges = MovingEdges::new(part.next, part.prev, at);
            if edges.next_squared < shortest || edges.prev_squared < shortest {
                return REJECTED;
            }
            let q = part.value_from(&edges).unwrap_or_else(|| {
                let mut c = *c;
                c[*k] = at;
                scaled_jacobian(&c)
            });
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
    fn values_above(&self, at: &[DVec2], bar: f64, out: &mut Vec<Value>) {
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
            let quads = self.quads.iter().zip(&self.valid).zip(&self.fixed_part).zip(&self.shortest_squared);
            for ((((c, k), &valid), part), &shortest) in quads {
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
                        let mut c = *c;
                        c[*k] = group[l];
                        scaled_jacobian(&c)
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

    /// Every corner's scaled Jacobian at `at` and its gradient with respect to `at`.
    fn corner_functions(&self, at: DVec2, out: &mut Vec<(f64, DVec2)>) {
        out.clear();
        for (c, k) in &self.quads {
            let mut c = *c;
            c[*k] = at;
            for i in 0..4 {
                let (prev, p, next) = (c[(i + 3) % 4], c[i], c[(i + 1) % 4]);
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
                let grad = if i == *k {
                    -(d_prev + d_next)
                } else if (i + 3) % 4 == *k {
                    d_prev
                } else if (i + 1) % 4 == *k {
                    d_next
                } else {
                    DVec2::ZERO
                };
                out.push((value, grad));
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
enum Objective {
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
fn interior_move(
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
            let target = super::embedded_polygon::target(points, v, topo.ring(v)).point;
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
fn boundary_move(
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

/// Quality statistics of every quad, computed in parallel and summed in a fixed order.
fn quad_stats(points: &[DVec2], quads: &[[u32; 4]], values: &mut Vec<f64>) -> QualityStats {
    values.clear();
    values.par_extend(quads.par_iter().map(|q| scaled_jacobian(&corners(points, q))));
    QualityStats::from_values(values)
}

/// What every sweep reads.
struct Context<'a> {
    quads: &'a [[u32; 4]],
    topo: &'a Topology,
    features: &'a Features,
    geometry: &'a BoundaryGeometry,
    settings: &'a MaxMinSettings,
    /// [`edge_floors`] at the stage's start.
    edge_floors: &'a [f64],
}

impl Context<'_> {
    /// Whether the stage may move `v`.
    fn eligible(&self, v: usize) -> bool {
        self.features.is_movable(v)
            && (!self.features.is_boundary(v) || (self.settings.boundary && self.geometry.slot(v).is_some()))
    }
}

/// Per-vertex bookkeeping of the stage.
struct Marks {
    /// Moved at least once.
    moved: Vec<bool>,
    /// A max-min search found no better position, and nothing in the star has moved since:
    /// the search would fail again (its outcome does not depend on the round's threshold).
    settled: Vec<bool>,
    /// A max-min search with the grid has run here (see `MaxMinSettings::warm_start`).
    searched: Vec<bool>,
    /// As `settled`, for a search for the average above `average_floor` (whose outcome
    /// depends on that floor): the recovery sweeps skip most of the mesh after the first.
    settled_average: Vec<bool>,
    average_floor: f64,
}

/// One Gauss-Seidel sweep over the eligible vertices selected by `select`, colour class by
/// colour class: a class is evaluated in parallel and applied in order. Returns how many
/// vertices moved.
fn sweep(
    points: &mut [DVec2],
    params: &mut [f64],
    ctx: &Context,
    select: impl Fn(usize) -> bool + Sync,
    objective: Objective,
    marks: &mut Marks,
) -> usize {
    let max_min = matches!(objective, Objective::MaxMin { .. });
    if let Objective::Average { floor } = objective {
        if marks.average_floor.to_bits() != floor.to_bits() {
            marks.settled_average.fill(false);
            marks.average_floor = floor;
        }
    }
    let mut members: Vec<u32> = Vec::new();
    let mut results: Vec<(u32, Option<(DVec2, f64)>)> = Vec::new();
    let mut count = 0;
    for c in 0..ctx.topo.colour_count() {
        members.clear();
        members.extend(ctx.topo.colour_class(c).iter().filter(|&&v| {
            let v = v as usize;
            let settled = if max_min { marks.settled[v] } else { marks.settled_average[v] };
            select(v) && ctx.eligible(v) && !settled
        }));
        if members.is_empty() {
            continue;
        }
        results.clear();
        {
            let (pts, prm, warm) = (&*points, &*params, &marks.searched[..]);
            let solve = |&v: &u32| {
                let vi = v as usize;
                let found = if ctx.features.is_boundary(vi) {
                    boundary_move(pts, prm, ctx, vi, objective)
                } else {
                    // The grid has placed v near its optimum once: later rounds only follow
                    // its neighbours' moves, which the active set does at a fraction of the cost.
                    let solver = match ctx.settings.solver {
                        LocalSolver::GridActiveSet if warm[vi] => LocalSolver::ActiveSet,
                        s => s,
                    };
                    interior_move(pts, ctx, vi, solver, objective).map(|p| (p, 0.0))
                };
                (v, found)
            };
            // Handing a few vertices to the thread pool costs more than solving them here.
            if members.len() < PARALLEL_MIN {
                results.extend(members.iter().map(solve));
            } else {
                results.par_extend(members.par_iter().map(solve));
            }
        }
        // Sequential: the same result whatever the thread count.
        for &(v, found) in &results {
            let v = v as usize;
            marks.searched[v] |= max_min && ctx.settings.warm_start;
            let Some((p, s)) = found else {
                if max_min {
                    marks.settled[v] = true;
                } else {
                    marks.settled_average[v] = true;
                }
                continue;
            };
            points[v] = p;
            marks.moved[v] = true;
            // Every search whose star contains v now sees another star.
            marks.settled[v] = false;
            marks.settled_average[v] = false;
            for u in ctx.topo.star_vertices(ctx.quads, v) {
                marks.settled[u as usize] = false;
                marks.settled_average[u as usize] = false;
            }
            if let Some(slot) = ctx.geometry.slot(v) {
                params[slot] = s;
            }
            count += 1;
        }
    }
    count
}

/// Marks in `in_region` the vertices of the quads whose value is below `threshold`; returns
/// how many there are.
fn mark_region(quads: &[[u32; 4]], values: &[f64], threshold: f64, in_region: &mut [bool]) -> usize {
    in_region.fill(false);
    let mut count = 0;
    for (q, &value) in quads.iter().zip(values) {
        if value < threshold {
            for &u in q {
                count += usize::from(!in_region[u as usize]);
                in_region[u as usize] = true;
            }
        }
    }
    count
}

/// The threshold of a round: `threshold`, lowered so that at most `cap` quads that the stage
/// can move (not `stuck`) are below it; inverted quads always stay in (measured on Mesquite's
/// copy-morph-for-ricoh, 2,030 inverted quads: a cap below them left 18 more inverted).
/// `scratch` is reused between rounds.
fn capped_threshold(
    values: &[f64],
    stuck: &[bool],
    threshold: f64,
    cap: usize,
    scratch: &mut Vec<f64>,
) -> f64 {
    scratch.clear();
    scratch.extend(values.iter().zip(stuck).filter(|&(&v, &s)| v < threshold && !s).map(|(&v, _)| v));
    let cap = cap.max(scratch.iter().filter(|&&v| v <= 0.0).count());
    if scratch.len() <= cap {
        return threshold;
    }
    // The (cap + 1)-th smallest value: exactly `cap` quads are below it, or fewer with ties.
    let (_, &mut nth, _) = scratch.select_nth_unstable_by(cap, f64::total_cmp);
    nth
}

/// Mean value of the quads with a vertex in the region (0 for an empty region).
fn region_average(quads: &[[u32; 4]], values: &[f64], in_region: &[bool]) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for (q, &value) in quads.iter().zip(values) {
        if q.iter().any(|&u| in_region[u as usize]) {
            sum += value;
            count += 1;
        }
    }
    if count == 0 { 0.0 } else { sum / count as f64 }
}

/// Runs the max-min stage on `points` (and the boundary parameters `params`, one per slot of
/// `geometry`, as the sweeps keep them). `progress` is called after every round with the
/// round number and the global minimum; returning `false` cancels (the positions reached are
/// kept, they are never worse).
#[allow(clippy::too_many_arguments)]
pub fn max_min_stage(
    points: &mut [DVec2],
    params: &mut [f64],
    quads: &[[u32; 4]],
    topo: &Topology,
    features: &Features,
    geometry: &BoundaryGeometry,
    settings: &MaxMinSettings,
    mut progress: Option<&mut dyn FnMut(usize, f64) -> bool>,
) -> MaxMinReport {
    let start = Instant::now();
    let mut values = Vec::with_capacity(quads.len());
    let before = quad_stats(points, quads, &mut values);
    let mut report = MaxMinReport {
        before,
        after: before,
        rounds: 0,
        moves: 0,
        average_sweeps: 0,
        largest_grown_region: 0,
        history: vec![before.min],
        cancelled: false,
        seconds: 0.0,
    };
    if quads.is_empty() || before.min.is_nan() || before.min >= 1.0 - MIN_RISE {
        return report;
    }
    let edge_floors = edge_floors(points, quads);
    let ctx = Context { quads, topo, features, geometry, settings, edge_floors: &edge_floors };
    let mut in_region = vec![false; points.len()];
    // The region a growth would give (an escape still needs the round's own region).
    let mut grown_region = vec![false; points.len()];
    let mut marks = Marks {
        moved: vec![false; points.len()],
        settled: vec![false; points.len()],
        searched: vec![false; points.len()],
        settled_average: vec![false; points.len()],
        average_floor: f64::NAN,
    };
    // Quads with no vertex the stage may move keep their value: the stage works on the worst
    // of the others (its level), else a fixed worst quad would stall it from the start.
    let stuck: Vec<bool> = quads.iter().map(|q| q.iter().all(|&u| !ctx.eligible(u as usize))).collect();
    let level_of = |values: &[f64]| {
        values.iter().zip(&stuck).filter(|(_, s)| !**s).map(|(v, _)| *v).fold(f64::INFINITY, f64::min)
    };
    let mut level = level_of(&values);
    if level.is_nan() || level >= 1.0 - MIN_RISE {
        // Nothing movable, or every movable quad already perfect.
        return report;
    }
    let mut delta = settings.region_delta.max(0.0);
    let mut stats = before;
    // Two phases (see `average_first`); each greedy phase stalls in its own equilibrium, and
    // the other one often moves on from there.
    let mut ranked_by_average = settings.average_first;
    let mut switched = !settings.switch_phase;
    let mut escapes = 0;
    let region_cap =
        settings.min_region_quads.max((settings.region_quads_fraction * quads.len() as f64) as usize);
    let mut scratch = Vec::new();
    while report.rounds < settings.max_rounds {
        let threshold = capped_threshold(&values, &stuck, level + delta, region_cap, &mut scratch);
        let enough = if ranked_by_average { threshold + settings.region_delta } else { f64::INFINITY };
        mark_region(quads, &values, threshold, &mut in_region);
        let objective = Objective::MaxMin { enough };
        let round_moves = sweep(&mut *points, &mut *params, &ctx, |v| in_region[v], objective, &mut marks);
        report.rounds += 1;
        report.moves += round_moves;
        stats = quad_stats(points, quads, &mut values);
        let new_level = level_of(&values);
        let gain = new_level - level;
        level = new_level;
        report.history.push(stats.min);
        if let Some(cb) = progress.as_mut() {
            if !cb(report.rounds, stats.min) {
                report.cancelled = true;
                break;
            }
        }
        if round_moves == 0 || gain < settings.min_gain {
            let grown = (2.0 * delta.max(1e-3)).min(settings.max_region_delta);
            let grown_size = (delta < settings.max_region_delta)
                .then(|| mark_region(quads, &values, level + grown, &mut grown_region))
                .filter(|&size| size <= settings.max_grown_region);
            if let Some(grown_size) = grown_size {
                delta = grown;
                report.largest_grown_region = report.largest_grown_region.max(grown_size);
            } else if escapes < settings.escapes {
                // Every region vertex sits at its star's max-min given its neighbours: move
                // the region by average instead (keeping each star above the minimum plus
                // region_delta, or its current value), which unlocks the next max-min rounds.
                escapes += 1;
                let floor = level + settings.region_delta;
                let objective = Objective::Average { floor };
                report.moves +=
                    sweep(&mut *points, &mut *params, &ctx, |v| in_region[v], objective, &mut marks);
                stats = quad_stats(points, quads, &mut values);
                level = level_of(&values);
                report.history.push(stats.min);
                delta = settings.region_delta.max(0.0);
                marks.searched.fill(false);
            } else if !switched {
                switched = true;
                ranked_by_average = !ranked_by_average;
                delta = settings.region_delta.max(0.0);
            } else {
                break;
            }
        }
    }
    // Give back average where the minimum does not need it: the moved vertices and their
    // neighbours (whose quads the moves changed) raise their star's average while their star
    // stays above min(its value, the final level plus `recovery_margin`).
    let floor = level + settings.recovery_margin;
    let budget = settings
        .min_recovery_searches
        .max((settings.recovery_searches_per_vertex * points.len() as f64) as usize);
    let mut searches = 0;
    for _ in 0..settings.average_sweeps {
        let mut was_moved = marks.moved.clone();
        for v in (0..points.len()).filter(|&v| marks.moved[v]) {
            for u in topo.star_vertices(quads, v) {
                was_moved[u as usize] = true;
            }
        }
        let region = was_moved.iter().filter(|&&m| m).count();
        if searches > 0 && searches + region > budget {
            break;
        }
        searches += region;
        let before = region_average(quads, &values, &was_moved);
        let count = sweep(
            &mut *points,
            &mut *params,
            &ctx,
            |v| was_moved[v],
            Objective::Average { floor },
            &mut marks,
        );
        report.moves += count;
        report.average_sweeps += 1;
        stats = quad_stats(points, quads, &mut values);
        if count == 0 || region_average(quads, &values, &was_moved) - before < settings.average_min_gain {
            break;
        }
    }
    if settings.average_sweeps > 0 {
        report.history.push(stats.min);
    }
    report.after = stats;
    report.seconds = start.elapsed().as_secs_f64();
    report
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
            let part = FixedPart::new(&c, k);
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
                valid: quads.iter().map(|(c, _)| scaled_jacobian(c) > 0.0).collect(),
                fixed_part: quads.iter().map(|(c, k)| FixedPart::new(c, *k)).collect(),
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

    #[test]
    fn a_round_takes_at_most_the_cap_of_worst_movable_quads_and_every_inverted_one() {
        let values = [0.9, -0.2, 0.5, 0.1, 0.3, 0.7, -0.1, 0.2, 0.05, 0.6];
        let mut stuck = [false; 10];
        stuck[8] = true; // 0.05: no vertex may move, never counted.
        let mut scratch = Vec::new();
        let below = |t: f64| values.iter().zip(&stuck).filter(|&(&v, &s)| v < t && !s).count();
        // Under the cap the threshold is kept.
        assert_eq!(capped_threshold(&values, &stuck, 0.4, 8, &mut scratch), 0.4);
        // 6 movable quads below 0.65 (-0.2, -0.1, 0.1, 0.2, 0.3, 0.5), cap 4: below 0.3.
        let t = capped_threshold(&values, &stuck, 0.65, 4, &mut scratch);
        assert_eq!(t, 0.3);
        assert_eq!(below(t), 4);
        // A cap below the inverted count keeps every inverted quad.
        let t = capped_threshold(&values, &stuck, 0.65, 1, &mut scratch);
        assert_eq!(t, 0.1);
        assert_eq!(below(t), 2);
    }
}

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
//!
//! The stage's parts, one a file: `settings.rs` (the settings, their defaults and the report),
//! `star.rs` (a vertex's star evaluated at candidate positions, and the edge floors no move may
//! cross), `search.rs` (the local solvers, what a move aims at and the context they read),
//! `region.rs` (the quads' values and the region a round works on). This file drives them: the
//! sweeps, the rounds, the region's growth, the escapes, the phase switch and the average
//! recovery. Its parts import from one another only downwards (`search` -> `star`, `settings`).

mod region;
mod search;
mod settings;
mod star;

pub use settings::{LocalSolver, MaxMinReport, MaxMinSettings};

use crate::features::Features;
use crate::smooth::boundary::BoundaryGeometry;
use crate::topology::Topology;
use glam::DVec2;
use rayon::prelude::*;
use region::{capped_threshold, mark_region, quad_stats, region_average};
use search::{Context, MIN_RISE, Objective, boundary_move, interior_move};
use star::edge_floors;
use std::time::Instant;

/// Classes with fewer region vertices than this are solved on the calling thread.
const PARALLEL_MIN: usize = 32;

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
    let stuck: Vec<bool> =
        quads.iter().map(|q| crate::face::vertices(q).iter().all(|&u| !ctx.eligible(u as usize))).collect();
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

//! How iterates are ranked: by [`QualityStats::better_than_with_tie`] (inverted count, then
//! minimum scaled Jacobian, then average; the one rule), never accepting one that is worse
//! than the input.

use crate::quality::{QualityStats, corners, scaled_jacobian};
use glam::DVec2;
use rayon::prelude::*;

/// Minimum differences that count when ranking iterates by minimum scaled Jacobian; closer
/// minima are a tie decided by the average, so a negligible gain of the worst quad does not
/// beat a large gain of the average.
pub const MIN_TIE: f64 = 1e-3;

/// The tie on the minimum when the sweeps' iterates are ranked and the max-min stage follows:
/// the stage sets the minimum, so the sweeps are kept for their average unless their minimum
/// falls clearly. Measured on the 200k-quad plate with holes: with 1e-3 the run keeps sweep
/// 10 (min 0.708, avg 0.924) over every later one (min about 0.68, avg up to 0.948) and ends
/// at 0.862/0.937 after the stage; with 0.02, 0.863/0.950. The quality floor's 56 meshes stay
/// at or above their floor.
pub const MIN_TIE_BEFORE_MAX_MIN: f64 = 0.02;

/// Whether `candidate` should replace `best`, given the `input` it may never be worse than.
pub fn improves(candidate: &QualityStats, best: &QualityStats, input: &QualityStats) -> bool {
    improves_with_tie(candidate, best, input, MIN_TIE)
}

/// As [`improves`], with minima closer than `tie` a tie decided by the average.
pub fn improves_with_tie(
    candidate: &QualityStats,
    best: &QualityStats,
    input: &QualityStats,
    tie: f64,
) -> bool {
    if candidate.inverted > input.inverted || candidate.min < input.min {
        return false;
    }
    candidate.better_than_with_tie(best, tie)
}

/// Quads below which statistics are computed on the calling thread.
const PARALLEL_MIN: usize = 4096;

/// Per-quad scaled Jacobians into `values` (parallel), and their statistics (summed in a
/// fixed order, so the same on any thread count).
pub fn stats_of(points: &[DVec2], quads: &[[u32; 4]], values: &mut Vec<f64>) -> QualityStats {
    values.clear();
    let value = |q: &[u32; 4]| scaled_jacobian(&corners(points, q));
    if quads.len() >= PARALLEL_MIN {
        values.par_extend(quads.par_iter().map(value));
    } else {
        values.extend(quads.iter().map(value));
    }
    QualityStats::from_values(values)
}

//! The quads' values after each round and what the stage draws from them: the region a round
//! works on (its threshold, capped on large meshes) and the region's average. Separate from
//! the driver so that the region rules can be read and tested on plain arrays.

use crate::quality::{QualityStats, corners, scaled_jacobian};
use glam::DVec2;
use rayon::prelude::*;

/// Quality statistics of every quad, computed in parallel and summed in a fixed order.
pub(super) fn quad_stats(points: &[DVec2], quads: &[[u32; 4]], values: &mut Vec<f64>) -> QualityStats {
    values.clear();
    values.par_extend(quads.par_iter().map(|q| scaled_jacobian(&corners(points, q))));
    QualityStats::from_values(values)
}

/// Marks in `in_region` the vertices of the quads whose value is below `threshold`; returns
/// how many there are.
pub(super) fn mark_region(
    quads: &[[u32; 4]],
    values: &[f64],
    threshold: f64,
    in_region: &mut [bool],
) -> usize {
    in_region.fill(false);
    let mut count = 0;
    for (q, &value) in quads.iter().zip(values) {
        if value < threshold {
            for &u in crate::face::vertices(q) {
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
pub(super) fn capped_threshold(
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
pub(super) fn region_average(quads: &[[u32; 4]], values: &[f64], in_region: &[bool]) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for (q, &value) in quads.iter().zip(values) {
        if crate::face::vertices(q).iter().any(|&u| in_region[u as usize]) {
            sum += value;
            count += 1;
        }
    }
    if count == 0 { 0.0 } else { sum / count as f64 }
}

#[cfg(test)]
mod tests {
    use super::*;

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

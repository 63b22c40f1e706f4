//! Boundary fidelity: how far the new boundary polyline is from the original one.
//!
//! Moving boundary vertices always lie on the original polyline, so the boundary can change
//! only where a new edge (a chord between two consecutive boundary vertices) cuts across the
//! original polyline between them. Each chord is compared with the stretch of the original
//! polyline it replaces: the original vertices in between against the chord (original ->
//! new) and sample points of the chord against that stretch (new -> original). Restricting
//! the comparison to the corresponding stretch can only overestimate distances, so the
//! figures are upper bounds of the true one-sided and symmetric Hausdorff distances.

use super::boundary::BoundaryGeometry;
use glam::DVec2;

/// Sample points per chord for the new -> original direction.
const CHORD_SAMPLES: usize = 8;

/// Distance from `p` to segment `a`-`b`.
pub fn point_segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let d = b - a;
    let t =
        if d.length_squared() > 0.0 { ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
    (a + d * t - p).length()
}

/// Deviations of one chord of loop `l`, from arclength `s0` to `s1` (unwrapped, s0 <= s1):
/// (new -> original, original -> new).
pub fn chord_deviation(g: &BoundaryGeometry, l: usize, s0: f64, s1: f64) -> (f64, f64) {
    let (a, b) = (g.eval(l, s0), g.eval(l, s1));
    // The original polyline between s0 and s1: its vertices strictly inside, plus the ends.
    let mut stretch: [DVec2; 34] = [DVec2::ZERO; 34];
    let mut count = 0;
    stretch[count] = a;
    count += 1;
    let mut overflow = false;
    g.for_each_vertex_between(l, s0, s1, |p| {
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
    (new_to_original, original_to_new)
}

/// Boundary fidelity of a result.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BoundaryFidelity {
    /// Largest distance of the new boundary polyline from the original one.
    pub max_deviation: f64,
    /// Symmetric Hausdorff distance between the new and the original boundary polylines.
    pub hausdorff: f64,
    /// `max_deviation` divided by the mesh's mean edge length.
    pub max_deviation_relative: f64,
    /// `hausdorff` divided by the mesh's mean edge length.
    pub hausdorff_relative: f64,
}

/// Fidelity of the boundary described by slot arclengths `params` against the original.
pub fn measure(g: &BoundaryGeometry, params: &[f64], mean_edge: f64) -> BoundaryFidelity {
    let (mut dev, mut haus) = (0.0f64, 0.0f64);
    for l in 0..g.loop_count() {
        let (a, b) = g.loop_slots(l);
        let len = g.loop_length(l);
        if len <= 0.0 || !len.is_finite() {
            // Nothing on a loop of zero (or overflowing) length can move, and unwrapping the
            // arclengths below would never end.
            continue;
        }
        for k in a..b {
            let next = if k + 1 < b { k + 1 } else { a };
            let s0 = params[k];
            let mut s1 = params[next];
            while s1 <= s0 {
                s1 += len;
            }
            let (n2o, o2n) = chord_deviation(g, l, s0, s1);
            dev = dev.max(n2o);
            haus = haus.max(n2o).max(o2n);
        }
    }
    let rel = |x: f64| if mean_edge > 0.0 { x / mean_edge } else { 0.0 };
    BoundaryFidelity {
        max_deviation: dev,
        hausdorff: haus,
        max_deviation_relative: rel(dev),
        hausdorff_relative: rel(haus),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_segment_distances() {
        let (a, b) = (DVec2::ZERO, DVec2::new(2.0, 0.0));
        assert_eq!(point_segment_distance(DVec2::new(1.0, 0.5), a, b), 0.5);
        assert_eq!(point_segment_distance(DVec2::new(3.0, 0.0), a, b), 1.0);
    }
}

//! Boundary fidelity: how far the new boundary polyline is from the original one.
//!
//! Moving boundary vertices always lie on the original polyline, so the boundary can change
//! only where a new edge (a chord between two consecutive boundary vertices) cuts across the
//! original polyline between them. Each chord is compared with the stretch of the original
//! polyline it replaces ([`BoundaryGeometry::chord_deviation`]): the original vertices in
//! between against the chord (original -> new) and sample points of the chord against that
//! stretch (new -> original). Restricting the comparison to the corresponding stretch can
//! only overestimate distances, so the figures are upper bounds of the true one-sided and
//! symmetric Hausdorff distances.

use super::boundary::BoundaryGeometry;

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
            let d = g.chord_deviation(l, s0, s1);
            dev = dev.max(d.new_to_original);
            haus = haus.max(d.new_to_original).max(d.original_to_new);
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

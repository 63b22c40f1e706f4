//! `Options::max_boundary_deviation` on curved surfaces (issue 42): every new edge along a
//! feature curve (here the boundary arcs of a half cylinder) stays within the tolerance times
//! its length of the original curve, measured independently of the optimizer, and the report's
//! curve deviation bounds what is measured.

mod common;

use common::surfaces::grid;
use glam::DVec3;
use quadopt::surface::{SurfaceMesh, SurfaceOptimizer};
use quadopt::{Effort, Options};

/// A half cylinder of radius 1 in 10 x 6 quads whose rows zigzag along the arc (so the quads
/// are skewed, and straightening them moves the boundary vertices along the arcs, their edges
/// cutting across them).
fn zigzag_half_cylinder() -> SurfaceMesh {
    let (points, faces) = grid(10, 6, false, false, |i, j| {
        let shift = if i > 0 && i < 10 { 0.35 * if j % 2 == 0 { 1.0 } else { -1.0 } } else { 0.0 };
        let a = std::f64::consts::PI * (f64::from(i) + shift) / 10.0;
        DVec3::new(a.cos(), a.sin(), f64::from(j) / 6.0 * 1.5)
    });
    SurfaceMesh::new(points, faces, None).unwrap()
}

fn distance_to_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
    (a + (b - a) * t - p).length()
}

/// The largest distance, relative to its edge's length, of sample points of the output's
/// boundary edges from the input's boundary (every input boundary edge).
fn boundary_edge_deviation(input: &SurfaceMesh, output: &[DVec3]) -> f64 {
    let boundary: Vec<(DVec3, DVec3)> = input
        .edges()
        .iter()
        .filter(|e| e.is_boundary())
        .map(|e| (input.points()[e.a as usize], input.points()[e.b as usize]))
        .collect();
    let mut worst = 0.0f64;
    for e in input.edges().iter().filter(|e| e.is_boundary()) {
        let (a, b) = (output[e.a as usize], output[e.b as usize]);
        for k in 1..16 {
            let q = a + (b - a) * (f64::from(k) / 16.0);
            let d = boundary.iter().map(|&(u, w)| distance_to_segment(q, u, w)).fold(f64::INFINITY, f64::min);
            worst = worst.max(d / (b - a).length());
        }
    }
    worst
}

#[test]
fn the_curve_tolerance_holds_on_surfaces_in_every_preset() {
    let input = zigzag_half_cylinder();
    for effort in [Effort::Fast, Effort::Balanced, Effort::Best] {
        // Without a tolerance the arcs' vertices even out and their edges cut across the arcs.
        let mut free = input.clone();
        let optimizer = SurfaceOptimizer::new(&free, 45.0, &[]).unwrap();
        let r = optimizer.run(&mut free, &Options::default().with_effort(effort), None).unwrap();
        let unlimited = boundary_edge_deviation(&input, free.points());
        assert!(unlimited > 0.01, "{effort:?}: the test needs boundary edges off the arcs ({unlimited})");
        assert!(r.fidelity.max_curve_deviation > 0.0, "{effort:?}: {:?}", r.fidelity);
        for tolerance in [0.0, 0.002, 0.01] {
            let mut mesh = input.clone();
            let options = Options::default().with_effort(effort).with_max_boundary_deviation(Some(tolerance));
            let r = optimizer.run(&mut mesh, &options, None).unwrap();
            let measured = boundary_edge_deviation(&input, mesh.points());
            let what = format!("{effort:?}, tolerance {tolerance}");
            assert!(measured <= tolerance + 1e-12, "{what}: a boundary edge {measured} of its length off");
            // The report bounds what is measured (the measure samples fewer points).
            let longest = (input.edges().iter().filter(|e| e.is_boundary()))
                .map(|e| (mesh.points()[e.a as usize] - mesh.points()[e.b as usize]).length())
                .fold(0.0, f64::max);
            assert!(
                r.fidelity.max_curve_deviation <= tolerance * longest + 1e-12,
                "{what}: {:?}",
                r.fidelity
            );
            assert!(r.output.min >= r.input.min && r.output.inverted <= r.input.inverted, "{what}: {r:?}");
            if tolerance > 0.0 {
                assert!(r.output.avg > r.input.avg, "{what}: nothing improved: {r:?}");
            }
            // The measure of the output agrees with the run's report.
            let m = optimizer.measure(mesh.points()).unwrap();
            assert!(
                (m.fidelity.max_curve_deviation - r.fidelity.max_curve_deviation).abs() < 1e-12,
                "{what}"
            );
        }
    }
}

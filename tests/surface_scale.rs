//! Meshes on curved surfaces at any scale (issue 42): the same quality and the same run from
//! 1e-300 to 1e300, bit for bit for powers of two, as in the plane (tests/scale.rs). An open
//! quarter cylinder (feature curves on its boundary) and a closed sphere (its orientation
//! decided by its enclosed volume, the cube of its size).

mod common;

use common::Rng;
use common::surfaces::cube_sphere;
use glam::DVec3;
use quadopt::Options;
use quadopt::face::Face;
use quadopt::surface::{SurfaceMesh, SurfaceOptimizer, SurfaceReport};

/// An `n` x `n` grid on a quarter cylinder of radius 1 and height 1, its interior vertices
/// pushed along the cylinder so a few quads are poor and one is folded.
fn quarter_cylinder(n: usize) -> (Vec<DVec3>, Vec<Face>) {
    let mut rng = Rng(7);
    let mut points = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (mut a, mut z) = (i as f64 / n as f64, j as f64 / n as f64);
            if i > 0 && i < n && j > 0 && j < n {
                a += 0.45 * rng.next() / n as f64;
                z += 0.45 * rng.next() / n as f64;
            }
            let a = a * std::f64::consts::FRAC_PI_2;
            points.push(DVec3::new(a.cos(), a.sin(), z));
        }
    }
    // One interior vertex pushed past its neighbour: a folded quad.
    let v = (n / 2) * (n + 1) + n / 2;
    let a = (n as f64 / 2.0 + 1.3) / n as f64 * std::f64::consts::FRAC_PI_2;
    points[v] = DVec3::new(a.cos(), a.sin(), points[v].z);
    let w = n as u32 + 1;
    let faces = (0..n * n)
        .map(|k| {
            let v = ((k / n) * (n + 1) + k % n) as u32;
            [v, v + 1, v + 1 + w, v + w]
        })
        .collect();
    (points, faces)
}

fn sphere() -> (Vec<DVec3>, Vec<Face>) {
    let (mut points, faces) = cube_sphere(6);
    let mut rng = Rng(3);
    for p in &mut points {
        let d = DVec3::new(rng.next(), rng.next(), rng.next()) * 0.08;
        *p = (*p + d - *p * d.dot(*p)).normalize();
    }
    (points, faces)
}

fn scaled(points: &[DVec3], factor: f64) -> Vec<DVec3> {
    points.iter().map(|p| *p * factor).collect()
}

/// The input's signed and Verdict values, and a run's report and output positions.
fn run(
    points: Vec<DVec3>,
    faces: &[Face],
    options: &Options,
) -> (Vec<f64>, Vec<f64>, SurfaceReport, Vec<DVec3>) {
    let mut mesh = SurfaceMesh::new(points, faces.to_vec(), None).unwrap();
    let optimizer = SurfaceOptimizer::new(&mesh, options.feature_angle_deg, &[]).unwrap();
    let measure = optimizer.measure(mesh.points()).unwrap();
    let report = optimizer.run(&mut mesh, options, None).unwrap();
    (measure.values, measure.verdict_values, report, mesh.points().to_vec())
}

fn meshes() -> [(&'static str, (Vec<DVec3>, Vec<Face>)); 2] {
    [("quarter cylinder", quarter_cylinder(6)), ("sphere", sphere())]
}

#[test]
fn surface_quality_and_runs_are_the_same_at_every_scale() {
    for options in [Options::default(), Options::fast()] {
        for (name, (points, faces)) in meshes() {
            let (values, verdict, report, _) = run(points.clone(), &faces, &options);
            assert!(report.input.inverted > 0 || name == "sphere", "{name}: the test needs a fold");
            assert!(report.output.min > report.input.min, "{name}: {report:?}");
            for factor in [1e-300, 1e-200, 1e-100, 1e-50, 1e-10, 1e10, 1e50, 1e100, 1e200, 1e300] {
                let (v, vd, r, out) = run(scaled(&points, factor), &faces, &options);
                let what = format!("{name} at {factor:e}");
                for (a, b) in values.iter().zip(&v).chain(verdict.iter().zip(&vd)) {
                    assert!((a - b).abs() < 1e-9, "{what}: a face's value {b} against {a}");
                }
                assert_eq!(r.input.inverted, report.input.inverted, "{what}");
                assert_eq!(r.output.inverted, report.output.inverted, "{what}: {r:?}");
                assert!((r.output.min - report.output.min).abs() < 1e-6, "{what}: {r:?} against {report:?}");
                assert!((r.output.avg - report.output.avg).abs() < 1e-6, "{what}: {r:?} against {report:?}");
                assert!((r.output_verdict.min - report.output_verdict.min).abs() < 1e-6, "{what}: {r:?}");
                assert!(r.fidelity.max_distance_relative() < 1e-9, "{what}: {:?}", r.fidelity);
                assert!(out.iter().all(|p| p.is_finite()), "{what}");
            }
        }
    }
}

#[test]
fn a_surface_run_scaled_by_a_power_of_two_is_bit_identical() {
    let options = Options::default();
    for (name, (points, faces)) in meshes() {
        let (values, _, report, out) = run(points.clone(), &faces, &options);
        for e in [-600, -300, -100, -20, 20, 100, 300, 600] {
            let factor = 2f64.powi(e);
            let (v, _, r, o) = run(scaled(&points, factor), &faces, &options);
            assert_eq!(v, values, "{name} at 2^{e}: the input's values");
            assert_eq!(
                (r.output.min, r.output.avg),
                (report.output.min, report.output.avg),
                "{name} at 2^{e}"
            );
            assert_eq!(r.iterations, report.iterations, "{name} at 2^{e}");
            for (a, b) in out.iter().zip(&o) {
                assert_eq!(*a * factor, *b, "{name} at 2^{e}: a vertex");
            }
            let d = report.fidelity.max_distance * factor;
            assert_eq!(r.fidelity.max_distance, d, "{name} at 2^{e}");
        }
    }
}

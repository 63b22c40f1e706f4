//! The optimizer on curved surfaces (issue 33): vertices stay on the input surface and on
//! their feature curves, corners and fixed vertices keep their bits, the result is never worse
//! than the input and the same on any thread count.

mod common;

use common::Rng;
use common::surfaces::{cube, cube_sphere, grid};
use glam::DVec3;
use quadopt::face::Face;
use quadopt::surface::{SurfaceMesh, SurfaceOptimizer, SurfaceReport};
use quadopt::{Effort, Options};
use std::f64::consts::PI;

/// Moves every vertex by `amount` times a random tangent vector (`tangent` gives the plane),
/// then puts it back with `onto`; vertices for which `keep` holds stay.
fn perturb(
    points: &mut [DVec3],
    seed: u64,
    amount: f64,
    keep: impl Fn(usize) -> bool,
    normal: impl Fn(DVec3) -> DVec3,
    onto: impl Fn(DVec3) -> DVec3,
) {
    let mut rng = Rng(seed);
    for (v, p) in points.iter_mut().enumerate() {
        if keep(v) {
            continue;
        }
        let n = normal(*p);
        let d = DVec3::new(rng.next(), rng.next(), rng.next());
        let t = d - n * d.dot(n);
        *p = onto(*p + t * amount);
    }
}

fn run(mesh: &mut SurfaceMesh, options: &Options) -> SurfaceReport {
    let optimizer = SurfaceOptimizer::new(mesh, options.feature_angle_deg, &[]).unwrap();
    optimizer.run(mesh, options, None).unwrap()
}

/// The guarantees every run keeps.
fn check_guarantees(report: &SurfaceReport) {
    assert!(report.output.inverted <= report.input.inverted, "{report:?}");
    assert!(report.output.min >= report.input.min, "{report:?}");
    assert!(report.fidelity.max_distance_relative() < 1e-9, "{:?}", report.fidelity);
    assert!(report.fidelity.max_feature_distance_relative() < 1e-9, "{:?}", report.fidelity);
    // The split by face kind describes the same faces as the totals, before and after.
    for (kinds, total) in [(&report.input_by_kind, &report.input), (&report.output_by_kind, &report.output)] {
        let parts: Vec<_> = [kinds.quads, kinds.triangles].into_iter().flatten().collect();
        let inverted: usize = parts.iter().map(|p| p.inverted).sum();
        let min = parts.iter().map(|p| p.min).fold(f64::INFINITY, f64::min);
        assert_eq!((inverted, min), (total.inverted, total.min), "{report:?}");
    }
}

fn perturbed_sphere(n: u32, amount: f64, seed: u64) -> SurfaceMesh {
    let (mut points, faces) = cube_sphere(n);
    perturb(&mut points, seed, amount / f64::from(n), |_| false, |p| p.normalize(), |p| p.normalize());
    SurfaceMesh::new(points, faces, None).unwrap()
}

#[test]
fn sphere_vertices_stay_on_the_input_surface_and_quality_rises() {
    for effort in Effort::ALL {
        let mut mesh = perturbed_sphere(8, 0.5, 7);
        let input = mesh.points().to_vec();
        let report = run(&mut mesh, &Options::default().with_effort(effort));
        check_guarantees(&report);
        assert_eq!(report.patches, 1);
        assert!(report.output.min > report.input.min + 0.05, "{effort}: {report:?}");
        assert!(report.output.avg > report.input.avg, "{effort}: {report:?}");
        assert!(report.output_verdict.min > report.input_verdict.min, "{effort}: {report:?}");
        // On the input's triangles, so inside the unit sphere by at most their sag, and
        // never outside it.
        let sag = input.iter().map(|p| 1.0 - p.length()).fold(0.0, f64::max) + 0.02;
        for p in mesh.points() {
            let r = p.length();
            assert!(r <= 1.0 + 1e-12 && r > 1.0 - sag, "{p} at radius {r}");
        }
    }
}

#[test]
fn cube_edges_stay_straight_and_corners_stay_put() {
    let n = 5;
    let (mut points, faces, lattice) = cube(n);
    let extreme = |c: u32| c == 0 || c == n;
    let on_edges = |v: usize| lattice[v].iter().filter(|&&c| extreme(c)).count();
    // Face vertices move in their face's plane, edge vertices along their edge.
    let mut rng = Rng(11);
    for (v, p) in points.iter_mut().enumerate() {
        let l = lattice[v];
        if on_edges(v) == 3 {
            continue;
        }
        for a in 0..3 {
            if !extreme(l[a]) {
                p[a] += 0.35 * rng.next() / f64::from(n);
            }
        }
    }
    let input = points.clone();
    let mut mesh = SurfaceMesh::new(points, faces, None).unwrap();
    let report = run(&mut mesh, &Options::best());
    check_guarantees(&report);
    assert_eq!((report.patches, report.feature_curves, report.corners), (6, 12, 8));
    assert!(report.output.min > report.input.min + 0.1, "{report:?}");
    for (v, (p, q)) in mesh.points().iter().zip(&input).enumerate() {
        let l = lattice[v];
        match on_edges(v) {
            3 => assert_eq!(p.to_array().map(f64::to_bits), q.to_array().map(f64::to_bits), "corner {v}"),
            // On an edge: its two extreme coordinates exactly.
            2 => {
                for a in 0..3 {
                    if extreme(l[a]) {
                        assert_eq!(p[a], q[a], "edge vertex {v} left its edge: {q} -> {p}");
                    }
                }
            }
            // On a face: within rounding of its plane.
            _ => {
                let a = (0..3).find(|&a| extreme(l[a])).unwrap();
                assert!((p[a] - q[a]).abs() < 1e-14, "face vertex {v} left its face: {q} -> {p}");
            }
        }
    }
    // The edge vertices spread out evenly again.
    assert!(report.output.min > 0.9, "{report:?}");
}

#[test]
fn fixed_vertices_keep_their_bits_and_the_result_does_not_depend_on_threads() {
    let base = perturbed_sphere(6, 0.6, 3);
    let fixed: Vec<bool> = (0..base.points().len()).map(|v| v % 7 == 0).collect();
    let make =
        || SurfaceMesh::new(base.points().to_vec(), base.faces().to_vec(), Some(fixed.clone())).unwrap();
    let mut outputs = Vec::new();
    for threads in [1, 2, 3] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let mut mesh = make();
        let report = pool.install(|| run(&mut mesh, &Options::default()));
        check_guarantees(&report);
        for (v, (p, q)) in mesh.points().iter().zip(base.points()).enumerate() {
            if fixed[v] {
                assert_eq!(p.to_array().map(f64::to_bits), q.to_array().map(f64::to_bits));
            }
        }
        outputs.push(mesh.points().iter().map(|p| p.to_array().map(f64::to_bits)).collect::<Vec<_>>());
    }
    assert!(outputs.windows(2).all(|w| w[0] == w[1]));
}

/// A cylinder of radius 1 and height 2 without caps, `m` segments around, `k` along.
fn tube(m: u32, k: u32) -> (Vec<DVec3>, Vec<Face>) {
    grid(m, k, true, false, |i, j| {
        let a = 2.0 * PI * f64::from(i) / f64::from(m);
        DVec3::new(a.cos(), a.sin(), 2.0 * f64::from(j) / f64::from(k))
    })
}

#[test]
fn the_max_min_stage_runs_only_below_a_nearly_perfect_minimum() {
    // A fine tube of nearly square faces: the sweeps end within 1e-3 of a perfect minimum,
    // where the stage has nothing to gain (the plane's rule).
    let (m, k) = (96, 24);
    let (points, faces) = tube(m, k);
    let rim = |v: usize| v < m as usize || v >= (m * k) as usize;
    let mut fine = points.clone();
    let radial = |p: DVec3| DVec3::new(p.x, p.y, 0.0).normalize();
    perturb(&mut fine, 9, 0.002, rim, radial, |p| {
        let r = radial(p);
        DVec3::new(r.x, r.y, p.z)
    });
    let mut mesh = SurfaceMesh::new(fine, faces, None).unwrap();
    let report = run(&mut mesh, &Options::default().with_effort(Effort::Balanced));
    check_guarantees(&report);
    assert!(report.output.min >= 1.0 - 1e-3, "{report:?}");
    assert!(report.max_min.is_none(), "{report:?}");
    // A perturbed sphere stays further from it: the stage runs.
    let mut sphere = perturbed_sphere(6, 0.3, 3);
    let report = run(&mut sphere, &Options::default().with_effort(Effort::Balanced));
    check_guarantees(&report);
    assert!(report.output.min < 1.0 - 1e-3, "{report:?}");
    assert!(report.max_min.is_some(), "{report:?}");
}

#[test]
fn tube_rims_are_slid_along_and_the_wall_is_kept() {
    let (m, k) = (24, 8);
    let (mut points, faces) = tube(m, k);
    let rim = |v: usize| v < m as usize || v >= (m * k) as usize;
    let radial = |p: DVec3| DVec3::new(p.x, p.y, 0.0).normalize();
    perturb(&mut points, 5, 0.12, rim, radial, |p| {
        let r = radial(p);
        DVec3::new(r.x, r.y, p.z)
    });
    // The rims too, along themselves.
    for (v, p) in points.iter_mut().enumerate() {
        if rim(v) && v % 3 == 1 {
            let a = p.y.atan2(p.x) + 0.3 * 2.0 * PI / f64::from(m);
            *p = DVec3::new(a.cos(), a.sin(), p.z);
        }
    }
    let input = points.clone();
    let mut mesh = SurfaceMesh::new(points, faces, None).unwrap();
    let report = run(&mut mesh, &Options::default());
    check_guarantees(&report);
    assert_eq!((report.feature_curves, report.corners), (2, 0));
    assert!(report.output.min > report.input.min + 0.05, "{report:?}");
    for (v, p) in mesh.points().iter().enumerate() {
        if rim(v) {
            assert_eq!(p.z, input[v].z, "rim vertex {v} left its rim");
        }
        // On the input's flat faces: never outside the cylinder, and inside it by at most a
        // face's sag (a perturbed face spans less than 35 degrees: cos 17.5 > 0.95).
        let r = DVec3::new(p.x, p.y, 0.0).length();
        assert!(r <= 1.0 + 1e-12 && r > 0.95, "{p}");
    }
}

#[test]
fn a_fold_is_untangled_on_the_sphere() {
    let (mut points, faces) = cube_sphere(6);
    // Push one vertex past its neighbour, along the sphere: its faces fold over.
    let v = faces[40][0] as usize;
    let u = faces[40][2] as usize;
    points[v] = (points[v] + (points[u] - points[v]) * 1.6).normalize();
    let mut mesh = SurfaceMesh::new(points, faces, None).unwrap();
    let report = run(&mut mesh, &Options::default());
    assert!(report.input.inverted > 0, "{report:?}");
    check_guarantees(&report);
    assert_eq!(report.output.inverted, 0, "{report:?}");
    // The fold is not taken for a feature: the sphere stays one patch.
    assert_eq!((report.patches, report.feature_curves), (1, 0));
}

#[test]
fn a_moved_mesh_or_other_faces_are_refused() {
    let mesh = perturbed_sphere(4, 0.3, 1);
    let optimizer = SurfaceOptimizer::new(&mesh, 45.0, &[]).unwrap();
    let mut other =
        SurfaceMesh::new(mesh.points()[..mesh.points().len()].to_vec(), mesh.faces()[1..].to_vec(), None);
    if let Ok(other) = other.as_mut() {
        assert!(optimizer.run(other, &Options::default(), None).is_err());
    }
    let mut moved = mesh.clone();
    let mut p = moved.points().to_vec();
    p[0] *= 1.01;
    moved.set_points(&p).unwrap();
    let before = moved.points().to_vec();
    assert!(optimizer.run(&mut moved, &Options::default(), None).is_err());
    assert_eq!(moved.points(), &before[..]);
    assert!(SurfaceOptimizer::new(&mesh, 45.0, &[[0, 0]]).is_err());
}

/// A torus (radii 2 and 0.6) of `nu` x `nv` quads, and the torus's exact normal at a point.
fn torus(nu: u32, nv: u32) -> (Vec<DVec3>, Vec<Face>) {
    grid(nu, nv, true, true, |i, j| {
        let (t, p) = (2.0 * PI * f64::from(i) / f64::from(nu), 2.0 * PI * f64::from(j) / f64::from(nv));
        let r = 2.0 + 0.6 * p.cos();
        DVec3::new(r * t.cos(), r * t.sin(), 0.6 * p.sin())
    })
}

fn torus_normal(p: DVec3) -> DVec3 {
    let centre = DVec3::new(p.x, p.y, 0.0).normalize() * 2.0;
    (p - centre).normalize()
}

fn onto_torus(p: DVec3) -> DVec3 {
    let centre = DVec3::new(p.x, p.y, 0.0).normalize() * 2.0;
    centre + (p - centre).normalize() * 0.6
}

/// A map of 3D points (a surface's normal, or the projection onto it).
type Map = fn(DVec3) -> DVec3;

/// Random meshes on closed and open surfaces, quads and triangles, random fixed vertices and
/// presets: every run keeps the guarantees (never worse by the signed measure, no face valid
/// in the input inverted, on the input surface and curves), fixed vertices and corners keep
/// their bits, and the run is the same again.
#[test]
fn random_surface_meshes_keep_every_guarantee() {
    let mut rng = Rng(0x5eed);
    for case in 0..24u64 {
        let kind = case % 3;
        let (mut points, mut faces, normal, onto): (_, _, Map, Map) = match kind {
            0 => {
                let (p, f) = cube_sphere(3 + (case % 4) as u32);
                (p, f, |p: DVec3| p.normalize(), |p: DVec3| p.normalize())
            }
            1 => {
                let (p, f) = torus(16 + 2 * (case % 3) as u32, 8);
                (p, f, torus_normal, onto_torus)
            }
            _ => {
                let (p, f) = tube(12 + (case % 5) as u32, 4);
                let radial = |p: DVec3| DVec3::new(p.x, p.y, 0.0).normalize();
                (p, f, radial, |p: DVec3| {
                    let r = DVec3::new(p.x, p.y, 0.0).normalize();
                    DVec3::new(r.x, r.y, p.z)
                })
            }
        };
        // Split some quads into two triangles: a quad-dominant mesh.
        if case % 2 == 1 {
            let mut split = Vec::new();
            for f in faces {
                if rng.next() > 0.6 {
                    split.push(quadopt::face::triangle(f[0], f[1], f[2]));
                    split.push(quadopt::face::triangle(f[0], f[2], f[3]));
                } else {
                    split.push(f);
                }
            }
            faces = split;
        }
        let n = points.len();
        let open_rim = |v: usize| kind == 2 && (points_rim(v, n));
        let amount = 0.08 + 0.25 * (rng.next() + 1.0) / 2.0;
        perturb(&mut points, case, amount, open_rim, normal, onto);
        let fixed: Vec<bool> = (0..n).map(|_| rng.next() > 0.85).collect();
        let effort = Effort::ALL[(case % 3) as usize];
        let input = points.clone();
        let make = || SurfaceMesh::new(input.clone(), faces.clone(), Some(fixed.clone())).unwrap();
        let mut mesh = make();
        let optimizer = SurfaceOptimizer::new(&mesh, 45.0, &[]).unwrap();
        let input_values = optimizer.input_values();
        let report = optimizer.run(&mut mesh, &Options::default().with_effort(effort), None).unwrap();
        check_guarantees(&report);
        let output = optimizer.measure(mesh.points()).unwrap();
        // Measured again from the positions alone (the normals projected anew): the same up
        // to rounding.
        let (a, b) = (output.signed, report.output);
        assert!(
            a.inverted == b.inverted && (a.min - b.min).abs() < 1e-12 && (a.avg - b.avg).abs() < 1e-12,
            "case {case}: {a:?} {b:?}"
        );
        for (f, (&before, &after)) in input_values.iter().zip(&output.values).enumerate() {
            assert!(before <= 0.0 || after > 0.0, "case {case}: face {f} inverted ({before} -> {after})");
        }
        let roles = optimizer.features().roles();
        for v in 0..n {
            if fixed[v] || roles[v] == quadopt::surface::VertexRole::Corner {
                assert_eq!(
                    mesh.points()[v].to_array().map(f64::to_bits),
                    input[v].to_array().map(f64::to_bits)
                );
            }
        }
        let mut again = make();
        optimizer.run(&mut again, &Options::default().with_effort(effort), None).unwrap();
        assert_eq!(again.points(), mesh.points(), "case {case}");
    }
}

/// The rim vertices of [`tube`] with `n` vertices: its first and last rings (of `n / 5` each
/// for the 4-row tubes of the random test).
fn points_rim(v: usize, n: usize) -> bool {
    let ring = n / 5;
    v < ring || v >= n - ring
}

/// The surface samples of `data/` under every preset: folds repaired, never worse, on the
/// surface and the curves, Verdict's minimum raised too.
#[test]
fn surface_samples_are_repaired_by_every_preset() {
    let files = common::samples::surface_sample_files();
    assert_eq!(files.len(), 4, "{files:?}");
    for path in files {
        let data = quadopt::io::read_mesh(&path).unwrap();
        let points: Vec<DVec3> = data.points.iter().map(|&p| DVec3::from_array(p)).collect();
        for effort in Effort::ALL {
            let mut mesh = SurfaceMesh::new(points.clone(), data.quads.clone(), None).unwrap();
            let report = run(&mut mesh, &Options::default().with_effort(effort));
            check_guarantees(&report);
            let name = path.display();
            assert!(report.input.inverted > 0 && report.output.inverted == 0, "{name} {effort}: {report:?}");
            assert!(
                report.output.min > 0.15 && report.output.avg > report.input.avg,
                "{name} {effort}: {report:?}"
            );
            assert!(report.output_verdict.min > report.input_verdict.min, "{name} {effort}: {report:?}");
            assert!(report.feature_curves > 0 || report.patches == 1, "{name}");
        }
    }
}

/// Mesquite's three meshes on curved surfaces (CI-only: `../shared`), under every preset: the
/// guarantees, and the minimum raised.
#[test]
fn mesquite_curved_meshes_are_improved_on_their_surfaces() {
    let Some(dir) = common::shared::mesquite("Mesquite's curved meshes") else { return };
    for name in ["bias-sphere-quads", "quads_on_sphere_529", "paraboloid"] {
        let data = quadopt::io::read_mesh(dir.join("untangled").join(format!("{name}.vtk"))).unwrap();
        let points: Vec<DVec3> = data.points.iter().map(|&p| DVec3::from_array(p)).collect();
        for effort in Effort::ALL {
            let mut mesh = SurfaceMesh::new(points.clone(), data.quads.clone(), None).unwrap();
            let report = run(&mut mesh, &Options::default().with_effort(effort));
            check_guarantees(&report);
            assert!(report.output.min > report.input.min, "{name} {effort}: {report:?}");
            assert_eq!(report.output.inverted, 0, "{name} {effort}");
        }
    }
}

#[test]
fn a_cone_apex_shared_by_thousands_of_quads_keeps_every_face() {
    // Only the apex can move (the zigzag boundary is all corners). Its star is 5,000 faces: a
    // vertex lookup in it was quadratic (benches/fans.rs times it). Every face is below the
    // guard's floor, so each is bounded by its own input value: the apex may move only where
    // no face gets worse.
    let (points, faces) = common::surfaces::cone_apex(5000, 3);
    let input = SurfaceMesh::new(points, faces, None).unwrap();
    let values = |m: &SurfaceMesh| {
        SurfaceOptimizer::new(m, 45.0, &[]).unwrap().measure(m.points()).unwrap().verdict_values
    };
    for effort in [Effort::Fast, Effort::Balanced, Effort::Best] {
        let mut mesh = input.clone();
        let report = run(&mut mesh, &Options::default().with_effort(effort));
        check_guarantees(&report);
        assert_eq!(report.movable, 1);
        assert_eq!(&mesh.points()[1..], &input.points()[1..]);
        let (before, after) = (values(&input), values(&mesh));
        assert!(before.iter().zip(&after).all(|(b, a)| a >= b), "{effort:?}: a face got worse");
    }
}

//! Quad-dominant meshes (triangles among the quads) get the guarantees of quad meshes: every
//! preset and baseline keeps the faces valid that were valid, never lowers the minimum, keeps
//! fixed vertices bit-identical and boundary vertices on their polyline; triangles are
//! measured as Verdict's triangles; fixed triangles leave the quads' run as it was.

mod common;

use common::Rng;
use common::grids::Grid;
use quadopt::face::{self, NO_VERTEX};
use quadopt::{BoundaryMode, DVec2, Effort, Mesh, Method, Optimizer, Options, Topology, VertexKind};

/// An n x n grid of unit cells with every `every`-th cell split into two triangles along a
/// diagonal, interior vertices jittered by `amount` of the cell: a quad-dominant mesh.
fn mixed_grid(n: usize, every: usize, amount: f64, seed: u64) -> Mesh {
    let grid = Grid::square(n);
    let mut rng = Rng(seed);
    let points = grid.points(|i, j| {
        let p = DVec2::new(i as f64, j as f64);
        if grid.is_interior(i, j) { p + amount * DVec2::new(rng.next(), rng.next()) } else { p }
    });
    let mut faces = Vec::new();
    for (k, q) in grid.quads().into_iter().enumerate() {
        if k % every == every / 2 {
            // Alternate diagonals so that both kinds of triangle corners meet the boundary.
            if k % 2 == 0 {
                faces.push(face::triangle(q[0], q[1], q[2]));
                faces.push(face::triangle(q[0], q[2], q[3]));
            } else {
                faces.push(face::triangle(q[0], q[1], q[3]));
                faces.push(face::triangle(q[1], q[2], q[3]));
            }
        } else {
            faces.push(q);
        }
    }
    Mesh::with_faces(points, faces, None).unwrap()
}

fn presets() -> [(&'static str, Options); 6] {
    [
        ("fast", Options::default().with_effort(Effort::Fast)),
        ("balanced", Options::default()),
        ("best", Options::default().with_effort(Effort::Best)),
        ("laplace", Options::default().with_method(Method::Laplacian).with_max_min(false)),
        ("cotan", Options::default().with_method(Method::Cotangent).with_max_min(false)),
        ("angle", Options::default().with_method(Method::AngleBased).with_max_min(false)),
    ]
}

/// Whether `p` lies on the original boundary polyline of `mesh` (within `tol`).
fn on_boundary(original: &Mesh, topo: &Topology, p: DVec2, tol: f64) -> bool {
    topo.boundary_loops().any(|lp| {
        (0..lp.len()).any(|i| {
            let (a, b) =
                (original.points()[lp[i] as usize], original.points()[lp[(i + 1) % lp.len()] as usize]);
            let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            (a + t * (b - a) - p).length() <= tol
        })
    })
}

#[test]
fn every_preset_keeps_the_guarantees_on_quad_dominant_meshes() {
    for (seed, amount) in [(1, 0.3), (2, 0.45), (3, 0.7)] {
        let input = mixed_grid(12, 5, amount, seed);
        assert!(input.triangle_count() > 10);
        let topo = Topology::new(&input);
        let before = input.quality();
        for (name, options) in presets() {
            for boundary in [BoundaryMode::Slide, BoundaryMode::Snap, BoundaryMode::Fixed] {
                let mut mesh = input.clone();
                let report = Optimizer::new(&mesh)
                    .run(&mut mesh, &options.clone().with_boundary(boundary), None)
                    .unwrap();
                let after = mesh.quality();
                let what = format!("{name} {boundary:?} seed {seed}");
                assert_eq!(mesh.faces(), input.faces(), "{what}: connectivity kept");
                assert!(
                    after.inverted <= before.inverted,
                    "{what}: {} -> {}",
                    before.inverted,
                    after.inverted
                );
                if before.inverted == 0 {
                    assert!(after.min >= before.min, "{what}: min {} -> {}", before.min, after.min);
                }
                assert_eq!(report.output, after, "{what}");
                // No face that was valid is inverted now.
                for (k, (&b, &a)) in input.quality_values().iter().zip(&mesh.quality_values()).enumerate() {
                    assert!(!(b > 0.0 && a <= 0.0), "{what}: face {k} {b} -> {a}");
                }
                for (v, (&p, &q)) in input.points().iter().zip(mesh.points()).enumerate() {
                    match topo.kind(v) {
                        VertexKind::Boundary => {
                            assert!(
                                on_boundary(&input, &topo, q, 1e-12),
                                "{what}: vertex {v} left the boundary"
                            )
                        }
                        _ if input.fixed()[v] => assert_eq!(p.to_array(), q.to_array()),
                        _ => {}
                    }
                }
                let kinds = report.output_by_kind;
                assert_eq!(
                    (kinds.quad_count + kinds.triangle_count, kinds.triangle_count),
                    (144 + input.triangle_count() / 2, input.triangle_count()),
                    "{what}"
                );
                assert_eq!(report.input_by_kind, input.quality_by_face_kind(), "{what}");
                assert_eq!(kinds, mesh.quality_by_face_kind(), "{what}");
            }
        }
    }
}

#[test]
fn tangled_quad_dominant_meshes_are_untangled() {
    let input = mixed_grid(10, 4, 0.9, 7);
    let before = input.quality();
    assert!(before.inverted > 0, "the perturbation inverts faces");
    for (name, options) in presets().into_iter().take(3) {
        let mut mesh = input.clone();
        let report = quadopt::optimize(&mut mesh, &options).unwrap();
        assert_eq!(report.output.inverted, 0, "{name}: {:?}", report.tangled);
        assert!(report.output.min > 0.2, "{name}: {}", report.output.min);
    }
}

#[test]
fn triangles_are_measured_as_verdict_triangles() {
    // An equilateral triangle scores 1, a right isosceles one sin(45 deg) 2/sqrt(3).
    let h = 3.0_f64.sqrt() / 2.0;
    let points = vec![
        DVec2::new(0., 0.),
        DVec2::new(1., 0.),
        DVec2::new(0.5, h),
        DVec2::new(0., 1.),
        DVec2::new(1., 1.),
    ];
    let mesh = Mesh::with_faces(points.clone(), vec![face::triangle(0, 1, 2)], None).unwrap();
    assert!((mesh.quality().min - 1.0).abs() < 1e-15);
    let right = Mesh::with_faces(points.clone(), vec![face::triangle(0, 1, 3)], None).unwrap();
    let want = 0.5_f64.sqrt() * 2.0 / 3.0_f64.sqrt();
    assert!((right.quality().min - want).abs() < 1e-15, "{}", right.quality().min);
    // A clockwise triangle next to a counter-clockwise quad is inverted.
    let folded = Mesh::with_faces(
        vec![
            DVec2::new(0., 0.),
            DVec2::new(1., 0.),
            DVec2::new(1., 1.),
            DVec2::new(0., 1.),
            DVec2::new(0.5, 0.5),
        ],
        vec![[0, 1, 2, 3], face::triangle(2, 3, 4)],
        None,
    )
    .unwrap();
    let values = folded.quality_values();
    assert!(values[1] < 0.0 && values[0] > 0.0, "{values:?}");
    let kinds = folded.quality_by_face_kind();
    assert_eq!((kinds.quad_count, kinds.triangle_count), (1, 1));
    assert_eq!(kinds.triangles.unwrap().inverted, 1);
}

#[test]
fn malformed_faces_are_refused() {
    let p = vec![DVec2::new(0., 0.), DVec2::new(1., 0.), DVec2::new(0., 1.)];
    // The sentinel is a fourth vertex only.
    assert!(Mesh::with_faces(p.clone(), vec![[0, NO_VERTEX, 1, 2]], None).is_err());
    assert!(Mesh::with_faces(p.clone(), vec![face::triangle(0, 1, 1)], None).is_err());
    assert!(Mesh::with_faces(p.clone(), vec![face::triangle(0, 1, 3)], None).is_err());
    // The quad-only constructor refuses triangles.
    assert!(Mesh::new(p.clone(), vec![face::triangle(0, 1, 2)], None).is_err());
    assert_eq!(Mesh::with_faces(p, vec![face::triangle(0, 1, 2)], None).unwrap().triangle_count(), 1);
}

#[test]
fn fixed_triangles_leave_the_quads_run_as_it_was() {
    // A jittered quad grid with its boundary fixed, then the same grid with a fan of fixed
    // triangles glued along its bottom side: the quads' interior vertices see only quads, so
    // they end where they ended without the triangles, up to the rounding of the normalized
    // frame, which the triangles' vertices widen (2e-8 measured).
    let n = 8;
    let grid = Grid::square(n);
    let mut rng = Rng(11);
    let points = grid.points(|i, j| {
        let p = DVec2::new(i as f64, j as f64);
        if grid.is_interior(i, j) { p + 0.35 * DVec2::new(rng.next(), rng.next()) } else { p }
    });
    let quads = grid.quads();
    let options = Options::default().with_boundary(BoundaryMode::Fixed);
    let mut alone = Mesh::new(points.clone(), quads.clone(), None).unwrap();
    quadopt::optimize(&mut alone, &options).unwrap();

    // One equilateral triangle on each bottom edge: quality 1, never the worst face.
    let mut mixed_points = points.clone();
    let mut faces = quads.clone();
    for i in 0..n {
        let apex = mixed_points.len() as u32;
        mixed_points.push(DVec2::new(i as f64 + 0.5, -(3.0_f64.sqrt()) / 2.0));
        faces.push(face::triangle(grid.index(i + 1, 0) as u32, grid.index(i, 0) as u32, apex));
    }
    let mut fixed = vec![false; mixed_points.len()];
    for f in faces.iter().filter(|f| face::is_triangle(f)) {
        for &v in face::vertices(f) {
            fixed[v as usize] = true;
        }
    }
    let mut mixed = Mesh::with_faces(mixed_points.clone(), faces, Some(fixed)).unwrap();
    assert_eq!(mixed.triangle_count(), n);
    quadopt::optimize(&mut mixed, &options).unwrap();
    for v in 0..points.len() {
        let (a, b) = (alone.points()[v], mixed.points()[v]);
        assert!((a - b).length() < 1e-6, "vertex {v}: {a} alone, {b} with the triangles");
    }
    assert_eq!(mixed.points()[points.len()..], mixed_points[points.len()..]);
    let quads_now = mixed.quality_by_face_kind().quads.unwrap();
    assert!((quads_now.min - alone.quality().min).abs() < 1e-6);
    assert!((quads_now.avg - alone.quality().avg).abs() < 1e-6);
}

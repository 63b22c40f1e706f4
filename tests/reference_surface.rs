//! The reference surface (src/surface): the exact point-triangle routine against an
//! independent computation, the tree's query against testing every triangle, distances to a
//! sphere against analytic bounds, degenerate triangles, and malformed input.

use std::collections::HashSet;
use std::f64::consts::{PI, TAU};

use glam::DVec3;
use quadopt::Error;
use quadopt::face::{self, Face, NO_VERTEX};
use quadopt::surface::{
    Closest, NO_TRIANGLE, ReferenceSurface, TriangleRegion, closest_point_on_segment,
    closest_point_on_triangle,
};
use rayon::prelude::*;

/// SplitMix64: a seeded generator, so every run tests the same points.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e3779b97f4a7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58476d1ce4e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d049bb133111eb);
        z ^ (z >> 31)
    }
    /// Uniform in [-1, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
    fn vec(&mut self, scale: f64) -> DVec3 {
        DVec3::new(self.unit(), self.unit(), self.unit()) * scale
    }
}

/// The closest point of a non-degenerate triangle by another method: the projection onto the
/// plane if its barycentric coordinates (solved by Cramer's rule) are all non-negative, else
/// the closest of the three edges.
fn reference_closest(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let n = (b - a).cross(c - a).normalize();
    let q = p - n * n.dot(p - a);
    let area = n.dot((b - a).cross(c - a));
    let u = n.dot((c - b).cross(q - b)) / area;
    let v = n.dot((a - c).cross(q - c)) / area;
    let w = 1.0 - u - v;
    if u >= 0.0 && v >= 0.0 && w >= 0.0 {
        return q;
    }
    [(a, b), (b, c), (c, a)]
        .into_iter()
        .map(|(s, t)| closest_point_on_segment(p, s, t).0)
        .min_by(|x, y| (p - *x).length().total_cmp(&(p - *y).length()))
        .unwrap()
}

#[test]
fn point_triangle_matches_an_independent_computation_in_every_region() {
    let mut rng = Rng(1);
    let mut regions = HashSet::new();
    for _ in 0..20_000 {
        let (a, b, c) = (rng.vec(1.0), rng.vec(1.0), rng.vec(1.0));
        // Skip slivers, where the reference's barycentric test is itself ill-conditioned.
        let n = (b - a).cross(c - a).length();
        if n < 0.05 {
            continue;
        }
        let p = rng.vec(2.0);
        let (q, region) = closest_point_on_triangle(p, a, b, c);
        regions.insert(region);
        let r = reference_closest(p, a, b, c);
        let (dq, dr) = ((p - q).length(), (p - r).length());
        assert!(
            (dq - dr).abs() <= 1e-12 * (1.0 + dr),
            "p {p} triangle {a} {b} {c}: {dq} vs {dr} ({region:?})"
        );
        assert!((q - r).length() <= 1e-9, "p {p} triangle {a} {b} {c}: {q} vs {r} ({region:?})");
        // The point is where the region says.
        match region {
            TriangleRegion::VertexA => assert_eq!(q, a),
            TriangleRegion::VertexB => assert_eq!(q, b),
            TriangleRegion::VertexC => assert_eq!(q, c),
            TriangleRegion::EdgeAB => assert!((q - a).cross(b - a).length() <= 1e-12),
            TriangleRegion::EdgeBC => assert!((q - b).cross(c - b).length() <= 1e-12),
            TriangleRegion::EdgeCA => assert!((q - c).cross(a - c).length() <= 1e-12),
            TriangleRegion::Interior => {
                // p - q is along the normal.
                assert!((p - q).cross((b - a).cross(c - a)).length() <= 1e-12 * (1.0 + (p - q).length()));
            }
            TriangleRegion::Degenerate => panic!("a triangle of area {n} is not degenerate"),
        }
    }
    use TriangleRegion::*;
    for r in [VertexA, VertexB, VertexC, EdgeAB, EdgeBC, EdgeCA, Interior] {
        assert!(regions.contains(&r), "region {r:?} never hit: {regions:?}");
    }
}

#[test]
fn degenerate_triangles_give_the_closest_point_of_their_edges_and_never_nan() {
    let mut rng = Rng(2);
    for k in 0..3000 {
        let a = rng.vec(1.0);
        let d = rng.vec(1.0);
        // All corners equal, two equal, three collinear (c between a and b, or beyond).
        let (b, c) = match k % 4 {
            0 => (a, a),
            1 => (a, d),
            2 => (a + d, a + d * 0.25),
            _ => (a + d, a + d * 3.0),
        };
        let p = rng.vec(2.0);
        let (q, region) = closest_point_on_triangle(p, a, b, c);
        assert!(q.is_finite(), "{a} {b} {c} {p}");
        // Exactly collinear corners in floating point are the first two cases; the others may
        // round to a tiny area and go through the regular regions, which must still agree.
        if k % 4 < 2 {
            assert_eq!(region, TriangleRegion::Degenerate);
        }
        let best = [(a, b), (b, c), (c, a)]
            .into_iter()
            .map(|(s, t)| (p - closest_point_on_segment(p, s, t).0).length())
            .fold(f64::INFINITY, f64::min);
        assert!(((p - q).length() - best).abs() <= 1e-12, "{a} {b} {c} {p}: {} vs {best}", (p - q).length());
    }
    // A surface made only of zero-area faces still answers.
    let points = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0, DVec3::X];
    let s = ReferenceSurface::new(&points, &[face::triangle(0, 1, 2), [0, 1, 2, 3]]).unwrap();
    let c = s.closest_point(DVec3::new(1.5, 2.0, 0.0));
    assert_eq!((c.point, c.distance, c.triangle, c.face), (DVec3::new(1.5, 0.0, 0.0), 2.0, 0, 0));
    assert_eq!(s.triangle_normal(0), DVec3::ZERO);
}

/// A parametric grid of quads over (u, v) in [0, 1]^2, `nu` x `nv` cells; `wrap_u`/`wrap_v`
/// close it in that direction.
fn grid(
    nu: usize,
    nv: usize,
    wrap_u: bool,
    wrap_v: bool,
    f: impl Fn(f64, f64) -> DVec3,
) -> (Vec<DVec3>, Vec<Face>) {
    let (cu, cv) = (if wrap_u { nu } else { nu + 1 }, if wrap_v { nv } else { nv + 1 });
    let mut points = Vec::new();
    for j in 0..cv {
        for i in 0..cu {
            points.push(f(i as f64 / nu as f64, j as f64 / nv as f64));
        }
    }
    let id = |i: usize, j: usize| ((j % cv) * cu + (i % cu)) as u32;
    let mut faces = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (points, faces)
}

fn torus(nu: usize, nv: usize) -> (Vec<DVec3>, Vec<Face>) {
    grid(nu, nv, true, true, |u, v| {
        let (u, v) = (u * TAU, v * TAU);
        DVec3::new((1.0 + 0.3 * v.cos()) * u.cos(), (1.0 + 0.3 * v.cos()) * u.sin(), 0.3 * v.sin())
    })
}

/// A latitude-longitude sphere of radius `r`: quads, and a fan of triangles at each pole.
fn sphere(nu: usize, nv: usize, r: f64) -> (Vec<DVec3>, Vec<Face>) {
    let at = |i: usize, j: usize| {
        let (u, v) = (i as f64 / nu as f64 * TAU, j as f64 / nv as f64 * PI);
        DVec3::new(v.sin() * u.cos(), v.sin() * u.sin(), v.cos()) * r
    };
    let mut points = vec![DVec3::Z * r, -DVec3::Z * r];
    for j in 1..nv {
        for i in 0..nu {
            points.push(at(i, j));
        }
    }
    let id = |i: usize, j: usize| (2 + (j - 1) * nu + i % nu) as u32;
    let mut faces = Vec::new();
    for i in 0..nu {
        faces.push(face::triangle(0, id(i, 1), id(i + 1, 1)));
    }
    for j in 1..nv - 1 {
        for i in 0..nu {
            faces.push([id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)]);
        }
    }
    for i in 0..nu {
        faces.push(face::triangle(1, id(i + 1, nv - 1), id(i, nv - 1)));
    }
    (points, faces)
}

/// The tree's answer is exactly that of testing every triangle, with and without a hint,
/// and on any number of threads.
fn check_tree(points: &[DVec3], faces: &[Face], spread: f64, seed: u64) {
    let s = ReferenceSurface::new(points, faces).unwrap();
    let mut rng = Rng(seed);
    let queries: Vec<DVec3> = (0..3000)
        .map(|k| match k % 3 {
            // Near a vertex, near the surface, and anywhere around it.
            0 => points[(rng.next() % points.len() as u64) as usize] + rng.vec(0.02),
            1 => points[(rng.next() % points.len() as u64) as usize] + rng.vec(spread * 0.2),
            _ => rng.vec(spread * 1.5),
        })
        .chain(points.iter().copied())
        .collect();
    let hints: Vec<u32> = queries.iter().map(|_| (rng.next() % s.triangle_count() as u64) as u32).collect();
    let serial: Vec<Closest> = queries.iter().map(|&q| s.closest_point(q)).collect();
    for ((&q, c), &hint) in queries.iter().zip(&serial).zip(&hints) {
        assert_eq!(*c, s.closest_point_exhaustive(q), "query {q}");
        assert_eq!(*c, s.closest_point_from(q, hint), "query {q} hint {hint}");
        assert_eq!(c.face, s.triangle_face(c.triangle));
        assert_eq!(c.distance, (q - c.point).length());
    }
    // A vertex of the surface is on it.
    for c in &serial[3000..] {
        assert_eq!(c.distance, 0.0);
    }
    let parallel: Vec<Closest> = queries.par_iter().map(|&q| s.closest_point(q)).collect();
    assert_eq!(serial, parallel);
}

#[test]
fn the_tree_finds_what_testing_every_triangle_finds_on_a_torus() {
    let (points, faces) = torus(40, 24);
    check_tree(&points, &faces, 1.3, 3);
}

#[test]
fn the_tree_finds_what_testing_every_triangle_finds_on_a_sphere() {
    let (points, faces) = sphere(32, 20, 1.0);
    check_tree(&points, &faces, 1.0, 4);
}

#[test]
fn the_tree_finds_what_testing_every_triangle_finds_on_a_plane() {
    // Exact ties: many points are equally close to two or more triangles of the plane.
    // Cells of 1/8, so every coordinate and every product in the query is exact.
    let (points, faces) = grid(32, 16, false, false, |u, v| DVec3::new(u * 4.0, v * 2.0, 0.0));
    check_tree(&points, &faces, 2.0, 5);
    let s = ReferenceSurface::new(&points, &faces).unwrap();
    // Above the grid vertex (1/2, 1/2), shared by six triangles at distance exactly 1: the
    // lowest-numbered one.
    let q = DVec3::new(0.5, 0.5, 1.0);
    let c = s.closest_point(q);
    assert_eq!((c.point, c.distance), (DVec3::new(0.5, 0.5, 0.0), 1.0));
    let tied: Vec<u32> = (0..s.triangle_count() as u32)
        .filter(|&t| {
            let [a, b, c] = s.triangle_corners(t);
            (q - closest_point_on_triangle(q, a, b, c).0).length() == 1.0
        })
        .collect();
    assert_eq!(tied.len(), 6, "{tied:?}");
    assert_eq!(c.triangle, tied[0]);
    assert_eq!(s.closest_point_from(q, tied[5]), c);
}

/// The local walk from the triangle of a point on the surface finds the closest point the
/// exhaustive search finds, for a step of up to `step` along the triangle's plane and up to
/// `near` off it: how the optimizer uses it, a vertex's candidate lifted from its tangent
/// plane, walked from its triangle. (Far off the surface the distance can have several local
/// minima, one near each triangle on the concave side; the walk finds the one of its sheet.)
fn check_walk(points: &[DVec3], faces: &[Face], near: f64, step: f64, seed: u64) {
    let s = ReferenceSurface::new(points, faces).unwrap();
    let mut rng = Rng(seed);
    for _ in 0..3000 {
        let from = s.closest_point(points[(rng.next() % points.len() as u64) as usize] + rng.vec(0.05));
        let n = s.triangle_normal(from.triangle).normalize();
        let along = rng.vec(step);
        let q = from.point + (along - n * n.dot(along)) + n * (rng.unit() * near);
        let walked = s.closest_point_near(q, from.triangle);
        let exact = s.closest_point_exhaustive(q);
        assert!(
            (walked.distance - exact.distance).abs() <= 1e-12
                && (walked.point - exact.point).length() <= 1e-12,
            "query {q} from {from:?}: walked {walked:?}, exhaustive {exact:?}"
        );
        assert_eq!(walked.face, s.triangle_face(walked.triangle));
        assert_eq!(walked.distance, (q - walked.point).length());
        // The same query gives the same answer (the optimizer's determinism rests on it).
        assert_eq!(walked, s.closest_point_near(q, from.triangle));
    }
}

#[test]
fn the_walk_from_a_nearby_triangle_finds_the_closest_point_on_a_sphere_and_a_torus() {
    // Sphere edges of about 0.1 to 0.2, torus edges of 0.05 to 0.16: steps of two edges.
    let (points, faces) = sphere(32, 20, 1.0);
    check_walk(&points, &faces, 0.02, 0.3, 6);
    let (points, faces) = torus(40, 24);
    check_walk(&points, &faces, 0.01, 0.1, 7);
}

#[test]
fn the_walk_from_any_triangle_finds_the_closest_point_on_a_plane() {
    // The distance to a convex planar region has no local minimum but the global one, so the
    // walk (or, past its step limit, the tree) finds the exhaustive distance from any start:
    // across edges, around interior vertices, and along the border and round its corners for
    // points outside the grid.
    let (points, faces) = grid(32, 16, false, false, |u, v| DVec3::new(u * 4.0, v * 2.0, 0.0));
    let s = ReferenceSurface::new(&points, &faces).unwrap();
    let mut rng = Rng(8);
    for k in 0..4000 {
        let q = match k % 2 {
            0 => DVec3::new(2.0, 1.0, 0.0) + rng.vec(3.0),
            // Near a grid vertex, where the walk goes round the vertex's fan.
            _ => points[(rng.next() % points.len() as u64) as usize] + rng.vec(0.01),
        };
        let hint = (rng.next() % s.triangle_count() as u64) as u32;
        let walked = s.closest_point_near(q, hint);
        let exact = s.closest_point_exhaustive(q);
        assert!(
            (walked.distance - exact.distance).abs() <= 1e-12,
            "query {q} hint {hint}: {walked:?} {exact:?}"
        );
    }
}

#[test]
fn the_walk_stays_on_the_sheet_it_starts_on() {
    // Two parallel sheets 0.01 apart: a point 0.008 above the lower one, walked from a lower
    // triangle, stays on the lower sheet (0.008 away) where the global query takes the upper
    // one (0.002 away): a vertex on one side of a thin wall is kept on its side.
    let (lower, lower_faces) = grid(8, 8, false, false, |u, v| DVec3::new(u, v, 0.0));
    let (upper, upper_faces) = grid(8, 8, false, false, |u, v| DVec3::new(u, v, 0.01));
    let n = lower.len() as u32;
    let points: Vec<DVec3> = lower.iter().chain(&upper).copied().collect();
    let faces: Vec<Face> =
        lower_faces.iter().copied().chain(upper_faces.iter().map(|f| f.map(|v| v + n))).collect();
    let s = ReferenceSurface::new(&points, &faces).unwrap();
    let q = DVec3::new(0.43, 0.61, 0.008);
    let global = s.closest_point(q);
    assert!((global.distance - 0.002).abs() < 1e-12 && global.face >= 64, "{global:?}");
    let lower_start = s.closest_point(DVec3::new(0.05, 0.05, -0.1)).triangle;
    let walked = s.closest_point_near(q, lower_start);
    assert!((walked.distance - 0.008).abs() < 1e-12 && walked.face < 64, "{walked:?}");
    assert_eq!(walked.point, DVec3::new(0.43, 0.61, 0.0));
}

#[test]
fn the_walk_without_a_triangle_to_start_from_is_the_global_query() {
    let (points, faces) = torus(40, 24);
    let s = ReferenceSurface::new(&points, &faces).unwrap();
    let mut rng = Rng(9);
    for _ in 0..500 {
        let q = rng.vec(2.0);
        let global = s.closest_point(q);
        assert_eq!(s.closest_point_near(q, NO_TRIANGLE), global);
        assert_eq!(s.closest_point_near(q, s.triangle_count() as u32), global);
    }
    // A point that is not finite gives what the global query gives for it, never a panic.
    let nan = DVec3::new(f64::NAN, 0.0, 0.0);
    assert_eq!(format!("{:?}", s.closest_point_near(nan, 3)), format!("{:?}", s.closest_point(nan)));
}

#[test]
fn distances_to_a_sphere_mesh_lie_within_its_analytic_bounds() {
    let r = 2.0;
    let (points, faces) = sphere(48, 24, r);
    let s = ReferenceSurface::new(&points, &faces).unwrap();
    // Every triangle lies between the sphere and its plane's distance from the centre.
    let inner = (0..s.triangle_count() as u32)
        .map(|t| s.triangle_normal(t).dot(s.triangle_corners(t)[0]))
        .fold(f64::INFINITY, f64::min);
    assert!(inner > 0.99 * r && inner < r, "{inner}");
    let mut rng = Rng(6);
    for _ in 0..5000 {
        let dir = loop {
            let d = rng.vec(1.0);
            if d.length() > 0.1 {
                break d.normalize();
            }
        };
        let radius = r * (1.0 + 0.5 * rng.unit());
        let q = dir * radius;
        let c = s.closest_point(q);
        // The closest point is on the mesh, so between the two spheres.
        let at = c.point.length();
        assert!(at <= r * (1.0 + 1e-14) && at >= inner * (1.0 - 1e-14), "{at}");
        // Outside: at least radius - r away, at most radius - inner (the mesh point on the
        // ray through q). Inside the inner sphere: the mirror bounds.
        let slack = 1e-12;
        if radius >= r {
            assert!(
                c.distance >= radius - r - slack && c.distance <= radius - inner + slack,
                "{radius} {}",
                c.distance
            );
        } else if radius <= inner {
            assert!(
                c.distance >= inner - radius - slack && c.distance <= r - radius + slack,
                "{radius} {}",
                c.distance
            );
        } else {
            assert!(c.distance <= r - inner + slack, "{radius} {}", c.distance);
        }
    }
}

#[test]
fn triangles_come_in_face_order_and_quads_are_split_as_documented() {
    let (points, faces) = sphere(6, 4, 1.0);
    let s = ReferenceSurface::new(&points, &faces).unwrap();
    // 6 + 6 pole triangles and 12 quads.
    assert_eq!(s.triangle_count(), 12 + 2 * 12);
    let mut t = 0;
    for (i, f) in faces.iter().enumerate() {
        let tris: Vec<[u32; 3]> = s.triangles()[t..t + face::corner_count(f) - 2].to_vec();
        for k in 0..tris.len() {
            assert_eq!(s.triangle_face((t + k) as u32), i as u32);
        }
        if face::is_triangle(f) {
            assert_eq!(tris, vec![[f[0], f[1], f[2]]]);
        } else {
            assert!(
                tris == vec![[f[0], f[1], f[2]], [f[0], f[2], f[3]]]
                    || tris == vec![[f[0], f[1], f[3]], [f[1], f[2], f[3]]],
                "{f:?} {tris:?}"
            );
            // Outward, as the faces are.
            for k in 0..2 {
                let n = s.triangle_normal((t + k) as u32);
                assert!(n.dot(s.triangle_corners((t + k) as u32)[0]) > 0.0);
            }
        }
        t += tris.len();
    }
    // A roof-shaped quad: the flatter fold (b-d, 54.7 degrees against a-c's 60) is chosen,
    // so the surface holds the diagonal b-d at z = 0 (a-c would put (1/2, 1/2) at z = 1/2).
    let points = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 1.0), DVec3::Y];
    let s = ReferenceSurface::new(&points, &[[0, 1, 2, 3]]).unwrap();
    assert_eq!(s.triangles(), &[[0, 1, 3], [1, 2, 3]]);
    let c = s.closest_point(DVec3::new(0.5, 0.5, 0.0));
    assert_eq!(c.distance, 0.0);
}

#[test]
fn malformed_input_is_an_error() {
    let p = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE];
    assert_eq!(ReferenceSurface::new(&p, &[]).unwrap_err(), Error::NoQuads);
    assert_eq!(
        ReferenceSurface::new(&p, &[[0, 1, 4, 2]]).unwrap_err(),
        Error::IndexOutOfRange { quad: 0, corner: 2, index: 4, vertex_count: 4 }
    );
    assert_eq!(
        ReferenceSurface::new(&p, &[face::triangle(0, 1, 2), [0, NO_VERTEX, 1, 2]]).unwrap_err(),
        Error::IndexOutOfRange { quad: 1, corner: 1, index: NO_VERTEX as u64, vertex_count: 4 }
    );
    assert_eq!(
        ReferenceSurface::new(&p, &[[0, 1, 2, 1]]).unwrap_err(),
        Error::RepeatedVertex { quad: 0, vertex: 1 }
    );
    let mut bad = p;
    bad[3].z = f64::NAN;
    assert_eq!(
        ReferenceSurface::new(&bad, &[face::triangle(0, 1, 2)]).unwrap_err(),
        Error::NonFiniteCoordinate { vertex: 3 }
    );
    bad[3].z = f64::INFINITY;
    assert_eq!(
        ReferenceSurface::new(&bad, &[face::triangle(0, 1, 2)]).unwrap_err(),
        Error::NonFiniteCoordinate { vertex: 3 }
    );
    // An unused vertex is fine, and a hint that is not a triangle is ignored.
    let s = ReferenceSurface::new(&p, &[face::triangle(0, 1, 2)]).unwrap();
    // A query point that is not finite gives NaN, not a panic.
    for q in [DVec3::new(f64::NAN, 0.0, 0.0), DVec3::new(0.0, f64::INFINITY, 0.0)] {
        for c in [s.closest_point(q), s.closest_point_from(q, 0), s.closest_point_exhaustive(q)] {
            assert!(c.distance.is_nan() && c.point.is_nan() && c.triangle == 0, "{c:?}");
        }
    }
    assert_eq!(
        s.closest_point_from(DVec3::new(0.2, 0.2, 1.0), 99),
        s.closest_point(DVec3::new(0.2, 0.2, 1.0))
    );
}

#[test]
fn thin_triangles_give_a_point_on_the_triangle_no_farther_than_its_edges() {
    // Needles (one tiny angle) and slivers (one angle near pi), down to widths near rounding:
    // the point must lie on the triangle (in its plane, inside its edges) and be no farther
    // than the closest edge point.
    let mut rng = Rng(7);
    for k in 0..4000 {
        let a = rng.vec(1.0);
        let d = rng.vec(1.0);
        let e = rng.vec(1.0);
        let width = 10f64.powi(-3 - (k % 10));
        let (b, c) = if k % 2 == 0 {
            // A needle: tip a, short far edge bc.
            (a + d, a + d + e * width)
        } else {
            // A sliver: c just off the middle of ab.
            (a + d, a + d * 0.5 + e * width)
        };
        let p = rng.vec(2.0);
        let (q, region) = closest_point_on_triangle(p, a, b, c);
        assert!(q.is_finite());
        let edges = [(a, b), (b, c), (c, a)]
            .into_iter()
            .map(|(s, t)| (p - closest_point_on_segment(p, s, t).0).length())
            .fold(f64::INFINITY, f64::min);
        assert!((p - q).length() <= edges * (1.0 + 1e-14), "{region:?} {} > {edges}", (p - q).length());
        let n = (b - a).cross(c - a);
        if n.length() > 0.0 && region == TriangleRegion::Interior {
            // In the plane: the distance along the normal is the whole distance.
            let along = n.normalize().dot(p - q).abs();
            assert!(((p - q).length() - along).abs() <= 1e-9 * (p - q).length().max(1e-300), "{region:?}");
        }
        // On the triangle: its distance to the triangle's edges is at most the width.
        let to_edges = [(a, b), (b, c), (c, a)]
            .into_iter()
            .map(|(s, t)| (q - closest_point_on_segment(q, s, t).0).length())
            .fold(f64::INFINITY, f64::min);
        assert!(to_edges <= 2.0 * width, "{to_edges} {width}");
    }
}

//! Surface meshes in 3D (issue 33, items 1, 2 and 8): validation, orientation, components,
//! vertex normals, and feature curves and corners.

mod common;

use common::surfaces::{cube, cube_sphere, grid, uv_sphere};
use glam::DVec3;
use quadopt::Error;
use quadopt::face::{self, Face};
use quadopt::surface::{SurfaceFeatures, SurfaceMesh, VertexRole};
use std::f64::consts::PI;

fn is_extreme(c: u32, n: u32) -> bool {
    c == 0 || c == n
}

#[test]
fn unit_cube_has_twelve_sharp_edges_and_eight_corners() {
    let (points, faces, _) = cube(1);
    let mesh = SurfaceMesh::new(points, faces, None).unwrap();
    assert!(mesh.is_closed());
    assert_eq!(mesh.components().len(), 1);
    let c = mesh.components()[0];
    assert_eq!((c.vertices, c.edges, c.faces, c.euler_characteristic(), c.genus()), (8, 12, 6, 2, Some(0)));
    assert!(mesh.reoriented().is_empty());
    assert!(!mesh.has_inward_component());
    // Outward normals at the corners: along the diagonal from the centre.
    for (p, n) in mesh.points().iter().zip(mesh.vertex_normals()) {
        let out = (*p - DVec3::splat(0.5)).normalize();
        assert!((n.dot(out) - 1.0).abs() < 1e-12, "{p} {n}");
    }
    let f = SurfaceFeatures::detect_default(&mesh);
    assert_eq!(f.sharp_edge_count(), 12);
    assert_eq!(f.feature_edge_count(), 12);
    assert_eq!(f.corners(), (0..8).collect::<Vec<u32>>());
    assert_eq!(f.curves().len(), 12);
    for curve in f.curves() {
        assert!(!curve.closed);
        assert_eq!(curve.vertices.len(), 2);
        assert!(mesh.find_edge(curve.vertices[0], curve.vertices[1]).is_some());
    }
}

#[test]
fn subdivided_cube_puts_every_edge_vertex_on_its_own_curve() {
    let n = 3;
    let (points, faces, lattice) = cube(n);
    let mesh = SurfaceMesh::new(points, faces, None).unwrap();
    let c = mesh.components()[0];
    assert_eq!((c.vertices, c.faces, c.genus()), (56, 54, Some(0)));
    let f = SurfaceFeatures::detect_default(&mesh);
    assert_eq!(f.sharp_edge_count(), 12 * n as usize);
    assert_eq!(f.curves().len(), 12);
    assert_eq!(f.corners().len(), 8);
    for (v, role) in f.roles().iter().enumerate() {
        let extreme = lattice[v].iter().filter(|&&c| is_extreme(c, n)).count();
        match (extreme, role) {
            (3, VertexRole::Corner) | (1, VertexRole::Free) => {}
            (2, &VertexRole::OnCurve(id)) => {
                // The curve is the cube edge through v: all its vertices share v's two extreme
                // coordinates, and it runs from a corner to a corner.
                let curve = &f.curves()[id as usize];
                assert_eq!(curve.vertices.len(), n as usize + 1);
                assert!(curve.vertices.contains(&(v as u32)));
                for &w in &curve.vertices {
                    for (a, b) in lattice[w as usize].iter().zip(&lattice[v]) {
                        if is_extreme(*b, n) {
                            assert_eq!(a, b);
                        }
                    }
                }
                let ends = [curve.vertices[0], *curve.vertices.last().unwrap()];
                assert!(ends.iter().all(|&e| f.roles()[e as usize] == VertexRole::Corner));
            }
            other => panic!("vertex {v} at {:?}: {other:?}", lattice[v]),
        }
    }
    // Projection onto a curve's original polyline.
    let curve = f.curves().iter().find(|c| c.vertices.len() == 4).unwrap();
    let a = mesh.points()[curve.vertices[0] as usize];
    let b = mesh.points()[curve.vertices[3] as usize];
    let mid = 0.5 * (a + b);
    let off = mid + DVec3::splat(0.1) - (b - a).normalize() * (b - a).normalize().dot(DVec3::splat(0.1));
    let (q, segment, d2) = curve.closest_point(mesh.points(), off);
    assert!((q - mid).length() < 1e-12);
    assert_eq!(segment, 1);
    assert!((d2 - (off - mid).length_squared()).abs() < 1e-15);
}

#[test]
fn inward_cube_is_turned_outward_and_mixed_faces_reoriented() {
    let (points, faces, _) = cube(2);
    let inward: Vec<Face> = faces.iter().map(|&f| face::reversed(f)).collect();
    let mesh = SurfaceMesh::new(points.clone(), inward.clone(), None).unwrap();
    assert!(mesh.has_inward_component());
    assert!(mesh.reoriented().is_empty());
    assert_eq!(mesh.faces(), &faces[..]);
    assert_eq!(mesh.faces_as_given(), inward);
    // Two faces given the wrong way: reversed back, and listed.
    let mut mixed = faces.clone();
    mixed[3] = face::reversed(mixed[3]);
    mixed[17] = face::reversed(mixed[17]);
    let mesh = SurfaceMesh::new(points, mixed, None).unwrap();
    assert_eq!(mesh.reoriented(), &[3, 17]);
    assert_eq!(mesh.faces(), &faces[..]);
    assert!(!mesh.has_inward_component());
}

#[test]
fn sphere_is_closed_valid_and_smooth() {
    for (points, faces) in [
        cube_sphere(6),
        // A UV sphere: the poles are triangles fans, the rest quads.
        uv_sphere(12, 8),
    ] {
        let mesh = SurfaceMesh::new(points.clone(), faces, None).unwrap();
        assert!(mesh.is_closed());
        assert_eq!(mesh.components().len(), 1);
        assert_eq!(mesh.components()[0].genus(), Some(0));
        assert!(!mesh.has_inward_component());
        for (p, n) in points.iter().zip(mesh.vertex_normals()) {
            assert!(n.dot(*p) > 0.99, "{p} {n}");
        }
        let f = SurfaceFeatures::detect_default(&mesh);
        assert_eq!(f.sharp_edge_count(), 0);
        assert!(f.curves().is_empty());
        assert!(f.roles().iter().all(|r| *r == VertexRole::Free));
        assert!(mesh.verdict_quality_values().iter().all(|&q| q > 0.5));
        assert!(mesh.signed_quality_values().iter().all(|&q| q > 0.5));
    }
}

#[test]
fn half_cylinder_has_its_boundary_as_four_curves_between_four_corners() {
    let (m, k, length) = (6, 4, 3.0);
    let (points, faces) = grid(m, k, false, false, |i, j| {
        let a = PI * f64::from(i) / f64::from(m);
        DVec3::new(a.cos(), a.sin(), length * f64::from(j) / f64::from(k))
    });
    let mesh = SurfaceMesh::new(points, faces, None).unwrap();
    assert!(!mesh.is_closed());
    assert_eq!(mesh.boundary_edge_count(), 2 * (m + k) as usize);
    assert_eq!(mesh.components()[0].genus(), None);
    let f = SurfaceFeatures::detect_default(&mesh);
    assert_eq!(f.sharp_edge_count(), 0);
    let id = |i: u32, j: u32| j * (m + 1) + i;
    assert_eq!(f.corners(), vec![id(0, 0), id(m, 0), id(0, k), id(m, k)]);
    let mut lengths: Vec<usize> = f.curves().iter().map(|c| c.vertices.len()).collect();
    lengths.sort();
    assert_eq!(lengths, vec![5, 5, 7, 7]);
    assert!(f.curves().iter().all(|c| !c.closed));
    // The arc at z = 0 is one curve, holding every vertex of that end.
    let VertexRole::OnCurve(arc) = f.roles()[id(1, 0) as usize] else { panic!() };
    for i in 1..m {
        assert_eq!(f.roles()[id(i, 0) as usize], VertexRole::OnCurve(arc));
        assert_eq!(f.roles()[id(i, 1) as usize], VertexRole::Free);
    }
    let arc = &f.curves()[arc as usize];
    let mut ends = [arc.vertices[0], *arc.vertices.last().unwrap()];
    ends.sort();
    assert_eq!(ends, [id(0, 0), id(m, 0)]);
}

#[test]
fn tube_has_two_closed_boundary_curves_without_corners() {
    // Eight segments: every dihedral and every boundary turn is 45 degrees, exactly the
    // default threshold, which is not beyond it.
    let (points, faces) = grid(8, 3, true, false, |i, j| {
        let a = PI * f64::from(i) / 4.0;
        DVec3::new(a.cos(), a.sin(), f64::from(j))
    });
    let mesh = SurfaceMesh::new(points, faces, None).unwrap();
    let f = SurfaceFeatures::detect_default(&mesh);
    assert_eq!(f.sharp_edge_count(), 0);
    assert!(f.corners().is_empty());
    assert_eq!(f.curves().len(), 2);
    for (c, curve) in f.curves().iter().enumerate() {
        assert!(curve.closed);
        assert_eq!(curve.vertices.len(), 8);
        assert_eq!(curve.edge_count(), 8);
        for &v in &curve.vertices {
            assert_eq!(f.roles()[v as usize], VertexRole::OnCurve(c as u32));
        }
    }
    // Just below 45 degrees, the octagon's dihedrals and turns are all beyond it: eight
    // straight sharp lines along the tube, whose ends on the rims are junctions.
    let f = SurfaceFeatures::detect(&mesh, 44.9, &[]).unwrap();
    assert_eq!(f.sharp_edge_count(), 8 * 3);
    assert_eq!(f.corners(), (0..8).chain(24..32).collect::<Vec<u32>>());
    assert_eq!(f.curves().len(), 8 + 16);
    assert!(matches!(f.roles()[9], VertexRole::OnCurve(_)));
}

#[test]
fn torus_is_closed_with_genus_one() {
    let (big, small) = (2.0, 0.5);
    // Twelve segments both ways (eight around the tube would put its dihedrals near 45
    // degrees, on both sides of it: the quads' profile is the circle stretched by cos 15).
    let (points, faces) = grid(12, 12, true, true, |i, j| {
        let (t, p) = (2.0 * PI * f64::from(i) / 12.0, 2.0 * PI * f64::from(j) / 12.0);
        let r = big + small * p.cos();
        DVec3::new(r * t.cos(), r * t.sin(), small * p.sin())
    });
    // Given either way, it comes out outward.
    for faces in [faces.clone(), faces.iter().map(|&f| face::reversed(f)).collect()] {
        let mesh = SurfaceMesh::new(points.clone(), faces, None).unwrap();
        let c = mesh.components()[0];
        assert!(c.is_closed());
        assert_eq!((c.vertices, c.edges, c.faces), (144, 288, 144));
        assert_eq!((c.euler_characteristic(), c.genus()), (0, Some(1)));
        for (p, n) in points.iter().zip(mesh.vertex_normals()) {
            let centre = DVec3::new(p.x, p.y, 0.0).normalize() * big;
            assert!(n.dot((*p - centre).normalize()) > 0.99);
        }
        let f = SurfaceFeatures::detect_default(&mesh);
        assert_eq!(f.feature_edge_count(), 0);
    }
}

/// A 4 x 2 strip of unit quads folded along x = 0 by `fold_deg` (the dihedral angle).
fn folded_strip(fold_deg: f64) -> SurfaceMesh {
    let d = fold_deg.to_radians();
    let (points, faces) = grid(4, 2, false, false, |i, j| {
        let x = f64::from(i) - 2.0;
        let y = f64::from(j);
        if x <= 0.0 { DVec3::new(x, y, 0.0) } else { DVec3::new(x * d.cos(), y, x * d.sin()) }
    });
    SurfaceMesh::new(points, faces, None).unwrap()
}

#[test]
fn fold_just_below_and_above_the_feature_angle() {
    // Vertex (i, j) is 5 j + i; the fold runs through 2, 7, 12.
    let below = SurfaceFeatures::detect_default(&folded_strip(44.99));
    assert_eq!(below.sharp_edge_count(), 0);
    assert_eq!(below.corners(), vec![0, 4, 10, 14]);
    assert_eq!(below.curves().len(), 4);
    assert_eq!(below.roles()[7], VertexRole::Free);
    let at = SurfaceFeatures::detect_default(&folded_strip(45.0));
    assert_eq!(at.sharp_edge_count(), 0);
    let above = SurfaceFeatures::detect_default(&folded_strip(45.01));
    assert_eq!(above.sharp_edge_count(), 2);
    // The fold's ends are junctions (two boundary edges and the sharp one).
    assert_eq!(above.corners(), vec![0, 2, 4, 10, 12, 14]);
    assert_eq!(above.curves().len(), 7);
    let VertexRole::OnCurve(c) = above.roles()[7] else { panic!("{:?}", above.roles()[7]) };
    let mut fold = above.curves()[c as usize].vertices.clone();
    fold.sort();
    assert_eq!(fold, vec![2, 7, 12]);
}

#[test]
fn filleted_profile_is_sharp_only_below_its_turns() {
    // Plate, a quarter-circle fillet in three chords, plate: the profile turns by 15 degrees
    // where the fillet meets a plate and by 30 between chords.
    let mut profile = vec![(-2.0, 0.0), (-1.0, 0.0), (0.0, 0.0)];
    for i in 1..=3 {
        let a = (-90.0 + 30.0 * f64::from(i)).to_radians();
        profile.push((a.cos(), 1.0 + a.sin()));
    }
    profile.extend([(1.0, 2.0), (1.0, 3.0)]);
    let m = profile.len() as u32 - 1;
    let (points, faces) = grid(m, 2, false, false, |i, j| {
        let (x, z) = profile[i as usize];
        DVec3::new(x, f64::from(j), z)
    });
    let mesh = SurfaceMesh::new(points, faces, None).unwrap();
    let count = |angle: f64| SurfaceFeatures::detect(&mesh, angle, &[]).unwrap().sharp_edge_count();
    assert_eq!(count(45.0), 0);
    assert_eq!(count(30.0), 0);
    assert_eq!(count(29.9), 4);
    assert_eq!(count(15.0), 4);
    assert_eq!(count(14.9), 8);
    assert!(matches!(
        SurfaceFeatures::detect(&mesh, 190.0, &[]),
        Err(Error::InvalidOption { name: "feature_angle", .. })
    ));
}

#[test]
fn user_marked_edges_make_curves_and_bad_pairs_are_named() {
    // A flat 4 x 4 plate in the plane z = 1: vertex (i, j) is 5 j + i.
    let (points, faces) = grid(4, 4, false, false, |i, j| DVec3::new(f64::from(i), f64::from(j), 1.0));
    let mesh = SurfaceMesh::new(points, faces, None).unwrap();
    assert_eq!(SurfaceFeatures::detect_default(&mesh).corners(), vec![0, 4, 20, 24]);
    // An interior chain 6 - 7 - 8 (given in either order): its ends are curve ends.
    let f = SurfaceFeatures::detect(&mesh, 45.0, &[[7, 6], [7, 8]]).unwrap();
    assert_eq!(f.corners(), vec![0, 4, 6, 8, 20, 24]);
    assert_eq!(f.curves().len(), 5);
    let VertexRole::OnCurve(c) = f.roles()[7] else { panic!() };
    assert_eq!(f.curves()[c as usize].vertices.len(), 3);
    assert!(f.edge_kinds()[mesh.find_edge(6, 7).unwrap()].marked);
    // A chain across the plate, 10 - 11 - 12 - 13 - 14: its ends become junctions.
    let f = SurfaceFeatures::detect(&mesh, 45.0, &[[10, 11], [11, 12], [12, 13], [13, 14]]).unwrap();
    assert_eq!(f.corners(), vec![0, 4, 10, 14, 20, 24]);
    assert_eq!(f.curves().len(), 7);
    // Marking a boundary edge changes nothing.
    let f = SurfaceFeatures::detect(&mesh, 45.0, &[[0, 1]]).unwrap();
    assert_eq!(f.feature_edge_count(), 16);
    // A diagonal, a far pair, an out-of-range vertex, a loop: each named.
    for (k, pair) in [[0, 6], [0, 24], [3, 99], [5, 5]].into_iter().enumerate() {
        let err = SurfaceFeatures::detect(&mesh, 45.0, &[[1, 2], pair]).unwrap_err();
        let Error::InvalidOption { name: "feature_edges", ref reason } = err else { panic!("{k}: {err:?}") };
        assert!(reason.contains(&format!("marked edge 1, vertices ({}, {})", pair[0], pair[1])), "{reason}");
    }
}

#[test]
fn quad_dominant_pyramid_is_closed() {
    let points = vec![
        DVec3::new(0., 0., 0.),
        DVec3::new(1., 0., 0.),
        DVec3::new(1., 1., 0.),
        DVec3::new(0., 1., 0.),
        DVec3::new(0.5, 0.5, 1.),
    ];
    // Base given upward (inward), sides outward: the base is the minority and is reversed.
    let faces = vec![
        [0, 1, 2, 3],
        face::triangle(0, 1, 4),
        face::triangle(1, 2, 4),
        face::triangle(2, 3, 4),
        face::triangle(3, 0, 4),
    ];
    let mesh = SurfaceMesh::new(points, faces, None).unwrap();
    assert_eq!(mesh.reoriented(), &[0]);
    assert_eq!(mesh.faces()[0], [0, 3, 2, 1]);
    assert_eq!(mesh.triangle_count(), 4);
    let c = mesh.components()[0];
    assert_eq!((c.vertices, c.edges, c.faces, c.genus()), (5, 8, 5, Some(0)));
    let f = SurfaceFeatures::detect_default(&mesh);
    // Between the normals: 116.6 degrees across a base edge, 78.5 across a side edge.
    assert_eq!(f.sharp_edge_count(), 8);
    assert_eq!(f.corners(), vec![0, 1, 2, 3, 4]);
    assert_eq!(f.curves().len(), 8);
}

#[test]
fn malformed_input_is_refused_with_the_offending_item() {
    let (points, faces) = grid(2, 1, false, false, |i, j| DVec3::new(f64::from(i), f64::from(j), 0.5));
    assert_eq!(SurfaceMesh::new(points.clone(), vec![], None).unwrap_err(), Error::NoQuads);
    assert_eq!(
        SurfaceMesh::new(points.clone(), vec![faces[0], [1, 2, 9, 4]], None).unwrap_err(),
        Error::IndexOutOfRange { quad: 1, corner: 2, index: 9, vertex_count: 6 }
    );
    assert_eq!(
        SurfaceMesh::new(points.clone(), vec![face::triangle(0, 1, 1)], None).unwrap_err(),
        Error::RepeatedVertex { quad: 0, vertex: 1 }
    );
    assert_eq!(
        SurfaceMesh::new(points.clone(), faces.clone(), Some(vec![false; 5])).unwrap_err(),
        Error::FixedLengthMismatch { expected: 6, got: 5 }
    );
    let mut bad = points.clone();
    bad[3].z = f64::INFINITY;
    assert_eq!(
        SurfaceMesh::new(bad, faces.clone(), None).unwrap_err(),
        Error::NonFiniteCoordinate { vertex: 3 }
    );
    // A third face on edge (1, 4), standing up out of the strip.
    let mut p3 = points.clone();
    p3.push(DVec3::new(1.0, 0.0, 1.5));
    p3.push(DVec3::new(1.0, 1.0, 1.5));
    let mut f3 = faces.clone();
    f3.push([1, 4, 7, 6]);
    let err = SurfaceMesh::new(p3, f3, None).unwrap_err();
    assert!(matches!(err, Error::NonManifoldEdge { a: 1, b: 4, count: 3, .. }), "{err:?}");
    // A Moebius strip: a ring of 6 quads with a half twist, in 3D.
    let mut p = Vec::new();
    for i in 0..6 {
        let t = 2.0 * PI * f64::from(i) / 6.0;
        let half = t / 2.0;
        let centre = DVec3::new(2.0 * t.cos(), 2.0 * t.sin(), 0.0);
        let across = DVec3::new(half.cos() * t.cos(), half.cos() * t.sin(), half.sin()) * 0.5;
        p.push(centre - across);
        p.push(centre + across);
    }
    let mut quads: Vec<Face> = (0..5).map(|i| [2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1]).collect();
    quads.push([10, 1, 0, 11]);
    assert!(matches!(SurfaceMesh::new(p.clone(), quads.clone(), None), Err(Error::NonOrientable { .. })));
    // Without the twist it is an orientable ring with two boundary loops.
    quads[5] = [10, 0, 1, 11];
    let mesh = SurfaceMesh::new(p, quads, None).unwrap();
    assert_eq!(mesh.boundary_edge_count(), 12);
    assert!(!mesh.is_closed());
}

#[test]
fn closed_and_open_components_together() {
    let (mut points, mut faces, _) = cube(1);
    let (p, f) = grid(2, 2, false, false, |i, j| DVec3::new(f64::from(i) + 5.0, f64::from(j), 0.0));
    let offset = points.len() as u32;
    points.extend(p);
    faces.extend(f.iter().map(|f| f.map(|v| v + offset)));
    let mesh = SurfaceMesh::new(points, faces, Some(vec![true; 17])).unwrap();
    assert!(!mesh.is_closed());
    let kinds: Vec<(bool, usize)> = mesh.components().iter().map(|c| (c.is_closed(), c.faces)).collect();
    assert_eq!(kinds, vec![(true, 6), (false, 4)]);
    assert_eq!(mesh.face_components(), &[0, 0, 0, 0, 0, 0, 1, 1, 1, 1]);
    assert!(mesh.fixed().iter().all(|&f| f));
    let mut moved = mesh.clone();
    let mut p = mesh.points().to_vec();
    p[16].z = 0.25;
    moved.set_points(&p).unwrap();
    assert_eq!(moved.points()[16].z, 0.25);
    assert_eq!(moved.vertex_normals(), mesh.vertex_normals());
    p[2].x = f64::NAN;
    assert_eq!(moved.set_points(&p).unwrap_err(), Error::NonFiniteCoordinate { vertex: 2 });
    assert_eq!(moved.set_points(&p[..3]).unwrap_err(), Error::VertexCountMismatch { expected: 17, got: 3 });
    let f = SurfaceFeatures::detect_default(&mesh);
    assert_eq!(f.sharp_edge_count(), 12);
    assert_eq!(f.corners().len(), 8 + 4);
    assert_eq!(f.curves().len(), 12 + 4);
}

/// The plain dihedral rule: edges whose faces' normals differ by more than `angle`.
fn bent_beyond(mesh: &SurfaceMesh, angle: f64) -> usize {
    let n = |f: u32| quadopt::surface::face_vector_area(mesh.points(), &mesh.faces()[f as usize]);
    let angle_of = |e: &quadopt::surface::SurfaceEdge| {
        let (a, b) = (n(e.faces[0]), n(e.faces[1]));
        a.cross(b).length().atan2(a.dot(b)).to_degrees()
    };
    mesh.edges().iter().filter(|e| !e.is_boundary() && angle_of(e) > angle + 1e-3).count()
}

#[test]
fn a_low_poly_torus_bends_everywhere_and_has_no_crease() {
    // Eight segments around, six around the tube (offset by half a segment, so no face is
    // flat): 48 edges bend by 58 to 64 degrees, past the feature angle, and every edge around
    // them by at least 23. The plain dihedral rule would make most vertices corners.
    let (points, faces) = grid(8, 6, true, true, |i, j| {
        let (t, p) = (2.0 * PI * f64::from(i) / 8.0, 2.0 * PI * (f64::from(j) + 0.5) / 6.0);
        let r = 2.0 + 0.7 * p.cos();
        DVec3::new(r * t.cos(), r * t.sin(), 0.7 * p.sin())
    });
    let mesh = SurfaceMesh::new(points, faces, None).unwrap();
    assert_eq!(bent_beyond(&mesh, 45.0), 48);
    let f = SurfaceFeatures::detect_default(&mesh);
    assert_eq!((f.feature_edge_count(), f.corners().len()), (0, 0));
    // At 30 degrees they stand out from the flattest edges around them by more: creases.
    assert_eq!(
        SurfaceFeatures::detect(&mesh, 30.0, &[]).unwrap().sharp_edge_count(),
        bent_beyond(&mesh, 45.0)
    );
}

#[test]
fn boxes_keep_every_edge_however_coarse() {
    for n in [1, 2, 5] {
        let (points, faces, _) = cube(n);
        let mesh = SurfaceMesh::new(points, faces, None).unwrap();
        let f = SurfaceFeatures::detect_default(&mesh);
        assert_eq!(f.sharp_edge_count(), 12 * n as usize, "cube({n})");
        assert_eq!(f.corners().len(), 8, "cube({n})");
        assert_eq!(f.curves().len(), 12, "cube({n})");
    }
}

/// A 6 x `rows` plate (vertex (i, j) is 7 j + i), flat for y <= 1 and folded along x = 3 beyond,
/// ever more steeply: a V-shaped valley that starts inside the plate and runs to the boundary.
/// Its floor bends past 45 degrees from (3, 2) on, and so does the plate's fold at y = 1 next
/// to the boundary (the edges (0, 1)-(1, 1) and (5, 1)-(6, 1)).
fn valley(rows: u32) -> SurfaceMesh {
    let (points, faces) = grid(6, rows, false, false, |i, j| {
        let (x, y) = (f64::from(i), f64::from(j));
        DVec3::new(x, y, 1.5 * (y - 1.0).max(0.0) * (x - 3.0).abs() / 3.0)
    });
    SurfaceMesh::new(points, faces, None).unwrap()
}

#[test]
fn a_crease_that_dies_out_within_two_edges_is_faceting() {
    let v = |i: u32, j: u32| (7 * j + i) as usize;
    // One edge of valley floor, (3, 2) to the boundary at (3, 3), and the two fold edges at
    // y = 1, each from the boundary to a vertex with no other feature edge: they bend past the
    // feature angle, and the plain rule would make (3, 2), (1, 1) and (5, 1) corners.
    let short = valley(3);
    assert_eq!(bent_beyond(&short, 45.0), 3);
    let f = SurfaceFeatures::detect_default(&short);
    assert_eq!(f.sharp_edge_count(), 0);
    for at in [v(3, 2), v(1, 1), v(5, 1)] {
        assert_eq!(f.roles()[at], VertexRole::Free);
    }
    // Three edges of floor, (3, 2) to the boundary at (3, 5): a crease.
    let long = valley(5);
    assert_eq!(bent_beyond(&long, 45.0), 5);
    let f = SurfaceFeatures::detect_default(&long);
    assert_eq!(f.sharp_edge_count(), 3);
    assert_eq!(f.roles()[v(3, 2)], VertexRole::Corner);
    assert!(matches!(f.roles()[v(3, 3)], VertexRole::OnCurve(_)));
    assert_eq!(f.roles()[v(1, 1)], VertexRole::Free);
    // Marked edges are kept, however short.
    let f = SurfaceFeatures::detect(&short, 45.0, &[[v(3, 2) as u32, v(3, 3) as u32]]).unwrap();
    assert_eq!(f.roles()[v(3, 2)], VertexRole::Corner);
}

//! A large mesh is optimized in an internal order chosen for memory locality: the results
//! must come back in the caller's numbering, the same whatever that numbering is, with fixed
//! vertices bit for bit and tangled quads named by the caller's indices.

mod common;
use common::Rng;
use quadopt::TangleReason;
use quadopt::quality::{corners, scaled_jacobian};
use quadopt::synthetic::Synthetic;
use quadopt::{DVec2, Mesh, Optimizer, Options};

/// A mesh large enough to be renumbered (at least 16,384 vertices).
fn large() -> Synthetic {
    Synthetic { nx: 150, ny: 150, holes: 4, jitter: 0.3, ..Synthetic::default() }
}

/// A random permutation of 0..n.
fn permutation(n: usize, rng: &mut Rng) -> Vec<u32> {
    let mut p: Vec<u32> = (0..n as u32).collect();
    for i in (1..n).rev() {
        let j = ((rng.next() * 0.5 + 0.5) * (i + 1) as f64) as usize;
        p.swap(i, j.min(i));
    }
    p
}

/// `mesh` with its vertices and quads numbered by random permutations; `new_of[v]` is the
/// new index of vertex `v`, `quad_new_of[k]` that of quad `k`.
fn shuffled(mesh: &Mesh, seed: u64) -> (Mesh, Vec<u32>, Vec<u32>) {
    let mut rng = Rng(seed);
    let old_of = permutation(mesh.points().len(), &mut rng);
    let quad_old_of = permutation(mesh.quads().len(), &mut rng);
    let mut new_of = vec![0u32; old_of.len()];
    for (i, &v) in old_of.iter().enumerate() {
        new_of[v as usize] = i as u32;
    }
    let mut quad_new_of = vec![0u32; quad_old_of.len()];
    for (k, &q) in quad_old_of.iter().enumerate() {
        quad_new_of[q as usize] = k as u32;
    }
    let points = old_of.iter().map(|&v| mesh.points()[v as usize]).collect();
    let fixed = old_of.iter().map(|&v| mesh.fixed()[v as usize]).collect();
    let quads = quad_old_of.iter().map(|&k| mesh.quads()[k as usize].map(|v| new_of[v as usize])).collect();
    (Mesh::new(points, quads, Some(fixed)).unwrap(), new_of, quad_new_of)
}

fn with_fixed(mesh: &Mesh, fixed: &[usize]) -> Mesh {
    let mut flags = mesh.fixed().to_vec();
    for &v in fixed {
        flags[v] = true;
    }
    Mesh::new(mesh.points().to_vec(), mesh.quads().to_vec(), Some(flags)).unwrap()
}

#[test]
fn a_large_mesh_numbered_any_way_gives_the_same_result() {
    let base = large().generate();
    assert!(base.points().len() >= 16_384, "{} vertices: not renumbered", base.points().len());
    // Some interior vertices fixed, spread over the mesh.
    let pinned: Vec<usize> = (0..base.points().len()).step_by(997).collect();
    let mesh = with_fixed(&base, &pinned);
    let options = Options::default().with_max_iterations(30);
    // The generator's row-major order is local and kept; shuffled copies are renumbered,
    // each into the same internal order. Results in the original numbering:
    let mut reference: Option<(Vec<DVec2>, quadopt::Report)> = None;
    for seed in [1, 2, 3] {
        let (input, new_of, _) = shuffled(&mesh, seed);
        let mut got = input.clone();
        let report = Optimizer::new(&got).run(&mut got, &options, None).unwrap();
        assert!(report.output.min > report.input.min, "{report:?}");
        assert_eq!(report.output.inverted, 0);
        // The report describes the mesh given and returned, in the caller's order.
        assert_eq!(report.output, got.quality(), "seed {seed}");
        assert_eq!(report.input, input.quality(), "seed {seed}");
        let out: Vec<DVec2> = (0..mesh.points().len()).map(|v| got.points()[new_of[v] as usize]).collect();
        for &v in &pinned {
            assert_eq!(out[v].to_array().map(f64::to_bits), mesh.points()[v].to_array().map(f64::to_bits));
        }
        let Some((first, first_report)) = &reference else {
            reference = Some((out, report));
            continue;
        };
        let (a, b) = (&report.output, &first_report.output);
        // The same quads, summed in another order.
        assert!(a.min == b.min && a.inverted == b.inverted && (a.avg - b.avg).abs() < 1e-13, "seed {seed}");
        assert_eq!(report.iterations, first_report.iterations, "seed {seed}");
        for (v, (p, q)) in first.iter().zip(&out).enumerate() {
            assert_eq!(
                q.to_array().map(f64::to_bits),
                p.to_array().map(f64::to_bits),
                "seed {seed}, vertex {v}"
            );
        }
    }
}

#[test]
fn tangled_quads_are_reported_in_the_callers_numbering() {
    // An interior quad turned inside out (its second and fourth corners swapped) with all four
    // vertices fixed: nothing can untangle it.
    let base = Synthetic { holes: 0, jitter: 0.0, ..large() }.generate();
    let k = base.quads().len() / 2 + 70;
    let q = base.quads()[k];
    let mut points = base.points().to_vec();
    points.swap(q[1] as usize, q[3] as usize);
    let mut fixed = base.fixed().to_vec();
    for &v in &q {
        fixed[v as usize] = true;
    }
    let mesh = Mesh::new(points, base.quads().to_vec(), Some(fixed)).unwrap();
    assert!(scaled_jacobian(&corners(mesh.points(), &mesh.quads()[k])) < 0.0);
    let options = Options::default().with_max_iterations(10);
    let (input, _, quad_new_of) = shuffled(&mesh, 3);
    for (mesh, k) in [(mesh, k), (input, quad_new_of[k] as usize)] {
        let mut out = mesh.clone();
        let report = Optimizer::new(&out).run(&mut out, &options, None).unwrap();
        assert!(
            report.tangled.iter().any(|t| t.quad as usize == k && t.reason == TangleReason::AllVerticesFixed),
            "quad {k} not reported: {:?}",
            report.tangled
        );
        for t in &report.tangled {
            let sj = scaled_jacobian(&corners(out.points(), &out.quads()[t.quad as usize]));
            assert!(sj <= 0.0, "quad {} reported tangled but at {sj}", t.quad);
        }
    }
}

#[test]
fn a_mesh_with_other_quads_is_an_error_and_is_left_as_it_was() {
    // Renumbered (large, scattered) and in its own order (small).
    let small = Synthetic { nx: 10, ny: 10, holes: 0, ..Synthetic::default() }.generate();
    let (big, _, _) = shuffled(&large().generate(), 4);
    for mesh in [small, big] {
        let optimizer = Optimizer::new(&mesh);
        let mut reversed = mesh.quads().to_vec();
        reversed.reverse();
        // One quad fewer; the same quads in another order.
        for quads in [mesh.quads()[1..].to_vec(), reversed] {
            let other = Mesh::new(mesh.points().to_vec(), quads, None).unwrap();
            let mut m = other.clone();
            let err = optimizer.run(&mut m, &Options::default(), None).unwrap_err();
            assert!(matches!(err, quadopt::Error::ConnectivityMismatch { .. }), "{err}");
            assert_eq!(m.points(), other.points());
        }
        // Another vertex count.
        let mut points = mesh.points().to_vec();
        points.push(DVec2::new(1e3, 1e3));
        let mut m = Mesh::new(points, mesh.quads().to_vec(), None).unwrap();
        let before = m.points().to_vec();
        let err = optimizer.run(&mut m, &Options::default(), None).unwrap_err();
        assert!(matches!(err, quadopt::Error::VertexCountMismatch { .. }), "{err}");
        assert_eq!(m.points(), &before[..]);
        // Its own mesh runs.
        let mut m = mesh.clone();
        optimizer.run(&mut m, &Options::default(), None).unwrap();
    }
}

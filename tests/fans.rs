//! Fans: one vertex shared by thousands of quads, the input that made the untangler's local
//! program and the topology's ring building blow up (issue 8, items 2 and 7).
//!
//! The fan of n quads has its centre (vertex 0) at the origin in the untangled configuration;
//! quad i is (centre, a_i, d_i, a_i+1) with a_i on the unit circle and d_i between them at
//! radius 1.5. Every boundary vertex is a corner (the boundary turns by about 180 degrees at
//! each), so only the centre may move. The centre is pushed outside the fan, to (2, 0.3), which
//! inverts most quads. At the origin every corner of every quad is positive and the origin is
//! inside the untangler's search box (the neighbours' bounding box shrunk by 10%), so the
//! centre's max-min program has a positive optimum: one untangling move provably untangles the
//! fan. After smoothing the best placement is the origin again: the corner at the centre is
//! the smallest in each quad, those corners add up to 360 degrees, so their minimum is at most
//! 360/n degrees, reached only with all equal; its scaled Jacobian is sin(2 pi / n).

use quadopt::{Mesh, Optimizer, Options, Progress, Topology, VertexKind};
use std::f64::consts::TAU;

#[path = "common/fans.rs"]
mod fans;
use fans::tangled_fan;

#[test]
fn fans_of_800_and_2000_quads_are_untangled_at_every_scale() {
    for n in [800, 2000] {
        for scale in [1e-5, 1.0, 1e5] {
            let mut mesh = tangled_fan(n, scale);
            let before = mesh.points().to_vec();
            let report = quadopt::optimize(&mut mesh, &Options::default()).unwrap();
            let at = format!("{n} quads at scale {scale:e}");
            assert!(report.input.inverted > n as usize / 2, "{at}: only {} inverted", report.input.inverted);
            assert_eq!(report.output.inverted, 0, "{at}");
            assert!(report.tangled.is_empty(), "{at}: {:?}", report.tangled.first());
            assert!(!report.cancelled, "{at}");
            assert!(report.untangle_sweeps >= 1, "{at}");
            // Only the centre may move: every boundary vertex is a corner.
            assert_eq!(&mesh.points()[1..], &before[1..], "{at}: a boundary vertex moved");
            // The best placement of the centre is the origin, with minimum sin(2 pi / n). The
            // run places it for the ring rounded to the normalization's grid (2^-21 of the
            // shortest edge), so these thin quads (sin(2 pi / n) = 3e-3) end within about
            // 2^-21 / (2 pi / n) of it in relative terms: 2e-5 at 2,000 quads.
            let best = (TAU / n as f64).sin();
            assert!(
                report.output.min > (1.0 - 1e-4) * best && report.output.min <= best * (1.0 + 1e-9),
                "{at}: min {} against the best possible {best}",
                report.output.min
            );
            // The max-min optimum of 2,000 nearly parallel constraints is flat: the grid's
            // rounding of the ring moves it by 2e-5 of the radius.
            assert!(mesh.points()[0].length() < 1e-4 * scale, "{at}: centre at {}", mesh.points()[0]);
        }
    }
}

#[test]
fn a_cancel_at_the_first_call_stops_the_untangling_of_a_fan() {
    let mut mesh = tangled_fan(2000, 1e5);
    let optimizer = Optimizer::new(&mesh);
    let mut calls: Vec<Progress> = Vec::new();
    let mut cancel = |p: &Progress| {
        calls.push(*p);
        false
    };
    let report = optimizer.run(&mut mesh, &Options::default(), Some(&mut cancel)).unwrap();
    assert!(report.cancelled);
    assert_eq!(calls.len(), 1, "called again after cancelling");
    // The call came from untangling (no smoothing sweep had run), and none ran after it.
    assert_eq!(calls[0].iteration, 0);
    assert!(calls[0].energy.is_nan());
    assert_eq!((report.iterations, report.untangle_sweeps), (0, 1));
    assert!(!report.converged);
    // The untangling done before the cancel is kept: that one sweep untangled the fan.
    assert_eq!(report.output.inverted, 0);
    assert!(report.output.min > 0.0);
}

#[test]
fn a_cancel_at_a_later_call_keeps_the_untangled_fan() {
    // Cancelling at the second call: the first came from untangling, the second from the
    // first smoothing sweep.
    let mut mesh = tangled_fan(800, 1e-5);
    let optimizer = Optimizer::new(&mesh);
    let mut iterations = Vec::new();
    let mut cancel_second = |p: &Progress| {
        iterations.push(p.iteration);
        iterations.len() < 2
    };
    let report = optimizer.run(&mut mesh, &Options::default(), Some(&mut cancel_second)).unwrap();
    assert!(report.cancelled);
    assert_eq!(iterations, [0, 1]);
    assert_eq!((report.iterations, report.output.inverted), (1, 0));
}

/// Checks the rings of a fan of `n` quads around vertex 0 built by [`tangled_fan`] (its
/// geometry does not matter here), whose quad `i` is (0, a_i, d_i, a_i+1) with a_i = 1 + 2i
/// and d_i = 2 + 2i, when only its first `kept` quads are kept.
fn check_fan_rings(t: &Topology, quads: &[[u32; 4]], n: u32, kept: u32) {
    let a = |i: u32| 1 + 2 * (i % n);
    let d = |i: u32| 2 + 2 * (i % n);
    let closed = kept == n;
    assert_eq!(t.kind(0), if closed { VertexKind::Interior } else { VertexKind::Boundary });
    assert_eq!(t.quad_count(0), kept as usize);
    // Counter-clockwise: a_i then a_i+1; an open fan starts at its boundary (a_0) and ends
    // with the previous boundary vertex (a_kept).
    let ring = t.ring(0);
    assert_eq!(ring.len(), kept as usize + usize::from(!closed));
    let s = if closed { ring.iter().position(|&v| v == a(0)).unwrap() as u32 } else { 0 };
    assert!(ring.iter().enumerate().all(|(k, &v)| v == a(k as u32 + s)), "ring of the centre");
    let mut full = Vec::new();
    t.full_ring_into(quads, 0, &mut full);
    assert_eq!(full.len(), 2 * kept as usize + usize::from(!closed));
    for (k, &v) in full.iter().enumerate() {
        let i = k as u32 / 2 + s;
        assert_eq!(v, if k % 2 == 0 { a(i) } else { d(i) }, "full ring entry {k}");
    }
    // Every a_i with two quads: d_i, centre, d_i-1; every d_i: a_i+1, a_i.
    for i in 1..kept {
        assert_eq!(t.kind(a(i) as usize), VertexKind::Boundary);
        assert_eq!(t.ring(a(i) as usize), &[d(i), 0, d(i + n - 1)]);
        t.full_ring_into(quads, a(i) as usize, &mut full);
        assert_eq!(full, &[d(i), a(i + 1), 0, a(i + n - 1), d(i + n - 1)]);
    }
    for i in 0..kept {
        assert_eq!(t.ring(d(i) as usize), &[a(i + 1), a(i)]);
    }
}

/// The colour classes are a partition of the vertices with a ring, no two of a class in one
/// quad.
fn check_colours(t: &Topology, quads: &[[u32; 4]]) {
    let mut colour = vec![usize::MAX; t.vertex_count()];
    for c in 0..t.colour_count() {
        for &v in t.colour_class(c) {
            assert_eq!(colour[v as usize], usize::MAX, "vertex {v} in two classes");
            colour[v as usize] = c;
        }
    }
    for (v, &c) in colour.iter().enumerate() {
        let ringed = matches!(t.kind(v), VertexKind::Interior | VertexKind::Boundary);
        assert_eq!(c != usize::MAX, ringed, "vertex {v}");
    }
    for q in quads {
        for i in 0..4 {
            for j in i + 1..4 {
                let (ci, cj) = (colour[q[i] as usize], colour[q[j] as usize]);
                assert!(ci == usize::MAX || ci != cj, "quad {q:?} has two vertices of colour {ci}");
            }
        }
    }
}

#[test]
fn topology_of_a_fan_of_200k_quads() {
    let n = 200_000;
    let mesh = tangled_fan(n, 1.0);
    let t = Topology::try_new(&mesh).unwrap();
    check_fan_rings(&t, mesh.quads(), n, n);
    // One boundary loop, interior on the left: a_0, d_0, a_1, d_1, ...
    assert_eq!(t.loop_count(), 1);
    let l = t.boundary_loop(0);
    assert_eq!(l.len(), 2 * n as usize);
    let s = l.iter().position(|&v| v == 1).unwrap();
    assert!((0..l.len()).all(|k| l[(s + k) % l.len()] == 1 + k as u32), "boundary loop order");
    check_colours(&t, mesh.quads());
    // The centre shares a quad with every other vertex, so it is alone in its class.
    let centre_class = (0..t.colour_count()).find(|&c| t.colour_class(c).contains(&0)).unwrap();
    assert_eq!(t.colour_class(centre_class), &[0]);
}

#[test]
fn topology_of_an_open_fan_of_200k_quads() {
    // Leaving out the last quad opens the fan: the centre is on the boundary.
    let n = 200_000;
    let full = tangled_fan(n, 1.0);
    let quads = full.quads()[..n as usize - 1].to_vec();
    let mesh = Mesh::new(full.points().to_vec(), quads, None).unwrap();
    let t = Topology::new(&mesh);
    check_fan_rings(&t, mesh.quads(), n, n - 1);
    assert_eq!(t.loop_count(), 1);
    // Centre, a_0, d_0, ..., d_n-2, a_n-1: every vertex once, in index order.
    assert!(t.boundary_loop(0).iter().copied().eq(0..2 * n), "boundary loop order");
    check_colours(&t, mesh.quads());
}

#[test]
fn topology_of_two_fans_of_100k_quads_meeting_at_their_centre() {
    // Quads 0..k and n/2..n/2+k of the fan: two open fans touching only at the centre, which
    // is then non-manifold (and never moves); the boundary loops still cover every boundary
    // edge: 2k + 2 per fan.
    let (n, k) = (400_000u32, 100_000u32);
    let full = tangled_fan(n, 1.0);
    let half = (n / 2) as usize;
    let mut quads = full.quads()[..k as usize].to_vec();
    quads.extend_from_slice(&full.quads()[half..half + k as usize]);
    let mesh = Mesh::new(full.points().to_vec(), quads, None).unwrap();
    let t = Topology::new(&mesh);
    assert_eq!(t.kind(0), VertexKind::NonManifold);
    assert!(t.ring(0).is_empty());
    assert_eq!(t.quad_count(0), 2 * k as usize);
    let total: usize = t.boundary_loops().map(|l| l.len()).sum();
    assert_eq!(total, 4 * k as usize + 4);
    assert_eq!(t.boundary_loops().flatten().filter(|&&v| v == 0).count(), 2, "the centre once per fan");
    check_colours(&t, mesh.quads());
}

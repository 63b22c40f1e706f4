//! Meshes built to be hard (issue 4), shared by tests/hard_meshes.rs and tests/quality_floor.rs:
//! anisotropic graded grids, a structured mesh folded over several layers, a domain whose
//! boundary has near-touching parts, and jittered grids with many inverted quads. Each is made
//! from a valid mesh by moving interior vertices only.

use super::Rng;
use super::grids::{interior_mask, on_coordinates};
use quadopt::{DVec2, Mesh};

fn jitter(p: &mut [DVec2], movable: &[bool], amount: DVec2, rng: &mut Rng) {
    for (x, &m) in p.iter_mut().zip(movable) {
        if m {
            *x += DVec2::new(rng.next() * amount.x, rng.next() * amount.y);
        }
    }
}

pub fn hard_meshes() -> Vec<(&'static str, Mesh)> {
    let mut out = Vec::new();
    let mut rng = Rng(7);

    // Anisotropic graded grid: x spacing grows geometrically (ratio 1.25), cells 50:1 wide.
    let xs: Vec<f64> = (0..=16).map(|i| (1.25f64.powi(i) - 1.0) * 4.0).collect();
    let ys: Vec<f64> = (0..=12).map(|j| j as f64 * 0.08).collect();
    let (mut p, q) = on_coordinates(&xs, &ys, |_, _| false);
    let inner = interior_mask(p.len(), &q);
    for (k, x) in p.iter_mut().enumerate() {
        if inner[k] {
            let i = k % xs.len();
            let dx = (xs[(i + 1).min(xs.len() - 1)] - xs[i.saturating_sub(1)]) * 0.3;
            *x += DVec2::new(rng.next() * dx, rng.next() * 0.03);
        }
    }
    out.push(("graded anisotropic", Mesh::new(p, q, None).unwrap()));

    // Boundary layer: rows graded 1e-3 .. 1 in y, jittered in x by a fraction of the width.
    let xs: Vec<f64> = (0..=14).map(|i| i as f64).collect();
    let ys: Vec<f64> = (0..=12).map(|j| if j == 0 { 0.0 } else { 1e-3 * 1.9f64.powi(j) }).collect();
    let (mut p, q) = on_coordinates(&xs, &ys, |_, _| false);
    let inner = interior_mask(p.len(), &q);
    jitter(&mut p, &inner, DVec2::new(0.35, 0.0), &mut rng);
    out.push(("boundary layer", Mesh::new(p, q, None).unwrap()));

    // Folded over several layers: in a 14x14 grid the band of rows 3..=9, columns 4..=10, is
    // mirrored (row 3 goes to row 9 and back), so six layers of quads lie upside down.
    let xs: Vec<f64> = (0..=14).map(|i| i as f64).collect();
    let (mut p, q) = on_coordinates(&xs, &xs, |_, _| false);
    for (k, x) in p.iter_mut().enumerate() {
        let (i, j) = (k % 15, k / 15);
        if (3..=9).contains(&j) && (4..=10).contains(&i) {
            x.y = 12.0 - x.y + 0.1 * rng.next();
        }
    }
    out.push(("folded layers", Mesh::new(p, q, None).unwrap()));

    // Near-touching boundary: a 20x8 plate with a slit 1/100 of a cell wide cut from the
    // left edge (two boundary parts almost touching); interior jittered.
    let xs: Vec<f64> = (0..=20).map(|i| i as f64).collect();
    let ys: Vec<f64> = vec![0.0, 1.0, 2.0, 3.0, 3.995, 4.005, 5.0, 6.0, 7.0, 8.0];
    let (mut p, q) = on_coordinates(&xs, &ys, |i, j| j == 4 && i < 14);
    let inner = interior_mask(p.len(), &q);
    jitter(&mut p, &inner, DVec2::new(0.3, 0.0), &mut rng);
    out.push(("near-touching slit", Mesh::new(p, q, None).unwrap()));

    // Jittered plate with holes: 30x30 grid, three square holes, interior jittered hard
    // enough to fold dozens of quads.
    let xs: Vec<f64> = (0..=30).map(|i| i as f64).collect();
    let hole = |i: usize, j: usize| {
        (5..9).contains(&i) && (5..9).contains(&j)
            || (18..24).contains(&i) && (8..12).contains(&j)
            || (10..14).contains(&i) && (20..26).contains(&j)
    };
    let (mut p, q) = on_coordinates(&xs, &xs, hole);
    let inner = interior_mask(p.len(), &q);
    jitter(&mut p, &inner, DVec2::splat(0.62), &mut rng);
    out.push(("jittered plate, holes", Mesh::new(p, q, None).unwrap()));
    out
}

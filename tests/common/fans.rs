//! The tangled fan of tests/fans.rs and benches/fans.rs, included with `#[path]` by both.

use quadopt::{DVec2, Mesh};
use std::f64::consts::TAU;

/// A fan of `n` quads around vertex 0 (boundary at radii 1 and 1.5) scaled by `scale`, with
/// its centre pushed outside it to (2, 0.3).
pub fn tangled_fan(n: u32, scale: f64) -> Mesh {
    let mut points = vec![DVec2::new(2.0, 0.3) * scale];
    for i in 0..n {
        let (a, d) = (TAU * i as f64 / n as f64, TAU * (i as f64 + 0.5) / n as f64);
        points.push(DVec2::new(a.cos(), a.sin()) * scale);
        points.push(DVec2::new(d.cos(), d.sin()) * (1.5 * scale));
    }
    let quads = (0..n).map(|i| [0, 1 + 2 * i, 2 + 2 * i, 1 + 2 * ((i + 1) % n)]).collect();
    Mesh::new(points, quads, None).unwrap()
}

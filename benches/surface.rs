//! Criterion benchmarks of the reference surface (src/surface, issue 33):
//!
//! - `surface/build/N`: triangulating a torus of N/2 quads and building its tree;
//! - `surface/closest/N`, `surface/closest_from_hint/N`: 1,000 closest-point queries from
//!   points near the surface (vertices moved by up to a third of an edge, as in a sweep),
//!   without and with the triangle the unmoved vertex was on as the hint, and
//!   `surface/closest_near/N` the local walk from that triangle (what the optimizer runs);
//! - `surface/closest_far/N`: 1,000 queries from anywhere in the torus's box and around it;
//! - `surface/exhaustive/N` on a small torus: the same near queries testing every triangle,
//!   the baseline the tree is measured against.
//!
//! `cargo bench --bench surface` runs them; docs/reference_surface.md has the numbers.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use quadopt::face::Face;
use quadopt::surface::ReferenceSurface;
use std::f64::consts::TAU;
use std::hint::black_box;
use std::time::Duration;

/// A torus (radii 1 and 0.3) of `nu` x `nv` quads.
fn torus(nu: usize, nv: usize) -> (Vec<DVec3>, Vec<Face>) {
    let mut points = Vec::with_capacity(nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            let (u, v) = (i as f64 / nu as f64 * TAU, j as f64 / nv as f64 * TAU);
            points.push(DVec3::new(
                (1.0 + 0.3 * v.cos()) * u.cos(),
                (1.0 + 0.3 * v.cos()) * u.sin(),
                0.3 * v.sin(),
            ));
        }
    }
    let id = |i: usize, j: usize| ((j % nv) * nu + (i % nu)) as u32;
    let mut faces = Vec::with_capacity(nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (points, faces)
}

/// A seeded generator of numbers in [-1, 1).
fn generator(mut state: u64) -> impl FnMut() -> f64 {
    move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// 1,000 points near the surface (a vertex moved by up to `step` per axis) and, for each, the
/// triangle that vertex is on.
fn near_queries(s: &ReferenceSurface, points: &[DVec3], step: f64) -> Vec<(DVec3, u32)> {
    let mut rnd = generator(7);
    (0..1000)
        .map(|k| {
            let v = points[(k * 7919) % points.len()];
            let hint = s.closest_point(v).triangle;
            (v + DVec3::new(rnd(), rnd(), rnd()) * step, hint)
        })
        .collect()
}

fn benches(c: &mut Criterion) {
    let mut group = c.benchmark_group("surface");
    group.sample_size(20).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    // 250 x 200 quads: 100,000 triangles, edges about 0.025 and 0.0094 long.
    let (points, faces) = torus(250, 200);
    group.bench_function(BenchmarkId::new("build", 100_000), |b| {
        b.iter(|| ReferenceSurface::new(black_box(&points), black_box(&faces)).unwrap())
    });
    let s = ReferenceSurface::new(&points, &faces).unwrap();
    let near = near_queries(&s, &points, 0.003);
    let mut rnd = generator(11);
    let far: Vec<DVec3> = (0..1000).map(|_| DVec3::new(rnd() * 1.6, rnd() * 1.6, rnd() * 0.6)).collect();
    group.throughput(Throughput::Elements(1000));
    group.bench_function(BenchmarkId::new("closest", 100_000), |b| {
        b.iter(|| near.iter().map(|&(q, _)| s.closest_point(q).distance).sum::<f64>())
    });
    group.bench_function(BenchmarkId::new("closest_from_hint", 100_000), |b| {
        b.iter(|| near.iter().map(|&(q, hint)| s.closest_point_from(q, hint).distance).sum::<f64>())
    });
    group.bench_function(BenchmarkId::new("closest_near", 100_000), |b| {
        b.iter(|| near.iter().map(|&(q, hint)| s.closest_point_near(q, hint).distance).sum::<f64>())
    });
    group.bench_function(BenchmarkId::new("closest_far", 100_000), |b| {
        b.iter(|| far.iter().map(|&q| s.closest_point(q).distance).sum::<f64>())
    });
    // 40 x 25 quads: 2,000 triangles, tree against testing them all.
    let (points, faces) = torus(40, 25);
    let small = ReferenceSurface::new(&points, &faces).unwrap();
    let near = near_queries(&small, &points, 0.02);
    group.bench_function(BenchmarkId::new("closest", 2_000), |b| {
        b.iter(|| near.iter().map(|&(q, _)| small.closest_point(q).distance).sum::<f64>())
    });
    group.bench_function(BenchmarkId::new("exhaustive", 2_000), |b| {
        b.iter(|| near.iter().map(|&(q, _)| small.closest_point_exhaustive(q).distance).sum::<f64>())
    });
    group.finish();
}

criterion_group!(surface, benches);
criterion_main!(surface);

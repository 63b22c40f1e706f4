//! Criterion benchmarks of the optimizer on synthetic meshes (a grid with four circular holes
//! and jittered interior vertices, see `quadopt::synthetic`) of about 10k, 100k and 1M quads:
//!
//! - `sweep/N`: one embedded-polygon sweep with sliding boundary (plus the per-run set-up a
//!   sweep cannot do without: corner detection, boundary geometry and the quality of the
//!   result), topology built once outside the timing;
//! - `optimize/N`: a full run with the default options (untangling, guarded moves, automatic
//!   boundary mode, size-independent termination);
//! - `topology/N`: building the CSR topology.
//!
//! `cargo bench --bench optimize` runs them. A full run on 1M quads takes minutes and criterion
//! needs at least ten samples, so `optimize/1000000` only runs with QUADOPT_BENCH_1M=1;
//! `QUADOPT_BENCH_SIZES=10000,100000` picks other sizes.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use quadopt::synthetic::Synthetic;
use quadopt::{BoundaryMode, Optimizer, Options, Topology};
use std::hint::black_box;
use std::time::Duration;

fn sizes() -> Vec<usize> {
    // `cargo test --all-targets` runs each benchmark once as a smoke test (no `--bench`
    // argument): the smallest size is enough for that.
    let benchmarking = std::env::args().any(|a| a == "--bench");
    std::env::var("QUADOPT_BENCH_SIZES")
        .ok()
        .map(|s| s.split(',').filter_map(|n| n.trim().parse().ok()).collect())
        .unwrap_or_else(|| if benchmarking { vec![10_000, 100_000, 1_000_000] } else { vec![10_000] })
}

fn benches(c: &mut Criterion) {
    let full_1m = std::env::var_os("QUADOPT_BENCH_1M").is_some();
    for n in sizes() {
        let mesh = Synthetic::with_quads(n).generate();
        let optimizer = Optimizer::new(&mesh);
        let mut group = c.benchmark_group(format!("{n}"));
        group.sample_size(10).warm_up_time(Duration::from_millis(500));
        group.bench_function(BenchmarkId::new("topology", n), |b| b.iter(|| Topology::new(black_box(&mesh))));
        let sweep = Options {
            boundary: BoundaryMode::Slide,
            max_iterations: 1,
            untangle: false,
            ..Options::default()
        };
        group.bench_function(BenchmarkId::new("sweep", n), |b| {
            b.iter_batched_ref(
                || mesh.clone(),
                |m| optimizer.run(m, &sweep, None).unwrap(),
                criterion::BatchSize::LargeInput,
            )
        });
        if n < 1_000_000 || full_1m {
            group.measurement_time(Duration::from_secs(if n >= 100_000 { 60 } else { 10 }));
            group.bench_function(BenchmarkId::new("optimize", n), |b| {
                b.iter_batched_ref(
                    || mesh.clone(),
                    |m| optimizer.run(m, &Options::default(), None).unwrap(),
                    criterion::BatchSize::LargeInput,
                )
            });
        }
        group.finish();
    }
}

criterion_group!(name = optimize; config = Criterion::default(); targets = benches);
criterion_main!(optimize);

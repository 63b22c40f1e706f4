//! Criterion benchmarks of fans, one vertex shared by many quads (issue 8, items 2 and 7):
//!
//! - `untangle/N/SCALE`: a full default run on a fan of N quads (800 and 2,000) scaled by
//!   SCALE (1e-5, 1, 1e5), whose centre was pushed outside the fan so most quads are inverted
//!   (target: under 1 s each; they took from seconds to well over 10 minutes before the
//!   untangler's local program was solved in linear time);
//! - `topology/200000`: building the topology of a fan of 200k quads (target: about the time
//!   of a 200k-quad grid; it took 10 s and more when ring building was quadratic);
//! - `cone/N`: a default run on a cone whose apex is shared by N quads (2,000 and 20,000) on a
//!   curved surface (issue 42; target: the time grows as the valence does, about 10x from one
//!   to the other; a star's vertex lookup was quadratic in its size, and 50,000 took 35 s).
//!
//! `cargo bench --bench fans` runs them.

use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use quadopt::{Optimizer, Options, Topology};
use std::hint::black_box;
use std::time::Duration;

#[path = "../tests/common/fans.rs"]
mod fans;
use fans::tangled_fan;

#[allow(dead_code)]
#[path = "../tests/common/surfaces.rs"]
mod surfaces;

fn benches(c: &mut Criterion) {
    let mut group = c.benchmark_group("fans");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    for n in [800, 2000] {
        for scale in [1e-5, 1.0, 1e5] {
            let mesh = tangled_fan(n, scale);
            let optimizer = Optimizer::new(&mesh);
            let id = BenchmarkId::new("untangle", format!("{n}/{scale:e}"));
            group.bench_function(id, |b| {
                b.iter_batched_ref(
                    || mesh.clone(),
                    |m| {
                        let r = optimizer.run(m, &Options::default(), None).unwrap();
                        assert_eq!(r.output.inverted, 0);
                        r
                    },
                    BatchSize::LargeInput,
                )
            });
        }
    }
    let fan = tangled_fan(200_000, 1.0);
    group
        .bench_function(BenchmarkId::new("topology", 200_000), |b| b.iter(|| Topology::new(black_box(&fan))));
    for n in [2000, 20_000] {
        let (points, faces) = surfaces::cone_apex(n, 1);
        let mesh = quadopt::surface::SurfaceMesh::new(points, faces, None).unwrap();
        let optimizer = quadopt::surface::SurfaceOptimizer::new(&mesh, 45.0, &[]).unwrap();
        group.bench_function(BenchmarkId::new("cone", n), |b| {
            b.iter_batched_ref(
                || mesh.clone(),
                |m| optimizer.run(m, &Options::default(), None).unwrap(),
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

criterion_group!(fan_benches, benches);
criterion_main!(fan_benches);

//! Criterion benchmarks of the optimizer on synthetic meshes (a grid with four circular holes
//! and jittered interior vertices, see `quadopt::synthetic`) of about 10k, 100k and 1M quads:
//!
//! - `sweep/N`: one embedded-polygon sweep with sliding boundary, no max-min stage (plus the per-run set-up a
//!   sweep cannot do without: corner detection, boundary geometry and the quality of the
//!   result), topology built once outside the timing;
//! - `optimize/N`: a full run with the default options (untangling, guarded moves, automatic
//!   boundary mode, size-independent termination);
//! - `topology/N`: building the CSR topology;
//! - `samples/optimize/NAME`: a full default run on each sample mesh of `data/` (topology
//!   included; a sample on a curved surface runs the surface optimizer, built outside the
//!   timing);
//! - `quad_dominant/PRESET/quads` and `quad_dominant/PRESET/mixed`: a full run
//!   (`quadopt::optimize`, topology included) with each preset (fast, balanced, best) on the
//!   synthetic mesh of about 10k quads and on its quad-dominant twin
//!   ([`Synthetic::generate_quad_dominant`] with a fifth of the quads split into two triangles:
//!   the same vertices at the same positions, 1.2 times the faces). Issue 32's target: time
//!   per face on the quad-dominant mesh within 1.5 times that on the quad mesh. Two more
//!   pairs take the max-min stage out, which runs on the quad-dominant mesh only (its
//!   triangles leave the minimum far below 1 after the sweeps, the quad mesh's is within 1e-3
//!   of 1 and the stage is skipped): `quad_dominant/sweep/*` (one sweep, as `sweep/N`) and
//!   `quad_dominant/PRESET-no-maxmin/*` (balanced and best without the stage).
//!   `QUADOPT_BENCH_QD_QUADS=N` picks another size, `QUADOPT_BENCH_QD_SPLIT=F` another
//!   fraction; before the group it prints both meshes' face counts and each run's sweeps and
//!   max-min stage.
//!
//! - `curved/PRESET/{sphere,cylinder,plane}`: a full run with each preset on a cube-sphere of
//!   about 10k quads (each vertex moved along the sphere by up to a fifth of an edge, no face
//!   folded), on the synthetic planar mesh of the same face count rolled onto a half cylinder
//!   (an isometry: the same mesh and the same quality problem on a curved surface), and on
//!   that planar mesh itself (`SurfaceOptimizer`, features and reference built outside the
//!   timing, as `Optimizer`'s topology is); `curved/sweep/*` one guarded sweep of each. Issue
//!   33's target: time per face on the surface within 2x of the plane's, which the cylinder
//!   measures on the same mesh (the sphere is another mesh: it needs more sweeps, its line
//!   before the group says how many). `QUADOPT_BENCH_CURVED_QUADS=N` picks another size.
//!
//! Before each size's group it prints the peak heap bytes of a default run (topology build
//! included, the caller's mesh excluded) per vertex. `cargo bench --bench optimize` runs them. A full run on 1M quads takes minutes and criterion
//! needs at least ten samples, so `optimize/1000000` only runs with QUADOPT_BENCH_1M=1;
//! `QUADOPT_BENCH_SIZES=10000,100000` picks other sizes.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use quadopt::synthetic::Synthetic;
use quadopt::{BoundaryMode, Effort, Optimizer, Options, Topology};
use std::hint::black_box;
use std::time::Duration;

#[path = "../tests/common/counting_alloc.rs"]
mod counting_alloc;
#[path = "../tests/common/surfaces.rs"]
#[allow(dead_code)]
mod surfaces;
use counting_alloc::peak_of;

/// Prints the working set of a default run (topology included) per vertex.
fn report_working_set(mesh: &quadopt::Mesh) {
    let vertices = mesh.points().len();
    let ((), bytes) = peak_of(|| {
        let mut m = mesh.clone();
        let optimizer = Optimizer::new(&m);
        optimizer.run(&mut m, &Options::default(), None).unwrap();
    });
    // The clone of the mesh is the caller's data, not the library's working set.
    let own = bytes.saturating_sub(mesh_bytes(mesh));
    println!(
        "working set/{vertices} vertices: {:.1} bytes per vertex ({} MB)",
        own as f64 / vertices as f64,
        own >> 20
    );
}

fn mesh_bytes(mesh: &quadopt::Mesh) -> usize {
    size_of_val(mesh.points()) + size_of_val(mesh.fixed()) + size_of_val(mesh.quads())
}

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
        if n < 1_000_000 || full_1m {
            report_working_set(&mesh);
        }
        let mut group = c.benchmark_group(format!("{n}"));
        group.sample_size(10).warm_up_time(Duration::from_millis(500));
        group.bench_function(BenchmarkId::new("topology", n), |b| b.iter(|| Topology::new(black_box(&mesh))));
        let sweep = Options::default()
            .with_boundary(BoundaryMode::Slide)
            .with_max_iterations(1)
            .with_untangle(false)
            .with_max_min(false);
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

/// A full default run on each sample mesh of `data/` (`samples/NAME`).
fn samples(c: &mut Criterion) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    let mut files: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    files.retain(|p| quadopt::io::Format::from_path(p).is_ok());
    files.sort();
    let mut group = c.benchmark_group("samples");
    group.sample_size(10).warm_up_time(Duration::from_millis(300)).measurement_time(Duration::from_secs(3));
    for path in files {
        let data = quadopt::io::read_mesh(&path).unwrap();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        // The samples on curved surfaces: the surface optimizer, its set-up outside the timing.
        let Ok(planar) = quadopt::io::PlanarMesh::new(&data) else {
            let points = data.points.iter().map(|&p| glam::DVec3::from_array(p)).collect();
            let surface = quadopt::surface::SurfaceMesh::new(points, data.quads.clone(), None).unwrap();
            let optimizer = quadopt::surface::SurfaceOptimizer::new(&surface, 45.0, &[]).unwrap();
            group.bench_function(BenchmarkId::new("optimize", name), |b| {
                b.iter_batched_ref(
                    || surface.clone(),
                    |m| optimizer.run(m, &Options::default(), None).unwrap(),
                    criterion::BatchSize::LargeInput,
                )
            });
            continue;
        };
        let mesh = planar.mesh;
        group.bench_function(BenchmarkId::new("optimize", name), |b| {
            b.iter_batched_ref(
                || mesh.clone(),
                |m| quadopt::optimize(m, &Options::default()).unwrap(),
                criterion::BatchSize::SmallInput,
            )
        });
    }
    group.finish();
}

/// Per preset, a full run on a quad mesh and on its quad-dominant twin (the same vertices, a
/// fraction of the quads split into triangles): `quad_dominant/PRESET/{quads,mixed}`.
fn quad_dominant(c: &mut Criterion) {
    let env = |name: &str| std::env::var(name).ok().and_then(|s| s.trim().parse::<f64>().ok());
    let n = env("QUADOPT_BENCH_QD_QUADS").map_or(10_000, |n| n as usize);
    let split = env("QUADOPT_BENCH_QD_SPLIT").unwrap_or(0.2);
    let spec = Synthetic::with_quads(n);
    let quads = spec.generate();
    let mixed = spec.generate_quad_dominant(split).unwrap();
    assert_eq!(quads.points(), mixed.points(), "the twins must share their vertices");
    println!(
        "quad_dominant: quad mesh {} faces, quad-dominant mesh {} faces ({} triangles), {} vertices each",
        quads.faces().len(),
        mixed.faces().len(),
        mixed.triangle_count(),
        quads.points().len()
    );
    let mut group = c.benchmark_group("quad_dominant");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(5));
    let sweep = Options::default()
        .with_boundary(BoundaryMode::Slide)
        .with_max_iterations(1)
        .with_untangle(false)
        .with_max_min(false);
    for (kind, mesh) in [("quads", &quads), ("mixed", &mixed)] {
        let optimizer = Optimizer::new(mesh);
        group.bench_function(BenchmarkId::new("sweep", kind), |b| {
            b.iter_batched_ref(
                || mesh.clone(),
                |m| optimizer.run(m, &sweep, None).unwrap(),
                criterion::BatchSize::LargeInput,
            )
        });
    }
    let runs = Effort::ALL.into_iter().map(|e| (e.to_string(), Options::default().with_effort(e)));
    let no_stage = [Effort::Balanced, Effort::Best]
        .into_iter()
        .map(|e| (format!("{e}-no-maxmin"), Options::default().with_effort(e).with_max_min(false)));
    for (name, options) in runs.chain(no_stage) {
        for (kind, mesh) in [("quads", &quads), ("mixed", &mixed)] {
            let report = quadopt::optimize(&mut mesh.clone(), &options).unwrap();
            let stage = report.max_min.as_ref().map_or("no max-min stage".to_string(), |g| {
                format!("max-min stage {} rounds, {:.3} s", g.rounds, g.seconds)
            });
            println!(
                "quad_dominant/{name}/{kind}: {} sweeps ({} untangling), {stage}, min {:.3} -> {:.3}, {:.3} s",
                report.iterations,
                report.untangle_sweeps,
                report.input.min,
                report.output.min,
                report.seconds
            );
            group.bench_function(BenchmarkId::new(&name, kind), |b| {
                b.iter_batched_ref(
                    || mesh.clone(),
                    |m| quadopt::optimize(m, &options).unwrap(),
                    criterion::BatchSize::LargeInput,
                )
            });
        }
    }
    group.finish();
}

/// A cube-sphere of `6 n^2` quads, each vertex moved along the sphere by up to a fifth of an
/// edge of the cube's middle (seeded; no face folds: the edges near the cube's corners are
/// shorter).
fn perturbed_sphere(n: u32) -> quadopt::surface::SurfaceMesh {
    let (mut points, faces) = surfaces::cube_sphere(n);
    let mut state = 0x5eed_u64;
    let mut rnd = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let step = 0.15 * std::f64::consts::FRAC_PI_2 / f64::from(n);
    for p in &mut points {
        let d = glam::DVec3::new(rnd(), rnd(), rnd());
        *p = (*p + (d - *p * d.dot(*p)) * step).normalize();
    }
    quadopt::surface::SurfaceMesh::new(points, faces, None).unwrap()
}

/// The planar mesh rolled onto a half cylinder (its width is half the circumference, its
/// y-axis the cylinder's): an isometry, so the same mesh with the same quality problem, on a
/// curved surface.
fn rolled(plane: &quadopt::Mesh) -> quadopt::surface::SurfaceMesh {
    let (lo, hi) = plane
        .points()
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p.x), hi.max(p.x)));
    let r = (hi - lo) / std::f64::consts::PI;
    let points = plane
        .points()
        .iter()
        .map(|p| {
            let a = (p.x - 0.5 * (lo + hi)) / r;
            glam::DVec3::new(r * a.sin(), p.y, r * (1.0 - a.cos()))
        })
        .collect();
    quadopt::surface::SurfaceMesh::new(points, plane.faces().to_vec(), Some(plane.fixed().to_vec())).unwrap()
}

fn curved(c: &mut Criterion) {
    let quads = std::env::var("QUADOPT_BENCH_CURVED_QUADS").ok().and_then(|s| s.trim().parse::<f64>().ok());
    let n = ((quads.unwrap_or(10_000.0) / 6.0).sqrt().round() as u32).max(2);
    let sphere = perturbed_sphere(n);
    let plane = Synthetic::with_quads(sphere.faces().len()).generate();
    let cylinder = rolled(&plane);
    println!(
        "curved: sphere {} faces, {} vertices; plane and cylinder {} faces, {} vertices",
        sphere.faces().len(),
        sphere.points().len(),
        plane.faces().len(),
        plane.points().len()
    );
    let surface_optimizer = quadopt::surface::SurfaceOptimizer::new(&sphere, 45.0, &[]).unwrap();
    let cylinder_optimizer = quadopt::surface::SurfaceOptimizer::new(&cylinder, 45.0, &[]).unwrap();
    let optimizer = Optimizer::new(&plane);
    let mut group = c.benchmark_group("curved");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(5));
    let sweep = Options::default().with_max_iterations(1).with_untangle(false).with_max_min(false);
    let runs = [("sweep".to_string(), sweep)]
        .into_iter()
        .chain(Effort::ALL.into_iter().map(|e| (e.to_string(), Options::default().with_effort(e))));
    for (name, options) in runs {
        let r = surface_optimizer.run(&mut sphere.clone(), &options, None).unwrap();
        let y = cylinder_optimizer.run(&mut cylinder.clone(), &options, None).unwrap();
        let p = optimizer.run(&mut plane.clone(), &options, None).unwrap();
        let line = |what: &str,
                    sweeps: usize,
                    input: &quadopt::QualityStats,
                    output: &quadopt::QualityStats,
                    seconds: f64| {
            format!(
                "{what} {sweeps} sweeps, min/avg {:.3}/{:.4} -> {:.3}/{:.4}, {seconds:.4} s",
                input.min, input.avg, output.min, output.avg
            )
        };
        let stage = |m: &Option<quadopt::MaxMinGain>| match m {
            Some(m) => format!(" (max-min stage {} rounds, {:.4} s)", m.rounds, m.seconds),
            None => String::new(),
        };
        println!(
            "curved/{name}: {}{}; {}{}; {}{}",
            line("sphere", r.iterations, &r.input, &r.output, r.seconds),
            stage(&r.max_min),
            line("cylinder", y.iterations, &y.input, &y.output, y.seconds),
            stage(&y.max_min),
            line("plane", p.iterations, &p.input, &p.output, p.seconds),
            stage(&p.max_min)
        );
        group.bench_function(BenchmarkId::new(&name, "sphere"), |b| {
            b.iter_batched_ref(
                || sphere.clone(),
                |m| surface_optimizer.run(m, &options, None).unwrap(),
                criterion::BatchSize::LargeInput,
            )
        });
        group.bench_function(BenchmarkId::new(&name, "cylinder"), |b| {
            b.iter_batched_ref(
                || cylinder.clone(),
                |m| cylinder_optimizer.run(m, &options, None).unwrap(),
                criterion::BatchSize::LargeInput,
            )
        });
        group.bench_function(BenchmarkId::new(&name, "plane"), |b| {
            b.iter_batched_ref(
                || plane.clone(),
                |m| optimizer.run(m, &options, None).unwrap(),
                criterion::BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

criterion_group!(name = optimize; config = Criterion::default(); targets = benches, samples, quad_dominant, curved);
criterion_main!(optimize);

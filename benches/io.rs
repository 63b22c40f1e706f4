//! Criterion benchmarks of the mesh files (issue 45, item 4): reading and writing the
//! synthetic mesh of about 1M quads (`quadopt generate --quads 1000000`: a grid with four
//! holes and jittered interior vertices, z = 0) in each format, in memory (no disk):
//!
//! - `io/write/FORMAT`: [`quadopt::io::write_mesh_bytes`] into a buffer;
//! - `io/read/FORMAT`: [`quadopt::io::read_mesh_bytes`] of those bytes.
//!
//! FORMAT is `vtk`, `obj`, `off`, `msh` (ASCII 4.1), `msh-binary` (binary 4.1), `vtu`
//! (ASCII), `vtu-binary` (inline base64) and `vtu-appended` (appended raw). The mesh carries
//! a per-face quality array, as `quadopt optimize`'s output does. `QUADOPT_BENCH_IO_QUADS=N`
//! picks another size; `QUADOPT_BENCH_IO_FORMATS=vtk,msh` a subset.
//! `cargo bench --bench io` runs them.

use criterion::{Criterion, criterion_group, criterion_main};
use quadopt::io::{Encoding, Format, MeshData, read_mesh_bytes, write_mesh_bytes};
use quadopt::synthetic::Synthetic;
use std::hint::black_box;
use std::time::Duration;

fn mesh(quads: usize) -> MeshData {
    let mesh = Synthetic::with_quads(quads).generate();
    let points = mesh.points().iter().map(|p| [p.x, p.y, 0.0]).collect();
    let mut data = MeshData::new(points, mesh.quads_as_given());
    data.quality = Some(mesh.quality_values());
    data
}

fn bench(c: &mut Criterion) {
    let quads =
        std::env::var("QUADOPT_BENCH_IO_QUADS").ok().and_then(|s| s.parse().ok()).unwrap_or(1_000_000);
    let only = std::env::var("QUADOPT_BENCH_IO_FORMATS").ok();
    let base = mesh(quads);
    let cases: [(&str, Format, Encoding); 8] = [
        ("vtk", Format::Vtk, Encoding::Ascii),
        ("obj", Format::Obj, Encoding::Ascii),
        ("off", Format::Off, Encoding::Ascii),
        ("msh", Format::Msh, Encoding::Ascii),
        ("msh-binary", Format::Msh, Encoding::Binary),
        ("vtu", Format::Vtu, Encoding::Ascii),
        ("vtu-binary", Format::Vtu, Encoding::Binary),
        ("vtu-appended", Format::Vtu, Encoding::Appended),
    ];
    let mut g = c.benchmark_group("io");
    g.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    for (name, format, encoding) in cases {
        if only.as_deref().is_some_and(|o| !o.split(',').any(|f| f == name)) {
            continue;
        }
        let mut data = base.clone();
        data.encoding = encoding;
        let bytes = write_mesh_bytes(format, &data).expect("write");
        eprintln!("io/{name}: {} MB for {} quads", bytes.len() / 1_000_000, base.quads.len());
        g.bench_function(format!("write/{name}"), |b| {
            b.iter(|| write_mesh_bytes(format, black_box(&data)).unwrap())
        });
        g.bench_function(format!("read/{name}"), |b| {
            b.iter(|| read_mesh_bytes(black_box(&bytes), format).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

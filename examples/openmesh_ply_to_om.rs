//! Loads a PLY quad mesh with OpenMesh (openmesh-sys), optimizes it with quadopt and writes the
//! result as an OM file (OpenMesh's own format, which keeps every f64 bit and the fixed flags).
//!
//!     cargo run --release --features openmesh --example openmesh_ply_to_om -- IN.ply OUT.om
//!
//! Without arguments it first writes a jittered demo grid as `demo.ply` in the temporary
//! directory (f32 coordinates, as PLY through OpenMesh 9 stores them) and uses that.

use openmesh_sys::{MeshArrays, WriteOptions};
use quadopt::io::{MeshData, PlanarMesh};
use quadopt::synthetic::Synthetic;
use quadopt::{Optimizer, Options};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    let (input, output) = match args.as_slice() {
        [i, o] => (i.clone(), o.clone()),
        [] => {
            let dir = std::env::temp_dir();
            let demo = dir.join("demo.ply");
            let mesh = Synthetic { nx: 12, ny: 8, ..Synthetic::default() }.generate();
            let points = mesh.points().iter().map(|p| [p.x, p.y, 0.0]).collect();
            let arrays = MeshArrays::new(points, mesh.quads_as_given());
            openmesh_sys::write(&demo, &arrays, &WriteOptions { binary: true, round_to_f32: true })?;
            (demo, dir.join("demo_optimized.om"))
        }
        _ => return Err("usage: openmesh_ply_to_om [IN.ply OUT.om]".into()),
    };

    // Read with OpenMesh: flat arrays; a face OpenMesh could not add is an error, not a gap.
    let (arrays, info) = openmesh_sys::read(&input)?;
    println!(
        "{}: {} vertices, {} faces ({}), fixed flags: {}",
        input.display(),
        arrays.points.len(),
        arrays.face_count(),
        if info.binary { "binary" } else { "ASCII" },
        arrays.fixed.is_some()
    );

    // quadopt works on quads: convert, map the plane to 2D, optimize, map back.
    let quads = arrays
        .faces()
        .map(|f| <[u32; 4]>::try_from(f).map_err(|_| format!("a face with {} vertices; only quads", f.len())))
        .collect::<Result<Vec<_>, _>>()?;
    let mut data = MeshData { fixed: arrays.fixed.clone(), ..MeshData::new(arrays.points.clone(), quads) };
    let mut planar = PlanarMesh::new(&data)?;
    let report = Optimizer::new(&planar.mesh).run(&mut planar.mesh, &Options::default(), None)?;
    planar.write_back(&mut data);
    println!(
        "scaled Jacobian min {:.4} -> {:.4}, avg {:.4} -> {:.4}, inverted {} -> {}",
        report.input.min,
        report.output.min,
        report.input.avg,
        report.output.avg,
        report.input.inverted,
        report.output.inverted
    );

    // Write OM: full precision, the fixed flags as a vertex property and locked status.
    let mut result = MeshArrays::new(data.points, &data.quads);
    result.fixed = data.fixed;
    openmesh_sys::write(&output, &result, &WriteOptions::default())?;
    println!("wrote {}", output.display());
    Ok(())
}

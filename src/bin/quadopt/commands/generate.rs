//! `quadopt generate -o OUT`: a synthetic benchmark mesh.

use crate::fail::Fail;
use crate::mesh_files::MeshWriter;
use crate::plural::{count, faces};
use crate::stdout::report_on_stderr_if_written_to_stdout;
use quadopt::Error;
use quadopt::io::{Format, MeshData};
use quadopt::synthetic::Synthetic;
use std::path::Path;

/// Writes the mesh of `spec` to `output`, with a fraction `triangles` of its quads split into
/// two triangles each ([`Synthetic::generate_quad_dominant`]; 0 writes the quad mesh).
pub fn generate(output: &Path, format: Option<Format>, spec: &Synthetic, triangles: f64) -> Result<(), Fail> {
    let writer = MeshWriter::for_output(output, format, None)?;
    if !(0.0..1.0).contains(&spec.hole_size) {
        return Err(Fail::Usage(format!("--hole-size {} is not in [0, 1)", spec.hole_size)));
    }
    if !(spec.jitter >= 0.0 && spec.jitter.is_finite()) {
        return Err(Fail::Usage(format!("--jitter {} is not a finite number >= 0", spec.jitter)));
    }
    if !(0.0..=1.0).contains(&triangles) {
        return Err(Fail::Usage(format!(
            "--triangles {triangles} is not in [0, 1] (the fraction of quads split into two triangles)"
        )));
    }
    if spec.nx == 0 || spec.ny == 0 {
        return Err(Fail::Usage("--nx and --ny must be at least 1".into()));
    }
    let mesh = if triangles == 0.0 { spec.try_generate() } else { spec.generate_quad_dominant(triangles) };
    let mesh = mesh.map_err(|e| match e {
        // More holes than the grid has room for: the request itself is wrong.
        Error::InvalidOption { name: "holes", reason } => Fail::Usage(format!("--holes: {reason}")),
        e => Fail::from(e),
    })?;
    let points = mesh.points().iter().map(|p| [p.x, p.y, 0.0]).collect();
    let data = MeshData::new(points, mesh.quads_as_given());
    writer.write(output, &data)?;
    report_on_stderr_if_written_to_stdout(output);
    let q = mesh.quality();
    outln!(
        "wrote {}: {}, {}; scaled Jacobian min {:.4}, avg {:.4}, {} inverted",
        output.display(),
        count(mesh.points().len(), "vertex", "vertices"),
        faces(mesh.faces().len() - mesh.triangle_count(), mesh.triangle_count()),
        q.min,
        q.avg,
        q.inverted
    );
    Ok(())
}

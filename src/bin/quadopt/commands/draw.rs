//! `quadopt draw IN -o OUT.png`: a picture of a mesh, of its optimized version, or of both.

use crate::cli::OptArgs;
use crate::fail::Fail;
use crate::mesh_files::{Loaded, load};
use crate::picture;
use crate::picture_files::{PictureFormat, write_picture};
use crate::progress::run;
use quadopt::{Mesh, Optimizer, QualityStats};
use std::path::Path;

/// What `draw` draws.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Drawn {
    Input,
    Optimized,
    BeforeAfter,
}

pub fn draw(input: &Path, output: &Path, what: Drawn, opts: &OptArgs) -> Result<(), Fail> {
    let options = opts.options()?;
    let format = PictureFormat::of(output)?;
    let Loaded { mut planar, .. } = load(input, &opts.fix_physical)?;
    let name = input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let optimized = format!("optimized ({}, {})", options.method.name(), options.boundary.name());
    let picture = match what {
        Drawn::Input => {
            let q = planar.mesh.quality();
            let title = format!("{name}: min {:.3}, avg {:.3}, {} inverted", q.min, q.avg, q.inverted);
            picture::layout::single(&planar.mesh, &with_kinds(title, &planar.mesh))
        }
        Drawn::Optimized => {
            let report = run(&Optimizer::new(&planar.mesh), &mut planar.mesh, &options, true)?;
            let o = report.output;
            let title =
                format!("{name} {optimized}: min {:.3}, avg {:.3}, {} inverted", o.min, o.avg, o.inverted);
            picture::layout::single(&planar.mesh, &with_kinds(title, &planar.mesh))
        }
        Drawn::BeforeAfter => {
            let before = planar.mesh.try_clone().map_err(|e| Fail::Other(e.to_string()))?;
            run(&Optimizer::new(&planar.mesh), &mut planar.mesh, &options, true)?;
            picture::layout::before_after(&before, &planar.mesh, &name, ["input", &optimized])
        }
    };
    write_picture(output, format, &picture)
}

/// `title`, and for a mesh with triangles the min and avg of its quads and of its triangles.
fn with_kinds(title: String, mesh: &Mesh) -> String {
    if mesh.triangle_count() == 0 {
        return title;
    }
    let k = mesh.quality_by_face_kind();
    let pair = |s: Option<QualityStats>| s.map_or("-".to_string(), |s| format!("{:.3}/{:.3}", s.min, s.avg));
    format!("{title}; min/avg quads {}, triangles {}", pair(k.quads), pair(k.triangles))
}

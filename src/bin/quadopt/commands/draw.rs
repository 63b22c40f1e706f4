//! `quadopt draw IN -o OUT.png`: a picture of a mesh, of its optimized version, or of both.

use crate::cli::OptArgs;
use crate::fail::Fail;
use crate::mesh_files::{Curved, Input, Loaded, load_input, marked_edges};
use crate::picture;
use crate::picture::Picture;
use crate::picture_files::{PictureFormat, write_picture};
use crate::progress::{run, run_surface};
use quadopt::surface::SurfaceOptimizer;
use quadopt::{Mesh, Optimizer, Options, QualityStats};
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
    let name = input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let Loaded { mut planar, .. } = match load_input(input, &opts.fix_physical)? {
        Input::Planar(loaded) => {
            opts.check_planar()?;
            loaded
        }
        Input::Curved(curved) => {
            let picture = draw_surface(&name, curved, what, &options, opts)?;
            return write_picture(output, format, &picture);
        }
    };
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

/// The picture of a mesh on a curved surface ([`picture::surface`]'s view), coloured by the
/// signed scaled Jacobian against the input surface.
fn draw_surface(
    name: &str,
    curved: Curved,
    what: Drawn,
    options: &Options,
    opts: &OptArgs,
) -> Result<Picture, Fail> {
    let Curved { data, mut surface } = curved;
    let marked = marked_edges(&data, &surface, opts.feature_edges.as_deref(), &opts.feature_physical)?;
    let optimizer = SurfaceOptimizer::new(&surface, options.feature_angle_deg, &marked)
        .map_err(|e| Fail::Other(format!("{name}: {e}")))?;
    let before = optimizer.measure(surface.points())?;
    let optimized = format!("optimized ({}, effort {})", options.method.name(), options.effort);
    let title = |label: &str, s: &QualityStats| {
        format!(
            "{label}: min {:.3}, avg {:.3}, {} inverted (signed against the surface)",
            s.min, s.avg, s.inverted
        )
    };
    Ok(match what {
        Drawn::Input => picture::surface::single(&surface, &before.values, &title(name, &before.signed)),
        Drawn::Optimized => {
            run_surface(&optimizer, &mut surface, options, true)?;
            let after = optimizer.measure(surface.points())?;
            picture::surface::single(
                &surface,
                &after.values,
                &title(&format!("{name} {optimized}"), &after.signed),
            )
        }
        Drawn::BeforeAfter => {
            let input = surface.clone();
            run_surface(&optimizer, &mut surface, options, true)?;
            let after = optimizer.measure(surface.points())?;
            picture::surface::before_after(
                (&input, &before.values),
                (&surface, &after.values),
                name,
                ["input", &optimized],
            )
        }
    })
}

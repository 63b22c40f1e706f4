//! Optimizer runs, with a progress bar on stderr when a run takes a while.

use crate::fail::Fail;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use quadopt::surface::{SurfaceMesh, SurfaceOptimizer, SurfaceReport};
use quadopt::{Mesh, Optimizer, Options, Progress, Report};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// How long a run goes before the progress bar appears.
const PROGRESS_DELAY: Duration = Duration::from_millis(500);

/// Runs the optimizer. With `progress`, a run lasting more than [`PROGRESS_DELAY`] draws a
/// progress bar on stderr if stderr is a terminal (cleared at the end).
pub fn run(
    optimizer: &Optimizer,
    mesh: &mut Mesh,
    options: &Options,
    progress: bool,
) -> Result<Report, Fail> {
    Ok(with_bar(progress, |cb| optimizer.run(mesh, options, cb))?)
}

/// [`run`] for a mesh on a curved surface.
pub fn run_surface(
    optimizer: &SurfaceOptimizer,
    mesh: &mut SurfaceMesh,
    options: &Options,
    progress: bool,
) -> Result<SurfaceReport, Fail> {
    Ok(with_bar(progress, |cb| optimizer.run(mesh, options, cb))?)
}

/// Calls `f` with a progress callback that draws the bar, when `progress` is asked for and
/// stderr is a terminal; else without one.
fn with_bar<R>(progress: bool, f: impl FnOnce(Option<&mut dyn FnMut(&Progress) -> bool>) -> R) -> R {
    if !progress || !std::io::stderr().is_terminal() {
        return f(None);
    }
    let start = Instant::now();
    let mut bar: Option<ProgressBar> = None;
    let mut cb = |p: &Progress| {
        if bar.is_none() && start.elapsed() >= PROGRESS_DELAY {
            let b =
                ProgressBar::with_draw_target(Some(p.max_iterations as u64), ProgressDrawTarget::stderr());
            if let Ok(style) =
                ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} sweeps, {msg} ({elapsed})")
            {
                b.set_style(style.progress_chars("=> "));
            }
            bar = Some(b);
        }
        if let Some(b) = &bar {
            b.set_prefix(format!("pass {}/{}", p.pass, p.passes));
            b.set_length(p.max_iterations as u64);
            b.set_position(p.iteration as u64);
            // A surface run has no energy to show.
            if p.energy.is_nan() {
                b.set_message("on the surface".to_string());
            } else {
                b.set_message(format!("energy {:.6e}", p.energy));
            }
        }
        true
    };
    let result = f(Some(&mut cb));
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    result
}

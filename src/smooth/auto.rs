//! The automatic boundary mode: slide and snap for the whole mesh, keeping the better; then on
//! small meshes each loop switched to the other approach, keeping every switch that improves.

use super::options::BoundaryMode;
use super::ranking::improves;
use super::report::Progress;
use super::sweep::{Pass, RunContext};
use glam::DVec2;

/// Loops beyond which `Auto` decides for the whole mesh at once instead of per loop.
const AUTO_MAX_LOOPS: usize = 12;
/// Vertices beyond which `Auto` decides for the whole mesh at once.
const AUTO_MAX_VERTICES: usize = 50_000;

impl RunContext<'_> {
    /// `Auto`: slide and snap for the whole mesh, keep the better; then on small meshes try
    /// switching each loop to the other approach, keeping every switch that improves. Loops
    /// where no vertex may move are reported as fixed and never tried both ways (slide and
    /// snap coincide there), so a mesh whose boundary cannot move costs one pass.
    pub fn auto(
        &self,
        start: &[DVec2],
        progress: &mut Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> (Pass, Vec<BoundaryMode>) {
        let loops = self.topo.loop_count();
        let movable: Vec<bool> = (0..loops)
            .map(|l| self.topo.boundary_loop(l).iter().any(|&v| self.features.is_movable(v as usize)))
            .collect();
        let with = |mode| -> Vec<BoundaryMode> {
            movable.iter().map(|&m| if m { mode } else { BoundaryMode::Fixed }).collect()
        };
        let toggled: Vec<usize> = (0..loops).filter(|&l| movable[l]).collect();
        if toggled.is_empty() {
            let modes = with(BoundaryMode::Fixed);
            return (self.pass(start, &modes, (1, 1), progress), modes);
        }
        let per_loop =
            toggled.len() > 1 && toggled.len() <= AUTO_MAX_LOOPS && start.len() <= AUTO_MAX_VERTICES;
        let passes = 2 + if per_loop { toggled.len() } else { 0 };
        let (slide, snap) = (with(BoundaryMode::Slide), with(BoundaryMode::Snap));
        let mut best = self.pass(start, &slide, (1, passes), progress);
        let mut best_modes = slide;
        if best.cancelled {
            return (best, best_modes);
        }
        let other = self.pass(start, &snap, (2, passes), progress);
        if improves(&other.stats, &best.stats, &self.input) || other.cancelled {
            (best, best_modes) = (other, snap);
        }
        if per_loop && !best.cancelled {
            for (k, &l) in toggled.iter().enumerate() {
                let mut modes = best_modes.clone();
                modes[l] =
                    if modes[l] == BoundaryMode::Slide { BoundaryMode::Snap } else { BoundaryMode::Slide };
                let p = self.pass(start, &modes, (3 + k, passes), progress);
                let cancelled = p.cancelled;
                if improves(&p.stats, &best.stats, &self.input) {
                    (best, best_modes) = (p, modes);
                }
                if cancelled {
                    best.cancelled = true;
                    break;
                }
            }
        }
        (best, best_modes)
    }
}

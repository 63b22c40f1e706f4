//! The automatic boundary mode, in one pass: every movable boundary vertex computes both the
//! slide and the snap candidate in each sweep and takes the one whose star is better
//! ([`RunContext::auto_candidate`]); the report gives, per loop, the approach most of its
//! vertices took at the end.
//!
//! It replaced running slide and snap (and on small meshes one more pass per loop) to the end
//! and keeping the better: that cost 2 to 12 complete passes for the same quality (measured on
//! the 56 meshes of `tests/quality_floor.rs`, all at or above the floor).

use super::options::BoundaryMode;
use super::report::Progress;
use super::sweep::{Pass, RunContext};
use glam::DVec2;

impl RunContext<'_> {
    /// `Auto`: one pass with every loop that has a movable vertex in automatic mode; loops
    /// where no vertex may move are reported as fixed.
    pub fn auto(
        &self,
        start: &[DVec2],
        progress: &mut Option<&mut dyn FnMut(&Progress) -> bool>,
    ) -> (Pass, Vec<BoundaryMode>) {
        let movable: Vec<bool> = (0..self.topo.loop_count())
            .map(|l| self.topo.boundary_loop(l).iter().any(|&v| self.features.is_movable(v as usize)))
            .collect();
        let modes: Vec<BoundaryMode> =
            movable.iter().map(|&m| if m { BoundaryMode::Auto } else { BoundaryMode::Fixed }).collect();
        let pass = self.pass(start, &modes, (1, 1), progress);
        let chosen = self.chosen_modes(&pass, &movable);
        (pass, chosen)
    }

    /// What the automatic mode ended up doing on each loop: the approach most of its movable
    /// vertices would take at the final positions (slide on a tie).
    fn chosen_modes(&self, pass: &Pass, movable: &[bool]) -> Vec<BoundaryMode> {
        (0..movable.len())
            .map(|l| {
                if !movable[l] {
                    return BoundaryMode::Fixed;
                }
                let snaps = self
                    .topo
                    .boundary_loop(l)
                    .iter()
                    .filter(|&&v| self.features.is_movable(v as usize))
                    .map(|&v| self.auto_candidate(&pass.points, &pass.params, v as usize).mode)
                    .fold(0i64, |n, m| n + if m == BoundaryMode::Snap { 1 } else { -1 });
                if snaps > 0 { BoundaryMode::Snap } else { BoundaryMode::Slide }
            })
            .collect()
    }
}

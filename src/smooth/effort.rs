//! Effort presets: how much work a run spends for how much quality.
//!
//! One default cannot be both the fastest and the best: the sweeps reach most of the quality
//! in a few milliseconds on a small mesh, and the max-min stage buys the last 0.1-0.3 of the
//! minimum at many times that. A preset decides the sweep budget and how much of the max-min
//! stage runs; the options the caller sets still apply on top of it ([`Options::sweep_cap`]:
//! `max_iterations` caps every preset; `max_min = false` turns the stage off in every preset).
//! What each preset is measured against is in docs/performance.md.

use super::maxmin::MaxMinSettings;
use super::options::{Options, StopRule};
use std::str::FromStr;

/// How much work a run spends on quality. Every preset keeps every guarantee of a run (no more
/// inverted quads, a minimum never below the input's, fixed vertices untouched, the boundary on
/// the original polyline, the same result on any thread count); they differ in how far they
/// take the quality.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Effort {
    /// For meshers that smooth inside their own loop: the sweeps with the guard and
    /// untangling, at most [`Effort::FAST_SWEEPS`] of them, and no max-min stage.
    Fast,
    /// The default: the sweeps until the quality stops improving (at most
    /// [`Effort::BALANCED_SWEEPS`]), then a short max-min stage
    /// ([`Effort::BALANCED_ROUNDS`] rounds on the worst region, one sweep of average
    /// recovery).
    #[default]
    Balanced,
    /// The highest quality: the sweeps until the quality stops improving, then the full
    /// max-min stage (rounds until the minimum stalls, the region grown, escapes from its
    /// local equilibria, the average recovered).
    Best,
}

impl Effort {
    /// Every preset, fastest first.
    pub const ALL: [Effort; 3] = [Effort::Fast, Effort::Balanced, Effort::Best];

    /// Sweep budget of [`Effort::Fast`] (untangling sweeps not counted).
    ///
    /// Measured with `tools/bench_peers.py` (data/, Mesquite's planar meshes, the 9k and 186k
    /// plates): with 6 sweeps the presets dominate 178-179 of 189 peer runs, with 10 sweeps
    /// 176. Fewer sweeps answer gmsh's Relocate2D at its speed on four more meshes (mazewheel,
    /// halfCirc, plate_1hole_fine, the 9k plate) and lose one comparison of quality (halfCirc's
    /// average against Laplace2D's); 5 sweeps lose more (179 with noise, `fast` alone 130
    /// against 136).
    pub const FAST_SWEEPS: usize = 6;

    /// Sweeps in a row that leave the kept iterate unchanged after which [`Effort::Fast`]
    /// stops (under the quality stopping rule): on a mesh the sweeps cannot improve (a
    /// perfect grid, a uniform one at its best) the rest of its budget would be spent on
    /// vertices stepping back and forth by rounding-level amounts.
    pub const FAST_STALE_SWEEPS: usize = 2;

    /// Max-min rounds of [`Effort::Balanced`]'s stage. Measured on data/ and Mesquite's
    /// planar meshes against gmsh, GETMe and DMO (tools/bench_peers.py): 1 or 2 rounds
    /// dominate 134 peer runs, 3 rounds 126, 4 rounds 123, the full stage 93 (it is the
    /// slowest part of a run, and the peers are fast).
    pub const BALANCED_ROUNDS: usize = 2;

    /// Sweep budget of [`Effort::Balanced`]. The quality rule goes on while the sweeps gain
    /// steadily, and on a few meshes they gain slowly for the whole default cap of 1000
    /// (Mesquite's shest_grid32: average 0.937 after 200 sweeps, 0.959 after 1000, 33 ms
    /// against 161 ms). Measured: 180 of 189 peer runs dominated with 300, 179 without a
    /// budget; a budget of 20 loses the slow meshes outright (a graded boundary layer of
    /// tests/hard_meshes.rs at 0.47 / 0.92 instead of 1.00 / 1.00; 0.9975 / 0.9998 with 300).
    pub const BALANCED_SWEEPS: usize = 300;

    /// The short name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Effort::Fast => "fast",
            Effort::Balanced => "balanced",
            Effort::Best => "best",
        }
    }

    /// The most sweeps the preset runs (before [`Options::max_iterations`] caps it further).
    pub(crate) fn sweep_budget(self) -> usize {
        match self {
            Effort::Fast => Effort::FAST_SWEEPS,
            Effort::Balanced => Effort::BALANCED_SWEEPS,
            Effort::Best => usize::MAX,
        }
    }

    /// Sweeps in a row without a change of the kept iterate after which the preset stops
    /// (`None`: the stopping rule alone decides).
    pub(crate) fn stale_sweeps(self) -> Option<usize> {
        match self {
            Effort::Fast => Some(Effort::FAST_STALE_SWEEPS),
            Effort::Balanced | Effort::Best => None,
        }
    }

    /// The preset's max-min stage, `None` for none.
    pub(crate) fn max_min_settings(self) -> Option<MaxMinSettings> {
        match self {
            Effort::Fast => None,
            // Two rounds on the worst region, neither grown nor escaped, then one sweep of
            // average recovery: most of what the stage gains on the minimum at a small part
            // of its cost (docs/performance.md, "Presets").
            Effort::Balanced => Some(MaxMinSettings {
                max_rounds: Effort::BALANCED_ROUNDS,
                escapes: 0,
                average_sweeps: 1,
                max_region_delta: MaxMinSettings::default().region_delta,
                ..MaxMinSettings::default()
            }),
            Effort::Best => Some(MaxMinSettings::default()),
        }
    }
}

impl FromStr for Effort {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Effort::ALL
            .into_iter()
            .find(|e| e.name() == s)
            .ok_or_else(|| format!("unknown effort '{s}' (expected fast, balanced or best)"))
    }
}

impl std::fmt::Display for Effort {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl Options {
    /// The sweep cap of a run: [`Options::max_iterations`], or the preset's budget when that
    /// is smaller. The budget belongs to the quality stopping rule: a caller who chose the
    /// paper's energy rule ([`StopRule::Energy`]) runs until it or `max_iterations` stops.
    pub fn sweep_cap(&self) -> usize {
        match self.stop {
            StopRule::Quality => self.max_iterations.min(self.effort.sweep_budget()),
            StopRule::Energy => self.max_iterations,
        }
    }

    /// The settings of the max-min stage this run uses: the preset's, `None` when the preset
    /// has no stage or [`Options::max_min`] is off.
    pub(crate) fn max_min_settings(&self) -> Option<MaxMinSettings> {
        let settings = self.effort.max_min_settings().filter(|_| self.max_min)?;
        Some(MaxMinSettings { max_boundary_deviation: self.max_boundary_deviation, ..settings })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_balanced_is_the_default() {
        for e in Effort::ALL {
            assert_eq!(e.name().parse::<Effort>(), Ok(e));
            assert_eq!(e.to_string(), e.name());
        }
        assert!("medium".parse::<Effort>().unwrap_err().contains("fast, balanced or best"));
        assert_eq!(Effort::default(), Effort::Balanced);
        assert_eq!(Options::default().effort, Effort::Balanced);
    }

    #[test]
    fn the_callers_options_apply_on_top_of_every_preset() {
        for e in Effort::ALL {
            let o = Options::default().with_effort(e);
            assert_eq!(o.effort, e);
            // max_iterations caps every preset.
            assert_eq!(o.clone().with_max_iterations(3).sweep_cap(), 3);
            // The energy rule runs to max_iterations whatever the preset.
            let energy = o.clone().with_stop(StopRule::Energy).with_max_iterations(40);
            assert_eq!(energy.sweep_cap(), 40);
            // max_min = false turns every preset's stage off.
            assert!(o.clone().with_max_min(false).max_min_settings().is_none());
        }
        assert_eq!(Options::fast().sweep_cap(), Effort::FAST_SWEEPS);
        assert!(Options::fast().max_min_settings().is_none());
        assert_eq!(Options::balanced().sweep_cap(), Effort::BALANCED_SWEEPS);
        assert_eq!(Options::best().sweep_cap(), Options::DEFAULT.max_iterations);
        let (balanced, best) = (Options::balanced().max_min_settings(), Options::best().max_min_settings());
        assert_eq!(balanced.as_ref().map(|s| s.max_rounds), Some(Effort::BALANCED_ROUNDS));
        assert_eq!(best, Some(MaxMinSettings::default()));
        let deviation = Options::best().with_max_boundary_deviation(Some(0.25));
        assert_eq!(deviation.max_min_settings().unwrap().max_boundary_deviation, Some(0.25));
    }
}

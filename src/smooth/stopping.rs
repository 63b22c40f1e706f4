//! The stopping rules of a run: the quality rule (stop when what the user gets stops
//! improving) and the paper's energy rule.

use super::options::{Options, StopRule};
use crate::quality::QualityStats;

/// Decides after each sweep whether the run is done.
pub struct Stopper {
    rule: StopRule,
    /// Energy threshold, already divided per movable vertex unless absolute.
    tau: f64,
    per_vertex: f64,
    energy_old: f64,
    /// Best statistics seen by the quality rule and the sweeps since it last rose enough.
    reference: Option<QualityStats>,
    stalled: usize,
}

impl Stopper {
    /// A stopper for `options` on a run with `movable` movable vertices.
    pub fn new(options: &Options, movable: usize) -> Stopper {
        Stopper {
            rule: options.stop,
            tau: options.tau,
            per_vertex: if options.tau_absolute { 1.0 } else { movable.max(1) as f64 },
            energy_old: f64::NAN,
            reference: None,
            stalled: 0,
        }
    }

    /// Records one sweep (the statistics after it and the energy measured during it) and
    /// returns whether to stop. Also returns the energy change, for progress reports.
    pub fn after_sweep(&mut self, stats: &QualityStats, energy: f64) -> (bool, f64) {
        let change = (energy - self.energy_old).abs();
        self.energy_old = energy;
        let stop = match self.rule {
            StopRule::Energy => change / self.per_vertex < self.tau,
            StopRule::Quality => {
                let gained = self.reference.is_none_or(|r| significant_gain(stats, &r));
                if gained {
                    self.reference = Some(*stats);
                    self.stalled = 0;
                } else {
                    self.stalled += 1;
                }
                self.stalled >= StopRule::QUALITY_PATIENCE
            }
        };
        (stop, change)
    }

    /// Starts the quality rule from the statistics before the first sweep.
    pub fn start(&mut self, stats: &QualityStats) {
        self.reference = Some(*stats);
    }
}

/// Whether `now` is significantly better than `before`: fewer inverted quads, or a minimum
/// higher by more than the minimum gain, or an average higher by more than the average gain
/// without the minimum falling by more than that (a trade the ranking would not take).
fn significant_gain(now: &QualityStats, before: &QualityStats) -> bool {
    if now.inverted != before.inverted {
        return now.inverted < before.inverted;
    }
    now.min > before.min + StopRule::QUALITY_MIN_GAIN
        || (now.avg > before.avg + StopRule::QUALITY_AVG_GAIN
            && now.min >= before.min - StopRule::QUALITY_MIN_GAIN)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quality() -> Options {
        Options { stop: StopRule::Quality, ..Options::default() }
    }

    fn stats(inverted: usize, min: f64, avg: f64) -> QualityStats {
        QualityStats { min, avg, max: 1.0, inverted }
    }

    #[test]
    fn the_quality_rule_stops_after_patience_sweeps_without_gain() {
        let mut s = Stopper::new(&quality(), 10);
        s.start(&stats(2, -0.5, 0.5));
        assert!(!s.after_sweep(&stats(1, -0.4, 0.6), 1.0).0, "fewer inverted is progress");
        assert!(!s.after_sweep(&stats(0, 0.1, 0.7), 1.0).0);
        // Gains below both thresholds: stalled once, then done at the patience.
        assert!(!s.after_sweep(&stats(0, 0.1005, 0.70005), 1.0).0);
        assert!(s.after_sweep(&stats(0, 0.1009, 0.70009), 1.0).0);
    }

    #[test]
    fn small_gains_accumulate_against_the_last_reference() {
        // Each sweep gains 0.6e-4 in average: no single step counts, but two together do,
        // since gains are measured from the last significant state, not the previous sweep.
        let mut s = Stopper::new(&quality(), 10);
        s.start(&stats(0, 0.5, 0.8));
        assert!(!s.after_sweep(&stats(0, 0.5, 0.80006), 1.0).0);
        assert!(!s.after_sweep(&stats(0, 0.5, 0.80012), 1.0).0, "0.00012 over the reference");
        assert!(!s.after_sweep(&stats(0, 0.5, 0.80018), 1.0).0);
        assert!(s.after_sweep(&stats(0, 0.5, 0.80020), 1.0).0);
    }

    #[test]
    fn an_average_bought_with_the_minimum_is_no_gain() {
        let mut s = Stopper::new(&quality(), 10);
        s.start(&stats(0, 0.5, 0.8));
        assert!(!s.after_sweep(&stats(0, 0.4, 0.9), 1.0).0);
        assert!(s.after_sweep(&stats(0, 0.4, 0.95), 1.0).0);
    }

    #[test]
    fn the_energy_rule_compares_the_change_per_vertex_or_absolute() {
        let per_vertex = Options { tau: 1e-3, ..Options::default() };
        assert_eq!(per_vertex.stop, StopRule::Energy, "the default");
        let mut s = Stopper::new(&per_vertex, 100);
        let q = stats(0, 0.5, 0.8);
        assert!(!s.after_sweep(&q, 1.0).0, "no change is known after the first sweep");
        assert!(!s.after_sweep(&q, 0.8).0, "0.2 / 100 >= 1e-3");
        assert!(s.after_sweep(&q, 0.75).0, "0.05 / 100 < 1e-3");
        let absolute = Options { tau_absolute: true, ..per_vertex };
        let mut s = Stopper::new(&absolute, 100);
        s.after_sweep(&q, 1.0);
        assert!(!s.after_sweep(&q, 0.95).0, "0.05 >= 1e-3 absolute");
    }
}

//! The stopping rules of a run: the quality rule (stop when what the user gets stops
//! improving) and the paper's energy rule.

use super::options::{Options, StopRule};
use crate::quality::QualityStats;

/// What [`Stopper::after_sweep`] decided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AfterSweep {
    /// The rule is met: the run is done.
    pub stop: bool,
    /// |E_new - E_old| of the sweep (NaN after the first), for progress reports.
    pub energy_change: f64,
}

/// Decides after each sweep whether the run is done.
pub struct Stopper {
    rule: StopRule,
    /// Energy threshold, already divided per movable vertex unless absolute.
    tau: f64,
    per_vertex: f64,
    energy_old: f64,
    /// The quality rule's state.
    quality: QualityTrend,
}

impl Stopper {
    /// A stopper for `options` on a run with `movable` movable vertices.
    pub fn new(options: &Options, movable: usize) -> Stopper {
        Stopper {
            rule: options.stop,
            tau: options.tau,
            per_vertex: if options.tau_absolute { 1.0 } else { movable.max(1) as f64 },
            energy_old: f64::NAN,
            quality: QualityTrend::default(),
        }
    }

    /// Records one sweep (the statistics after it, those of the iterate the run keeps, and the
    /// energy measured during it) and says whether to stop.
    pub fn after_sweep(&mut self, stats: &QualityStats, kept: &QualityStats, energy: f64) -> AfterSweep {
        let energy_change = (energy - self.energy_old).abs();
        self.energy_old = energy;
        let stop = match self.rule {
            StopRule::Energy => energy_change / self.per_vertex < self.tau,
            StopRule::Quality => self.quality.after_sweep(stats, kept),
        };
        AfterSweep { stop, energy_change }
    }

    /// Starts the quality rule from the statistics before the first sweep and the iterate
    /// kept then.
    pub fn start(&mut self, stats: &QualityStats, kept: &QualityStats) {
        self.quality = QualityTrend::default();
        self.quality.best = Some(*stats);
        self.quality.checkpoints.push(*stats);
        self.quality.kept = Some(*kept);
    }
}

/// The best (fewest inverted, highest minimum, highest average) statistics of the sweeps so
/// far, sampled every window, and how many windows in a row had little left to gain; the
/// kept iterate, and for how many windows it has not changed.
#[derive(Default)]
struct QualityTrend {
    best: Option<QualityStats>,
    sweeps: usize,
    /// The best statistics at the end of each window (the first: the start).
    checkpoints: Vec<QualityStats>,
    settled: usize,
    kept: Option<QualityStats>,
    stale: usize,
}

/// Windows in a row with little left to gain after which the quality rule stops.
const SETTLED_WINDOWS: usize = 2;

impl QualityTrend {
    fn after_sweep(&mut self, stats: &QualityStats, kept: &QualityStats) -> bool {
        let best = match self.best {
            None => *stats,
            Some(b) => QualityStats {
                inverted: b.inverted.min(stats.inverted),
                min: b.min.max(stats.min),
                avg: b.avg.max(stats.avg),
                max: b.max.max(stats.max),
            },
        };
        self.best = Some(best);
        self.sweeps += 1;
        if self.sweeps % StopRule::QUALITY_WINDOW != 0 {
            return false;
        }
        self.checkpoints.push(best);
        // The sweeps no longer produce anything the run would return.
        self.stale = if self.kept.is_some_and(|k| same(&k, kept)) { self.stale + 1 } else { 0 };
        self.kept = Some(*kept);
        if self.stale >= StopRule::QUALITY_STALE_WINDOWS {
            return true;
        }
        let n = self.checkpoints.len();
        if n < 3 {
            return false;
        }
        let [c0, c1, c2] = [self.checkpoints[n - 3], self.checkpoints[n - 2], self.checkpoints[n - 1]];
        let repaired = c2.inverted < c1.inverted;
        // Near a perfect mesh the thresholds shrink with the gap left to 1, so the sweeps
        // converge there (cheaply: the gains shrink fast) to within QUALITY_LEAST_LEFT instead
        // of stopping 5e-3 short.
        let left = |gap: f64, most: f64| {
            most.min(StopRule::QUALITY_GAP_FRACTION * gap).max(StopRule::QUALITY_LEAST_LEFT)
        };
        let settled = !repaired
            && tail(c1.min - c0.min, c2.min - c1.min) < left(1.0 - c2.min, StopRule::QUALITY_MIN_LEFT)
            && tail(c1.avg - c0.avg, c2.avg - c1.avg) < left(1.0 - c2.avg, StopRule::QUALITY_AVG_LEFT);
        self.settled = if settled { self.settled + 1 } else { 0 };
        self.settled >= SETTLED_WINDOWS
    }
}

/// Differences of statistics at or below this are rounding (statistics are sums of values in
/// [-1, 1] over the quads: their rounding is far smaller).
const ROUNDING: f64 = 1e-12;

/// Whether two kept iterates rank the same. An iterate better by rounding only (1e-16) may
/// replace the kept one; counted as a change, it would make the stop depend on rounding, and
/// the run would not be the same after scaling or translating the mesh.
pub(crate) fn same(a: &QualityStats, b: &QualityStats) -> bool {
    a.inverted == b.inverted && (a.min - b.min).abs() <= ROUNDING && (a.avg - b.avg).abs() <= ROUNDING
}

/// The gain still to come after window gains `before` then `last`, if they shrink
/// geometrically: the tail last r / (1 - r), r = last / before. No gain: nothing to come; a
/// gain that does not shrink: unbounded.
///
/// Gains at rounding level count as none: a gain of 1e-16 after none would otherwise be an
/// unbounded tail, and the stop would depend on rounding (on the mesh's scale).
fn tail(before: f64, last: f64) -> f64 {
    if last <= ROUNDING {
        return 0.0;
    }
    if before <= last {
        return f64::INFINITY;
    }
    let r = last / before;
    last * r / (1.0 - r)
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

    /// Feeds `avg(k)` (k = 1, 2, ...) with a fixed minimum, each iterate kept; returns the sweep
    /// the rule stopped at.
    fn stops_at(avg: impl Fn(usize) -> f64, cap: usize) -> Option<usize> {
        let mut s = Stopper::new(&quality(), 10);
        s.start(&stats(0, 0.5, avg(0)), &stats(0, 0.5, avg(0)));
        (1..=cap).find(|&k| s.after_sweep(&stats(0, 0.5, avg(k)), &stats(0, 0.5, avg(k)), 1.0).stop)
    }

    #[test]
    fn the_tail_of_geometric_gains() {
        assert_eq!(tail(0.01, 0.0), 0.0);
        assert_eq!(tail(0.01, -0.01), 0.0, "a loss leaves nothing to gain");
        assert_eq!(tail(0.0, 1e-16), 0.0, "a gain at rounding level is none");
        assert_eq!(tail(0.01, 0.01), f64::INFINITY, "a steady gain goes on");
        // Gains 0.004 then 0.002 (r = 1/2): 0.001 + 0.0005 + ... = 0.002 to come.
        assert!((tail(0.004, 0.002) - 0.002).abs() < 1e-15);
    }

    #[test]
    fn a_fast_converging_average_stops_once_its_tail_is_small() {
        // avg(k) = 0.9 - 0.1 * 0.5^k: the gain left after sweep k is 0.1 * 0.5^k, 1e-4 at
        // k = 10. The first window end with two window gains to compare is sweep 10 (tail
        // 0.1 * (0.5^5 - 0.5^10) / 31 = 9.8e-5, settled), the second 15: two in a row.
        assert_eq!(stops_at(|k| 0.9 - 0.1 * 0.5f64.powi(k as i32), 1000), Some(15));
    }

    #[test]
    fn a_slowly_converging_average_goes_on_while_much_is_left() {
        // avg(k) = 0.96 - 0.2 * 0.999^k: 0.2 * 0.999^k is left, so the rule may stop only
        // once that is near QUALITY_AVG_LEFT, 4e-3 (k about 3900): not within a 1000-sweep cap.
        assert_eq!(stops_at(|k| 0.96 - 0.2 * 0.999f64.powi(k as i32), 1000), None);
        // At 0.995^k, 4e-3 is left at k = 780: the rule stops there, not much earlier.
        let k = stops_at(|k| 0.96 - 0.2 * 0.995f64.powi(k as i32), 1000).unwrap();
        assert!((700..=800).contains(&k), "stopped at {k}");
        // A steady gain goes on too.
        assert_eq!(stops_at(|k| 0.5 + 1e-5 * k as f64, 1000), None);
    }

    #[test]
    fn an_oscillating_average_stops_at_its_best() {
        // A limit cycle around 0.87 (the energy rule runs such meshes to the cap).
        let k = stops_at(|k| 0.87 + if k % 2 == 0 { 1e-3 } else { -1e-3 }, 1000).unwrap();
        assert!(k <= 4 * StopRule::QUALITY_WINDOW, "stopped at {k}");
    }

    #[test]
    fn repairing_inverted_quads_or_raising_the_minimum_keeps_it_going() {
        let mut s = Stopper::new(&quality(), 10);
        s.start(&stats(50, -0.5, 0.5), &stats(50, -0.5, 0.5));
        // One inverted quad repaired per sweep, nothing else changes.
        for k in 1..=40 {
            let q = stats(50 - k, -0.5, 0.5);
            assert!(!s.after_sweep(&q, &q, 1.0).stop, "sweep {k}");
        }
        // The minimum rising steadily by 1e-4 per sweep: a window gains 5e-4, forever.
        let mut s = Stopper::new(&quality(), 10);
        s.start(&stats(0, 0.1, 0.8), &stats(0, 0.1, 0.8));
        for k in 1..=100 {
            let q = stats(0, 0.1 + 1e-4 * k as f64, 0.8);
            assert!(!s.after_sweep(&q, &q, 1.0).stop, "sweep {k}");
        }
    }

    #[test]
    fn sweeps_whose_iterates_are_never_kept_stop_the_run() {
        // The average rises steadily (the trend alone would go on), but every iterate has a
        // lower minimum than the kept one, which therefore never changes: the run stops after
        // QUALITY_STALE_WINDOWS windows.
        let kept = stats(0, 0.7, 0.9);
        let mut s = Stopper::new(&quality(), 10);
        s.start(&kept, &kept);
        let stop =
            (1..=1000).find(|&k| s.after_sweep(&stats(0, 0.6, 0.9 + 1e-4 * k as f64), &kept, 1.0).stop);
        assert_eq!(stop, Some(StopRule::QUALITY_STALE_WINDOWS * StopRule::QUALITY_WINDOW));
        // The same iterates, kept: the steady gain goes on.
        let mut s = Stopper::new(&quality(), 10);
        s.start(&kept, &kept);
        for k in 1..=200 {
            let q = stats(0, 0.6, 0.9 + 1e-4 * k as f64);
            assert!(!s.after_sweep(&q, &q, 1.0).stop, "sweep {k}");
        }
    }

    #[test]
    fn the_energy_rule_compares_the_change_per_vertex_or_absolute() {
        assert_eq!(Options::default().stop, StopRule::Quality, "the default");
        let per_vertex = Options { tau: 1e-3, stop: StopRule::Energy, ..Options::default() };
        let mut s = Stopper::new(&per_vertex, 100);
        let q = stats(0, 0.5, 0.8);
        assert!(!s.after_sweep(&q, &q, 1.0).stop, "no change is known after the first sweep");
        assert!(!s.after_sweep(&q, &q, 0.8).stop, "0.2 / 100 >= 1e-3");
        assert!(s.after_sweep(&q, &q, 0.75).stop, "0.05 / 100 < 1e-3");
        let absolute = Options { tau_absolute: true, ..per_vertex };
        let mut s = Stopper::new(&absolute, 100);
        s.after_sweep(&q, &q, 1.0);
        assert!(!s.after_sweep(&q, &q, 0.95).stop, "0.05 >= 1e-3 absolute");
    }
}

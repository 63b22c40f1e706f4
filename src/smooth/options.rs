//! Options of a run: the interior method, the boundary mode, the stopping rule and the
//! safeguards.

use super::effort::Effort;
use crate::error::{Error, Result};
use std::str::FromStr;

/// How interior vertices are moved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Method {
    /// The embedded polygon method of Akram, Si and Chen (Sections 3.1-3.2).
    #[default]
    EmbeddedPolygon,
    /// Uniform Laplacian: each vertex moves towards the average of its edge-neighbours.
    Laplacian,
    /// Cotangent-weighted Laplacian.
    Cotangent,
    /// Xu and Newman's angle-based smoothing (2005): bisectors at edge and diagonal neighbours.
    AngleBased,
}

impl Method {
    /// Every method, in the order of the paper's comparison.
    pub const ALL: [Method; 4] =
        [Method::AngleBased, Method::Laplacian, Method::Cotangent, Method::EmbeddedPolygon];

    /// The short name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Method::EmbeddedPolygon => "ep",
            Method::Laplacian => "laplace",
            Method::Cotangent => "cotan",
            Method::AngleBased => "angle",
        }
    }
}

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "ep" | "embedded-polygon" => Ok(Method::EmbeddedPolygon),
            "laplace" | "laplacian" => Ok(Method::Laplacian),
            "cotan" | "cotangent" => Ok(Method::Cotangent),
            "angle" | "angle-based" => Ok(Method::AngleBased),
            _ => Err(format!("unknown method '{s}' (expected ep, laplace, cotan or angle)")),
        }
    }
}

/// How boundary vertices are treated (Section 3.3). Corners and fixed vertices never move.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BoundaryMode {
    /// Boundary vertices never move.
    Fixed,
    /// Approach 2: move along the original boundary polyline only.
    Slide,
    /// Approach 1: rotate to bisect, then project back onto the original boundary between the
    /// vertex's two boundary neighbours.
    Snap,
    /// Both approaches in one pass: each boundary vertex takes, in every sweep, the slide or the
    /// snap candidate, whichever leaves its star better (by the star's average when both keep
    /// it above the guard's floor, else by its minimum).
    #[default]
    Auto,
}

impl BoundaryMode {
    /// Every mode.
    pub const ALL: [BoundaryMode; 4] =
        [BoundaryMode::Fixed, BoundaryMode::Slide, BoundaryMode::Snap, BoundaryMode::Auto];

    /// The short name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            BoundaryMode::Fixed => "fixed",
            BoundaryMode::Slide => "slide",
            BoundaryMode::Snap => "snap",
            BoundaryMode::Auto => "auto",
        }
    }
}

impl FromStr for BoundaryMode {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "fixed" => Ok(BoundaryMode::Fixed),
            "slide" => Ok(BoundaryMode::Slide),
            "snap" => Ok(BoundaryMode::Snap),
            "auto" => Ok(BoundaryMode::Auto),
            _ => Err(format!("unknown boundary mode '{s}' (expected fixed, slide, snap or auto)")),
        }
    }
}

/// When a run stops (besides the iteration cap and cancellation).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum StopRule {
    /// Stop when what the user gets stops improving (the default). Every
    /// [`StopRule::QUALITY_WINDOW`] sweeps it looks at two things:
    ///
    /// - the kept iterate (the one the run returns, by the ranking of inverted count, minimum,
    ///   average): when it has not changed for [`StopRule::QUALITY_STALE_WINDOWS`] windows, the
    ///   run stops, since the sweeps no longer produce anything it would return;
    /// - the best minimum and average of the sweeps so far, against the two windows before:
    ///   while the gains shrink geometrically, the gain still to come is their geometric tail,
    ///   g r / (1 - r) with r the ratio of the last two window gains. The run stops at the
    ///   second window in a row that repaired no inverted quad and leaves less than
    ///   [`StopRule::QUALITY_MIN_LEFT`] of minimum and [`StopRule::QUALITY_AVG_LEFT`] of
    ///   average to come, and less than [`StopRule::QUALITY_GAP_FRACTION`] of their gaps to 1
    ///   (a flat or oscillating series has no tail; a steady gain has an unbounded one, and the
    ///   run goes on).
    ///
    /// Independent of mesh size: every quantity is per quad. Its measured cost is in the
    /// README (one Mesquite mesh, a TFI chevron the sweeps leave only after some 100 sweeps
    /// near a fixed point, ends 0.087 lower in average than with [`StopRule::Energy`]).
    #[default]
    Quality,
    /// Stop on the collective torsion-spring energy of Eq. 1: when its change falls below
    /// [`Options::tau`], per movable vertex or absolute as [`Options::tau_absolute`] says.
    Energy,
}

impl StopRule {
    /// Sweeps per window of [`StopRule::Quality`].
    pub const QUALITY_WINDOW: usize = 5;
    /// Gain of the minimum scaled Jacobian still to come below which the quality rule may
    /// stop. Loose, because the max-min stage that follows sets the minimum.
    pub const QUALITY_MIN_LEFT: f64 = 5e-3;
    /// Gain of the average scaled Jacobian still to come below which the quality rule may stop.
    /// Loose too: the max-min stage's average recovery gives most of it back. Measured on the
    /// 186k-quad plate with holes: 1e-3 takes 110 sweeps to an average of 0.9468 (0.9486
    /// after the stage), 2e-3 60 to 0.9450 (0.9472), 4e-3 35 to 0.9419 (0.9448), the run's
    /// CPU time 14.7 -> 10.9 s; every mesh of the quality floor stays at or above it (most
    /// stop at the rule's first chance, 15 sweeps, either way). With 5e-4, 260 sweeps to 0.950.
    pub const QUALITY_AVG_LEFT: f64 = 4e-3;
    /// Near a perfect mesh, the gains still to come must also be below this fraction of the
    /// gap to 1 (of the minimum, of the average).
    pub const QUALITY_GAP_FRACTION: f64 = 0.1;
    /// The smallest gain still to come that the quality rule waits for. Measured: on a
    /// synthetic 1M-quad jittered grid, 1e-4 took 85 sweeps (26.6 s) to a minimum of 0.99985,
    /// 5e-4 takes 35 (10.9 s) to 0.99943 (average 0.999996 -> 0.999976); every sample and
    /// Mesquite mesh ends the same but three near-perfect ones, 1e-4 lower in minimum.
    pub const QUALITY_LEAST_LEFT: f64 = 5e-4;
    /// Windows without a change of the kept iterate after which the quality rule stops.
    pub const QUALITY_STALE_WINDOWS: usize = 4;

    /// The short name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            StopRule::Quality => "quality",
            StopRule::Energy => "energy",
        }
    }
}

impl FromStr for StopRule {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "quality" => Ok(StopRule::Quality),
            "energy" => Ok(StopRule::Energy),
            _ => Err(format!("unknown stopping rule '{s}' (expected quality or energy)")),
        }
    }
}

/// Optimization options.
///
/// The defaults keep the paper's method and parameters (lambda = 1, feature angle 45
/// degrees) and add what makes the result never worse than the input: guarded moves,
/// untangling, the automatic boundary mode and a size-independent stopping rule. Set
/// [`Options::paper`] reproduces the plain method of the paper.
///
/// Build options from the defaults with the chainable `with_*` methods, one per field. The
/// struct is `#[non_exhaustive]`, so a later version can add a field without breaking a
/// caller: outside this crate options are built from [`Options::DEFAULT`] (the same as
/// [`Options::default()`]) or [`Options::paper()`], never as a struct literal. Fields stay
/// public to read and to assign.
///
/// ```
/// use quadopt::{optimize, BoundaryMode, Method, Options, Mesh};
/// # use quadopt::DVec2;
///
/// // Laplacian smoothing with the boundary held, at most 50 sweeps.
/// let options = Options::default()
///     .with_method(Method::Laplacian)
///     .with_boundary(BoundaryMode::Fixed)
///     .with_max_iterations(50);
/// assert_eq!(options.lambda, 1.0); // every other field keeps its default
/// options.validate().unwrap();
///
/// // The builder is `const`: options can be a constant of the caller's.
/// const GENTLE: Options = Options::DEFAULT.with_lambda(0.5).with_max_min(false);
/// assert!(GENTLE.guard && !GENTLE.max_min);
///
/// // A 2x2 patch with its centre vertex dragged off-centre.
/// let mut points: Vec<DVec2> =
///     (0..9).map(|k| DVec2::new((k % 3) as f64, (k / 3) as f64)).collect();
/// points[4] = DVec2::new(1.6, 1.5);
/// let quads = vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
/// let mut mesh = Mesh::new(points, quads, None)?;
/// let report = optimize(&mut mesh, &options)?;
/// assert!(report.output.min > report.input.min);
/// # Ok::<(), quadopt::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Options {
    /// Interior smoothing method. Default: [`Method::EmbeddedPolygon`].
    pub method: Method,
    /// Boundary treatment. Default: [`BoundaryMode::Auto`].
    pub boundary: BoundaryMode,
    /// Step factor of Eq. 8, in (0, 1]. Default: 1.
    pub lambda: f64,
    /// When to stop. Default: [`StopRule::Quality`].
    pub stop: StopRule,
    /// Threshold of [`StopRule::Energy`] on the energy change between sweeps (>= 0): per
    /// movable vertex by default, absolute (the paper's tau) when `tau_absolute` is set.
    /// Default: 1e-7.
    pub tau: f64,
    /// Compare `tau` with the absolute change of the collective energy, as the paper does;
    /// this depends on mesh size (large meshes may never reach it). Default: false.
    pub tau_absolute: bool,
    /// Iteration cap (>= 1). Default: 1000.
    pub max_iterations: usize,
    /// A boundary vertex whose turning angle differs from 180 degrees by more than this is a
    /// corner and never moves, in degrees within [0, 180]. Default: 45.
    pub feature_angle_deg: f64,
    /// Guarded moves: a vertex with a valid star may not lower any face of its star below
    /// min(that face's current value, floor), where the floor is the larger of `guard_floor`
    /// and the input's minimum scaled Jacobian (so a valid mesh's worst quad never gets worse).
    /// Default: true.
    pub guard: bool,
    /// The guard's floor, in (0, 1]. Default: 0.05.
    pub guard_floor: f64,
    /// Untangle inverted quads before smoothing. Default: true.
    pub untangle: bool,
    /// Return the best iterate seen (never worse than the input) instead of the last one.
    /// Default: true.
    pub keep_best: bool,
    /// Largest allowed distance between a new boundary edge and the stretch of the original
    /// boundary it replaces, relative to that edge's length (`None`: unlimited). On a curved
    /// surface, every edge along a feature curve (the boundary, sharp and marked edges) keeps
    /// it. Default: `None`.
    pub max_boundary_deviation: Option<f64>,
    /// After the sweeps, the max-min stage (`src/smooth/maxmin/`): the vertices of the worst
    /// quads move to maximize their star's minimum scaled Jacobian, so the global minimum
    /// rises and never falls, as far as the [`Effort`] preset takes it. `false` turns the
    /// stage off in every preset. Default: true.
    pub max_min: bool,
    /// How much work the run spends on quality ([`Effort`]): the sweep budget and how much of
    /// the max-min stage runs. The fields above still apply on top of it. Default:
    /// [`Effort::Balanced`]. Build options for a preset with [`Options::fast`],
    /// [`Options::balanced`] or [`Options::best`].
    pub effort: Effort,
}

impl Default for Options {
    fn default() -> Self {
        Options::DEFAULT
    }
}

/// A chainable `const` builder method per field:
/// `Options::DEFAULT.with_tau(1e-6).with_guard(false)`.
macro_rules! builders {
    ($($with:ident => $field:ident: $ty:ty),* $(,)?) => {
        $(
            #[doc = concat!("Sets [`", stringify!($field), "`](Options#structfield.", stringify!($field), ").")]
            #[must_use]
            pub const fn $with(mut self, value: $ty) -> Options {
                self.$field = value;
                self
            }
        )*
    };
}

impl Options {
    /// The defaults (what [`Options::default()`] returns), as a constant to build on.
    pub const DEFAULT: Options = Options {
        method: Method::EmbeddedPolygon,
        boundary: BoundaryMode::Auto,
        lambda: 1.0,
        stop: StopRule::Quality,
        tau: 1e-7,
        tau_absolute: false,
        max_iterations: 1000,
        feature_angle_deg: 45.0,
        guard: true,
        guard_floor: 0.05,
        untangle: true,
        keep_best: true,
        max_boundary_deviation: None,
        max_min: true,
        effort: Effort::Balanced,
    };

    builders! {
        with_method => method: Method,
        with_boundary => boundary: BoundaryMode,
        with_lambda => lambda: f64,
        with_stop => stop: StopRule,
        with_tau => tau: f64,
        with_tau_absolute => tau_absolute: bool,
        with_max_iterations => max_iterations: usize,
        with_feature_angle_deg => feature_angle_deg: f64,
        with_guard => guard: bool,
        with_guard_floor => guard_floor: f64,
        with_untangle => untangle: bool,
        with_keep_best => keep_best: bool,
        with_max_boundary_deviation => max_boundary_deviation: Option<f64>,
        with_max_min => max_min: bool,
        with_effort => effort: Effort,
    }

    /// The [`Effort::Fast`] preset with every other option at its default: for meshers that
    /// smooth inside their own loop.
    pub const fn fast() -> Options {
        Options::DEFAULT.with_effort(Effort::Fast)
    }

    /// The [`Effort::Balanced`] preset, the default (the same as [`Options::DEFAULT`]).
    pub const fn balanced() -> Options {
        Options::DEFAULT.with_effort(Effort::Balanced)
    }

    /// The [`Effort::Best`] preset: the highest quality, at more time.
    pub const fn best() -> Options {
        Options::DEFAULT.with_effort(Effort::Best)
    }

    /// The paper's plain method: no guard, no untangling, no max-min stage, the last iterate,
    /// Approach 2 on the boundary, the energy rule with the absolute threshold tau = 1e-4.
    pub const fn paper() -> Options {
        Options {
            boundary: BoundaryMode::Slide,
            stop: StopRule::Energy,
            tau: 1e-4,
            tau_absolute: true,
            guard: false,
            untangle: false,
            keep_best: false,
            max_min: false,
            ..Options::DEFAULT
        }
    }

    /// Checks every option's range, naming the first bad one.
    pub fn validate(&self) -> Result<()> {
        let bad = |name, reason: String| Err(Error::InvalidOption { name, reason });
        if !(self.lambda > 0.0 && self.lambda <= 1.0) {
            return bad("lambda", format!("{} is not in (0, 1]", self.lambda));
        }
        if !(self.tau >= 0.0 && self.tau.is_finite()) {
            return bad("tau", format!("{} is not a finite number >= 0", self.tau));
        }
        if self.max_iterations == 0 {
            return bad("max_iterations", "must be at least 1".into());
        }
        if !(0.0..=180.0).contains(&self.feature_angle_deg) {
            return bad("feature_angle_deg", format!("{} is not in [0, 180]", self.feature_angle_deg));
        }
        if !(self.guard_floor > 0.0 && self.guard_floor <= 1.0) {
            return bad("guard_floor", format!("{} is not in (0, 1]", self.guard_floor));
        }
        if let Some(d) = self.max_boundary_deviation {
            if d.is_nan() || d < 0.0 {
                return bad("max_boundary_deviation", format!("{d} is not a number >= 0"));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The defaults the field docs state, and one setter per field.
    #[test]
    fn defaults_are_the_documented_ones_and_setters_set_one_field() {
        let d = Options::default();
        assert_eq!(
            (d.method, d.boundary, d.stop),
            (Method::EmbeddedPolygon, BoundaryMode::Auto, StopRule::Quality)
        );
        assert_eq!((d.lambda, d.tau, d.feature_angle_deg, d.guard_floor), (1.0, 1e-7, 45.0, 0.05));
        assert_eq!((d.tau_absolute, d.max_iterations, d.max_boundary_deviation), (false, 1000, None));
        assert!(d.guard && d.untangle && d.keep_best && d.max_min);
        assert_eq!(d.effort, Effort::Balanced);
        d.validate().unwrap();
        let set = Options::default()
            .with_method(Method::Laplacian)
            .with_boundary(BoundaryMode::Snap)
            .with_lambda(0.5)
            .with_stop(StopRule::Energy)
            .with_tau(2e-3)
            .with_tau_absolute(true)
            .with_max_iterations(7)
            .with_feature_angle_deg(30.0)
            .with_guard(false)
            .with_guard_floor(0.2)
            .with_untangle(false)
            .with_keep_best(false)
            .with_max_boundary_deviation(Some(0.1))
            .with_max_min(false)
            .with_effort(Effort::Best);
        let literal = Options {
            method: Method::Laplacian,
            boundary: BoundaryMode::Snap,
            lambda: 0.5,
            stop: StopRule::Energy,
            tau: 2e-3,
            tau_absolute: true,
            max_iterations: 7,
            feature_angle_deg: 30.0,
            guard: false,
            guard_floor: 0.2,
            untangle: false,
            keep_best: false,
            max_boundary_deviation: Some(0.1),
            max_min: false,
            effort: Effort::Best,
        };
        assert_eq!(set, literal);
    }
}

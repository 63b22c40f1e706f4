//! Options: [`QuadoptOptions`] and the enums and callback type of its fields, reading the
//! caller's prefix of the growable struct, the conversion to the crate's [`Options`] (every
//! field validated and named), and [`quadopt_options_init`], the one way to initialize them.

use crate::smooth::{BoundaryMode, Effort, Method, Options, StopRule};
use std::ffi::c_void;
use std::mem::size_of;

use super::boundary::{boundary, require_non_null};
use super::status::{FfiError, QuadoptStatus};

/// Interior smoothing method, stored as a `uint32_t` in `QuadoptOptions::method`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QuadoptMethod {
    /// The embedded polygon method of Akram, Si and Chen (the default).
    EmbeddedPolygon = 0,
    /// Uniform Laplacian smoothing.
    Laplacian = 1,
    /// Cotangent-weighted Laplacian smoothing.
    Cotangent = 2,
    /// Xu and Newman's angle-based smoothing.
    AngleBased = 3,
}

/// Boundary treatment, stored as a `uint32_t` in `QuadoptOptions::boundary`. Corners and
/// fixed vertices never move in any mode.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QuadoptBoundary {
    /// Both approaches in one pass: each boundary vertex takes, every sweep, the slide or the
    /// snap candidate that leaves its star better (the default).
    Auto = 0,
    /// Boundary vertices never move.
    Fixed = 1,
    /// Move boundary vertices along the original boundary polyline only.
    Slide = 2,
    /// Rotate to bisect, then project back onto the original boundary.
    Snap = 3,
}

/// When a run stops, stored as a `uint32_t` in `QuadoptOptions::stop_rule`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QuadoptStopRule {
    /// When the collective energy changes by less than `tau` (per movable vertex, or
    /// absolute with `tau_absolute`), as in the paper.
    Energy = 0,
    /// When the result stops improving (the default): checked every 5 sweeps, stop once the
    /// kept iterate has not changed for 4 windows, or at the second window in a row that
    /// repaired no inverted quad and whose shrinking gains leave less than 5e-3 of minimum and
    /// 4e-3 of average scaled Jacobian to come (their geometric tail).
    Quality = 1,
}

/// Effort preset, stored as a `uint32_t` in `QuadoptOptions::effort` and
/// `QuadoptReport::effort`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QuadoptEffort {
    /// The default: the sweeps until the quality stops improving, then a max-min stage that
    /// stops when it stops paying.
    Balanced = 0,
    /// For meshers that smooth inside their own loop: a few guarded sweeps with untangling,
    /// no max-min stage.
    Fast = 1,
    /// The highest quality, at more time.
    Best = 2,
}

impl QuadoptEffort {
    pub(super) fn of(effort: Effort) -> QuadoptEffort {
        match effort {
            Effort::Balanced => QuadoptEffort::Balanced,
            Effort::Fast => QuadoptEffort::Fast,
            Effort::Best => QuadoptEffort::Best,
        }
    }
}

/// Progress of a run, passed to the progress callback after every sweep (and regularly while
/// untangling, with `iteration` 0 and NaN energies).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadoptProgress {
    /// Sweeps done so far in the current pass (1-based; 0 while untangling).
    pub iteration: usize,
    /// The iteration cap of a pass.
    pub max_iterations: usize,
    /// Current pass (1-based). Every mode runs one pass since the automatic mode decides per
    /// vertex; the field stays for compatibility.
    pub pass: usize,
    /// Number of passes planned.
    pub passes: usize,
    /// Collective torsion-spring energy measured during the last sweep.
    pub energy: f64,
    /// Absolute change of the energy in the last sweep.
    pub energy_change: f64,
}

/// Progress callback: called on the calling thread after every sweep with the progress (valid
/// only during the call) and the options' `progress_user_data`. Return false to cancel: the
/// call then fails with `QUADOPT_STATUS_CANCELLED` and writes nothing. The callback may call
/// other quadopt functions, but must not throw a C++ exception or `longjmp` out of itself
/// (that would unwind through Rust frames; catch inside and return false instead), and must
/// not `fork` (the run's worker would be missing in the child).
pub type QuadoptProgressFn =
    Option<unsafe extern "C" fn(progress: *const QuadoptProgress, user_data: *mut c_void) -> bool>;

/// Optimization options. Fill with `quadopt_options_init(&options, sizeof options)`, then
/// change fields. Growable: the library reads only the first `struct_size` bytes. Every size
/// a published header declared is accepted, from the first (80 bytes on LP64, ending before
/// `max_min`) on: the fields a caller's older, shorter struct lacks take their defaults. A
/// `struct_size` smaller than the first version's is `QUADOPT_STATUS_INVALID_ARGUMENT`; bytes
/// beyond this version's struct are ignored.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct QuadoptOptions {
    /// `sizeof(QuadoptOptions)` as the caller compiled it; set by `quadopt_options_init()`.
    pub struct_size: u32,
    /// Interior method, a `QuadoptMethod` value (default `QUADOPT_METHOD_EMBEDDED_POLYGON`).
    pub method: u32,
    /// Boundary treatment, a `QuadoptBoundary` value (default `QUADOPT_BOUNDARY_AUTO`).
    pub boundary: u32,
    /// Iteration cap per pass, >= 1 (default 1000).
    pub max_iterations: u32,
    /// Step factor, in (0, 1] (default 1).
    pub lambda: f64,
    /// Threshold of `QUADOPT_STOP_RULE_ENERGY` on the energy change between sweeps, finite and >= 0: per movable
    /// vertex, or absolute when `tau_absolute` is set (default 1e-7; the default quality rule ignores it).
    pub tau: f64,
    /// Boundary vertices turning by more than this many degrees are corners and never move,
    /// in [0, 180] (default 45).
    pub feature_angle_deg: f64,
    /// Floor of the guarded moves, in (0, 1] (default 0.05).
    pub guard_floor: f64,
    /// Largest allowed distance between a new boundary edge and the original boundary it
    /// replaces, relative to that edge's length; on a curved surface, of every new edge along
    /// a feature curve (the boundary, sharp and marked edges) from the curve. Any negative
    /// value means unlimited (default -1). NaN is an invalid option.
    pub max_boundary_deviation: f64,
    /// Nonzero: compare `tau` with the absolute energy change, as the paper does (default 0).
    pub tau_absolute: u8,
    /// Nonzero: guarded moves, so a valid mesh's worst quad never gets worse (default 1).
    pub guard: u8,
    /// Nonzero: untangle inverted quads before smoothing (default 1).
    pub untangle: u8,
    /// Nonzero: return the best iterate seen instead of the last one (default 1).
    pub keep_best: u8,
    /// When to stop, a `QuadoptStopRule` value (default `QUADOPT_STOP_RULE_QUALITY`, 1).
    pub stop_rule: u32,
    /// Progress callback, or NULL for none (default NULL).
    pub progress: QuadoptProgressFn,
    /// Passed unchanged to `progress` (default NULL).
    pub progress_user_data: *mut c_void,
    /// Nonzero: the max-min stage after the sweeps, which raises the worst quad and never
    /// lowers the minimum (default 1). Added in 0.2: a caller's struct without it (its
    /// `struct_size` ends before this field) gets the default.
    pub max_min: u32,
    /// Reserved; set to 0. Ignored by this version.
    pub reserved1: u32,
    /// How much work the run spends on quality, a `QuadoptEffort` value (default
    /// `QUADOPT_EFFORT_BALANCED`, 0): the sweep budget and how much of the max-min stage
    /// runs. `max_iterations` still caps every preset, and `max_min = 0` turns the stage off in
    /// every preset. A caller's struct from an older header, without it, gets the default.
    pub effort: u32,
    /// Reserved; set to 0. Ignored by this version.
    pub reserved2: u32,
}

/// Size of the first published `QuadoptOptions`: callers' structs must be at least this large.
/// Fields added later are appended and read only when the caller's `struct_size` covers them.
/// The first version ended where `max_min` (added in 0.2) begins.
pub(super) const OPTIONS_V1_SIZE: usize = std::mem::offset_of!(QuadoptOptions, max_min);

/// The caller's options (defaults for NULL), reading only the declared prefix.
///
/// # Safety
/// `options` must be NULL or point to a readable `struct_size` field followed by at least
/// `struct_size - 4` readable bytes.
pub(super) unsafe fn read_options(options: *const QuadoptOptions) -> Result<QuadoptOptions, FfiError> {
    let mut out = default_options();
    if options.is_null() {
        return Ok(out);
    }
    require_non_null(options, "options")?;
    // SAFETY: non-null and aligned; every version of the struct starts with `struct_size`.
    let declared = unsafe { options.cast::<u32>().read() } as usize;
    let ours = size_of::<QuadoptOptions>();
    if declared < OPTIONS_V1_SIZE {
        return Err(FfiError::new(
            QuadoptStatus::InvalidArgument,
            format!(
                "options->struct_size is {declared}, smaller than the first QuadoptOptions ({OPTIONS_V1_SIZE} bytes)"
            ),
        ));
    }
    // Fields a caller's older, shorter struct lacks keep their defaults.
    let bytes = declared.min(ours);
    // SAFETY: the caller guarantees `declared >= bytes` readable bytes at `options`, and `out`
    // is a distinct local of `ours >= bytes` bytes. Every field is an integer, float, raw
    // pointer or nullable function pointer, for which any initialized bit pattern is valid.
    unsafe {
        std::ptr::copy_nonoverlapping(options.cast::<u8>(), (&raw mut out).cast::<u8>(), bytes);
    }
    Ok(out)
}

/// Converts the C options, validating enum values and ranges and naming the bad field.
pub(super) fn convert_options(o: &QuadoptOptions) -> Result<Options, FfiError> {
    let bad = |name: &str, reason: String| {
        FfiError::new(QuadoptStatus::InvalidOption, format!("invalid option {name}: {reason}"))
    };
    let method = match o.method {
        0 => Method::EmbeddedPolygon,
        1 => Method::Laplacian,
        2 => Method::Cotangent,
        3 => Method::AngleBased,
        m => return Err(bad("method", format!("{m} is not a QuadoptMethod (0 to 3)"))),
    };
    let boundary = match o.boundary {
        0 => BoundaryMode::Auto,
        1 => BoundaryMode::Fixed,
        2 => BoundaryMode::Slide,
        3 => BoundaryMode::Snap,
        b => return Err(bad("boundary", format!("{b} is not a QuadoptBoundary (0 to 3)"))),
    };
    let stop = match o.stop_rule {
        0 => StopRule::Energy,
        1 => StopRule::Quality,
        r => return Err(bad("stop_rule", format!("{r} is not a QuadoptStopRule (0 or 1)"))),
    };
    let effort = match o.effort {
        0 => Effort::Balanced,
        1 => Effort::Fast,
        2 => Effort::Best,
        e => return Err(bad("effort", format!("{e} is not a QuadoptEffort (0 to 2)"))),
    };
    let max_boundary_deviation =
        if o.max_boundary_deviation < 0.0 { None } else { Some(o.max_boundary_deviation) };
    let options = Options {
        method,
        boundary,
        lambda: o.lambda,
        stop,
        tau: o.tau,
        tau_absolute: o.tau_absolute != 0,
        max_iterations: o.max_iterations as usize,
        feature_angle_deg: o.feature_angle_deg,
        guard: o.guard != 0,
        guard_floor: o.guard_floor,
        untangle: o.untangle != 0,
        keep_best: o.keep_best != 0,
        max_boundary_deviation,
        max_min: o.max_min != 0,
        effort,
    };
    options.validate()?;
    Ok(options)
}

pub(super) fn default_options() -> QuadoptOptions {
    let d = Options::default();
    QuadoptOptions {
        struct_size: size_of::<QuadoptOptions>() as u32,
        method: QuadoptMethod::EmbeddedPolygon as u32,
        boundary: QuadoptBoundary::Auto as u32,
        max_iterations: d.max_iterations as u32,
        lambda: d.lambda,
        tau: d.tau,
        feature_angle_deg: d.feature_angle_deg,
        guard_floor: d.guard_floor,
        max_boundary_deviation: d.max_boundary_deviation.unwrap_or(-1.0),
        tau_absolute: u8::from(d.tau_absolute),
        guard: u8::from(d.guard),
        untangle: u8::from(d.untangle),
        keep_best: u8::from(d.keep_best),
        stop_rule: match d.stop {
            StopRule::Energy => QuadoptStopRule::Energy,
            StopRule::Quality => QuadoptStopRule::Quality,
        } as u32,
        progress: None,
        progress_user_data: std::ptr::null_mut(),
        max_min: u32::from(d.max_min),
        reserved1: 0,
        effort: QuadoptEffort::of(d.effort) as u32,
        reserved2: 0,
    }
}

/// Fills the first `struct_size` bytes of `*out` with the default options: pass
/// `sizeof(QuadoptOptions)` as your header declares it, which may differ from this library's
/// when the program was built against another version of the header. Writes
/// `min(struct_size, sizeof of this library's struct)` bytes, sets `struct_size` to that number
/// and leaves any further bytes of a larger (newer) struct untouched, so it never writes past
/// the caller's struct, whichever version of the header the program was built with. The way to
/// initialize options.
///
/// Returns `QUADOPT_STATUS_NULL_POINTER` for a NULL `out`, and `QUADOPT_STATUS_INVALID_ARGUMENT`
/// for a misaligned one or a `struct_size` smaller than the first version of the struct
/// (nothing is written then).
///
/// # Safety
/// `out` must be NULL or point to `struct_size` writable, aligned bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_options_init(out: *mut QuadoptOptions, struct_size: usize) -> QuadoptStatus {
    boundary("quadopt_options_init", || {
        require_non_null(out.cast_const(), "out")?;
        if struct_size < OPTIONS_V1_SIZE {
            return Err(FfiError::new(
                QuadoptStatus::InvalidArgument,
                format!(
                    "struct_size is {struct_size}, smaller than the first QuadoptOptions ({OPTIONS_V1_SIZE} bytes)"
                ),
            ));
        }
        let mut value = default_options();
        let bytes = struct_size.min(size_of::<QuadoptOptions>());
        value.struct_size = bytes as u32;
        // SAFETY: `out` is non-null and aligned (checked) and holds `struct_size >= bytes`
        // writable bytes by the caller's contract; `value` is a local of at least `bytes` bytes.
        unsafe { std::ptr::copy_nonoverlapping((&raw const value).cast::<u8>(), out.cast::<u8>(), bytes) };
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffi::report::REPORT_V1_SIZE;
    use crate::ffi::test_support::*;
    use crate::ffi::*;

    #[test]
    fn every_invalid_option_is_named() {
        let (coords, quads) = patch(2);
        let d = default_options();
        let cases: Vec<(QuadoptOptions, &str)> = vec![
            (QuadoptOptions { method: 4, ..d }, "method"),
            (QuadoptOptions { method: u32::MAX, ..d }, "method"),
            (QuadoptOptions { boundary: 4, ..d }, "boundary"),
            (QuadoptOptions { lambda: 0.0, ..d }, "lambda"),
            (QuadoptOptions { lambda: f64::NAN, ..d }, "lambda"),
            (QuadoptOptions { lambda: 1.5, ..d }, "lambda"),
            (QuadoptOptions { tau: -1.0, ..d }, "tau"),
            (QuadoptOptions { tau: f64::INFINITY, ..d }, "tau"),
            (QuadoptOptions { max_iterations: 0, ..d }, "max_iterations"),
            (QuadoptOptions { feature_angle_deg: 180.5, ..d }, "feature_angle_deg"),
            (QuadoptOptions { guard_floor: 0.0, ..d }, "guard_floor"),
            (QuadoptOptions { max_boundary_deviation: f64::NAN, ..d }, "max_boundary_deviation"),
        ];
        for (o, name) in cases {
            assert_eq!(optimize_status(&coords, 2, &quads, None, Some(&o)), QuadoptStatus::InvalidOption);
            assert!(last_error().contains(&format!("invalid option {name}:")), "{name}: {}", last_error());
        }
        // A bad option is reported even when the mesh is bad too.
        let o = QuadoptOptions { boundary: 77, ..d };
        assert_eq!(optimize_status(&coords, 2, &[], None, Some(&o)), QuadoptStatus::InvalidOption);
        // Any negative deviation means unlimited; nonzero bytes are true.
        let o = QuadoptOptions { max_boundary_deviation: f64::NEG_INFINITY, guard: 200, ..d };
        assert_eq!(optimize_status(&coords, 2, &quads, None, Some(&o)), QuadoptStatus::Ok);
    }

    #[test]
    fn options_init_writes_only_the_callers_struct() {
        // A newer caller's struct: ours followed by 16 bytes this library knows nothing of.
        #[repr(C)]
        struct Newer {
            ours: QuadoptOptions,
            extra: [u64; 2],
        }
        let mut newer = Newer { ours: default_options(), extra: [0xDEAD_BEEF; 2] };
        newer.ours.lambda = 0.25;
        let status = unsafe { quadopt_options_init(&raw mut newer.ours, size_of::<Newer>()) };
        assert_eq!(status, QuadoptStatus::Ok);
        assert_eq!(newer.ours.lambda, 1.0);
        assert_eq!(newer.ours.struct_size as usize, size_of::<QuadoptOptions>());
        assert_eq!(newer.extra, [0xDEAD_BEEF; 2]);
        // Too small, or NULL: an error, nothing written.
        let mut o = default_options();
        o.lambda = 0.5;
        let status = unsafe { quadopt_options_init(&raw mut o, OPTIONS_V1_SIZE - 8) };
        assert_eq!(status, QuadoptStatus::InvalidArgument);
        assert_eq!(o.lambda, 0.5);
        let status = unsafe { quadopt_options_init(std::ptr::null_mut(), 64) };
        assert_eq!(status, QuadoptStatus::NullPointer);
    }

    #[test]
    fn options_init_fills_the_defaults() {
        let mut o = QuadoptOptions { struct_size: 0, method: 9, ..default_options() };
        // SAFETY: `o` is a writable QuadoptOptions of the size passed.
        let status = unsafe { quadopt_options_init(&mut o, size_of::<QuadoptOptions>()) };
        assert_eq!(status, QuadoptStatus::Ok);
        assert_eq!(bytes_of(&o), bytes_of(&default_options()));
        assert_eq!(o.struct_size as usize, size_of::<QuadoptOptions>());
        assert_eq!((o.method, o.boundary, o.max_iterations), (0, 0, 1000));
        assert_eq!((o.lambda, o.tau, o.feature_angle_deg, o.guard_floor), (1.0, 1e-7, 45.0, 0.05));
        assert_eq!(o.max_boundary_deviation, -1.0);
        assert_eq!((o.tau_absolute, o.guard, o.untangle, o.keep_best), (0, 1, 1, 1));
        assert!(o.progress.is_none() && o.progress_user_data.is_null());
        assert_eq!(convert_options(&o).unwrap(), Options::default());
    }

    #[test]
    fn first_version_structs_get_the_new_defaults_and_their_bytes_only() {
        // A caller compiled against the first header: its options end before `max_min`, its
        // report before `max_min` too.
        let mut v1 = default_options();
        v1.struct_size = OPTIONS_V1_SIZE as u32;
        v1.max_min = 0; // beyond the caller's struct: must not be read
        let (points, r) = run_plate(&v1, REPORT_V1_SIZE);
        let (expected, _) = run_plate(&default_options(), size_of::<QuadoptReport>());
        assert_eq!(bits(&points), bits(&expected), "a v1 caller gets the stage (the default)");
        assert_eq!(r.struct_size as usize, REPORT_V1_SIZE, "bytes filled");
        assert_eq!((r.max_min, r.sweeps.min), (0xA5A5_A5A5, -9.0), "fields beyond v1 written");
        assert_eq!(OPTIONS_V1_SIZE, 80);
        assert_eq!(REPORT_V1_SIZE, 200);
    }

    #[test]
    fn the_effort_field_is_read_when_declared_and_its_preset_runs() {
        let mut fast = default_options();
        fast.effort = QuadoptEffort::Fast as u32;
        let (fast_points, r) = run_plate(&fast, size_of::<QuadoptReport>());
        assert_eq!((r.effort, r.max_min), (QuadoptEffort::Fast as u32, 0));
        assert!(r.iterations <= Effort::FAST_SWEEPS && r.output.min > r.input.min);
        let (balanced, rb) = run_plate(&default_options(), size_of::<QuadoptReport>());
        assert_eq!((rb.effort, rb.max_min), (QuadoptEffort::Balanced as u32, 1));
        assert_ne!(bits(&fast_points), bits(&balanced), "the presets differ on this plate");
        // A caller of the previous header: options and report end before `effort`.
        let before_effort = std::mem::offset_of!(QuadoptOptions, effort);
        let report_before_effort = std::mem::offset_of!(QuadoptReport, effort);
        fast.struct_size = before_effort as u32;
        let (points, r) = run_plate(&fast, report_before_effort);
        assert_eq!(bits(&points), bits(&balanced), "an older caller runs balanced");
        assert_eq!((r.struct_size as usize, r.effort), (report_before_effort, 0xA5A5_A5A5), "effort written");
        assert_eq!(before_effort, 88);
        let mut bad = default_options();
        bad.effort = 3;
        let e = convert_options(&bad).unwrap_err();
        assert!(e.status == QuadoptStatus::InvalidOption && e.message.contains("effort"), "{e:?}");
    }
}

//! The C header, the exported symbols and the struct layouts cannot drift apart.
//!
//! - `tests/bindgen/quadopt_sys.rs` holds the bindings that bindgen (pinned in Cargo.toml)
//!   generates from `include/quadopt.h`; [`bindings_match_the_header`] regenerates them at test
//!   time (libclang is loaded at run time: Debian's `libclang-dev`) and fails on any
//!   difference. `QUADOPT_BLESS=1 cargo test --test header` regenerates the header and this
//!   file together (also when a header change breaks this test's compilation);
//!   `QUADOPT_BLESS=1 cargo test --test bindgen` regenerates this file alone.
//! - The other tests drive the library only through those bindings (so through the
//!   header's declarations, linked against the library's exported symbols) and compare every
//!   struct's size, alignment and field offsets with `quadopt::ffi`.
//! - [`c_client_compiles_links_and_runs`] compiles `tests/c/smoke.c` against the header with
//!   `-std=c99 -Wall -Wextra -Werror -pedantic` (compiler found by the `cc` crate), links it
//!   to the cdylib (and, on linux-gnu, [`c_client_links_the_staticlib`] to the staticlib),
//!   runs it and compares the struct layouts the C compiler saw with the Rust ones.

// The bindings resolve against the `#[no_mangle]` symbols of the library.
use quadopt as _;

/// The checked-in bindgen output (included, not a `mod` file, so that rustfmt leaves it as
/// bindgen wrote it).
#[allow(non_camel_case_types, non_upper_case_globals, non_snake_case, dead_code, clippy::all)]
mod sys {
    include!("bindgen/quadopt_sys.rs");
}

#[path = "bindgen/generate.rs"]
mod generate;

use std::ffi::CStr;
use std::mem::{align_of, offset_of, size_of};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::ptr::{null, null_mut};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn bindings_match_the_header() {
    let path = root().join(generate::BINDINGS);
    let generated = generate::bindings(root());
    if std::env::var_os("QUADOPT_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &generated).unwrap();
        return;
    }
    let checked_in = std::fs::read_to_string(&path).unwrap_or_default();
    if checked_in != generated {
        let first = checked_in.lines().zip(generated.lines()).position(|(a, b)| a != b);
        panic!(
            "tests/bindgen/quadopt_sys.rs is out of date with include/quadopt.h (first difference at \
             line {}); regenerate with `QUADOPT_BLESS=1 cargo test --test header`",
            first.map_or(checked_in.lines().count().min(generated.lines().count()), |i| i) + 1
        );
    }
}

/// Asserts that a bindgen struct and its Rust definition have the same size, alignment and
/// offset of every listed field.
macro_rules! same_layout {
    ($c:ident, $rust:ty, [$($field:ident),* $(,)?]) => {{
        assert_eq!(size_of::<sys::$c>(), size_of::<$rust>(), "size of {}", stringify!($c));
        assert_eq!(align_of::<sys::$c>(), align_of::<$rust>(), "alignment of {}", stringify!($c));
        $(assert_eq!(
            offset_of!(sys::$c, $field),
            offset_of!($rust, $field),
            "offset of {}::{}", stringify!($c), stringify!($field)
        );)*
    }};
}

#[test]
fn struct_layouts_match_the_rust_definitions() {
    use quadopt::ffi;
    same_layout!(
        QuadoptProgress,
        ffi::QuadoptProgress,
        [iteration, max_iterations, pass, passes, energy, energy_change]
    );
    same_layout!(QuadoptQuality, ffi::QuadoptQuality, [min, avg, max, inverted]);
    same_layout!(
        QuadoptOptions,
        ffi::QuadoptOptions,
        [
            struct_size,
            method,
            boundary,
            max_iterations,
            lambda,
            tau,
            feature_angle_deg,
            guard_floor,
            max_boundary_deviation,
            tau_absolute,
            guard,
            untangle,
            keep_best,
            stop_rule,
            progress,
            progress_user_data,
            max_min,
            reserved1
        ]
    );
    same_layout!(
        QuadoptReport,
        ffi::QuadoptReport,
        [
            struct_size,
            converged,
            input,
            output,
            iterations,
            untangle_sweeps,
            reoriented_quads,
            corners,
            movable,
            tangled_quads,
            initial_energy,
            final_energy,
            seconds,
            max_boundary_deviation,
            hausdorff,
            max_boundary_deviation_relative,
            hausdorff_relative,
            loops_slide,
            loops_snap,
            loops_fixed,
            max_min,
            reserved1,
            sweeps
        ]
    );
    assert_eq!(size_of::<sys::QuadoptStatus>(), size_of::<ffi::QuadoptStatus>());
    assert_eq!(size_of::<sys::QuadoptMethod>(), 4);
    assert_eq!(size_of::<sys::QuadoptBoundary>(), 4);
}

#[test]
fn constants_match_the_rust_definitions() {
    use quadopt::ffi::{QuadoptBoundary as B, QuadoptMethod as M, QuadoptStatus as S};
    let statuses = [
        (sys::QUADOPT_STATUS_OK, S::Ok),
        (sys::QUADOPT_STATUS_NULL_POINTER, S::NullPointer),
        (sys::QUADOPT_STATUS_INVALID_ARGUMENT, S::InvalidArgument),
        (sys::QUADOPT_STATUS_INVALID_OPTION, S::InvalidOption),
        (sys::QUADOPT_STATUS_NO_QUADS, S::NoQuads),
        (sys::QUADOPT_STATUS_INDEX_OUT_OF_RANGE, S::IndexOutOfRange),
        (sys::QUADOPT_STATUS_REPEATED_VERTEX, S::RepeatedVertex),
        (sys::QUADOPT_STATUS_NON_MANIFOLD, S::NonManifold),
        (sys::QUADOPT_STATUS_NON_FINITE_COORDINATE, S::NonFiniteCoordinate),
        (sys::QUADOPT_STATUS_NON_ORIENTABLE, S::NonOrientable),
        (sys::QUADOPT_STATUS_MISMATCH, S::Mismatch),
        (sys::QUADOPT_STATUS_CANCELLED, S::Cancelled),
        (sys::QUADOPT_STATUS_PANIC, S::Panic),
        (sys::QUADOPT_STATUS_NOT_PLANAR, S::NotPlanar),
        (sys::QUADOPT_STATUS_OUT_OF_MEMORY, S::OutOfMemory),
        (sys::QUADOPT_STATUS_CLOSED_MESH, S::ClosedMesh),
    ];
    for (i, (c, rust)) in statuses.into_iter().enumerate() {
        assert_eq!((c as i64, rust as i64), (i as i64, i as i64), "{rust:?}");
    }
    let methods = [
        (sys::QUADOPT_METHOD_EMBEDDED_POLYGON, M::EmbeddedPolygon),
        (sys::QUADOPT_METHOD_LAPLACIAN, M::Laplacian),
        (sys::QUADOPT_METHOD_COTANGENT, M::Cotangent),
        (sys::QUADOPT_METHOD_ANGLE_BASED, M::AngleBased),
    ];
    for (c, rust) in methods {
        assert_eq!(c, rust as u32, "{rust:?}");
    }
    let modes = [
        (sys::QUADOPT_BOUNDARY_AUTO, B::Auto),
        (sys::QUADOPT_BOUNDARY_FIXED, B::Fixed),
        (sys::QUADOPT_BOUNDARY_SLIDE, B::Slide),
        (sys::QUADOPT_BOUNDARY_SNAP, B::Snap),
    ];
    for (c, rust) in modes {
        assert_eq!(c, rust as u32, "{rust:?}");
    }
    let version: Vec<u32> = env!("CARGO_PKG_VERSION").split('.').map(|p| p.parse().unwrap()).collect();
    assert_eq!(version, [sys::QUADOPT_VERSION_MAJOR, sys::QUADOPT_VERSION_MINOR, sys::QUADOPT_VERSION_PATCH]);
}

/// The 2x2 patch of unit squares with its centre dragged to (1.6, 1.5).
fn patch() -> (Vec<f64>, Vec<u32>) {
    let mut c = Vec::new();
    for j in 0..3 {
        for i in 0..3 {
            c.extend([i as f64, j as f64]);
        }
    }
    (c[8], c[9]) = (1.6, 1.5);
    (c, vec![0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7])
}

fn last_error() -> String {
    // SAFETY: never NULL; valid until the next call on this thread.
    unsafe { CStr::from_ptr(sys::quadopt_last_error()) }.to_string_lossy().into_owned()
}

/// The default options as a C caller gets them: `quadopt_options_init` for the header's struct.
fn default_options() -> sys::QuadoptOptions {
    let mut o = std::mem::MaybeUninit::<sys::QuadoptOptions>::zeroed();
    // SAFETY: `o` holds size_of::<QuadoptOptions>() writable, aligned bytes.
    let s = unsafe { sys::quadopt_options_init(o.as_mut_ptr(), size_of::<sys::QuadoptOptions>()) };
    assert_eq!(s, sys::QUADOPT_STATUS_OK, "{}", last_error());
    // SAFETY: zeroed (a valid QuadoptOptions: integers, floats, NULL pointers), then filled.
    unsafe { o.assume_init() }
}

#[test]
fn optimize_quality_and_handle_through_the_header() {
    let (mut coords, quads) = patch();
    // SAFETY: every pointer refers to a live buffer of the stated length.
    unsafe {
        let mut o = default_options();
        assert_eq!(o.struct_size as usize, size_of::<sys::QuadoptOptions>());
        o.boundary = sys::QUADOPT_BOUNDARY_FIXED;
        o.tau = 1e-12;
        let mut report = sys::quadopt_report_init();
        assert_eq!(report.struct_size as usize, size_of::<sys::QuadoptReport>());
        let s = sys::quadopt_optimize(coords.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), &o, &mut report);
        assert_eq!(s, sys::QUADOPT_STATUS_OK, "{}", last_error());
        assert!((coords[8] - 1.0).abs() < 1e-3 && (coords[9] - 1.0).abs() < 1e-3);
        assert_eq!((report.input.inverted, report.output.inverted, report.movable), (1, 0, 1));
        assert!(report.output.min > 0.999 && report.converged == 1 && report.loops_fixed == 1);

        // Quality of the result: four unit squares.
        let mut q = sys::QuadoptQuality { min: 0.0, avg: 0.0, max: 0.0, inverted: 9 };
        let mut per = [0.0; 4];
        let s = sys::quadopt_quality(coords.as_ptr(), 2, 9, quads.as_ptr(), 4, &mut q, per.as_mut_ptr(), 4);
        assert_eq!(s, sys::QUADOPT_STATUS_OK);
        assert!(q.min > 0.999 && q.inverted == 0 && per.iter().all(|&v| v > 0.999));

        // A handle gives the same answer.
        let mut handle: *mut sys::QuadoptOptimizer = null_mut();
        let (start, _) = patch();
        let s = sys::quadopt_optimizer_create(start.as_ptr(), 2, 9, quads.as_ptr(), 4, null(), &mut handle);
        assert_eq!(s, sys::QUADOPT_STATUS_OK);
        let mut again = start.clone();
        let s = sys::quadopt_optimizer_optimize(handle, again.as_mut_ptr(), 2, 9, &o, null_mut());
        assert_eq!(s, sys::QUADOPT_STATUS_OK);
        assert_eq!(again, coords);
        let s = sys::quadopt_optimizer_optimize(handle, again.as_mut_ptr(), 2, 8, &o, null_mut());
        assert_eq!(s, sys::QUADOPT_STATUS_MISMATCH);
        sys::quadopt_optimizer_free(handle);
    }
}

#[test]
fn errors_and_report_size_through_the_header() {
    let (coords, quads) = patch();
    // SAFETY: every pointer refers to a live buffer of the stated length.
    unsafe {
        let mut c = coords.clone();
        let mut bad = quads.clone();
        bad[6] = 9;
        let s = sys::quadopt_optimize(c.as_mut_ptr(), 2, 9, bad.as_ptr(), 4, null(), null(), null_mut());
        assert_eq!(s, sys::QUADOPT_STATUS_INDEX_OUT_OF_RANGE);
        assert!(last_error().contains("quad 1 corner 2"), "{}", last_error());
        let s = sys::quadopt_optimize(c.as_mut_ptr(), 7, 9, quads.as_ptr(), 4, null(), null(), null_mut());
        assert_eq!(s, sys::QUADOPT_STATUS_INVALID_ARGUMENT);
        let mut o = default_options();
        o.boundary = 4;
        let s = sys::quadopt_optimize(c.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), &o, null_mut());
        assert_eq!(s, sys::QUADOPT_STATUS_INVALID_OPTION);
        assert!(last_error().contains("invalid option boundary"), "{}", last_error());
        let mut report = sys::quadopt_report_init();
        // Smaller than the first published report (which ended where `max_min` begins).
        report.struct_size = (std::mem::offset_of!(sys::QuadoptReport, max_min) - 8) as u32;
        let s = sys::quadopt_optimize(c.as_mut_ptr(), 2, 9, quads.as_ptr(), 4, null(), null(), &mut report);
        assert_eq!(s, sys::QUADOPT_STATUS_INVALID_ARGUMENT);
        assert_eq!(report.iterations, 0);
        assert_eq!(c, coords, "a failed call wrote coords");
        let name = CStr::from_ptr(sys::quadopt_status_string(sys::QUADOPT_STATUS_CANCELLED as i32));
        assert_eq!(name.to_str().unwrap(), "cancelled");
        assert_eq!(CStr::from_ptr(sys::quadopt_version()).to_str().unwrap(), env!("CARGO_PKG_VERSION"));
    }
}

/// The host triple, which the cc crate needs outside a build script.
fn host_triple() -> String {
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let out = Command::new(rustc).arg("-vV").output().expect("rustc -vV runs");
    let text = String::from_utf8(out.stdout).unwrap();
    text.lines().find_map(|l| l.strip_prefix("host: ")).expect("rustc -vV names the host").to_owned()
}

/// The directory holding this build's cdylib (the test binary's own `deps` directory).
fn library_dir() -> PathBuf {
    std::env::current_exe().unwrap().parent().unwrap().to_path_buf()
}

/// Compiles `tests/c/smoke.c` with `-std=c99 -Wall -Wextra -Werror -pedantic`, links it with
/// `link` (the library and what it needs) and returns what the program printed, asserting
/// that it compiled, ran and passed its own checks.
fn build_and_run_c_client(name: &str, link: &[std::ffi::OsString]) -> String {
    let target = host_triple();
    let out_dir = std::env::temp_dir().join(format!("quadopt-c-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&out_dir).unwrap();
    let exe = out_dir.join("smoke");
    let compiler = cc::Build::new()
        .target(&target)
        .host(&target)
        .opt_level(0)
        .debug(false)
        .cargo_metadata(false)
        .out_dir(&out_dir)
        .get_compiler();
    let mut cmd = compiler.to_command();
    cmd.args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"])
        .arg("-I")
        .arg(root().join("include"))
        .arg(root().join("tests/c/smoke.c"))
        .arg("-o")
        .arg(&exe)
        .args(link);
    let build = cmd.output().expect("the C compiler runs");
    assert!(
        build.status.success(),
        "compiling tests/c/smoke.c ({name}) failed: {cmd:?}\n{}",
        String::from_utf8_lossy(&build.stderr)
    );
    let run = Command::new(&exe).output().expect("the C client runs");
    let stdout = String::from_utf8_lossy(&run.stdout).into_owned();
    let _ = std::fs::remove_dir_all(&out_dir);
    assert!(run.status.success() && stdout.ends_with("ok\n"), "C client ({name}) failed:\n{stdout}");
    stdout
}

#[test]
#[cfg(unix)]
fn c_client_compiles_links_and_runs() {
    let lib_dir = library_dir();
    let dylib =
        lib_dir.join(format!("{}quadopt{}", std::env::consts::DLL_PREFIX, std::env::consts::DLL_SUFFIX));
    assert!(dylib.exists(), "no cdylib at {}", dylib.display());
    let stdout = build_and_run_c_client(
        "cdylib",
        &[dylib.into(), format!("-Wl,-rpath,{}", lib_dir.display()).into(), "-lm".into()],
    );
    check_c_layouts(&stdout);
}

#[test]
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn c_client_links_the_staticlib() {
    let staticlib = library_dir().join("libquadopt.a");
    assert!(staticlib.exists(), "no staticlib at {}", staticlib.display());
    // The system libraries Rust's std needs, as CMakeLists.txt gives them to C/C++ consumers.
    let mut link: Vec<std::ffi::OsString> = vec![staticlib.into()];
    link.extend(cmake_native_static_libs().iter().map(|l| format!("-l{l}").into()));
    check_c_layouts(&build_and_run_c_client("staticlib", &link));
}

/// The Linux list of native libraries in CMakeLists.txt (`QUADOPT_NATIVE_STATIC_LIBS`, the
/// last `set` of it: the non-Apple, non-Windows branch).
fn cmake_native_static_libs() -> Vec<String> {
    let cmake =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("CMakeLists.txt")).unwrap();
    let line = cmake
        .lines()
        .rev()
        .find(|l| l.trim_start().starts_with("set(QUADOPT_NATIVE_STATIC_LIBS \""))
        .expect("CMakeLists.txt sets QUADOPT_NATIVE_STATIC_LIBS");
    let list = line.split('"').nth(1).unwrap();
    list.split(';').map(str::to_string).collect()
}

/// CMakeLists.txt's list covers every library rustc says a staticlib needs on this target
/// (`rustc --print native-static-libs`; libc is linked by every C compiler anyway).
#[test]
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn the_cmake_native_library_list_is_what_rustc_prints() {
    let dir = std::env::temp_dir().join(format!("quadopt-native-libs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("lib.rs"), "pub fn f() {}\n").unwrap();
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let out = std::process::Command::new(rustc)
        .args(["--crate-type", "staticlib", "--print", "native-static-libs", "-o"])
        .arg(dir.join("libx.a"))
        .arg(dir.join("lib.rs"))
        .output()
        .unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let note = String::from_utf8(out.stderr).unwrap();
    let listed = note
        .lines()
        .find_map(|l| l.split("native-static-libs:").nth(1))
        .unwrap_or_else(|| panic!("no native-static-libs note in {note}"));
    let cmake = cmake_native_static_libs();
    for lib in listed.split_whitespace().filter_map(|w| w.strip_prefix("-l")).filter(|&l| l != "c") {
        assert!(cmake.iter().any(|c| c == lib), "rustc needs -l{lib}; CMakeLists.txt lists {cmake:?}");
    }
}

/// Compares the "size" and "layout" lines the C client printed with the Rust definitions.
fn check_c_layouts(stdout: &str) {
    // The layouts the C compiler saw are the Rust ones.
    use quadopt::ffi::{QuadoptOptions, QuadoptProgress, QuadoptQuality, QuadoptReport, QuadoptStatus};
    let rust_sizes = [
        ("QuadoptOptions", size_of::<QuadoptOptions>()),
        ("QuadoptReport", size_of::<QuadoptReport>()),
        ("QuadoptQuality", size_of::<QuadoptQuality>()),
        ("QuadoptProgress", size_of::<QuadoptProgress>()),
        ("QuadoptStatus", size_of::<QuadoptStatus>()),
    ];
    let rust_offsets = [
        ("QuadoptOptions lambda", offset_of!(QuadoptOptions, lambda)),
        ("QuadoptOptions max_boundary_deviation", offset_of!(QuadoptOptions, max_boundary_deviation)),
        ("QuadoptOptions tau_absolute", offset_of!(QuadoptOptions, tau_absolute)),
        ("QuadoptOptions keep_best", offset_of!(QuadoptOptions, keep_best)),
        ("QuadoptOptions stop_rule", offset_of!(QuadoptOptions, stop_rule)),
        ("QuadoptOptions progress", offset_of!(QuadoptOptions, progress)),
        ("QuadoptOptions progress_user_data", offset_of!(QuadoptOptions, progress_user_data)),
        ("QuadoptReport input", offset_of!(QuadoptReport, input)),
        ("QuadoptReport output", offset_of!(QuadoptReport, output)),
        ("QuadoptReport iterations", offset_of!(QuadoptReport, iterations)),
        ("QuadoptReport tangled_quads", offset_of!(QuadoptReport, tangled_quads)),
        ("QuadoptReport initial_energy", offset_of!(QuadoptReport, initial_energy)),
        ("QuadoptReport hausdorff_relative", offset_of!(QuadoptReport, hausdorff_relative)),
        ("QuadoptReport loops_fixed", offset_of!(QuadoptReport, loops_fixed)),
        ("QuadoptOptions max_min", offset_of!(QuadoptOptions, max_min)),
        ("QuadoptReport sweeps", offset_of!(QuadoptReport, sweeps)),
        ("QuadoptProgress energy_change", offset_of!(QuadoptProgress, energy_change)),
    ];
    let mut seen = 0;
    for line in stdout.lines() {
        let parts: Vec<&str> = line.split(' ').collect();
        match parts[..] {
            ["size", name, n] => {
                let rust = rust_sizes.iter().find(|r| r.0 == name).expect("known struct").1;
                assert_eq!(n.parse::<usize>().unwrap(), rust, "sizeof({name}) in C");
                seen += 1;
            }
            ["layout", name, field, n] => {
                let key = format!("{name} {field}");
                let rust = rust_offsets.iter().find(|r| r.0 == key).expect("known field").1;
                assert_eq!(n.parse::<usize>().unwrap(), rust, "offsetof({name}, {field}) in C");
                seen += 1;
            }
            _ => {}
        }
    }
    assert_eq!(seen, rust_sizes.len() + rust_offsets.len(), "every layout line was checked");
}

//! `include/quadopt.h` must be exactly what cbindgen (pinned in Cargo.toml) generates from
//! `src/ffi/` (from `src/ffi/mod.rs`, following its modules) with `cbindgen.toml`.
//!
//! After changing the C API, regenerate the checked-in header with
//!
//! ```text
//! QUADOPT_BLESS=1 cargo test --test header
//! ```
//!
//! and review the diff; this also regenerates `tests/bindgen/quadopt_sys.rs`, the bindgen
//! bindings that `tests/bindgen.rs` checks and uses. Without `QUADOPT_BLESS` the test fails on any difference and prints
//! the first differing lines.

use std::path::Path;

#[path = "bindgen/generate.rs"]
mod bindgen_settings;

/// Generates the header text from `src/ffi/` alone (the same as
/// `cbindgen --config cbindgen.toml --output include/quadopt.h src/ffi/mod.rs`, which follows
/// the `mod` declarations of `src/ffi/mod.rs`), so public items of other modules never leak
/// into the C API.
fn generate(root: &Path) -> String {
    let config = cbindgen::Config::from_file(root.join("cbindgen.toml")).expect("cbindgen.toml parses");
    let bindings = cbindgen::Builder::new()
        .with_src(root.join("src/ffi/mod.rs"))
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header");
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).expect("the header is UTF-8")
}

/// The first few differing lines of two texts, as a diff hint.
fn diff_hint(expected: &str, actual: &str) -> String {
    let (e, a): (Vec<_>, Vec<_>) = (expected.lines().collect(), actual.lines().collect());
    let mut hint = String::new();
    let mut shown = 0;
    for i in 0..e.len().max(a.len()) {
        let (x, y) = (e.get(i).copied(), a.get(i).copied());
        if x != y {
            hint += &format!("line {}:\n  checked in: {:?}\n  generated:  {:?}\n", i + 1, x, y);
            shown += 1;
            if shown == 10 {
                hint += "  ...\n";
                break;
            }
        }
    }
    hint
}

#[test]
fn checked_in_header_matches_cbindgen_output() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = root.join("include/quadopt.h");
    let generated = generate(root);
    if std::env::var_os("QUADOPT_BLESS").is_some() {
        std::fs::write(&path, &generated).expect("write include/quadopt.h");
        // The bindings checked by tests/bindgen.rs follow the header.
        let bindings = bindgen_settings::bindings(root);
        std::fs::write(root.join(bindgen_settings::BINDINGS), bindings).expect("write the bindings");
        return;
    }
    let checked_in = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        checked_in == generated,
        "include/quadopt.h is out of date with src/ffi/; regenerate it with \
         `QUADOPT_BLESS=1 cargo test --test header` and review the diff.\n{}",
        diff_hint(&checked_in, &generated)
    );
}

#[test]
fn header_has_the_agreed_names() {
    // Spot checks of the naming scheme agreed for the C API (include guard, prefixes, enum
    // value names, size_t counts), independent of cbindgen's defaults.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let h = generate(root);
    for needle in [
        "#ifndef QUADOPT_H",
        "#define QUADOPT_H",
        "QUADOPT_STATUS_OK = 0",
        "QUADOPT_STATUS_NOT_PLANAR = 13",
        "QUADOPT_METHOD_ANGLE_BASED = 3",
        "QUADOPT_BOUNDARY_SNAP = 3",
        "#define QUADOPT_VERSION_MAJOR 0",
        "typedef struct QuadoptOptimizer QuadoptOptimizer;",
        "typedef bool (*QuadoptProgressFn)(const struct QuadoptProgress *progress,",
        "size_t vertex_count",
        "const char *quadopt_last_error(void);",
    ] {
        assert!(h.contains(needle), "header lacks {needle:?}");
    }
    assert!(!h.contains("uintptr_t"), "counts must be size_t");
}

//! Builds the C shim (shim/openmesh_shim.cpp, with the input checks of shim/prevalidate.cpp) with the `cc` crate as C++17, generates the Rust
//! declarations of shim/openmesh_shim.h with bindgen, and links OpenMeshCore.
//!
//! OpenMesh is found, in this order:
//! 1. `OPENMESH_DIR`: an installation prefix (a self-built OpenMesh): headers in
//!    `$OPENMESH_DIR/include`, the library in `$OPENMESH_DIR/lib` (or `lib64`);
//! 2. pkg-config, package `openmesh` (Debian's libopenmesh-dev ships openmesh.pc).
//!
//! When neither finds it, the build stops with a message naming the package to install.

use std::env;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Where OpenMesh's headers and library are.
struct OpenMesh {
    include_dirs: Vec<PathBuf>,
    lib_dirs: Vec<PathBuf>,
    origin: String,
}

fn from_prefix(prefix: &Path) -> OpenMesh {
    let lib_dirs = ["lib", "lib64"].iter().map(|d| prefix.join(d)).filter(|d| d.is_dir()).collect();
    OpenMesh {
        include_dirs: vec![prefix.join("include")],
        lib_dirs,
        origin: format!("OPENMESH_DIR={}", prefix.display()),
    }
}

/// `pkg-config --cflags --libs openmesh`, if pkg-config is there and knows the package.
fn from_pkg_config() -> Result<OpenMesh, String> {
    let pkg_config = env::var("PKG_CONFIG").unwrap_or_else(|_| "pkg-config".into());
    let out = Command::new(&pkg_config)
        .args(["--cflags", "--libs", "openmesh"])
        .output()
        .map_err(|e| format!("cannot run {pkg_config}: {e}"))?;
    if !out.status.success() {
        return Err(format!("{pkg_config} does not know the package `openmesh`"));
    }
    let flags = String::from_utf8_lossy(&out.stdout);
    let mut om =
        OpenMesh { include_dirs: Vec::new(), lib_dirs: Vec::new(), origin: "pkg-config openmesh".into() };
    for flag in flags.split_whitespace() {
        if let Some(dir) = flag.strip_prefix("-I") {
            om.include_dirs.push(dir.into());
        } else if let Some(dir) = flag.strip_prefix("-L") {
            om.lib_dirs.push(dir.into());
        }
    }
    if om.include_dirs.is_empty() {
        om.include_dirs.push("/usr/include".into());
    }
    Ok(om)
}

fn main() {
    println!("cargo:rerun-if-changed=shim/openmesh_shim.h");
    for file in ["openmesh_shim.cpp", "prevalidate.cpp", "prevalidate.h", "failure.h"] {
        println!("cargo:rerun-if-changed=shim/{file}");
    }
    println!("cargo:rerun-if-env-changed=OPENMESH_DIR");
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");
    println!("cargo:rerun-if-env-changed=PKG_CONFIG");

    let om = match env::var_os("OPENMESH_DIR") {
        Some(dir) => from_prefix(Path::new(&dir)),
        None => from_pkg_config().unwrap_or_else(|why| missing(&why)),
    };
    let header = Path::new("OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh");
    if !om.include_dirs.iter().any(|d| d.join(header).is_file()) {
        missing(&format!("{} gives no include directory with {}", om.origin, header.display()));
    }

    cc::Build::new()
        .cpp(true)
        .std("c++17")
        .file("shim/openmesh_shim.cpp")
        .file("shim/prevalidate.cpp")
        .include("shim")
        .includes(&om.include_dirs)
        // GCC 12 false positive inside OpenMesh 9.0's PropertyT<VectorT>::push_back().
        .flag_if_supported("-Wno-maybe-uninitialized")
        .warnings(true)
        .compile("openmesh_shim");

    for dir in &om.lib_dirs {
        println!("cargo:rustc-link-search=native={}", dir.display());
    }
    println!("cargo:rustc-link-lib=dylib=OpenMeshCore");
    // For dependents' build scripts (DEP_OPENMESHCORE_INCLUDE, DEP_OPENMESHCORE_SHIM).
    let include: Vec<String> = om.include_dirs.iter().map(|d| d.display().to_string()).collect();
    println!("cargo:include={}", include.join(if cfg!(windows) { ";" } else { ":" }));
    println!("cargo:shim={}", Path::new(&env::var("CARGO_MANIFEST_DIR").unwrap()).join("shim").display());

    let bindings = bindgen::Builder::default()
        .header("shim/openmesh_shim.h")
        .clang_args(["-x", "c", "-std=c99"])
        .allowlist_item("(omsys|Omsys|OMSYS).*")
        .generate_comments(true)
        .layout_tests(true)
        .formatter(bindgen::Formatter::Prettyplease)
        .generate()
        .unwrap_or_else(|e| {
            panic!("openmesh-sys: bindgen cannot parse shim/openmesh_shim.h ({e}); is libclang installed? (Debian: apt-get install libclang-dev)")
        });
    let out = PathBuf::from(env::var("OUT_DIR").unwrap()).join("bindings.rs");
    bindings
        .write_to_file(&out)
        .unwrap_or_else(|e| panic!("openmesh-sys: cannot write {}: {e}", out.display()));
}

/// Stops the build with what is missing and how to get it.
fn missing(why: &str) -> ! {
    panic!(
        "\n\nopenmesh-sys: OpenMesh (OpenMeshCore) was not found: {why}.\n\
         Install the Debian/Ubuntu package `libopenmesh-dev` (it provides pkg-config's `openmesh`),\n\
         or set OPENMESH_DIR to the prefix of an OpenMesh installation (with include/OpenMesh and lib/).\n\
         The quadopt CLI builds without OpenMesh when its `openmesh` feature is off (the default).\n\n"
    )
}

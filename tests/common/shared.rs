//! Data that is not part of the repository: the directory `shared` next to it (`../shared`
//! from the repository's root, found from `CARGO_MANIFEST_DIR`), which holds for example
//! Mesquite's test meshes. A test that needs it skips that part without it, and says so on
//! one line.

use std::io::Write;
use std::path::{Path, PathBuf};

/// `../shared/<sub>` relative to the repository, if it is a directory. If not, prints one
/// line saying that `what` is skipped and why, and gives `None`.
pub fn shared_dir(sub: &str, what: &str) -> Option<PathBuf> {
    match locate(Path::new(env!("CARGO_MANIFEST_DIR")), sub, what) {
        Ok(dir) => Some(dir),
        Err(line) => {
            // Straight to stderr, not through eprintln!, which the test harness captures: the
            // line shows in every run, not only in failing ones or with --nocapture.
            let _ = writeln!(std::io::stderr(), "{line}");
            None
        }
    }
}

/// Mesquite's quad test meshes (`../shared/meshes/mesquite`, with `tangled/` and
/// `untangled/`), as [`shared_dir`] finds them.
pub fn mesquite(what: &str) -> Option<PathBuf> {
    shared_dir("meshes/mesquite", what)
}

/// `../shared/<sub>` relative to the repository at `root`, or the line saying that `what` is
/// skipped and why.
pub fn locate(root: &Path, sub: &str, what: &str) -> Result<PathBuf, String> {
    let dir = root.join("../shared").join(sub);
    if dir.is_dir() {
        return Ok(dir);
    }
    Err(format!(
        "skipped: {what}, because {} is not a directory (../shared/{sub} next to the repository, \
         which is not part of it)",
        dir.display()
    ))
}

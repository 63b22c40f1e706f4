//! Output files that never clobber what they should not.
//!
//! - A regular file (or a path that does not exist yet) is replaced atomically: the text goes
//!   to a temporary file created exclusively, under an unpredictable short name, in the same
//!   directory, which is renamed over the path only once complete and synced. An existing
//!   file keeps its permissions (and, where the process may set them, its owner and group).
//!   A failed write leaves the old file as it was and no temporary file behind.
//! - A symbolic link is followed, and its target is replaced the same way (the link stays).
//! - Anything else (a device such as `/dev/null` or `/dev/full`, a FIFO, a descriptor link
//!   such as `/dev/stdout`) is opened and written in place, never replaced; every write and
//!   the final flush are checked, so `/dev/full` fails with "No space left on device".
//!
//! A process killed by a signal cannot run destructors, so the temporary files being written
//! are listed here: a signal handler (the CLI has one for SIGINT and SIGTERM) calls
//! [`remove_pending_temporary_files`] before the process ends.

use super::IoError;
use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// Temporary files being written, removed by [`remove_pending_temporary_files`].
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn pending() -> MutexGuard<'static, Vec<PathBuf>> {
    // A panic while holding the lock leaves a list that is still valid.
    PENDING.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes every temporary output file still being written. Meant for a signal handler (run
/// on an ordinary thread, as `signal-hook`'s iterator does) just before the process exits.
pub fn remove_pending_temporary_files() {
    for path in pending().drain(..) {
        let _ = fs::remove_file(path);
    }
}

/// Where writing a path leads.
#[derive(Debug, PartialEq)]
enum Target {
    /// A regular file, existing or not, replaced through a temporary file and a rename.
    Replace(PathBuf),
    /// Something that is not a regular file, written in place.
    InPlace,
}

/// Follows `path`'s symbolic links to what writing it should replace.
fn resolve(path: &Path) -> io::Result<Target> {
    let mut p = path.to_path_buf();
    // As many links as Linux follows before ELOOP.
    for _ in 0..40 {
        let meta = match fs::symlink_metadata(&p) {
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Target::Replace(p)),
            Err(e) => return Err(e),
            Ok(m) => m,
        };
        if meta.file_type().is_symlink() {
            // /proc/self/fd/N, /dev/fd/N (and /dev/stdout through them) name an open file,
            // which may be a pipe or a terminal: never replace it.
            if p.starts_with("/proc") || p.starts_with("/dev/fd") {
                return Ok(Target::InPlace);
            }
            let link = fs::read_link(&p)?;
            p = match p.parent() {
                Some(dir) => dir.join(link),
                None => link,
            };
        } else if meta.is_file() {
            return Ok(Target::Replace(p));
        } else {
            return Ok(Target::InPlace);
        }
    }
    Err(io::Error::other("too many levels of symbolic links"))
}

/// Writes a file as described in the module docs; `write` produces the contents (it may
/// write in small pieces: the stream is buffered). Errors name `path`.
pub fn write_output(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), IoError> {
    let file_error = |source| IoError::File { path: path.into(), action: "write", source };
    match resolve(path).map_err(file_error)? {
        Target::InPlace => {
            let file = fs::OpenOptions::new().write(true).open(path).map_err(file_error)?;
            let mut w = BufWriter::new(file);
            write(&mut w).and_then(|()| w.flush()).map_err(file_error)
        }
        Target::Replace(target) => replace(&target, write).map_err(file_error),
    }
}

/// Replaces the regular file `target` (or creates it) atomically.
fn replace(target: &Path, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<()> {
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let existing = match fs::metadata(target) {
        Ok(m) => Some(m),
        Err(e) if e.kind() == io::ErrorKind::NotFound => None,
        Err(e) => return Err(e),
    };
    let mut builder = tempfile::Builder::new();
    // 23 characters: short enough beside any legal name, random enough that no name can be
    // prepared in advance (creation is exclusive, so a planted file or link is never opened).
    builder.prefix(".quadopt-").suffix(".tmp").rand_bytes(10);
    #[cfg(unix)]
    if existing.is_none() {
        use std::os::unix::fs::PermissionsExt;
        // What creating the file directly would give: 0666 less the umask.
        builder.permissions(fs::Permissions::from_mode(0o666));
    }
    let tmp = builder.tempfile_in(dir).map_err(without_temporary_name)?;
    pending().push(tmp.path().to_path_buf());
    let result = (|| {
        #[cfg(unix)]
        if let Some(meta) = &existing {
            use std::os::unix::fs::{MetadataExt, PermissionsExt};
            // Owner first: changing it may clear set-id bits that the mode then restores.
            // Only a privileged process may give a file away; otherwise it keeps ours.
            let _ = std::os::unix::fs::fchown(tmp.as_file(), Some(meta.uid()), Some(meta.gid()));
            tmp.as_file().set_permissions(fs::Permissions::from_mode(meta.mode() & 0o7777))?;
        }
        let mut w = BufWriter::new(tmp.as_file());
        write(&mut w)?;
        w.flush()?;
        drop(w);
        tmp.as_file().sync_all()
    })();
    // Holding the list while renaming: a signal handler waits, then finds nothing to remove.
    let mut list = pending();
    let tmp_path = tmp.path().to_path_buf();
    let result = result.and_then(|()| tmp.persist(target).map(drop).map_err(|e| e.error));
    // On error the temporary file was dropped, which removed it.
    list.retain(|p| *p != tmp_path);
    result
}

/// tempfile's error on creating the temporary file, without the name it appends (`... at path
/// "/dir/.quadopt-XXXXXXXXXX.tmp"`): the caller's message names the file the user asked for,
/// and the temporary one is an internal detail that never exists after the failure.
fn without_temporary_name(e: io::Error) -> io::Error {
    let text = e.to_string();
    match text.rfind(" at path \"") {
        Some(end) if e.get_ref().is_some() => io::Error::new(e.kind(), &text[..end]),
        _ => e,
    }
}

/// Writes `bytes` to a file as [`write_output`] does.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_output(path, |w| w.write_all(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_names_the_file_asked_for_not_the_temporary_one() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("missing/out.vtk");
        let e = write_file(&path, b"x").unwrap_err().to_string();
        assert_eq!(e, format!("cannot write {}: {}", path.display(), io::Error::from_raw_os_error(2)));
        assert!(!e.contains(".quadopt-"), "{e}");
    }

    #[test]
    fn links_are_followed_to_what_they_name() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a.vtk");
        assert_eq!(resolve(&file).unwrap(), Target::Replace(file.clone()));
        fs::write(&file, "x").unwrap();
        #[cfg(unix)]
        {
            let link = dir.path().join("link.vtk");
            std::os::unix::fs::symlink("a.vtk", &link).unwrap();
            assert_eq!(resolve(&link).unwrap(), Target::Replace(dir.path().join("a.vtk")));
            let dangling = dir.path().join("dangling.vtk");
            std::os::unix::fs::symlink("sub/new.vtk", &dangling).unwrap();
            assert_eq!(resolve(&dangling).unwrap(), Target::Replace(dir.path().join("sub/new.vtk")));
            let looped = dir.path().join("loop.vtk");
            std::os::unix::fs::symlink("loop.vtk", &looped).unwrap();
            assert!(resolve(&looped).is_err());
        }
        assert_eq!(resolve(dir.path()).unwrap(), Target::InPlace);
        #[cfg(target_os = "linux")]
        {
            assert_eq!(resolve(Path::new("/dev/null")).unwrap(), Target::InPlace);
            assert_eq!(resolve(Path::new("/dev/stdout")).unwrap(), Target::InPlace);
        }
    }
}

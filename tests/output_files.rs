//! Output files (`quadopt::io::output`, used by `write_mesh` and the CLI): atomic replacement
//! through an exclusively created temporary file, permissions kept, links followed, devices
//! and FIFOs written in place with errors reported, nothing left behind on failure or SIGINT.
#![cfg(unix)]

use quadopt::io::{self, Format, MeshData};
use std::fs;
use std::os::unix::fs::{FileTypeExt, PermissionsExt, symlink};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("quadopt-out-{}-{test}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

fn square() -> MeshData {
    MeshData::new(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
        vec![[0, 1, 2, 3]],
    )
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> =
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

fn quadopt(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_quadopt")).args(args).output().unwrap()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn a_planted_link_at_any_predictable_name_is_never_followed() {
    let dir = scratch("planted");
    let victim = dir.join("victim.txt");
    fs::write(&victim, "precious").unwrap();
    let out = dir.join("out.vtk");
    // The names the old writer used (and other obvious guesses), each a link to the victim.
    let pid = std::process::id();
    let guesses =
        [format!(".out.vtk.{pid}.tmp"), ".out.vtk.tmp".into(), "out.vtk.tmp".into(), ".out.vtk~".into()];
    for g in &guesses {
        symlink(&victim, dir.join(g)).unwrap();
    }
    io::write_mesh(&out, &square()).unwrap();
    assert_eq!(fs::read_to_string(&victim).unwrap(), "precious");
    assert_eq!(io::read_mesh(&out).unwrap().points, square().points);
    for g in &guesses {
        assert!(fs::symlink_metadata(dir.join(g)).unwrap().file_type().is_symlink(), "{g}");
    }
    // Nothing else was left in the directory.
    let mut want: Vec<String> = guesses.to_vec();
    want.extend(["out.vtk".to_string(), "victim.txt".to_string()]);
    want.sort();
    assert_eq!(names(&dir), want);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_existing_file_keeps_its_permissions_and_a_new_one_gets_the_usual_mode() {
    let dir = scratch("mode");
    for mode in [0o600, 0o640, 0o755] {
        let out = dir.join(format!("m{mode:o}.obj"));
        fs::write(&out, "old").unwrap();
        fs::set_permissions(&out, fs::Permissions::from_mode(mode)).unwrap();
        io::write_mesh(&out, &square()).unwrap();
        assert_eq!(fs::metadata(&out).unwrap().permissions().mode() & 0o7777, mode);
        assert_eq!(io::read_mesh(&out).unwrap().quads, square().quads);
    }
    // A new file: 0666 less the umask, as any program creating it would get (never the
    // temporary file's private 0600 unless the umask says so). Compare with a plain create.
    let plain = dir.join("plain");
    fs::write(&plain, "").unwrap();
    let new = dir.join("new.off");
    io::write_mesh(&new, &square()).unwrap();
    assert_eq!(
        fs::metadata(&new).unwrap().permissions().mode() & 0o777,
        fs::metadata(&plain).unwrap().permissions().mode() & 0o777
    );
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_link_is_followed_and_its_target_replaced() {
    let dir = scratch("link");
    fs::create_dir(dir.join("real")).unwrap();
    let target = dir.join("real/target.msh");
    fs::write(&target, "old").unwrap();
    fs::set_permissions(&target, fs::Permissions::from_mode(0o600)).unwrap();
    let link = dir.join("out.msh");
    symlink("real/target.msh", &link).unwrap();
    io::write_mesh(&link, &square()).unwrap();
    assert!(fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link stays a link");
    assert_eq!(io::read_mesh(&target).unwrap().points, square().points);
    assert_eq!(fs::metadata(&target).unwrap().permissions().mode() & 0o777, 0o600);
    assert_eq!(names(&dir.join("real")), ["target.msh"]);
    assert_eq!(names(&dir), ["out.msh", "real"]);
    // A dangling link creates its target.
    let dangling = dir.join("new.obj");
    symlink("real/created.obj", &dangling).unwrap();
    io::write_mesh(&dangling, &square()).unwrap();
    assert!(dir.join("real/created.obj").is_file());
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_long_legal_name_works() {
    let dir = scratch("long");
    // 250 bytes: legal on every common file system (255 is the limit); the old temporary
    // name (`.NAME.PID.tmp`) was longer than that.
    let name = format!("{}.vtk", "a".repeat(246));
    assert_eq!(name.len(), 250);
    let out = dir.join(&name);
    io::write_mesh(&out, &square()).unwrap();
    assert_eq!(io::read_mesh(&out).unwrap().quads, square().quads);
    io::write_mesh(&out, &square()).unwrap();
    assert_eq!(names(&dir), std::slice::from_ref(&name));
    // The CLI too.
    let input = dir.join("in.obj");
    io::write_mesh(&input, &square()).unwrap();
    let r = quadopt(&["optimize", s(&input), "-o", s(&out), "--boundary", "fixed"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(names(&dir), [name, "in.obj".to_string()]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_full_device_is_an_error_and_stays_a_device() {
    let full = Path::new("/dev/full");
    if !full.exists() {
        return; // not Linux
    }
    let e = io::write_mesh_as(full, Format::Vtk, &square()).unwrap_err();
    let msg = e.to_string();
    assert!(msg.starts_with("cannot write /dev/full: No space left on device"), "{msg}");
    assert!(fs::metadata(full).unwrap().file_type().is_char_device());
    // The CLI: exit 1, one line, the device still a device.
    let dir = scratch("full");
    let input = dir.join("in.obj");
    io::write_mesh(&input, &square()).unwrap();
    let r = quadopt(&["optimize", s(&input), "-o", "/dev/full", "--format", "vtk"]);
    assert_eq!(r.status.code(), Some(1));
    let err = String::from_utf8(r.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("quadopt: error: cannot write /dev/full: No space left on device"), "{err}");
    assert!(fs::metadata(full).unwrap().file_type().is_char_device());
    // Without --format, a name with no known extension is refused before any work.
    let r = quadopt(&["optimize", s(&input), "-o", "/dev/full"]);
    assert_eq!(r.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&r.stderr).contains("unknown mesh format"));
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_fifo_is_written_in_place() {
    let dir = scratch("fifo");
    let fifo = dir.join("pipe.vtk");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        return; // no mkfifo
    }
    let path = fifo.clone();
    let reader = std::thread::spawn(move || fs::read_to_string(path).unwrap());
    io::write_mesh(&fifo, &square()).unwrap();
    let text = reader.join().unwrap();
    assert_eq!(io::read_mesh_str(&text, Format::Vtk).unwrap().points, square().points);
    assert!(fs::metadata(&fifo).unwrap().file_type().is_fifo(), "the FIFO was not replaced");
    assert_eq!(names(&dir), ["pipe.vtk"]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn dash_writes_to_stdout_and_the_report_to_stderr() {
    let dir = scratch("stdout");
    let input = dir.join("in.off");
    io::write_mesh(&input, &square()).unwrap();
    // In the input's format by default.
    let r = quadopt(&["optimize", s(&input), "-o", "-", "--boundary", "fixed"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let text = String::from_utf8(r.stdout).unwrap();
    assert_eq!(io::read_mesh_str(&text, Format::Off).unwrap().quads, square().quads);
    assert!(String::from_utf8_lossy(&r.stderr).contains("wrote the mesh to stdout"));
    // Another format with --format; generate needs it.
    let r = quadopt(&["optimize", s(&input), "-o", "-", "--format", "msh", "--json"]);
    let text = String::from_utf8(r.stdout).unwrap();
    assert!(text.starts_with("$MeshFormat"), "{text}");
    assert_eq!(io::read_mesh_str(&text, Format::Msh).unwrap().quads, square().quads);
    let r = quadopt(&["generate", "-o", "-", "--nx", "3", "--ny", "2"]);
    assert_eq!(r.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&r.stderr).contains("needs --format"));
    let r = quadopt(&["generate", "-o", "-", "--nx", "3", "--ny", "2", "--holes", "0", "--format", "obj"]);
    let m = io::read_mesh_str(&String::from_utf8(r.stdout).unwrap(), Format::Obj).unwrap();
    assert_eq!((m.points.len(), m.quads.len()), (12, 6));
    let r = quadopt(&["draw", s(&input), "-o", "-"]);
    assert!(String::from_utf8(r.stdout).unwrap().starts_with("<svg"));
    assert_eq!(names(&dir), ["in.off"]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn draw_checks_its_extension() {
    let dir = scratch("draw");
    let input = dir.join("in.obj");
    io::write_mesh(&input, &square()).unwrap();
    for bad in ["out.vtk", "out", "out.png.txt"] {
        let r = quadopt(&["draw", s(&input), "-o", s(&dir.join(bad))]);
        assert_eq!(r.status.code(), Some(1), "{bad}");
        let err = String::from_utf8(r.stderr).unwrap();
        assert!(err.contains("expected the extension .png or .svg") && err.lines().count() == 1, "{err}");
    }
    assert!(quadopt(&["draw", s(&input), "-o", s(&dir.join("ok.SVG"))]).status.success());
    assert!(quadopt(&["draw", s(&input), "-o", s(&dir.join("ok.PNG"))]).status.success());
    assert_eq!(names(&dir), ["in.obj", "ok.PNG", "ok.SVG"]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_failed_write_leaves_the_old_file_and_no_temporary() {
    let dir = scratch("failed");
    let out = dir.join("out.obj");
    fs::write(&out, "old").unwrap();
    let e = io::write_output(&out, |w| {
        w.write_all(b"half")?;
        Err(std::io::Error::other("disk on fire"))
    })
    .unwrap_err();
    assert!(e.to_string().contains("disk on fire"), "{e}");
    assert_eq!(fs::read_to_string(&out).unwrap(), "old");
    assert_eq!(names(&dir), ["out.obj"]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sigint_during_a_write_leaves_no_temporary_file() {
    let dir = scratch("sigint");
    let out = dir.join("big.vtk");
    // A mesh big enough that writing it takes a while; if the write still wins the race,
    // try a bigger one.
    for quads in ["400000", "1600000", "4000000"] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_quadopt"))
            .args(["generate", "-o", s(&out), "--quads", quads])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Wait for the temporary file to appear, then interrupt.
        let start = Instant::now();
        let mut seen = false;
        while start.elapsed() < Duration::from_secs(60) {
            if names(&dir).iter().any(|n| n.starts_with(".quadopt-")) {
                seen = true;
                break;
            }
            if child.try_wait().unwrap().is_some() {
                break;
            }
            std::thread::sleep(Duration::from_micros(200));
        }
        if seen {
            Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
        }
        let status = child.wait().unwrap();
        use std::os::unix::process::ExitStatusExt;
        if status.signal() == Some(2) {
            assert!(names(&dir).is_empty(), "left behind: {:?}", names(&dir));
            fs::remove_dir_all(&dir).unwrap();
            return;
        }
        // The write finished first: it must have produced the whole file, nothing else.
        assert!(status.success(), "{status:?}");
        assert_eq!(names(&dir), ["big.vtk"]);
        fs::remove_file(&out).unwrap();
    }
    panic!("never caught a write in progress");
}

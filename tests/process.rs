//! The C ABI under process-level conditions a host can create: `fork` after use, a thread
//! limit, an address-space limit. Each case runs in a process of its own (a forked child, or
//! this test binary run again with `QUADOPT_TEST_CHILD` set) so that limits and the library's
//! process-wide worker pool start from a known state. Linux only (`/proc`, `RLIMIT_AS`).
#![cfg(target_os = "linux")]

mod common;

use common::grids::{Grid, flat};
use quadopt::DVec2;
use quadopt::ffi::*;
use std::ffi::CStr;
use std::ptr::{null, null_mut};
use std::time::{Duration, Instant};

/// An `n` x `n` grid of unit squares with its interior vertices jittered (deterministically)
/// by up to 0.3: coordinates (2 per vertex) and quads.
fn jittered_grid(n: usize) -> (Vec<f64>, Vec<u32>) {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut jitter = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        0.3 * ((state >> 11) as f64 / (1u64 << 52) as f64 - 1.0)
    };
    let grid = Grid::square(n);
    let (points, quads) = grid.placed(|i, j| {
        let (dx, dy) = if grid.is_interior(i, j) { (jitter(), jitter()) } else { (0.0, 0.0) };
        DVec2::new(i as f64 + dx, j as f64 + dy)
    });
    flat(&points, &quads)
}

/// quadopt_optimize with the defaults on a copy of `coords`: the status and the result's bits.
fn optimize(coords: &[f64], quads: &[u32]) -> (QuadoptStatus, Vec<u64>) {
    let mut c = coords.to_vec();
    // SAFETY: live buffers of the stated lengths.
    let s = unsafe {
        quadopt_optimize(
            c.as_mut_ptr(),
            2,
            c.len() / 2,
            quads.as_ptr(),
            quads.len() / 4,
            null(),
            null(),
            null_mut(),
        )
    };
    (s, c.iter().map(|x| x.to_bits()).collect())
}

fn last_error() -> String {
    // SAFETY: never NULL, valid until the next call on this thread.
    unsafe { CStr::from_ptr(quadopt_last_error()) }.to_string_lossy().into_owned()
}

fn thread_count() -> usize {
    std::fs::read_dir("/proc/self/task").unwrap().count()
}

/// Waits for child `pid` until `deadline`; kills it when the deadline passes. The exit code,
/// or None for a child that was killed or died of a signal.
fn wait_with_deadline(pid: libc::pid_t, deadline: Duration) -> Option<i32> {
    let start = Instant::now();
    loop {
        let mut status = 0;
        // SAFETY: plain system call on our own child.
        let r = unsafe { libc::waitpid(pid, &mut status, libc::WNOHANG) };
        assert!(r >= 0, "waitpid failed");
        if r == pid {
            return libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status));
        }
        if start.elapsed() > deadline {
            // SAFETY: as above.
            unsafe {
                libc::kill(pid, libc::SIGKILL);
                libc::waitpid(pid, &mut status, 0);
            }
            return None;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Forks; the child runs `body` and exits with its code (3 if it panicked) without returning
/// into the test harness. The parent gets the child's exit code (None if it had to be killed).
fn in_forked_child(deadline: Duration, body: impl FnOnce() -> i32) -> Option<i32> {
    // SAFETY: the child only runs `body` and then _exit, never returning to the harness.
    let pid = unsafe { libc::fork() };
    assert!(pid >= 0, "fork failed");
    if pid == 0 {
        let code = std::panic::catch_unwind(std::panic::AssertUnwindSafe(body)).unwrap_or(3);
        // SAFETY: ends the child at once, without running the parent's exit handlers.
        unsafe { libc::_exit(code) };
    }
    wait_with_deadline(pid, deadline)
}

#[test]
fn a_child_forked_after_use_finishes_its_calls() {
    let (coords, quads) = jittered_grid(40);
    let (s, expected) = optimize(&coords, &quads);
    assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
    // A pre-forking server: another thread is inside quadopt while the main one forks.
    let stop = std::sync::atomic::AtomicBool::new(false);
    std::thread::scope(|scope| {
        scope.spawn(|| {
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                assert_eq!(optimize(&coords, &quads), (QuadoptStatus::Ok, expected.clone()));
            }
        });
        std::thread::sleep(Duration::from_millis(50));
        let same_result = || i32::from(optimize(&coords, &quads) != (QuadoptStatus::Ok, expected.clone()));
        let deadline = Duration::from_secs(60);
        // The child calls twice, then forks a grandchild of its own that calls again.
        let child = in_forked_child(deadline, || {
            let first = same_result() + same_result();
            first + in_forked_child(deadline, same_result).map_or(10, |code| 4 * code)
        });
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        assert_eq!(child, Some(0), "the forked child blocked (None) or got another result");
    });
    // The parent's pool still works.
    assert_eq!(optimize(&coords, &quads), (QuadoptStatus::Ok, expected));
}

/// The Rust API on a copy of the grid: the output's bits (or a panic).
fn optimize_rust(coords: &[f64], quads: &[u32]) -> Vec<u64> {
    let points = coords.chunks(2).map(|c| glam::DVec2::new(c[0], c[1])).collect();
    let quads = quads.chunks(4).map(|q| [q[0], q[1], q[2], q[3]]).collect();
    let mut mesh = quadopt::Mesh::new(points, quads, None).unwrap();
    quadopt::optimize(&mut mesh, &quadopt::Options::default()).unwrap();
    mesh.points().iter().flat_map(|p| [p.x.to_bits(), p.y.to_bits()]).collect()
}

#[test]
fn a_child_forked_after_the_rust_api_finishes_its_calls() {
    // 10,000 quads: colour classes large enough for the parallel loops.
    let (coords, quads) = jittered_grid(100);
    let expected = optimize_rust(&coords, &quads);
    let deadline = Duration::from_secs(120);
    let child = in_forked_child(deadline, || {
        let first = i32::from(optimize_rust(&coords, &quads) != expected);
        first
            + in_forked_child(deadline, || i32::from(optimize_rust(&coords, &quads) != expected))
                .map_or(10, |c| 4 * c)
    });
    assert_eq!(child, Some(0), "the forked child blocked (None) or got another result");
    // Inside a rayon pool of the caller's, the run uses that pool (and gives the same result).
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    assert_eq!(pool.install(|| optimize_rust(&coords, &quads)), expected);
}

/// Runs this binary's test `name` again in a fresh process with `QUADOPT_TEST_CHILD=name`
/// and two worker threads.
fn run_in_child(name: &str) {
    run_in_child_with(name, &[]);
}

fn run_in_child_with(name: &str, env: &[(&str, &str)]) {
    let out = std::process::Command::new(std::env::current_exe().unwrap())
        .args(["--exact", name, "--nocapture", "--test-threads=1"])
        .env("QUADOPT_TEST_CHILD", name)
        .env("RAYON_NUM_THREADS", "2")
        .envs(env.iter().copied())
        .output()
        .unwrap();
    let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success() && stdout.contains("1 passed"), "child {name}:\n{stdout}\n{stderr}");
}

fn is_child(name: &str) -> bool {
    std::env::var("QUADOPT_TEST_CHILD").as_deref() == Ok(name)
}

/// Bytes of address space this process uses now.
fn address_space() -> u64 {
    let statm = std::fs::read_to_string("/proc/self/statm").unwrap();
    // SAFETY: plain query.
    let page = unsafe { libc::sysconf(libc::_SC_PAGESIZE) } as u64;
    statm.split_whitespace().next().unwrap().parse::<u64>().unwrap() * page
}

fn set_address_space_limit(bytes: libc::rlim_t) {
    let mut limit = libc::rlimit { rlim_cur: 0, rlim_max: 0 };
    // SAFETY: plain system calls on this process with a valid struct.
    unsafe {
        assert_eq!(libc::getrlimit(libc::RLIMIT_AS, &mut limit), 0);
        limit.rlim_cur = bytes.min(limit.rlim_max);
        assert_eq!(libc::setrlimit(libc::RLIMIT_AS, &limit), 0);
    }
}

#[test]
fn threads_that_cannot_start_give_a_status_leave_none_behind_and_later_calls_work() {
    const NAME: &str = "threads_that_cannot_start_give_a_status_leave_none_behind_and_later_calls_work";
    if !is_child(NAME) {
        return run_in_child(NAME);
    }
    let (coords, quads) = jittered_grid(6);
    let baseline = thread_count();
    // A megabyte of address space to spare: no room for a worker's stack.
    set_address_space_limit(address_space() + (1 << 20));
    let (s, c) = optimize(&coords, &quads);
    let message = last_error();
    set_address_space_limit(libc::RLIM_INFINITY);
    assert_eq!(s, QuadoptStatus::OutOfMemory, "{message}");
    assert!(message.contains("cannot start a worker thread"), "{message}");
    assert_eq!(c, coords.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), "coordinates were written");
    assert_eq!(thread_count(), baseline);
    let (s, _) = optimize(&coords, &quads);
    assert_eq!((s, thread_count()), (QuadoptStatus::Ok, baseline + 2), "{}", last_error());
}

/// The case: a valid 200-million-vertex input (3.2 GB of coordinates, all but one
/// quad's unused, so its pages are never touched) with room for less than the library's copy
/// of it. Every entry point returns QUADOPT_STATUS_OUT_OF_MEMORY instead of aborting.
#[test]
#[cfg(target_pointer_width = "64")]
fn a_valid_input_too_large_for_the_address_space_is_an_out_of_memory_status() {
    const NAME: &str = "a_valid_input_too_large_for_the_address_space_is_an_out_of_memory_status";
    if !is_child(NAME) {
        return run_in_child(NAME);
    }
    let n = 200_000_000;
    let mut coords = vec![0.0f64; 2 * n];
    coords[..8].copy_from_slice(&[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0]);
    let quads = [0u32, 1, 2, 3];
    let fixed = vec![0u8; n];
    set_address_space_limit(address_space() + (2 << 30));
    let mut out = QuadoptQuality::default();
    let mut handle = null_mut();
    // SAFETY: live buffers of the stated lengths.
    let statuses = unsafe {
        [
            quadopt_optimize(
                coords.as_mut_ptr(),
                2,
                n,
                quads.as_ptr(),
                1,
                fixed.as_ptr(),
                null(),
                null_mut(),
            ),
            quadopt_quality(coords.as_ptr(), 2, n, quads.as_ptr(), 1, &mut out, null_mut(), 0),
            quadopt_optimizer_create(coords.as_ptr(), 2, n, quads.as_ptr(), 1, null(), &mut handle),
        ]
    };
    let message = last_error();
    set_address_space_limit(libc::RLIM_INFINITY);
    assert_eq!(statuses, [QuadoptStatus::OutOfMemory; 3], "{message}");
    assert!(
        message.contains("out of memory: cannot allocate 3200000000 bytes for vertex coordinates"),
        "{message}"
    );
    assert!(handle.is_null() && out == QuadoptQuality::default());
    assert_eq!(coords[2..8], [1.0, 0.0, 1.0, 1.0, 0.0, 1.0]);
    // The synthetic generator (behind `quadopt generate`) fails the same way.
    set_address_space_limit(address_space() + (256 << 20));
    let grid = quadopt::synthetic::Synthetic { nx: 20_000, ny: 20_000, ..Default::default() }.try_generate();
    set_address_space_limit(libc::RLIM_INFINITY);
    assert!(matches!(grid, Err(quadopt::Error::OutOfMemory { .. })), "{:?}", grid.map(|m| m.points().len()));
}

/// Under every address-space limit from "no room at all" to "room enough", each entry point
/// either succeeds with the unlimited result or returns QUADOPT_STATUS_OUT_OF_MEMORY having
/// written nothing: no allocation on the way aborts the process.
#[test]
fn every_address_space_limit_gives_the_result_or_out_of_memory() {
    const NAME: &str = "every_address_space_limit_gives_the_result_or_out_of_memory";
    if !is_child(NAME) {
        // glibc: every block of 64 KiB or more gets its own mapping, returned when freed, and
        // one arena, so that a limit counts what the calls allocate, not what malloc keeps.
        let tunables =
            "glibc.malloc.mmap_threshold=65536:glibc.malloc.trim_threshold=65536:glibc.malloc.arena_max=1";
        return run_in_child_with(NAME, &[("GLIBC_TUNABLES", tunables)]);
    }
    let (coords, quads) = jittered_grid(100);
    let (v, q) = (coords.len() / 2, quads.len() / 4);
    let mut options = std::mem::MaybeUninit::<QuadoptOptions>::zeroed();
    // SAFETY: `options` holds size_of::<QuadoptOptions>() writable, aligned bytes.
    let s = unsafe { quadopt_options_init(options.as_mut_ptr(), size_of::<QuadoptOptions>()) };
    assert_eq!(s, QuadoptStatus::Ok, "{}", last_error());
    // SAFETY: zeroed (a valid QuadoptOptions), then filled with the defaults.
    let mut options = unsafe { options.assume_init() };
    options.max_iterations = 5;
    let optimize = |c: &mut [f64]| {
        // SAFETY: live buffers of the stated lengths.
        unsafe { quadopt_optimize(c.as_mut_ptr(), 2, v, quads.as_ptr(), q, null(), &options, null_mut()) }
    };
    let mut expected = coords.clone();
    assert_eq!(optimize(&mut expected), QuadoptStatus::Ok, "{}", last_error());
    let mut handle = null_mut();
    // SAFETY: live buffers; `handle` receives a pointer.
    let s =
        unsafe { quadopt_optimizer_create(coords.as_ptr(), 2, v, quads.as_ptr(), q, null(), &mut handle) };
    assert_eq!(s, QuadoptStatus::Ok);
    let mut quality = QuadoptQuality::default();
    // SAFETY: live buffers.
    let s = unsafe { quadopt_quality(coords.as_ptr(), 2, v, quads.as_ptr(), q, &mut quality, null_mut(), 0) };
    assert_eq!(s, QuadoptStatus::Ok);

    let base = address_space();
    let (mut refused, mut succeeded) = (0, 0);
    for extra in (0..=40).map(|k| k << 18) {
        let mut one_shot = coords.clone();
        let mut via_handle = coords.clone();
        let mut created = null_mut();
        let mut q2 = QuadoptQuality::default();
        set_address_space_limit(base + extra);
        // SAFETY: live buffers of the stated lengths; `handle` is live.
        let statuses = unsafe {
            [
                optimize(&mut one_shot),
                quadopt_optimizer_optimize(handle, via_handle.as_mut_ptr(), 2, v, &options, null_mut()),
                quadopt_quality(coords.as_ptr(), 2, v, quads.as_ptr(), q, &mut q2, null_mut(), 0),
                quadopt_optimizer_create(coords.as_ptr(), 2, v, quads.as_ptr(), q, null(), &mut created),
            ]
        };
        set_address_space_limit(libc::RLIM_INFINITY);
        let outputs = [&one_shot, &via_handle];
        for (k, s) in statuses.iter().enumerate() {
            match s {
                QuadoptStatus::Ok => succeeded += 1,
                QuadoptStatus::OutOfMemory => refused += 1,
                other => panic!("limit +{extra}: call {k} returned {other:?}"),
            }
        }
        for (out, s) in outputs.iter().zip(&statuses) {
            let want = if *s == QuadoptStatus::Ok { &expected } else { &coords };
            assert!(out.iter().zip(want).all(|(a, b)| a.to_bits() == b.to_bits()), "limit +{extra}: {s:?}");
        }
        assert_eq!(q2 == quality, statuses[2] == QuadoptStatus::Ok, "limit +{extra}");
        assert_eq!(created.is_null(), statuses[3] != QuadoptStatus::Ok, "limit +{extra}");
        // SAFETY: NULL or a handle created above.
        unsafe { quadopt_optimizer_free(created) };
    }
    // The sweep spans both outcomes (where the tunables above apply).
    println!("{refused} calls refused, {succeeded} succeeded");
    if cfg!(target_env = "gnu") {
        assert!(refused >= 4 && succeeded >= 4, "refused {refused}, succeeded {succeeded}");
    }
    // SAFETY: created above.
    unsafe { quadopt_optimizer_free(handle) };
}

/// `quadopt generate` with grids too large for the indices or for the memory: a one-line error
/// and exit status 1, not an abort or a panic.
#[test]
fn generate_refuses_grids_too_large_with_one_line() {
    use std::os::unix::process::CommandExt;
    let out = std::env::temp_dir().join(format!("quadopt-process-{}.obj", std::process::id()));
    let run = |args: &[&str], address_space: Option<libc::rlim_t>| {
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_quadopt"));
        cmd.arg("generate").arg("-o").arg(&out).args(args);
        if let Some(bytes) = address_space {
            // SAFETY: only an async-signal-safe system call between fork and exec.
            unsafe {
                cmd.pre_exec(move || {
                    let mut limit = libc::rlimit { rlim_cur: 0, rlim_max: 0 };
                    if libc::getrlimit(libc::RLIMIT_AS, &mut limit) != 0 {
                        return Err(std::io::Error::last_os_error());
                    }
                    limit.rlim_cur = bytes.min(limit.rlim_max);
                    if libc::setrlimit(libc::RLIMIT_AS, &limit) != 0 {
                        return Err(std::io::Error::last_os_error());
                    }
                    Ok(())
                });
            }
        }
        let o = cmd.output().unwrap();
        (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    for (args, limit, expected) in [
        (
            &["--quads", "100000000000"][..],
            None,
            "quadopt: error: invalid option grid size: a 352749 x 352749 grid",
        ),
        (&["--nx", "4294967295", "--ny", "4294967295"][..], None, "more than uint32 indices can number"),
        (
            &["--nx", "20000", "--ny", "20000"][..],
            Some(400 << 20),
            "quadopt: error: out of memory: cannot allocate",
        ),
    ] {
        let (code, stderr) = run(args, limit);
        assert_eq!(code, Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(expected) && stderr.lines().count() == 1, "{args:?}: {stderr}");
    }
    assert!(!out.exists(), "nothing is written on an error");
}

/// An absurd `RAYON_NUM_THREADS` under an address-space limit of 4 GiB: quadopt's pool is capped
/// at `quadopt::max_threads()` workers (not one thread per requested count until the address
/// space runs out, where a thread's signal stack failing to map aborts the process), and the
/// call gives the unlimited result.
#[test]
fn an_absurd_thread_count_gets_the_capped_pool() {
    const NAME: &str = "an_absurd_thread_count_gets_the_capped_pool";
    if !is_child(NAME) {
        return run_in_child_with(NAME, &[("RAYON_NUM_THREADS", "100000")]);
    }
    let (coords, quads) = jittered_grid(6);
    let baseline = thread_count();
    set_address_space_limit(4 << 30);
    let (s, c) = optimize(&coords, &quads);
    let message = last_error();
    set_address_space_limit(libc::RLIM_INFINITY);
    assert_eq!(s, QuadoptStatus::Ok, "{message}");
    let cap = quadopt::max_threads();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    assert_eq!(cap, (4 * cores).max(16));
    assert_eq!(thread_count(), baseline + cap);
    // The Rust API runs on the same pool, with the same result.
    assert_eq!(optimize_rust(&coords, &quads), c);
    assert_eq!(thread_count(), baseline + cap);
}

/// The attack's case: the CLI with `RAYON_NUM_THREADS=100000` under an address-space limit of
/// 4 GiB optimizes the mesh (with a capped pool) on every try, and never aborts.
#[test]
fn the_cli_with_an_absurd_thread_count_never_aborts() {
    use std::os::unix::process::CommandExt;
    let dir = std::env::temp_dir().join(format!("quadopt-threads-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (input, output) = (dir.join("in.obj"), dir.join("out.obj"));
    let (coords, quads) = jittered_grid(20);
    let mut obj = String::new();
    for p in coords.chunks(2) {
        obj += &format!("v {} {} 0\n", p[0], p[1]);
    }
    for q in quads.chunks(4) {
        obj += &format!("f {} {} {} {}\n", q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1);
    }
    std::fs::write(&input, obj).unwrap();
    // Limits a few pages apart: where the address space runs out varies from try to try.
    for k in 0..6u64 {
        let bytes: libc::rlim_t = (4 << 30) + k * 37 * 4096;
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_quadopt"));
        cmd.arg("optimize").arg(&input).arg("-o").arg(&output).env("RAYON_NUM_THREADS", "100000");
        // SAFETY: only async-signal-safe system calls between fork and exec.
        unsafe {
            cmd.pre_exec(move || {
                let mut limit = libc::rlimit { rlim_cur: 0, rlim_max: 0 };
                if libc::getrlimit(libc::RLIMIT_AS, &mut limit) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                limit.rlim_cur = bytes.min(limit.rlim_max);
                if libc::setrlimit(libc::RLIMIT_AS, &limit) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                Ok(())
            });
        }
        let o = cmd.output().unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "try {k}: {:?}\n{stderr}", o.status);
        assert!(output.exists(), "try {k}: nothing written");
        std::fs::remove_file(&output).unwrap();
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

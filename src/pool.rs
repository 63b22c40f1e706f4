//! quadopt's worker threads: one rayon pool per process, never rayon's global pool. The C ABI
//! and the Rust API (`Optimizer::run` called outside any rayon pool) run on it.
//!
//! - The pool has `RAYON_NUM_THREADS` workers, else one per core of the available
//!   parallelism, and never more than [`max_threads`] (four per core or 16, whichever is more): an absurd
//!   count (`RAYON_NUM_THREADS=100000`) gets the capped pool, not thousands of threads that
//!   exhaust the address space. Workers are started one at a time, each after the previous one
//!   is running, so every allocation a starting thread makes (its stack, and the signal stack
//!   the Rust runtime maps in the new thread, whose failure aborts the process) is done before
//!   the next thread asks for memory; a spawn that fails is an error, handled below.
//! - The pool is built on first use. A pool that cannot start (a thread limit, no memory for
//!   a stack) leaves no thread behind: the threads it did start are joined. The call then runs
//!   on a single worker joined before it returns, or fails with a status if even that one
//!   cannot start; a later call tries the full pool again.
//! - After `fork` the child has only the forking thread, so the parent's workers do not exist
//!   there: the pool is remembered with the id of the process that built it, and a process
//!   that finds another id builds its own (the parent's pool is left alone, never touched).
//! - The run itself executes on a worker (so that its parallel loops use this pool), while the
//!   progress callback stays on the calling thread: the worker hands each progress report to
//!   the caller and waits for the answer.
//! - Before any `fork` of the process (a `pthread_atfork` handler), the forking thread waits
//!   until every worker of the pool is idle: all have started, and none is still freeing the
//!   job it ran. So no worker is inside the allocator, holding one of its locks, when the child
//!   is made. glibc's malloc takes its own locks around `fork`, but allocators without fork
//!   handlers do not (ASan's before LLVM 18, which GCC 12 ships: a child forked right after its
//!   parent's first call hung in its own first allocation). A fork during a run waits for the
//!   run's workers to reach a parallel loop's join, at most about one sweep.
//!
//! Worker threads run only library code, so they are marked as inside the library for the
//! C ABI's quiet panic hook (`crate::quiet_threads`).

use rayon::{ThreadBuilder, ThreadPool, ThreadPoolBuilder};
use std::sync::atomic::{AtomicPtr, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, TryRecvError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// The pool of one process.
struct ProcessPool {
    /// The process that built it; in any other process (a forked child) its threads are gone.
    pid: u32,
    pool: ThreadPool,
}

/// The current process's pool, or NULL before first use. A published pool is never freed: a
/// reference handed out stays valid, and a forked child must not tear down its parent's.
static SHARED: AtomicPtr<ProcessPool> = AtomicPtr::new(std::ptr::null_mut());

/// Test hook: how many threads one pool may start (the next one fails as under a thread
/// limit), without touching process limits.
#[cfg(test)]
pub(crate) static THREAD_LIMIT: std::sync::atomic::AtomicUsize =
    std::sync::atomic::AtomicUsize::new(usize::MAX);

/// Worker threads per core of the available parallelism at most (see [`max_threads`]).
const THREADS_PER_CORE: usize = 4;

/// The cap's floor, so that a machine reporting one core can still run a few threads.
const MIN_THREAD_CAP: usize = 16;

/// The most worker threads quadopt starts in one pool: four per core of the available
/// parallelism ([`std::thread::available_parallelism`]), and at least 16. quadopt's own pool
/// takes `RAYON_NUM_THREADS` (else one per core) up to this cap; the CLI's `--threads` is
/// capped alike. More threads than this cannot make a run faster (the result is the same on
/// any number of threads), and thousands of them only exhaust the address space.
pub fn max_threads() -> usize {
    cores().saturating_mul(THREADS_PER_CORE).max(MIN_THREAD_CAP)
}

/// The available parallelism (1 when it cannot be determined).
fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The worker count of this process's pool: `RAYON_NUM_THREADS` when it is a positive number
/// (as rayon reads it), else the available parallelism; never more than [`max_threads`].
fn pool_threads() -> usize {
    let requested = std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|s| s.trim().parse::<usize>().ok())
        .filter(|&n| n > 0)
        .unwrap_or_else(cores);
    requested.min(max_threads())
}

/// The threads could not be started; the message says why.
#[derive(Debug)]
pub(crate) struct NoThreads(pub String);

/// Runs `job` on a worker thread while the calling thread answers the job's progress reports
/// with `on_progress`, and returns the job's result. A panic in `job` resumes on the calling
/// thread (where the C boundary catches it, or the Rust caller sees it).
///
/// `job` receives the function it calls with each report; that function returns
/// `on_progress`'s answer (false also once the caller has stopped listening).
pub(crate) fn run_with_progress<P: Send, R: Send>(
    job: impl FnOnce(&mut dyn FnMut(P) -> bool) -> R + Send,
    mut on_progress: impl FnMut(P) -> bool,
) -> Result<R, NoThreads> {
    with_pool(move |pool| {
        let mut result = None;
        pool.in_place_scope(|scope| {
            let (report, reports) = mpsc::channel::<P>();
            let (answer, answers) = mpsc::channel::<bool>();
            let slot = &mut result;
            scope.spawn(move |_| {
                let mut ask = |p: P| report.send(p).is_ok() && wait_for_answer(&answers);
                *slot = Some(job(&mut ask));
                // `report` is dropped here (or while unwinding): the caller's loop ends.
            });
            // If `on_progress` unwinds, `answer` is dropped and the waiting job sees false.
            while let Some(p) = receive(&reports) {
                if answer.send(on_progress(p)).is_err() {
                    break;
                }
            }
        });
        // Had the job panicked, the scope would have re-raised it: it completed and filled the slot.
        result.expect("the job completed")
    })
}

/// Polls `rx` for a moment: the other side (a short callback, a sweep of a small mesh) usually
/// answers within microseconds, and waking a sleeping thread costs more than that.
fn poll_briefly<T>(rx: &Receiver<T>) -> Result<T, TryRecvError> {
    let until = Instant::now() + Duration::from_micros(50);
    loop {
        match rx.try_recv() {
            Err(TryRecvError::Empty) if Instant::now() < until => std::thread::yield_now(),
            other => return other,
        }
    }
}

/// The next message, or `None` once the sender is gone.
fn receive<T>(rx: &Receiver<T>) -> Option<T> {
    match poll_briefly(rx) {
        Ok(message) => Some(message),
        Err(TryRecvError::Disconnected) => None,
        Err(TryRecvError::Empty) => rx.recv().ok(),
    }
}

/// Waits for the caller's answer to a progress report (false once the caller is gone). A
/// callback that calls quadopt again needs a worker while this one waits, so after a
/// millisecond without an answer this worker runs pending pool work (a pool of one thread
/// would otherwise deadlock).
fn wait_for_answer(answers: &Receiver<bool>) -> bool {
    match poll_briefly(answers) {
        Ok(go) => return go,
        Err(TryRecvError::Disconnected) => return false,
        Err(TryRecvError::Empty) => {}
    }
    loop {
        match answers.recv_timeout(Duration::from_millis(1)) {
            Ok(go) => return go,
            Err(RecvTimeoutError::Disconnected) => return false,
            Err(RecvTimeoutError::Timeout) => while rayon::yield_now() == Some(rayon::Yield::Executed) {},
        }
    }
}

/// Runs `f` with this process's pool, or with a single worker when the pool cannot start.
fn with_pool<R>(f: impl FnOnce(&ThreadPool) -> R) -> Result<R, NoThreads> {
    if let Some(pool) = shared() {
        return Ok(f(pool));
    }
    let (pool, threads) =
        build(Some(1)).map_err(|e| NoThreads(format!("cannot start a worker thread: {e}")))?;
    // Stopped and joined when `f` returns or unwinds, so nothing outlives the call.
    let single = Joined { pool: Some(pool), threads };
    Ok(f(single.pool.as_ref().expect("set above")))
}

/// A pool whose threads are joined when it is dropped.
struct Joined {
    pool: Option<ThreadPool>,
    threads: Vec<JoinHandle<()>>,
}

impl Drop for Joined {
    fn drop(&mut self) {
        // Dropping the pool tells its workers to stop once they are out of work.
        drop(self.pool.take());
        for handle in self.threads.drain(..) {
            let _ = handle.join();
        }
    }
}

/// This process's pool, built on first use (and again in a forked child); `None` when its
/// threads cannot all start.
fn shared() -> Option<&'static ThreadPool> {
    let pid = std::process::id();
    loop {
        let current = SHARED.load(Ordering::Acquire);
        // SAFETY: non-NULL values of SHARED come from Box::into_raw below and are never freed.
        if let Some(p) = unsafe { current.as_ref() } {
            if p.pid == pid {
                return Some(&p.pool);
            }
        }
        // First use, or a forked child holding its parent's pool: that one is left as it is
        // (its memory is this process's copy, its threads are not here). The new pool owns
        // its workers, so their handles are let go.
        let (pool, _detached) = build(None).ok()?;
        before_fork::install();
        let fresh = Box::into_raw(Box::new(ProcessPool { pid, pool }));
        match SHARED.compare_exchange(current, fresh, Ordering::AcqRel, Ordering::Acquire) {
            // SAFETY: just published from Box::into_raw; never freed.
            Ok(_) => return Some(unsafe { &(*fresh).pool }),
            // Another thread published a pool first: use that one, stop ours.
            // SAFETY: `fresh` was never published, so this is its only owner.
            Err(_) => drop(unsafe { Box::from_raw(fresh) }),
        }
    }
}

/// Builds a pool of `threads` workers (by default [`pool_threads`]: `RAYON_NUM_THREADS`, else
/// the available parallelism, capped at [`max_threads`]) and returns it with the workers'
/// handles. Each worker is started only once the previous one runs (see the module docs).
/// When a thread cannot start, the threads already started are joined before the error is
/// returned.
fn build(threads: Option<usize>) -> Result<(ThreadPool, Vec<JoinHandle<()>>), String> {
    let mut started = Vec::new();
    let built = ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or_else(pool_threads).clamp(1, max_threads()))
        .thread_name(|i| format!("quadopt-{i}"))
        .spawn_handler(|thread| {
            spawn_allowed(thread.index())?;
            let mut b = std::thread::Builder::new();
            if let Some(name) = thread.name() {
                b = b.name(name.to_owned());
            }
            if let Some(size) = thread.stack_size() {
                b = b.stack_size(size);
            }
            let (running, is_running) = mpsc::sync_channel::<()>(1);
            started.push(b.spawn(move || run_worker(thread, running))?);
            // The new thread has its stacks once it runs: wait for that before the next spawn.
            let _ = is_running.recv();
            Ok(())
        })
        .build();
    match built {
        Ok(pool) => Ok((pool, started)),
        Err(e) => {
            // rayon has told the started workers to stop; wait until they have.
            for handle in started {
                let _ = handle.join();
            }
            Err(e.to_string())
        }
    }
}

/// The `fork` handler that leaves the pool idle in the parent before the child is made.
#[cfg(unix)]
mod before_fork {
    use super::{Ordering, SHARED};
    use std::sync::Once;

    /// Registers the handler once per process (a forked child inherits it).
    pub(super) fn install() {
        static INSTALLED: Once = Once::new();
        // SAFETY: registers a function with C linkage that never unwinds (see `quiesce`).
        INSTALLED.call_once(|| unsafe {
            libc::pthread_atfork(Some(quiesce), None, None);
        });
    }

    /// Waits until every worker of this process's pool has run a trivial job, so each has
    /// finished what it was doing before and is idle. `broadcast` keeps its jobs on the caller's
    /// side: the workers free nothing after the caller wakes.
    extern "C" fn quiesce() {
        let _ = std::panic::catch_unwind(|| {
            // SAFETY: non-NULL values of SHARED are never freed (see `shared`).
            if let Some(p) = unsafe { SHARED.load(Ordering::Acquire).as_ref() } {
                // A parent's pool inherited by a child has no threads here: leave it alone.
                if p.pid == std::process::id() {
                    p.pool.broadcast(|_| ());
                }
            }
        });
    }
}

#[cfg(not(unix))]
mod before_fork {
    /// No `fork` here.
    pub(super) fn install() {}
}

/// The body of every worker thread; `running` tells the spawning thread that it has started.
fn run_worker(thread: ThreadBuilder, running: mpsc::SyncSender<()>) {
    crate::quiet_threads::mark_worker_thread();
    let _ = running.send(());
    drop(running);
    thread.run();
}

#[cfg(test)]
fn spawn_allowed(index: usize) -> std::io::Result<()> {
    if index < THREAD_LIMIT.load(Ordering::SeqCst) {
        return Ok(());
    }
    Err(std::io::Error::new(std::io::ErrorKind::WouldBlock, "thread limit (test hook)"))
}

#[cfg(not(test))]
fn spawn_allowed(_index: usize) -> std::io::Result<()> {
    Ok(())
}

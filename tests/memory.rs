//! Peak memory of the C ABI's calls, measured by a counting allocator.
use quadopt::ffi::*;
use quadopt::synthetic::Synthetic;
use std::alloc::{GlobalAlloc, Layout, System};
use std::ptr::{null, null_mut};
use std::sync::atomic::{AtomicUsize, Ordering::SeqCst};

struct Counting;
static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator, only counting.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(l) };
        if !p.is_null() {
            let now = CURRENT.fetch_add(l.size(), SeqCst) + l.size();
            PEAK.fetch_max(now, SeqCst);
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) };
        CURRENT.fetch_sub(l.size(), SeqCst);
    }
}

#[global_allocator]
static A: Counting = Counting;

fn measure(name: &str, coords: &[f64], quads: &[u32], boundary: u32) {
    use quadopt::{Optimizer, Options, QuadMesh, DVec2, BoundaryMode, Method};
    let pts: Vec<DVec2> = coords.chunks(2).map(|c| DVec2::new(c[0], c[1])).collect();
    let qs: Vec<[u32;4]> = quads.chunks(4).map(|q| [q[0],q[1],q[2],q[3]]).collect();
    let mut mesh = QuadMesh::new(pts, qs, None).unwrap();
    let base0 = CURRENT.load(SeqCst);
    PEAK.store(base0, SeqCst);
    let opt = Optimizer::new(&mesh);
    let topo_peak = PEAK.load(SeqCst) - base0;
    let topo_held = CURRENT.load(SeqCst) - base0;
    let b: usize = opt.topology().boundary_loops().map(|l| l.len()).sum();
    let (v, q) = (coords.len() / 2, quads.len() / 4);
    let mut worst = 0;
    for m in Method::ALL {
      let o = Options { boundary: [BoundaryMode::Auto, BoundaryMode::Fixed, BoundaryMode::Slide, BoundaryMode::Snap][boundary as usize], method: m, max_iterations: 30, ..Options::default() };
      let mut mm = mesh.clone();
      let base = CURRENT.load(SeqCst);
      PEAK.store(base, SeqCst);
      opt.run(&mut mm, &o, None).unwrap();
      worst = worst.max(PEAK.load(SeqCst) - base);
    }
    let _ = &mut mesh;
    let peak = worst;
    println!("{name:22} b{boundary} V {v:7} Q {q:7} B {b:6} topo {:6.1}/{:6.1} run {peak:10} /V {:6.1} /Q {:6.1} /B {:6.1} (run-64V)/B {:6.1}", topo_peak as f64/ v as f64, topo_held as f64 / v as f64, peak as f64 / v as f64, peak as f64 / q as f64, peak as f64 / b as f64, (peak as f64 - 64.0*v as f64)/b as f64);
}

fn flat(m: &quadopt::QuadMesh) -> (Vec<f64>, Vec<u32>) {
    (m.points().iter().flat_map(|p| [p.x, p.y]).collect(), m.quads().iter().flatten().copied().collect())
}

#[test]
fn peaks() {
    for n in [100u32, 300] {
        for jitter in [0.3, 0.45] {
            let m = Synthetic { nx: n, ny: n, jitter, ..Synthetic::default() }.generate();
            let (c, q) = flat(&m);
            for b in 0..4 { measure(&format!("synthetic {n} j{jitter}"), &c, &q, b); }
        }
        let m = Synthetic { nx: n * 50, ny: 1, holes: 0, jitter: 0.0, ..Synthetic::default() }.generate();
        let (c, q) = flat(&m);
        for b in 0..4 { measure(&format!("strip {n}"), &c, &q, b); }
        let m = Synthetic { nx: n , ny: n, holes: 400, hole_size: 0.5, jitter: 0.3, ..Synthetic::default() }.generate();
        let (c, q) = flat(&m);
        for b in 0..4 { measure(&format!("holes {n}"), &c, &q, b); }
    }
}

"""What the Python call adds to a run: ``quadopt.optimize`` on a 100,000-quad mesh against the
Rust run alone, what a Rust program does with the same mesh in memory (``Mesh::with_faces`` from
owned vectors, ``Optimizer::new``, ``Optimizer::run``, timed inside the extension:
``quadopt._quadopt._time_rust_run``), interleaved, medians.

The Python call's extra work: reading each input array once into the library's vectors (a
float64 array as it is, any other dtype converted on the way), the planarity rule, the
write-back of the moved vertices into the one new output array, each face's quality, and the
report as a dict. A benchmark, not a test: it prints the figures.

    python python/benchmarks/overhead.py [--quads N] [--repeat R] [--effort E]
"""

import argparse
import statistics
import time

import numpy as np

import quadopt
from quadopt import _quadopt


def jittered_grid(quads: int, jitter: float, seed: int):
    """A square grid of about ``quads`` unit quads, interior vertices moved by up to ``jitter``."""
    n = int(round(quads ** 0.5))
    rng = np.random.default_rng(seed)
    ys, xs = np.mgrid[0:n + 1, 0:n + 1].astype(np.float64)
    points = np.column_stack([xs.ravel(), ys.ravel()])
    interior = (points[:, 0] > 0) & (points[:, 0] < n) & (points[:, 1] > 0) & (points[:, 1] < n)
    points[interior] += rng.uniform(-jitter, jitter, size=(interior.sum(), 2))
    j, i = np.mgrid[0:n, 0:n]
    a = (j * (n + 1) + i).ravel()
    faces = np.column_stack([a, a + 1, a + n + 2, a + n + 1]).astype(np.int64)
    return points, faces


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quads", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--effort", default="balanced")
    parser.add_argument("--jitter", type=float, default=0.3)
    args = parser.parse_args()

    points, faces = jittered_grid(args.quads, args.jitter, seed=1)
    print(f"mesh: {len(points)} vertices, {len(faces)} quads; effort {args.effort}; {args.repeat} runs each")
    # The same values in other layouts: strided float64 points (read as they are, no copy
    # first) and int32 faces (converted while read).
    wide = np.zeros((len(points), 5))
    wide[:, 1:3] = points
    variants = {
        "float64 points, int64 faces": (points, faces),
        "strided float64 points, int32 faces": (wide[:, 1:3], faces.astype(np.int32)),
    }
    quadopt.optimize(points, faces, effort=args.effort)  # warm up: the worker pool, the allocator
    rust, python = [], {name: [] for name in variants}
    # Within each Python call, its own Rust work (the mesh built, the optimizer built and run) as
    # the extension timed it: the call's remainder is what the Python layer adds, free of the
    # drift between one run and the next.
    extra = {name: [] for name in variants}
    report = None
    for _ in range(args.repeat):
        rust += _quadopt._time_rust_run(points, faces, args.effort, 1)
        for name, (p, f) in variants.items():
            start = time.perf_counter()
            r = quadopt.optimize(p, f, effort=args.effort)
            python[name].append(time.perf_counter() - start)
            extra[name].append(python[name][-1] - _quadopt._last_run_seconds())
            report = report or r.report
    base = statistics.median(rust)
    print(f"Rust run alone (Mesh::with_faces + Optimizer::new + run): median {base:.4f} s  (min {min(rust):.4f}, max {max(rust):.4f})")
    for name, times in python.items():
        t = statistics.median(times)
        # Each Python call against the Rust run just before it: the machine's drift cancels.
        paired = statistics.median(p - r for p, r in zip(times, rust))
        print(f"quadopt.optimize, {name}: median {t:.4f} s  (min {min(times):.4f}, max {max(times):.4f}); "
              f"adds {t - base:+.4f} s = {100 * (t - base) / base:+.2f} % (paired: {paired:+.4f} s = "
              f"{100 * paired / base:+.2f} %)")
        e = statistics.median(extra[name])
        print(f"    the same calls less their own Rust work: {e:.4f} s = {100 * e / base:.2f} % of the run "
              f"(max {max(extra[name]):.4f} s)")
    # The work of the call that does not depend on the run, alone: reading the arrays, the
    # planarity rule, the mesh's validation, each face's quality and a summary.
    measure = []
    for _ in range(args.repeat):
        start = time.perf_counter()
        quadopt.quality(points, faces)
        measure.append(time.perf_counter() - start)
    print(f"quadopt.quality (arrays in, validation, per-face values, summary): median "
          f"{statistics.median(measure):.4f} s")
    print(f"the run: {report['iterations']} sweeps, {report['moved']} moved, "
          f"min {report['input']['min']:.4f} -> {report['output']['min']:.4f}, "
          f"{report['input']['inverted']} -> {report['output']['inverted']} inverted")


if __name__ == "__main__":
    main()

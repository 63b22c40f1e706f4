#!/usr/bin/env python3
"""Peak memory of `quadopt optimize` on synthetic meshes (the memory target of the speed work:
under 200 MB of resident memory on 1M quads).

Usage:  cargo build --release
        python3 tools/bench_memory.py                      # 100k and 1M quads
        python3 tools/bench_memory.py --quads 10000,100000 --repeat 5

For each size it writes `quadopt generate --quads N` (a grid with four circular holes and
jittered interior vertices, the mesh of `cargo bench --bench optimize`) to a temporary VTK file,
runs `quadopt optimize` with the default options on it `--repeat` times and prints the median
peak resident set size of the process (the kernel's ru_maxrss of that process alone, read with
wait4 by tools/peak_rss.py's launcher; its floor is about 5 MB), in MB and in bytes per vertex, with the run's own time. The figure is the whole
process: the file as read, its 2D copy, the library's working set (which `cargo bench --bench
optimize` prints per vertex) and the output as written. Needs Linux or macOS (wait4).
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peak_rss import launch  # noqa: E402  (a child's own peak memory)


def run_once(cmd):
    """Runs `cmd` and returns (peak RSS in bytes of that process alone, stdout), through
    tools/peak_rss.py's launcher: a direct child's ru_maxrss would start at this script's own
    peak (the 10k figure read 14.9 MB, this script's, where quadopt peaks at 7.5 MB)."""
    out, peak, _ = launch(cmd)
    # ru_maxrss is in KiB on Linux, in bytes on macOS.
    scale = 1 if sys.platform == "darwin" else 1024
    return peak * scale, out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quads", default="100000,1000000", help="comma-separated quad counts (default 100000,1000000)")
    ap.add_argument("--repeat", type=int, default=3, help="runs per size (default 3); the median is printed")
    ap.add_argument("--quadopt", default=os.path.join(ROOT, "target", "release", "quadopt"),
                    help="the quadopt binary (default target/release/quadopt)")
    args = ap.parse_args()
    if not os.path.exists(args.quadopt):
        sys.exit(f"{args.quadopt} not found: run `cargo build --release` first")
    print(f"{'quads':>9} {'vertices':>9} {'peak RSS MB':>12} {'B/vertex':>9} {'run s':>7}")
    with tempfile.TemporaryDirectory() as tmp:
        for n in (int(s) for s in args.quads.split(",")):
            mesh = os.path.join(tmp, f"synthetic_{n}.vtk")
            subprocess.run([args.quadopt, "generate", "--quads", str(n), "-o", mesh], check=True,
                           stdout=subprocess.DEVNULL)
            peaks, seconds, vertices = [], [], 0
            for _ in range(args.repeat):
                rss, out = run_once([args.quadopt, "optimize", mesh, "-o", os.path.join(tmp, "out.vtk"), "--json"])
                report = json.loads(out)
                peaks.append(rss)
                seconds.append(report["seconds"])
                vertices = report["vertices"]
            rss = statistics.median(peaks)
            print(f"{n:>9} {vertices:>9} {rss / 2**20:>12.1f} {rss / vertices:>9.1f} {statistics.median(seconds):>7.2f}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""How quadopt's time and memory grow with the mesh: each preset from 10k to 10M quads, planar and on a sphere.

Usage:  cargo build --release --bin quadopt
        VENV/bin/python tools/bench_scale.py                     # 10k ... 10M plane, 10k ... 1M sphere
        VENV/bin/python tools/bench_scale.py --sizes 10k,30k,100k,300k,1M --surface-sizes 10k,100k
        VENV/bin/python tools/bench_scale.py --sizes 10k --repeat 1 --presets fast --surface-sizes 10k \
            --plot target/bench-scale/smoke.svg    # a smoke test, seconds (not over the docs' figure)
        VENV/bin/python tools/bench_scale.py --from-json target/bench-scale/bench_scale.json   # table and plot again
Needs numpy and matplotlib (VENV: python3 -m venv VENV && VENV/bin/pip install numpy matplotlib)
and Linux (fork, wait4, /proc/meminfo). Run it niced on a shared machine (`nice -n 10`). The
full default run needs about 2 GB of memory at 10M planar quads and 1.5 GB on the 1M sphere,
and 0.7 GB of disk per 10M-quad mesh (its input and output at a time).

Meshes (written to --out DIR, default target/bench-scale; those above 1M quads deleted after
their runs unless --keep):
  * plane NAME: `quadopt generate --quads N -o OUT/plane_NAME.vtk`, the synthetic grid with four
    circular holes and jittered interior vertices of `cargo bench --bench optimize` and
    tools/bench_memory.py (its own few inverted quads included); --sizes, default
    10k,30k,100k,300k,1M,3M,10M.
  * sphere NAME: a cube-sphere made here with numpy, each face of the cube [-1, 1]^3 cut into
    n x n squares (n = round(sqrt(N / 6)), 6 n^2 quads), every vertex projected onto the unit
    sphere, then moved along the sphere (along a great circle, in a random tangent direction) by
    a random distance up to a fifth of its shortest edge (uniform over that disk; seed --seed,
    default 1); a vertex of a face that this folds (a corner whose cross product does not point
    outwards) gets half its move until no face is folded. All of its vertices move: the sphere
    has no boundary. Written as ASCII legacy VTK, OUT/sphere_NAME.vtk; quadopt finds it curved
    by itself (the script checks the report's "surface": true); --surface-sizes, default
    10k,30k,100k,300k,1M.
Both, and every output, in ASCII legacy VTK: of quadopt's formats the one read with the
smallest peak (binary VTU reads a little faster, 0.1-0.3 s per 1M quads, but peaks about 45 MB
higher per 1M quads, and `quadopt generate` writes no binary VTU).

Runs: per mesh and preset (--presets, default fast,balanced,best), --repeat (default 3) fresh
processes of `quadopt optimize IN -o OUT --json --effort PRESET` with the default options
otherwise (all cores, boundary auto). Per run: the report's "seconds" (the optimizer's own
timer, no file IO; on the sphere also its "setup_seconds", the features, patches and
reference trees it builds first, which tools/bench_surfaces.py adds to the time), the max-min
stage's seconds (in "seconds"; 0 when it did not run), "iterations"
(sweeps), the output's min / avg (the signed scaled Jacobian, the measure quadopt ranks by; on
the sphere also Verdict's), the process's wall time (fork to exit: reading, set-up, optimizing,
writing) and its peak resident set size (wait4's ru_maxrss of that process alone). Each run is
started by a small launcher (a fresh `python -I -S`, tools/peak_rss.py) that forks quadopt and
waits for it with wait4: on Linux a child's ru_maxrss starts at its parent's high-water mark
(kept over exec), so a child of this script would never read below this script's own peak
(36 MB with numpy loaded, hundreds after a large sphere). The launcher's is about 5 MB, the
floor of every reading ("rss_floor_kib": the peak of `quadopt --version`); a row within 10% of
it is marked. Rows are medians over the repeats. Progress lines go to stderr, one per run.

A size is skipped, with a note, when its estimated peak (the largest bytes per quad measured
so far for that kind of mesh, at least 300 on the plane and 2,000 on the sphere, times 1.5)
exceeds MemAvailable of /proc/meminfo, or its mesh and output would not fit on the disk of
--out.

Output:
  * stdout: a Markdown table, one row per mesh and preset: mesh, quads, preset, seconds (median
    of "seconds"), set-up s (sphere), wall s, sweeps, peak MB (MiB of ru_maxrss; "≤" where it
    is the launcher's floor), µs/quad (seconds per quad), µs/quad/sweep (seconds less the
    max-min stage's, per quad and sweep: the cost of a sweep, which the stopping rule's sweep
    count does not move), min / avg of the output.
  * --json PATH (default target/bench-scale/bench_scale.json): {"quadopt": binary, "version",
    "host": {"cpus", "mem_total_mb"}, "rss_floor_kib", "repeat", "presets", "sizes",
    "surface_sizes", "seed",
    "rows": [one per mesh and preset, the medians, with "times", "walls" and "peaks_kib" of every
    run], "runs": [every run's report values], "skipped": [{"mesh", "reason"}]}.
  * --plot PATH (default docs/images/scale.svg; .png works too): a log-log figure, left the
    optimizer's seconds against quads (one solid line per preset on the plane, one dashed per
    preset on the sphere, whose time is seconds + setup_seconds), right the peak resident MB
    against quads; faint grey lines of slope 1 in both: a curve parallel to them grows linearly.
--from-json PATH prints the table and draws the plot of an earlier --json file instead of
running.
"""

import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)

from bench_peers import note, parse_size, size_label  # noqa: E402  ("10k", "1m", ...)
from peak_rss import launch  # noqa: E402  (a child's own peak memory)

PRESETS = ["fast", "balanced", "best"]
SIZES = "10k,30k,100k,300k,1m,3m,10m"
SURFACE_SIZES = "10k,30k,100k,300k,1m"
# Peak resident bytes per quad assumed before any run of that kind (measured at 1M quads:
# plane 213, sphere 1,550), and the margin on the estimate.
MIN_BYTES_PER_QUAD = {"plane": 300, "sphere": 2000}
MEM_MARGIN = 1.5
# Bytes of ASCII VTK per quad (input or output; about 72 on the plane).
VTK_BYTES_PER_QUAD = 100
# Meshes above this many quads are deleted after their runs (unless --keep).
KEEP_MAX = 1000000
# The largest move of a sphere vertex, in its shortest edge.
SPHERE_JITTER = 0.2


# --------------------------------------------------------------------------------------------
# The cube-sphere
# --------------------------------------------------------------------------------------------


def cube_sphere(quads_wanted):
    """A cube-sphere of about quads_wanted quads: (points n x 3 on the unit sphere, quads m x 4
    counter-clockwise seen from outside)."""
    n = max(1, round(math.sqrt(quads_wanted / 6)))
    u, v = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
    u, v = u.ravel(), v.ravel()
    lattice, quads = [], []
    # The corners of the n x n squares of one face, as indices into its (n+1)^2 grid points.
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    base = (i * (n + 1) + j).ravel()
    square = np.stack([base, base + (n + 1), base + (n + 1) + 1, base + 1], axis=1)
    for axis in range(3):
        b, c = (axis + 1) % 3, (axis + 2) % 3  # e_b x e_c = e_axis
        for side in (0, n):
            ijk = np.empty((len(u), 3), dtype=np.int64)
            ijk[:, axis], ijk[:, b], ijk[:, c] = side, u, v
            offset = len(u) * len(lattice)
            lattice.append(ijk)
            # (u, v) -> (u+1, v) -> (u+1, v+1) is counter-clockwise about +e_axis.
            quads.append(offset + (square if side == n else square[:, ::-1]))
    lattice, quads = np.concatenate(lattice), np.concatenate(quads)
    key = (lattice[:, 0] * (n + 1) + lattice[:, 1]) * (n + 1) + lattice[:, 2]
    key, first, inverse = np.unique(key, return_index=True, return_inverse=True)
    points = -1.0 + 2.0 * lattice[first] / n
    points /= np.linalg.norm(points, axis=1)[:, None]
    return points, inverse.ravel()[quads]


def folded_faces(points, quads):
    """Whether each quad has a corner whose cross product (next - v) x (prev - v) does not point
    away from the sphere's centre (the outward normal at v)."""
    bad = np.zeros(len(quads), dtype=bool)
    for k in range(4):
        v, nxt, prv = (points[quads[:, (k + d) % 4]] for d in (0, 1, 3))
        bad |= np.einsum("ij,ij->i", np.cross(nxt - v, prv - v), v) <= 0
    return bad


def perturb_sphere(points, quads, seed):
    """Every vertex moved along the unit sphere, in a random tangent direction, by a random
    distance up to SPHERE_JITTER of its shortest edge (uniform over that disk); the vertices
    of folded faces get half their move until no face is folded."""
    rng = np.random.default_rng(seed)
    shortest = np.full(len(points), np.inf)
    for k in range(4):
        a, b = quads[:, k], quads[:, (k + 1) % 4]
        length = np.linalg.norm(points[a] - points[b], axis=1)
        np.minimum.at(shortest, a, length)
        np.minimum.at(shortest, b, length)
    g = rng.standard_normal(points.shape)
    tangent = g - np.einsum("ij,ij->i", g, points)[:, None] * points
    tangent /= np.linalg.norm(tangent, axis=1)[:, None]
    angle = SPHERE_JITTER * shortest * np.sqrt(rng.random(len(points)))  # arc length on the unit sphere
    for _ in range(60):
        moved = np.cos(angle)[:, None] * points + np.sin(angle)[:, None] * tangent
        bad = folded_faces(moved, quads)
        if not bad.any():
            return moved
        angle[np.unique(quads[bad])] *= 0.5
    raise RuntimeError("the sphere's perturbation folds faces however small")


def write_vtk(path, points, quads, title):
    """ASCII legacy VTK UNSTRUCTURED_GRID of quads (cell type 9)."""
    with open(path, "w") as f:
        f.write(f"# vtk DataFile Version 3.0\n{title}\nASCII\nDATASET UNSTRUCTURED_GRID\n")
        f.write(f"POINTS {len(points)} double\n")
        np.savetxt(f, points, fmt="%.17g")
        f.write(f"CELLS {len(quads)} {5 * len(quads)}\n")
        np.savetxt(f, np.hstack([np.full((len(quads), 1), 4), quads]), fmt="%d")
        f.write(f"CELL_TYPES {len(quads)}\n")
        f.write("9\n" * len(quads))


# --------------------------------------------------------------------------------------------
# Runs
# --------------------------------------------------------------------------------------------


def mem_available():
    """MemAvailable of /proc/meminfo in bytes (None where there is none)."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return None


def too_big(kind, n, out_dir, bytes_per_quad):
    """Why a mesh of n quads would not fit (None if it fits): its estimated peak against free
    memory, its mesh and output against free disk."""
    need = MEM_MARGIN * n * max(MIN_BYTES_PER_QUAD[kind], bytes_per_quad.get(kind, 0))
    avail = mem_available()
    if avail is not None and need > avail:
        return f"needs about {need / 2**30:.1f} GiB of memory, {avail / 2**30:.1f} GiB available"
    disk = shutil.disk_usage(out_dir).free
    if 2 * VTK_BYTES_PER_QUAD * n > disk:
        return f"needs about {2 * VTK_BYTES_PER_QUAD * n / 2**30:.1f} GiB of disk in {out_dir}, {disk / 2**30:.1f} GiB free"
    return None


def make_mesh(args, kind, n, path):
    """Writes the mesh of kind and about n quads to path."""
    if kind == "plane":
        subprocess.run([args.quadopt, "generate", "--quads", str(n), "-o", path], check=True, stdout=subprocess.DEVNULL)
    else:
        points, quads = cube_sphere(n)
        points = perturb_sphere(points, quads, args.seed)
        write_vtk(path, points, quads, f"cube-sphere, {len(quads)} quads, seed {args.seed} (tools/bench_scale.py)")


def run_quadopt(args, kind, mesh, in_path, out_path, preset):
    """One fresh `quadopt optimize` process: its report's values, wall time and peak RSS."""
    cmd = [args.quadopt, "optimize", in_path, "-o", out_path, "--json", "--effort", preset]
    out, peak_kib, wall = launch(cmd)
    j = json.loads(out)
    if bool(j.get("surface")) != (kind == "sphere"):
        raise RuntimeError(f"{mesh}: the report says surface={j.get('surface')}")
    if j.get("effort") != preset:
        note(f"{mesh}: asked for --effort {preset}, the report says {j.get('effort')}")
    run = dict(mesh=mesh, kind=kind, preset=preset, quads=j["quads"], vertices=j["vertices"],
               seconds=j["seconds"], setup_seconds=j.get("setup_seconds", 0.0),
               maxmin_seconds=(j.get("max_min") or {}).get("seconds", 0.0), iterations=j["iterations"],
               wall=wall, peak_kib=peak_kib, input=j["input"], output=j["output"])
    if kind == "sphere":
        run["output_verdict"] = j["output_verdict"]
    return run


def summarize(runs, floor_kib):
    """The row of one mesh and preset: medians of the runs (peak_at_floor: the peak is within
    10% of the launcher's own, so quadopt's may be lower)."""
    r = runs[0]
    secs = [x["seconds"] + x["setup_seconds"] for x in runs]
    row = dict(mesh=r["mesh"], kind=r["kind"], preset=r["preset"], quads=r["quads"], vertices=r["vertices"],
               seconds=statistics.median(x["seconds"] for x in runs),
               setup_seconds=statistics.median(x["setup_seconds"] for x in runs),
               maxmin_seconds=statistics.median(x["maxmin_seconds"] for x in runs),
               total_seconds=statistics.median(secs),
               wall=statistics.median(x["wall"] for x in runs),
               iterations=statistics.median(x["iterations"] for x in runs),
               peak_mb=statistics.median(x["peak_kib"] for x in runs) / 1024,
               input=r["input"], output=r["output"],
               times=[x["seconds"] for x in runs], walls=[x["wall"] for x in runs],
               peaks_kib=[x["peak_kib"] for x in runs])
    row["us_per_quad"] = row["seconds"] / row["quads"] * 1e6
    row["us_per_quad_sweep"] = (row["seconds"] - row["maxmin_seconds"]) / row["quads"] / max(row["iterations"], 1) * 1e6
    row["peak_at_floor"] = row["peak_mb"] * 1024 <= 1.1 * floor_kib
    if "output_verdict" in r:
        row["output_verdict"] = r["output_verdict"]
    if len({(x["output"]["min"], x["output"]["avg"], x["iterations"]) for x in runs}) > 1:
        note(f"{r['mesh']} {r['preset']}: the repeats gave different results")
    return row


def bench(args):
    """Runs every mesh and preset; returns the JSON record."""
    os.makedirs(args.out, exist_ok=True)
    presets = [p.strip() for p in args.presets.split(",") if p.strip()]
    plan = [("plane", n) for n in sizes(args.sizes)]
    if not args.skip_surface:
        plan += [("sphere", n) for n in sizes(args.surface_sizes)]
    rows, all_runs, skipped, bytes_per_quad = [], [], [], {}
    version, floor_kib, _ = launch([args.quadopt, "--version"])
    total, done, start = len(plan) * len(presets) * args.repeat, 0, time.perf_counter()
    for kind, n in plan:
        mesh = f"{kind} {size_label(n)}"
        why = too_big(kind, n, args.out, bytes_per_quad)
        if why:
            note(f"{mesh}: skipped, {why}")
            skipped.append(dict(mesh=mesh, reason=why))
            done += len(presets) * args.repeat
            continue
        name = f"{kind}_{size_label(n)}"
        in_path, out_path = os.path.join(args.out, name + ".vtk"), os.path.join(args.out, name + "_out.vtk")
        t0 = time.perf_counter()
        make_mesh(args, kind, n, in_path)
        note(f"{mesh}: mesh written in {time.perf_counter() - t0:.1f} s ({in_path})")
        try:
            for preset in presets:
                runs = []
                for k in range(args.repeat):
                    try:
                        r = run_quadopt(args, kind, mesh, in_path, out_path, preset)
                    except RuntimeError as e:
                        note(f"{mesh} {preset}: failed, {e}")
                        skipped.append(dict(mesh=mesh, preset=preset, reason=f"failed: {e}"))
                        done += args.repeat - k
                        runs = []
                        break
                    runs.append(r)
                    done += 1
                    bytes_per_quad[kind] = max(bytes_per_quad.get(kind, 0), r["peak_kib"] * 1024 / r["quads"])
                    setup = f" + {r['setup_seconds']:.2f} s set-up" if kind == "sphere" else ""
                    note(f"[{done}/{total}, {time.perf_counter() - start:.0f} s] {mesh} ({r['quads']} quads) {preset} "
                         f"{k + 1}/{args.repeat}: {r['seconds']:.2f} s{setup}, {r['iterations']} sweeps, "
                         f"wall {r['wall']:.2f} s, peak {r['peak_kib'] / 1024:.0f} MB, "
                         f"min/avg {r['output']['min']:.3f}/{r['output']['avg']:.3f}")
                if runs:
                    all_runs += runs
                    rows.append(summarize(runs, floor_kib))
        finally:
            if n > KEEP_MAX and not args.keep:
                for p in (in_path, out_path):
                    if os.path.exists(p):
                        os.remove(p)
    host = dict(cpus=os.cpu_count(), mem_total_mb=mem_total_mb())
    return dict(quadopt=args.quadopt, version=version.decode().strip(), host=host, rss_floor_kib=floor_kib,
                repeat=args.repeat, presets=presets,
                sizes=args.sizes, surface_sizes=None if args.skip_surface else args.surface_sizes, seed=args.seed,
                rows=rows, runs=all_runs, skipped=skipped)


def mem_total_mb():
    try:
        with open("/proc/meminfo") as f:
            return int(f.readline().split()[1]) // 1024
    except (OSError, ValueError, IndexError):
        return None


def sizes(spec):
    """Quad counts of a --sizes value ("10k,1m", or "none")."""
    if spec.strip().lower() == "none":
        return []
    return [parse_size(s) for s in spec.split(",") if s.strip()]


# --------------------------------------------------------------------------------------------
# Table and plot
# --------------------------------------------------------------------------------------------


def fmt_table(rows):
    out = ["| mesh | quads | preset | seconds | set-up s | wall s | sweeps | peak MB | µs/quad | µs/quad/sweep | min / avg |",
           "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |"]
    for r in rows:
        setup = f"{r['setup_seconds']:.2f}" if r["kind"] == "sphere" else "–"
        floor = " ≤" if r.get("peak_at_floor") else ""
        out.append(f"| {r['mesh']} | {r['quads']:,} | {r['preset']} | {r['seconds']:.3f} | {setup} | {r['wall']:.2f} | "
                   f"{r['iterations']:g} |{floor} {r['peak_mb']:.1f} | {r['us_per_quad']:.2f} | {r['us_per_quad_sweep']:.3f} | "
                   f"{r['output']['min']:.3f} / {r['output']['avg']:.4f} |")
    if any(r.get("peak_at_floor") for r in rows):
        out.append("")
        out.append("≤: at the launcher's own peak; quadopt's may be lower")
    return "\n".join(out)


def quads_label(x):
    """10000 -> "10k", 1e6 -> "1M"."""
    for scale, suffix in ((1e6, "M"), (1e3, "k")):
        if x >= scale:
            return f"{x / scale:g}{suffix}"
    return f"{x:g}"


def plot(record, path):
    """The log-log figure of the module docs."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import ticker

    rows = record["rows"]
    # Per preset: colour, marker, line width (balanced drawn wider: it often lies under best).
    style = {"fast": ("tab:blue", "o", 1.5), "balanced": ("tab:orange", "s", 3.0), "best": ("tab:green", "^", 1.5)}
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.2), facecolor="white")
    panels = [("total_seconds", "optimizer seconds (the report's own timer)", "time"),
              ("peak_mb", "peak resident memory of the process (MB)", "memory")]
    quads = [r["quads"] for r in rows] or [1]
    for ax, (key, ylabel, what) in zip(axes, panels):
        ax.set_facecolor("white")
        values = [r[key] for r in rows] or [1]
        # Slope-1 guides: y = c x for c a power of ten spanning the data.
        x0, x1 = min(quads) / 1.5, max(quads) * 1.5
        lo = math.floor(math.log10(min(values) / max(quads)))
        hi = math.ceil(math.log10(max(values) / min(quads)))
        for e in range(lo, hi + 1):
            ax.plot([x0, x1], [10**e * x0, 10**e * x1], color="0.6", lw=0.9, ls="-.", zorder=0,
                    label="slope 1 (linear)" if e == lo else None)
        for kind, ls in (("plane", "-"), ("sphere", "--")):
            for preset in record["presets"]:
                pts = sorted((r["quads"], r[key]) for r in rows if r["kind"] == kind and r["preset"] == preset)
                if pts:
                    label = f"{kind}, {preset}" + (" (incl. set-up)" if kind == "sphere" and what == "time" else "")
                    color, marker, lw = style.get(preset, (None, "o", 1.5))
                    ax.plot(*zip(*pts), ls=ls, marker=marker, ms=5, lw=lw, alpha=0.85, color=color, label=label,
                            mfc=color if kind == "plane" else "white")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.xaxis.set_major_formatter(ticker.FuncFormatter(lambda x, _: quads_label(x)))
        ax.yaxis.set_major_formatter(ticker.FuncFormatter(lambda y, _: f"{y:g}"))
        ax.yaxis.set_minor_formatter(ticker.NullFormatter())
        ax.xaxis.set_minor_formatter(ticker.NullFormatter())
        ax.set_xlim(x0, x1)
        ax.set_ylim(min(values) / 2, max(values) * 2)
        ax.set_xlabel("quads")
        ax.set_ylabel(ylabel)
        ax.grid(True, which="major", color="0.92")
        ax.set_title(f"{what} against mesh size")
        ax.legend(fontsize=8, loc="lower right")
    fig.suptitle(f"quadopt optimize, planar grid (solid) and cube-sphere (dashed), "
                 f"{record['host']['cpus']} threads, median of {record['repeat']}", fontsize=11)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, facecolor="white", metadata={"Date": None} if path.endswith(".svg") else None)
    plt.close(fig)


# --------------------------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------------------------


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0], formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[1:]))
    target = os.environ.get("CARGO_TARGET_DIR") or os.path.join(ROOT, "target")
    ap.add_argument("--quadopt", default=os.path.join(target, "release", "quadopt"),
                    help="quadopt binary (default $CARGO_TARGET_DIR or target/, then release/quadopt)")
    ap.add_argument("--sizes", default=SIZES,
                    help=f"planar sizes in quads, comma separated (k, m suffixes), or 'none' (default {SIZES})")
    ap.add_argument("--surface-sizes", default=SURFACE_SIZES,
                    help=f"cube-sphere sizes in quads, comma separated, or 'none' (default {SURFACE_SIZES})")
    ap.add_argument("--skip-surface", action="store_true", help="leave out the cube-sphere")
    ap.add_argument("--presets", default=",".join(PRESETS), help="presets to run, comma separated (default fast,balanced,best)")
    ap.add_argument("--repeat", type=int, default=3, help="runs per mesh and preset, medians reported (default 3)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the cube-sphere's perturbation (default 1)")
    ap.add_argument("--out", default=os.path.join(ROOT, "target", "bench-scale"),
                    help="where meshes and outputs go (default target/bench-scale, ignored by git)")
    ap.add_argument("--keep", action="store_true", help="keep the meshes above 1M quads (deleted after their runs otherwise)")
    ap.add_argument("--json", metavar="PATH", help="write the record here (default OUT/bench_scale.json)")
    ap.add_argument("--plot", metavar="PATH", default=os.path.join(ROOT, "docs", "images", "scale.svg"),
                    help="the log-log figure (.svg or .png; default docs/images/scale.svg; 'none': no plot)")
    ap.add_argument("--from-json", metavar="PATH", help="print the table and draw the plot of an earlier --json file instead of running")
    args = ap.parse_args()
    if args.repeat < 1:
        ap.error("--repeat must be at least 1")
    return args


def main():
    args = parse_args()
    if args.from_json:
        with open(args.from_json) as f:
            record = json.load(f)
    else:
        if not os.path.exists(args.quadopt):
            sys.exit(f"{args.quadopt} not found: run `cargo build --release --bin quadopt` first")
        record = bench(args)
        path = args.json or os.path.join(args.out, "bench_scale.json")
        with open(path, "w") as f:
            f.write(json.dumps(record, indent=1) + "\n")
        note(f"wrote {path}")
    print(fmt_table(record["rows"]))
    for s in record["skipped"]:
        print(f"\nskipped {s['mesh']}{' ' + s['preset'] if 'preset' in s else ''}: {s['reason']}")
    if args.plot.lower() != "none" and record["rows"]:
        plot(record, args.plot)
        note(f"wrote {args.plot}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Before/after comparison of two quadopt builds on the sample and Mesquite meshes.

Usage:  pip install numpy meshio
        python3 tools/compare_runs.py run BIN LABEL.json [-- EXTRA OPTIONS]
        python3 tools/compare_runs.py diff BEFORE.json AFTER.json
        QUADOPT_PERTURB=K python3 tools/compare_runs.py run ...

`run` optimizes every mesh in data/ and in the Mesquite test meshes (../shared/meshes/mesquite
relative to the repository, or $QUADOPT_MESQUITE) with `BIN optimize IN -o OUT --json` and the
extra options, three times (the time is the fastest run's own `seconds`), and records the
output's min/avg scaled Jacobian, inverted count and its smallest edge ratio (shortest over
longest edge of a quad, over all quads; the scaled Jacobian does not see aspect ratio, so a
quad squashed into a thin rectangle scores near 1 and only this column shows it).
`diff` prints both side by side, marks a min or avg that fell by more than 1e-3 as WORSE, and
sums the times.

The max-min stage is chaotic in its input's last bits: the same mesh with every coordinate
moved by 1e-9 of itself can end 0.05 apart on the minimum. One run per mesh then says little
about a change to the stage. With QUADOPT_PERTURB=K each mesh is also run as K copies whose
coordinates are multiplied by 1 + 1e-9 r (r uniform in [-1, 1], a fixed seed per copy), and
min and avg are the medians over the original and its copies (time: the original's).
"""
import json
import os
import random
import statistics
import subprocess
import sys
import tempfile

import meshio
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def meshes():
    mesquite = os.environ.get("QUADOPT_MESQUITE",
                              os.path.join(ROOT, "..", "shared", "meshes", "mesquite"))
    found = [os.path.join(ROOT, "data", f) for f in sorted(os.listdir(os.path.join(ROOT, "data")))
             if f.endswith(".vtk")]
    for sub in ("tangled", "untangled"):
        d = os.path.join(mesquite, sub)
        if os.path.isdir(d):
            found += [os.path.join(d, f) for f in sorted(os.listdir(d)) if f.endswith(".vtk")]
    return found


def edge_ratio(path):
    """Smallest shortest/longest edge ratio over the quads of a mesh file."""
    m = meshio.read(path)
    quads = np.concatenate([c.data for c in m.cells if c.type == "quad"])
    p = m.points[:, :2][quads]                       # (n, 4, 2)
    e = np.linalg.norm(np.roll(p, -1, axis=1) - p, axis=2)
    return float((e.min(axis=1) / e.max(axis=1)).min())


def perturbed(path, seed, out):
    """`path` (legacy ASCII VTK) with every point coordinate multiplied by 1 + 1e-9 r."""
    lines = open(path).read().split("\n")
    i = next(k for k, l in enumerate(lines) if l.startswith("POINTS"))
    n, vals, j = int(lines[i].split()[1]), [], i + 1
    while len(vals) < 3 * n:
        vals += [float(x) for x in lines[j].split()]
        j += 1
    rng = random.Random(seed)
    vals = [v * (1 + 1e-9 * rng.uniform(-1, 1)) for v in vals]
    body = [" ".join(repr(v) for v in vals[k:k + 3]) for k in range(0, 3 * n, 3)]
    open(out, "w").write("\n".join(lines[:i + 1] + body + lines[j:]))


def quality_of(binary, path, out, extra):
    proc = subprocess.run([binary, "optimize", path, "-o", out, "--json", *extra], capture_output=True, text=True)
    return json.loads(proc.stdout)["output"] if proc.returncode == 0 else None


def run(binary, label, extra):
    results = {}
    copies = int(os.environ.get("QUADOPT_PERTURB", "0"))
    with tempfile.TemporaryDirectory() as tmp:
        for path in meshes():
            name = os.path.splitext(os.path.basename(path))[0]
            key = name if "mesquite" not in path else "mq/" + name
            out = os.path.join(tmp, name + ".vtk")
            best = None
            for _ in range(3):
                proc = subprocess.run([binary, "optimize", path, "-o", out, "--json", *extra],
                                      capture_output=True, text=True)
                if proc.returncode != 0:
                    best = {"error": proc.stderr.strip().splitlines()[-1:]}
                    break
                r = json.loads(proc.stdout)
                if best is None or r["seconds"] < best["seconds"]:
                    best = {"seconds": r["seconds"], "min": r["output"]["min"],
                            "avg": r["output"]["avg"], "inverted": r["output"]["inverted"],
                            "edge_ratio": edge_ratio(out)}
            if copies and "error" not in best:
                mins, avgs = [best["min"]], [best["avg"]]
                for c in range(copies):
                    src = os.path.join(tmp, f"{name}.p{c}.vtk")
                    perturbed(path, c, src)
                    q = quality_of(binary, src, out, extra)
                    if q is not None:
                        mins.append(q["min"])
                        avgs.append(q["avg"])
                best["min"], best["avg"] = statistics.median(mins), statistics.median(avgs)
                best["spread"] = [min(mins), max(mins), min(avgs), max(avgs)]
            results[key] = best
            print(key, best, file=sys.stderr)
    with open(label, "w") as f:
        json.dump(results, f, indent=1)


def diff(a_path, b_path):
    a, b = json.load(open(a_path)), json.load(open(b_path))
    print(f"{'mesh':34} {'min before':>10} {'min after':>10} {'avg before':>10} {'avg after':>10}"
          f" {'ratio before':>12} {'ratio after':>12} {'s before':>9} {'s after':>9}")
    ta = tb = 0.0
    for k in a:
        if k not in b or "error" in a[k] or "error" in b[k]:
            print(f"{k:34} skipped ({a.get(k)}, {b.get(k)})")
            continue
        x, y = a[k], b[k]
        ta += x["seconds"]
        tb += y["seconds"]
        flag = ""
        if y["min"] < x["min"] - 1e-3 or y["avg"] < x["avg"] - 1e-3:
            flag = " WORSE"
        elif y["min"] > x["min"] + 1e-3 or y["avg"] > x["avg"] + 1e-3:
            flag = " better"
        print(f"{k:34} {x['min']:10.3f} {y['min']:10.3f} {x['avg']:10.3f} {y['avg']:10.3f}"
              f" {x['edge_ratio']:12.1e} {y['edge_ratio']:12.1e}"
              f" {x['seconds']:9.3f} {y['seconds']:9.3f}{flag}")
    print(f"{'total seconds':34} {'':43} {'':25} {ta:9.3f} {tb:9.3f}")


if __name__ == "__main__":
    if len(sys.argv) >= 4 and sys.argv[1] == "run":
        extra = sys.argv[5:] if len(sys.argv) > 4 and sys.argv[4] == "--" else []
        run(sys.argv[2], sys.argv[3], extra)
    elif len(sys.argv) == 4 and sys.argv[1] == "diff":
        diff(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)

#!/usr/bin/env python3
"""Before/after comparison of two quadopt builds on the sample and Mesquite meshes.

Usage:  pip install numpy meshio
        python3 tools/compare_runs.py run BIN LABEL.json [-- EXTRA OPTIONS]
        python3 tools/compare_runs.py diff BEFORE.json AFTER.json

`run` optimizes every mesh in data/ and in the Mesquite test meshes (../shared/meshes/mesquite
relative to the repository, or $QUADOPT_MESQUITE) with `BIN optimize IN -o OUT --json` and the
extra options, three times (the time is the fastest run's own `seconds`), and records the
output's min/avg scaled Jacobian, inverted count and its smallest edge ratio (shortest over
longest edge of a quad, over all quads; the scaled Jacobian does not see aspect ratio, so a
quad squashed into a thin rectangle scores near 1 and only this column shows it).
`diff` prints both side by side, marks a min or avg that fell by more than 1e-3 as WORSE, and
sums the times.
"""
import json
import os
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


def run(binary, label, extra):
    results = {}
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

#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Test of the plugin's float build, the one for the desktop MeshLab.

    python3 plugins/meshlab/tests/test_float.py [--build-dir DIR] [--cli QUADOPT] [CMAKE_ARGS...]

There is no desktop MeshLab 2025.07 here, so this builds what it is made of: MeshLab's library
(libmeshlab-common) with float scalars from the same sources as the plugin (some 2 minutes on 2
cores), the plugin with -DQUADOPT_MESHLAB_SCALAR=float -DQUADOPT_MESHLAB_COMMON=NONE (as the
README tells desktop users), and float_host/, a minimal MeshLab application that loads the
plugin through MeshLab's PluginManager and reads OBJ files with vcglib's reader. Then, on
planar, quad-dominant and surface samples with coordinates exact in float:

- the positions are the CLI's (on the same coordinates, in double) rounded to float, bit for
  bit, and each triangle's quality its polygon's CLI value rounded to float (on a surface,
  Verdict's measure, within a unit in the float's last place);
- a progress callback returning false cancels: the filter fails with "cancelled" and the mesh is
  as read.

Needs only the system's python3 (numpy is not used). Exits 1 on any failure.
"""
import argparse
import os
import struct
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from test_filter import ROOT, read_vtk_plain, verdict_plain, write_obj, write_vtk  # noqa: E402

SAMPLES = ["plate_2holes_mixed.vtk", "mazewheel.vtk", "sphere_surface.vtk", "bracket_surface_mixed.vtk"]


def f32(x):
    """x rounded to the nearest float (what MeshLab's float mesh stores)."""
    return struct.unpack("f", struct.pack("f", x))[0]


def run(cmd, **kw):
    res = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw)
    if res.returncode != 0:
        sys.stderr.write(res.stdout)
        sys.exit("test_float: %s failed" % " ".join(cmd[:3]))
    return res.stdout


def cache_value(build, name):
    with open(os.path.join(build, "CMakeCache.txt")) as f:
        for line in f:
            if line.startswith(name + ":"):
                return line.split("=", 1)[1].strip()
    sys.exit("test_float: %s not in %s/CMakeCache.txt" % (name, build))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", default=os.path.join(ROOT, "target", "meshlab-float-test"))
    ap.add_argument("--cli", default=None)
    args, cmake_args = ap.parse_known_args()
    build = os.path.abspath(args.build_dir)
    jobs = os.environ.get("QUADOPT_JOBS") or str(os.cpu_count() or 2)
    started = time.time()

    out = run([os.path.join(ROOT, "scripts", "meshlab-plugin"), "--build-dir", os.path.join(build, "plugin"),
               "-DQUADOPT_MESHLAB_SCALAR=float", "-DQUADOPT_MESHLAB_COMMON=NONE"] + cmake_args)
    plugin = out.strip().splitlines()[-1]
    meshlab = cache_value(os.path.join(build, "plugin", "build"), "QUADOPT_MESHLAB_RESOLVED_SOURCE_DIR")
    with open(os.path.join(meshlab, "ML_VERSION")) as f:
        version = f.read().strip()

    common_build = os.path.join(build, "meshlab-common")
    common = os.path.join(common_build, "src", "distrib", "libmeshlab-common.so")
    run(["cmake", "-S", meshlab, "-B", common_build, "-DCMAKE_BUILD_TYPE=Release",
         "-DMESHLAB_BUILD_ONLY_LIBRARIES=ON", "-DMESHLAB_PLUGINS=", "-DMESHLAB_ALLOW_OPTIONAL_EXTERNAL_LIBRARIES=OFF",
         "-DMESHLAB_BUILD_WITH_DOUBLE_SCALAR=OFF"])
    run(["cmake", "--build", common_build, "--target", "meshlab-common", "-j", jobs])
    host_build = os.path.join(build, "host")
    run(["cmake", "-S", os.path.join(HERE, "float_host"), "-B", host_build, "-DCMAKE_BUILD_TYPE=Release",
         "-DMESHLAB_SRC=" + os.path.join(meshlab, "src"), "-DMESHLAB_COMMON=" + common,
         "-DMESHLAB_VERSION=" + version])
    run(["cmake", "--build", host_build, "-j", jobs])
    host = os.path.join(host_build, "host")
    built = time.time()

    cli = args.cli or os.path.join(os.environ.get("CARGO_TARGET_DIR") or os.path.join(ROOT, "target"),
                                   "release", "quadopt")
    tmp = tempfile.mkdtemp(prefix="quadopt-meshlab-float-")
    failed = []

    def check(ok, what):
        if not ok:
            failed.append(what)
            print("FAIL: " + what, flush=True)

    def host_run(obj, extra=()):
        txt = obj + ".txt"
        res = subprocess.run([host, plugin, obj, txt] + list(extra), stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
        rows = [l.split() for l in open(txt)] if os.path.exists(txt) else []
        return res, rows

    print("| sample (float build) | #V | faces | positions = float(CLI) | face quality = float(CLI) | moved |")
    print("| --- | ---: | ---: | --- | --- | ---: |")
    for name in SAMPLES:
        pts, faces = read_vtk_plain(os.path.join(ROOT, "data", name))[:2]
        pts = [[f32(c) for c in p] for p in pts]  # what a float MeshLab holds
        obj, src, dst = (os.path.join(tmp, name + e) for e in (".obj", ".in.vtk", ".out.vtk"))
        write_obj(obj, pts, faces)
        res, rows = host_run(obj)
        check(res.returncode == 0, "%s: the filter ran (%s)" % (name, res.stderr.strip()))
        check("scaled Jacobian after:" in res.stdout, name + ": the report is in MeshLab's log")
        write_vtk(src, pts, faces)
        run([cli, "optimize", src, "-o", dst])
        cli_pts, _, arrays = read_vtk_plain(dst)
        q_vtk = os.path.join(tmp, name + ".q.vtk")
        run([cli, "quality", dst, "-o", q_vtk])
        per_face = read_vtk_plain(q_vtk)[2]["scaled_jacobian"]
        surface = "surface" in name
        if not surface:
            per_face = arrays["scaled_jacobian"]  # in the run's plane (see test_filter.py)
        else:
            # On a surface the filter stores Verdict's measure (see test_filter.py), computed
            # here by its definition: equal to the float rounding, within a unit in its last
            # place where this computation and the library's round differently.
            per_face = verdict_plain(cli_pts, faces)
        # %.9g prints a float exactly: the float nearest to the printed decimal is the value.
        got = [[f32(float(x)) for x in r] for r in rows[:len(pts)]]
        want = [[f32(c) for c in p] for p in cli_pts]
        same_pts = got == want
        tris = [f32(float(r[0])) for r in rows[len(pts):]]
        want_q = [f32(q) for q, c in zip(per_face, faces) for _ in range(len(c) - 2)]
        if surface:
            same_q = len(tris) == len(want_q) and all(
                a == b or abs(a - b) <= 2.0 ** -23 * max(abs(b), 2.0 ** -126) for a, b in zip(tris, want_q))
        else:
            same_q = tris == want_q
        moved = sum(1 for a, b in zip(got, pts) if a != b)
        check(same_pts, name + ": positions equal the CLI's rounded to float")
        check(same_q, name + ": face quality equals the CLI's rounded to float")
        check(moved > 0, name + ": vertices moved")
        print("| %s | %d | %d | %s | %s | %d |" % (name, len(pts), len(faces), "identical" if same_pts else "DIFFERENT",
                                                   "identical" if same_q else "DIFFERENT", moved))

    pts, faces = read_vtk_plain(os.path.join(ROOT, "data", "plate_2holes_mixed.vtk"))[:2]
    pts = [[f32(c) for c in p] for p in pts]
    obj = os.path.join(tmp, "cancel.obj")
    write_obj(obj, pts, faces)
    res, rows = host_run(obj, ["cancel"])
    check(res.returncode == 2 and "cancelled" in res.stderr, "cancel: the filter fails with 'cancelled'")
    check([[f32(float(x)) for x in r] for r in rows[:len(pts)]] == pts, "cancel: the mesh is as read")
    print("test_float: build %.0f s, tests %.0f s; %s" % (built - started, time.time() - built,
                                                         "%d failed" % len(failed) if failed else "all passed"))
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Tests of quadopt's MeshLab filter plugin, through PyMeshLab.

    python3 plugins/meshlab/tests/test_filter.py [--build-dir DIR] [--cli QUADOPT] [CMAKE_ARGS...]

Builds the plugin with scripts/meshlab-plugin (a virtual environment with pymeshlab 2025.7.post1
under DIR, default target/meshlab-test/), loads it into pymeshlab and runs the filter on data/'s
planar, quad-dominant and surface samples, each compared with quadopt's command-line tool on the
same mesh and options (QUADOPT, default the CLI that the plugin build made:
$CARGO_TARGET_DIR/release/quadopt):

- the positions are the CLI's bit for bit, with the defaults, every preset (and a preset changes
  the result as --effort does), a boundary mode, a feature angle and a sweep cap; for a mesh
  read from a file, made in memory (pymeshlab.Mesh with polygons), in a tilted plane;
- selected vertices (with "keep selected vertices fixed") keep their coordinates bit for bit and
  the rest equals the CLI given them as fixed vertices;
- each face's quality (on each triangle of its polygon) is the per-face scaled Jacobian of the
  result: in the plane the CLI's per-face output, on a surface Verdict's 3D measure (checked
  against Verdict's definition here and the report's output_verdict), and the filter's output
  values are the CLI's report;
- a pentagon, a plain triangle mesh and an invalid parameter raise an error naming the problem,
  in MeshLab's log too, with the mesh untouched.

Other CMAKE_ARGS go to the plugin's CMake (scripts/meshlab-plugin). Prints a table of the
samples (filter against CLI) at the end; exits 1 on any failure.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
FILTER = "apply_coord_quadopt_quad_quality"

# (file, kind): data/'s samples the filter runs on.
SAMPLES = [
    ("plate_2holes.vtk", "planar"),
    ("patch_slotted.vtk", "planar"),
    ("mazewheel.vtk", "planar"),
    ("plate_2holes_mixed.vtk", "quad-dominant"),
    ("patch_notched_mixed.vtk", "quad-dominant"),
    ("mazewheel_mixed.vtk", "quad-dominant"),
    ("sphere_surface.vtk", "surface, closed"),
    ("cylinder_holes_surface.vtk", "surface, open"),
    ("bracket_surface.vtk", "surface, sharp edges"),
    ("bracket_surface_mixed.vtk", "surface, quad-dominant"),
]


# --------------------------------------------------------------------------------------------
# Outer part: build, then run the tests under the virtual environment's python.
def outer():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", default=os.path.join(ROOT, "target", "meshlab-test"))
    ap.add_argument("--cli", default=None, help="quadopt's command-line tool to compare with")
    args, cmake_args = ap.parse_known_args()
    build = os.path.abspath(args.build_dir)
    started = time.time()
    out = subprocess.run(
        [os.path.join(ROOT, "scripts", "meshlab-plugin"), "--build-dir", build] + cmake_args,
        stdout=subprocess.PIPE, text=True)
    if out.returncode != 0:
        sys.exit("test_filter: scripts/meshlab-plugin failed")
    lines = out.stdout.strip().splitlines()
    plugin = lines[-1] if lines else ""
    if not os.path.isfile(plugin):
        sys.exit("test_filter: scripts/meshlab-plugin printed no plugin path (last line: %r)" % plugin)
    built = time.time()
    cli = args.cli or os.path.join(os.environ.get("CARGO_TARGET_DIR") or os.path.join(ROOT, "target"),
                                   "release", "quadopt")
    if not os.access(cli, os.X_OK):
        sys.exit("test_filter: no quadopt command-line tool at %s (cargo build --release)" % cli)
    python = os.path.join(build, "venv", "bin", "python")
    rc = subprocess.call([python, os.path.abspath(__file__), "--inner", plugin, cli])
    print("test_filter: build %.0f s, tests %.0f s" % (built - started, time.time() - built))
    sys.exit(rc)


# --------------------------------------------------------------------------------------------
# Inner part: under a python with pymeshlab and numpy.
NO_VERTEX = 0xFFFFFFFF


def read_vtk_plain(path):
    """Points (lists of 3 floats), faces (lists of indices) and scalar arrays (lists) of a legacy
    ASCII VTK file."""
    tok = open(path).read().split()
    i = tok.index("POINTS")
    n = int(tok[i + 1])
    flat = [float(t) for t in tok[i + 3:i + 3 + 3 * n]]
    pts = [flat[3 * j:3 * j + 3] for j in range(n)]
    i = tok.index("CELLS")
    count = int(tok[i + 1])
    k = i + 3
    faces = []
    for _ in range(count):
        m = int(tok[k])
        faces.append([int(t) for t in tok[k + 1:k + 1 + m]])
        k += m + 1
    arrays = {}
    j, size = k, None
    while j < len(tok):
        if tok[j] in ("CELL_DATA", "POINT_DATA"):
            size = int(tok[j + 1])
            j += 2
        elif tok[j] == "SCALARS":
            name = tok[j + 1]
            j += 3
            if tok[j].isdigit():  # the optional component count
                j += 1
            if tok[j] == "LOOKUP_TABLE":
                j += 2
            arrays[name] = [float(x) for x in tok[j:j + size]]
            j += size
        else:
            j += 1
    return pts, faces, arrays


def verdict_plain(pts, faces):
    """Verdict's scaled Jacobian of each face, in plain Python (its definition: a quad's
    corners, each the triple product of its two edges with the quad's centre normal over
    their lengths, the smallest; a triangle's, 2/sqrt(3) times the sine of its smallest
    corner, capped at 1)."""
    def sub(a, b):
        return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]

    def cross(a, b):
        return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

    def dot(a, b):
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]

    def norm(a):
        return dot(a, a) ** 0.5

    out = []
    for c in faces:
        p = [pts[v] for v in c]
        if len(c) == 3:
            e = [sub(p[1], p[0]), sub(p[2], p[1]), sub(p[0], p[2])]
            area2 = norm(cross(e[0], e[2]))
            lengths = [norm(x) for x in e]
            prod = max(lengths[0] * lengths[2], lengths[1] * lengths[0], lengths[2] * lengths[1])
            out.append(min(1.0, 2.0 / 3.0 ** 0.5 * area2 / prod) if prod > 0 else 0.0)
            continue
        n = cross(sub(p[2], p[0]), sub(p[3], p[1]))
        n = [x / norm(n) for x in n]
        vals = []
        for k in range(4):
            a, b = sub(p[(k + 1) % 4], p[k]), sub(p[(k + 3) % 4], p[k])
            vals.append(dot(cross(a, b), n) / (norm(a) * norm(b)))
        out.append(min(vals))
    return out


def read_vtk(path):
    """read_vtk_plain() with numpy arrays."""
    import numpy as np
    pts, faces, arrays = read_vtk_plain(path)
    return np.array(pts, dtype=np.float64).reshape(-1, 3), faces, {k: np.array(v) for k, v in arrays.items()}


def write_vtk(path, pts, faces, fixed=None):
    with open(path, "w") as f:
        f.write("# vtk DataFile Version 3.0\nquadopt MeshLab plugin test\nASCII\nDATASET UNSTRUCTURED_GRID\n")
        f.write("POINTS %d double\n" % len(pts))
        for p in pts:
            f.write("%r %r %r\n" % (float(p[0]), float(p[1]), float(p[2])))
        f.write("CELLS %d %d\n" % (len(faces), sum(len(c) + 1 for c in faces)))
        for c in faces:
            f.write("%d %s\n" % (len(c), " ".join(map(str, c))))
        f.write("CELL_TYPES %d\n" % len(faces))
        for c in faces:
            f.write("%d\n" % (9 if len(c) == 4 else 5))
        if fixed is not None:
            f.write("POINT_DATA %d\nSCALARS fixed int 1\nLOOKUP_TABLE default\n" % len(pts))
            for v in fixed:
                f.write("%d\n" % (1 if v else 0))


def write_obj(path, pts, faces):
    with open(path, "w") as f:
        for p in pts:
            f.write("v %r %r %r\n" % (float(p[0]), float(p[1]), float(p[2])))
        for c in faces:
            f.write("f %s\n" % " ".join(str(i + 1) for i in c))


class Failures:
    def __init__(self):
        self.failed = []
        self.passed = 0

    def check(self, ok, what):
        if ok:
            self.passed += 1
        else:
            self.failed.append(what)
            print("FAIL: " + what, flush=True)
        return ok


def inner(plugin, cli):
    import numpy as np
    import pymeshlab

    pymeshlab.load_plugin(plugin)
    t = Failures()
    t.check(FILTER in pymeshlab.filter_list(), "the filter is listed after load_plugin")
    tmp = tempfile.mkdtemp(prefix="quadopt-meshlab-")
    counter = [0]

    def fresh(ext):
        counter[0] += 1
        return os.path.join(tmp, "m%d.%s" % (counter[0], ext))

    # Every MeshSet stays alive to the end: after a filter fails, pymeshlab 2025.7 keeps a
    # pointer to that MeshSet's log (until a filter succeeds) and the next file it loads logs
    # there, which crashes if the MeshSet was freed meanwhile.
    keep = []

    def load(pts, faces, how="obj"):
        """A MeshSet holding the mesh, read from an OBJ file (exact coordinates) or made by
        pymeshlab.Mesh from the polygons (which rounds coordinates to float)."""
        ms = pymeshlab.MeshSet()
        keep.append(ms)
        if how == "obj":
            path = fresh("obj")
            write_obj(path, pts, faces)
            ms.load_new_mesh(path)
        else:
            ms.add_mesh(pymeshlab.Mesh(vertex_matrix=np.asarray(pts, dtype=np.float64),
                                       face_list_of_indices=[np.array(c, dtype=np.uint32) for c in faces]))
        return ms

    def run_filter(ms, **kwargs):
        start = time.perf_counter()
        out = ms.apply_filter(FILTER, **kwargs)
        wall = time.perf_counter() - start
        m = ms.current_mesh()
        return out, m.vertex_matrix().copy(), m.face_scalar_array().copy(), wall

    def run_cli(pts, faces, fixed=None, args=()):
        src, dst, q = fresh("vtk"), fresh("vtk"), fresh("vtk")
        write_vtk(src, pts, faces, fixed)
        res = subprocess.run([cli, "optimize", src, "-o", dst, "--json"] + list(args),
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if res.returncode != 0:
            raise RuntimeError("quadopt optimize failed: " + res.stderr)
        report = json.loads(res.stdout)
        out_pts, out_faces, arrays = read_vtk(dst)
        # quadopt's own per-face values of the result (on a surface: against its own surface,
        # as the filter stores them).
        res = subprocess.run([cli, "quality", dst, "-o", q], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
        if res.returncode != 0:
            raise RuntimeError("quadopt quality failed: " + res.stderr)
        per_face = read_vtk(q)[2]["scaled_jacobian"]
        assert out_faces == [list(c) for c in faces], "the CLI changed the faces"
        return out_pts, per_face, report, arrays.get("scaled_jacobian")

    def per_polygon(values, faces, name):
        """The per-triangle values of a mesh whose triangles come polygon after polygon, as
        one per polygon (every triangle of a polygon must carry its value)."""
        out = []
        k = 0
        for c in faces:
            tri = values[k:k + len(c) - 2]
            k += len(c) - 2
            t.check(len(tri) == len(c) - 2 and np.all(tri == tri[0]),
                    "%s: every triangle of a polygon has the polygon's quality" % name)
            out.append(tri[0] if len(tri) else np.nan)
        t.check(k == len(values), "%s: %d triangles for %d polygons" % (name, len(values), len(faces)))
        return np.array(out)

    def verdict_values(pts, faces):
        return np.array(verdict_plain([list(map(float, p)) for p in pts], faces))

    def same(a, b):
        a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
        return a.shape == b.shape and a.tobytes() == b.tobytes()

    def compare(name, pts, faces, ms, kwargs=None, cli_args=(), fixed=None, report_check=True):
        """Runs the filter on `ms` (holding pts, faces) and the CLI on the same mesh; checks
        positions, per-face quality and the report. Returns a table row."""
        held = ms.current_mesh().vertex_matrix().copy()
        t.check(held.shape == (len(pts), 3), "%s: pymeshlab holds %d vertices" % (name, len(pts)))
        out, got, tri_q, wall = run_filter(ms, **(kwargs or {}))
        cli_pts, cli_q, rep, cli_opt_q = run_cli(held, faces, fixed, cli_args)
        ok = t.check(same(got, cli_pts), "%s: positions equal the CLI's bit for bit (max |diff| %.3g)" % (
            name, float(np.abs(got - cli_pts).max()) if got.shape == cli_pts.shape else float("nan")))
        t.check(out["moved_vertices"] > 0 and not same(got, held), "%s: the filter moved vertices" % name)
        q = per_polygon(tri_q, faces, name)
        if rep.get("surface", False):
            # Verdict's 3D measure, face by face (an implementation of Verdict's definition
            # here), and over the mesh the CLI's report of the same run.
            ref = verdict_values(cli_pts, faces)
            t.check(np.allclose(q, ref, rtol=0, atol=1e-12),
                    "%s: per-face quality is Verdict's (max |diff| %.3g)" % (name, float(np.abs(q - ref).max())))
            stats = rep["output_verdict"]
            t.check(float(q.min()) == stats["min"] and int((q <= 0).sum()) == stats["inverted"],
                    "%s: per-face quality's min and inverted count are the report's Verdict" % name)
            t.check(abs(float(q.mean()) - stats["avg"]) < 1e-12, "%s: per-face quality's average" % name)
        else:
            # In the run's plane (`quadopt quality` would fit a tilted plane again, from the
            # moved vertices, and differ in the last bits).
            t.check(same(q, cli_opt_q), "%s: per-face quality equals the CLI's per-face output" % name)
        if report_check:
            for side in ("input", "output"):
                for key in ("min", "avg"):
                    t.check(out["%s_%s" % (side, key)] == rep[side][key],
                            "%s: %s %s %r equals the CLI's %r" % (name, side, key, out["%s_%s" % (side, key)],
                                                                 rep[side][key]))
                t.check(out[side + "_inverted"] == rep[side]["inverted"], "%s: %s inverted" % (name, side))
            t.check(out["surface"] == rep.get("surface", False), "%s: surface flag" % name)
            if rep.get("surface", False):
                for side in ("input", "output"):
                    t.check(out[side + "_verdict_min"] == rep[side + "_verdict"]["min"],
                            "%s: %s Verdict min" % (name, side))
            t.check(out["sweeps"] == rep["iterations"], "%s: sweeps %d, CLI %d" % (name, out["sweeps"],
                                                                                 rep["iterations"]))
        return {"name": name, "identical": ok, "in_min": out["input_min"], "in_avg": out["input_avg"],
                "in_inv": out["input_inverted"], "out_min": out["output_min"], "out_avg": out["output_avg"],
                "out_inv": out["output_inverted"], "seconds": out["seconds"], "wall": wall,
                "cli_seconds": rep["seconds"], "surface": rep.get("surface", False), "V": len(pts),
                "quads": out["quads"], "tris": out["triangles"], "out": out, "got": got, "held": held}

    rows = []
    samples = {}
    for name, kind in SAMPLES:
        pts, faces, _ = read_vtk(os.path.join(ROOT, "data", name))
        samples[name] = (pts, faces)
        t.check(all(len(c) in (3, 4) for c in faces), name + ": quads and triangles")
        row = compare(name, pts, faces, load(pts, faces))
        row["kind"] = kind
        rows.append(row)
        t.check(row["surface"] == kind.startswith("surface"), "%s: planar/surface as expected" % name)
        t.check(row["tris"] == sum(1 for c in faces if len(c) == 3), name + ": triangle count")
        t.check(row["out_min"] >= row["in_min"], name + ": the minimum does not drop")

    # A mesh made in memory (pymeshlab.Mesh from polygons; vcglib's ear cutting, float coordinates).
    for name in ("patch_notched_mixed.vtk", "bracket_surface_mixed.vtk"):
        pts, faces = samples[name]
        compare(name + " (pymeshlab.Mesh)", pts, faces, load(pts, faces, how="mesh"))

    # An unreferenced vertex (kept in place, and out of the planar frame's fit).
    pts, faces = samples["plate_2holes_mixed.vtk"]
    extra = np.vstack([pts, [[7.25, -1.5, 0.0]]])
    row = compare("plate_2holes_mixed + unreferenced vertex", extra, faces, load(extra, faces))
    t.check(same(row["got"][-1], extra[-1]), "the unreferenced vertex stays")

    # A planar mesh in a tilted plane (the CLI's frame; a plane x = const too).
    pts, faces = samples["plate_2holes_mixed.vtk"]
    axis = np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
    angle = 0.7
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rot = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)
    tilted = pts @ rot.T + np.array([0.5, -2.0, 3.25])
    row = compare("plate_2holes_mixed tilted", tilted, faces, load(tilted, faces))
    t.check(not row["surface"], "tilted plane: optimized in its plane")
    yz = np.column_stack([np.full(len(pts), 1.5), pts[:, 0], pts[:, 1]])
    row = compare("plate_2holes_mixed in x = 1.5", yz, faces, load(yz, faces))
    t.check(np.all(row["got"][:, 0] == 1.5), "plane x = 1.5: x is never written")

    # Presets: each equals the CLI's --effort, and fast differs from balanced.
    name = "mazewheel_mixed.vtk"
    pts, faces = samples[name]
    by_preset = {}
    for preset, effort in (("fast", "fast"), ("balanced", "balanced"), ("best", "best")):
        row = compare("%s preset=%s" % (name, preset), pts, faces, load(pts, faces), {"preset": preset},
                      ["--effort", effort])
        by_preset[preset] = row
    t.check(not same(by_preset["fast"]["got"], by_preset["balanced"]["got"]),
            "preset fast gives another result than balanced")
    t.check(not same(by_preset["best"]["got"], by_preset["balanced"]["got"]),
            "preset best gives another result than balanced")
    t.check(by_preset["fast"]["out"]["effort"] == 1 and by_preset["best"]["out"]["effort"] == 2,
            "the report's effort is the preset's")
    t.check(by_preset["best"]["out_min"] >= by_preset["fast"]["out_min"], "best's minimum >= fast's")

    # The other parameters reach quadopt.
    pts, faces = samples["plate_2holes_mixed.vtk"]
    compare("plate_2holes_mixed boundary=fixed", pts, faces, load(pts, faces), {"boundary": "fixed"},
            ["--boundary", "fixed"])
    compare("plate_2holes_mixed boundary=slide", pts, faces, load(pts, faces), {"boundary": "slide"},
            ["--boundary", "slide"])
    compare("patch_slotted max_sweeps=3", *samples["patch_slotted.vtk"], load(*samples["patch_slotted.vtk"]),
            {"max_sweeps": 3}, ["--max-iter", "3"])
    pts, faces = samples["bracket_surface_mixed.vtk"]
    a = compare("bracket_surface_mixed feature_angle=30", pts, faces, load(pts, faces), {"feature_angle": 30.0},
                ["--feature-angle", "30"])
    b = [r for r in rows if r["name"] == "bracket_surface_mixed.vtk"][0]
    t.check(not same(a["got"], b["got"]), "feature_angle=30 gives another result than 45")

    # Selected vertices stay bit for bit; the others equal the CLI with them fixed.
    for name, cond in (("plate_2holes_mixed.vtk", "(x < 2.2) && (y > 0.8)"), ("sphere_surface.vtk", "z > 0.3")):
        pts, faces = samples[name]
        ms = load(pts, faces)
        ms.apply_filter("compute_selection_by_condition_per_vertex", condselect=cond)
        sel = ms.current_mesh().vertex_selection_array().copy()
        t.check(0 < sel.sum() < len(sel), "%s: %d of %d vertices selected" % (name, sel.sum(), len(sel)))
        row = compare(name + " selected fixed", pts, faces, ms, {"keep_selected_fixed": True}, fixed=sel)
        t.check(same(row["got"][sel], row["held"][sel]), name + ": selected vertices keep their bits")
        t.check(row["out"]["fixed_vertices"] == int(sel.sum()), name + ": fixed count")
        ms = load(pts, faces)
        ms.apply_filter("compute_selection_by_condition_per_vertex", condselect=cond)
        out, got, _, _ = run_filter(ms)
        t.check(not same(got[sel], row["held"][sel]), name + ": without the option, selected vertices move")
        t.check(out["fixed_vertices"] == 0, name + ": without the option nothing is fixed")

    # Errors: the mesh untouched, the message in the exception and in MeshLab's log.
    def refused(name, ms, expect, **kwargs):
        m = ms.current_mesh()
        before = m.vertex_matrix().copy()
        had_quality = m.has_face_scalar()
        try:
            ms.apply_filter(FILTER, **kwargs)
            t.check(False, name + ": refused")
            return
        except pymeshlab.PyMeshLabException as e:
            msg = str(e)
        for word in expect:
            t.check(word in msg, "%s: the message says %r (%s)" % (name, word, msg))
        t.check(same(ms.current_mesh().vertex_matrix(), before), name + ": the mesh is untouched")
        t.check(ms.current_mesh().has_face_scalar() == had_quality, name + ": no face quality added")

    pent_pts = np.array([(0, 0, 0), (1, 0, 0), (2, 0, 0), (0, 1, 0), (1, 1, 0), (2, 1, 0), (2.5, 0.5, 0),
                         (0, 2, 0), (1, 2, 0.0)], dtype=np.float64)
    pent_faces = [[0, 1, 4, 3], [1, 2, 6, 5, 4], [3, 4, 8, 7]]
    refused("pentagon", load(pent_pts, pent_faces), ["polygon 1", "MeshLab faces 2, 3, 4", "has 5 vertices",
                                                      "quads and triangles only", "unchanged"])
    pts, faces = samples["plate_2holes.vtk"]
    tris = np.array([tr for c in faces for tr in ([c[0], c[1], c[2]], [c[0], c[2], c[3]])], dtype=np.int32)
    ms = pymeshlab.MeshSet()
    keep.append(ms)
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=pts, face_matrix=tris))
    refused("triangle mesh", ms, ["plain triangle mesh", "faux edges", "quad"])
    refused("max_sweeps=0", load(pts, faces), ["sweep cap"], max_sweeps=0)
    refused("feature_angle=200", load(pts, faces), ["feature"], feature_angle=200.0)

    # MeshLab's log (pymeshlab prints it with verbose=True): the report, and the error.
    probe = fresh("py")
    obj_ok, obj_bad = fresh("obj"), fresh("obj")
    write_obj(obj_ok, *samples["plate_2holes_mixed.vtk"])
    write_obj(obj_bad, pent_pts, pent_faces)
    with open(probe, "w") as f:
        f.write("import sys, pymeshlab\npymeshlab.load_plugin(sys.argv[1])\n"
                "ms = pymeshlab.MeshSet(verbose=True)\nms.load_new_mesh(sys.argv[2])\nms.apply_filter(%r)\n"
                "ms.load_new_mesh(sys.argv[3])\n"
                "try:\n    ms.apply_filter(%r)\nexcept pymeshlab.PyMeshLabException:\n    pass\n" % (FILTER, FILTER))
    res = subprocess.run([sys.executable, probe, plugin, obj_ok, obj_bad], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
    log = [l for l in res.stdout.splitlines() if l.startswith("LOG:")]
    # (pymeshlab's progress callback logs what the filter reports after each sweep.)
    for want in ("scaled Jacobian before: min", "scaled Jacobian after:  min", "sweeps", "quadopt: polygon 1",
                 "quadopt: sweep ", "quadopt: untangling"):
        t.check(any(want in l for l in log), "MeshLab's log has %r" % want)

    # The table.
    print("\n| sample | kind | #V | quads | tris | positions = CLI | input min / avg (inv) | output min / avg (inv) "
          "| quadopt s | filter wall s | CLI s |")
    print("| --- | --- | ---: | ---: | ---: | --- | --- | --- | ---: | ---: | ---: |")
    for r in rows:
        print("| %s | %s | %d | %d | %d | %s | %.4f / %.4f (%d) | %.4f / %.4f (%d) | %.4f | %.4f | %.4f |" % (
            r["name"], r["kind"], r["V"], r["quads"], r["tris"], "identical" if r["identical"] else "DIFFERENT",
            r["in_min"], r["in_avg"], r["in_inv"], r["out_min"], r["out_avg"], r["out_inv"], r["seconds"],
            r["wall"], r["cli_seconds"]))
    print("\n%d checks passed, %d failed" % (t.passed, len(t.failed)))
    return 1 if t.failed else 0


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "--inner":
        sys.exit(inner(sys.argv[2], sys.argv[3]))
    outer()

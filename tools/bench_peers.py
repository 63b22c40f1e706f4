#!/usr/bin/env python3
"""Side-by-side comparison of quadopt's presets with gmsh's 2D smoothers, GETMe and DMO, on the same meshes.

Usage:  python3 -m venv VENV && VENV/bin/pip install -r tools/requirements.txt numpy   # gmsh 4.15.2 (pinned)
        cargo build --release
        VENV/bin/python tools/bench_peers.py --sizes 10k,200k     # the benchmark: data/, Mesquite, two plates
        VENV/bin/python tools/bench_peers.py --json results.json  # also the 1M plate; rows and dominance as JSON
        VENV/bin/python tools/bench_peers.py --sizes none --only plate_2holes     # sample meshes only
        VENV/bin/python tools/bench_peers.py --from-json results.json --wide      # an earlier run, one row per mesh
        VENV/bin/python tools/bench_peers.py --sizes none --dominance-count       # the count alone, one JSON line
A quadopt without `--effort`: give each preset's flags instead, e.g.
        --preset-flags "fast=--no-maxmin --max-iter 10" --preset-flags balanced= --preset-flags best=

        VENV/bin/python tools/bench_peers.py --quad-dominant --getme DIR  # quad-dominant meshes (below)
The table goes to stdout, then the dominance count (below); notes (skipped meshes and tools,
checks that failed) go to stderr. Columns: mesh, quads, tool ("input" is the mesh as given; a
peer; "quadopt NAME" per preset), seconds (the median over the repeats of the tool's own timer
of the smoothing step alone, no meshing or file IO; see each tool below), CPU s (CPU seconds of
that step, all threads: gmsh's exactly, around the optimize call; quadopt's and DMO's as the
process's CPU time minus that of a run of the same program that only reads, sets up and writes:
quadopt `--max-iter 1 --boundary fixed --no-untangle --no-maxmin`, DMO `--iters 0`; none for
GETMe, whose driver has no such run), min SJ / avg SJ (minimum and mean scaled Jacobian over all
faces: quads, and triangles with --quad-dominant), inverted (faces with scaled Jacobian <= 0),
edge ratio (the smallest shortest/longest edge ratio of a face; "thin" after it: see below), and quadopt's time divided by the peer's,
wall-clock and CPU, where quadopt is the balanced preset (the default; the first preset run if
balanced was not) (below 1: quadopt is faster; no CPU ratio where either CPU time is missing or
under 1 ms, the noise of process accounting). "(!)" after a tool marks an output that failed a
check (see the notes). --wide gives one row per mesh: per tool "min / avg (inverted), seconds"
(each tool's own timer, as the dominance compares them), a peer run that no preset dominates
marked "(not dominated)".

Dominance
---------
A peer run (one gmsh optimizer, GETMe or DMO on one mesh) is DOMINATED when some quadopt preset
on the same mesh has
  * seconds <= the peer's (each tool's own timer of the smoothing step, medians; a time under
    1 ms counts as 1 ms, the timers' noise),
  * min >= the peer's min - 1e-3 and avg >= the peer's avg - 1e-3,
  * inverted <= the peer's inverted,
  * and an output that passed the checks.
Peers run on one thread, quadopt on all cores as users run it. A peer output that is thin (its
smallest edge ratio below a tenth of the input's: it squashed quads into thin rectangles, which
the scaled Jacobian scores well) is left out of the count. Printed after the table: per preset,
how many of the counted peer runs it dominates; in all, how many some preset dominates, out of
how many counted (and the thin ones left out); then each peer run NOT dominated, with the peer's
and every preset's time / min / avg / inverted and what each preset misses (slower, min, avg,
inverted, failed check). --json holds it as "dominance" (with the same lists); --from-json
recomputes it from the rows (a file written before the presets has one preset, "quadopt");
--dominance-count prints {"dominated", "counted", "thin", "peer_runs", "per_preset"} alone.

Meshes
------
* Synthetic plates: a 10 x 5 rectangle with ten circular holes (the geometry of
  data/plate_10holes.vtk), meshed by gmsh with Frontal-Delaunay (Mesh.Algorithm = 6) and
  Blossom recombination in its all-quad form (Mesh.RecombinationAlgorithm = 3: triangulate at
  twice the size, recombine, then split every element into quads; plain Blossom leaves a few
  triangles at these sizes), no smoothing (Mesh.Smoothing = 0), one thread, fixed seed; the mesh
  size is chosen for about 10k, 200k or 1M quads (--sizes, default 10k,200k,1m). This gives
  inputs like the issue's reference plate (min/avg scaled Jacobian about 0.2/0.87).
* every mesh in data/ and in the Mesquite test meshes (../shared/meshes/mesquite relative to the
  repository, or --mesquite DIR), when quadopt can read it: the planar ones (curved surfaces
  and meshes with triangles are skipped with a note).

Quad-dominant meshes (--quad-dominant, issue 32)
-----------------------------------------------
Instead of the meshes above: quads and triangles together. Per sample model of
tools/make_samples.py (its geometry and mesh size), the gmsh mesh with the triangles kept
(make_samples.gmsh_quads(..., mixed=True): Mesh.Algorithm = 8, Blossom recombination, or the
simple recombination (Mesh.RecombinationAlgorithm = 0) where Blossom leaves no triangle, no
all-quad subdivision), labelled qd/NAME ("raw"), and the same mesh perturbed by make_samples.perturb
with the model's seed, jitter and defect targets, defects at triangles first, plus a target of
PERTURB_INVERT (-0.3) when the model's own are all positive, so that faces invert
(qd/NAME+perturbed); then data/*_mixed.vtk and Mesquite's untangled/polarMesh.vtk (216 quads,
24 triangles). A triangle is scored by Verdict's triangle scaled Jacobian (see Evaluator); min,
avg and inverted are over all faces; the faces column gives the triangles among them. DMO is
quad-only and not run. GETMe gets the mixed mesh as a polygonal mesh (GetmeConfig(4) holds the
transformations of triangles and quads), but the driver in ../shared/peers/getme reads quads
only: --getme (or $QUADOPT_GETME_DIR) must name a copy of that directory whose getme_smooth.cpp
also reads and writes VTK type 5 (a triangle as four ids with -1 fourth, its loops over a face's
own corner count), made outside this repository (GETMe is GPL); with the unextended driver the
GETMe rows are missing, with a note. In the default (quad) runs a mesh with triangles is skipped
with a note.

Tools (each on the same input nodes; "held" = never moved)
----------------------------------------------------------
* gmsh Laplace2D, Relocate2D, UntangleMeshGeometry: `gmsh.model.mesh.optimize(name)` with
  General.NumThreads = 1, Mesh.Renumber = 0, on a plane surface, boundary nodes held (gmsh's 2D
  optimizers only move nodes classified on the surface). Synthetic plates are smoothed in the
  session that meshed them (OpenCASCADE plane surface). A mesh read from a file is rebuilt in a
  new session: every boundary node becomes a geometric point, every boundary edge a line, the
  boundary loops a plane surface (built-in kernel); interior nodes are added on that surface with
  the surface's own parametric coordinates, nodes flagged in a `fixed` array become geometric
  points too (so they are held), quads are given in the surface's orientation. Between the
  optimizers (and between repeats) every node is put back with `setNode`, and the script checks
  that the coordinates are bit-identical to the file's before each run. Only the optimize call
  is timed (time.perf_counter). Why a plane surface: on a discrete surface (a mesh merged or
  added as is) none of the three optimizers moves any node, even with force=True. Checked on the
  2k-quad plate: the rebuilt surface gives UntangleMeshGeometry's result of the meshing session
  to 1e-16, and Laplace2D's and Relocate2D's within 0.03 on the minimum and 3e-4 on the average
  (they visit the nodes in another order). UntangleMeshGeometry is skipped above
  --untangle-max-quads (default 50000; it took 50 CPU-s on 13.7k quads and did not finish in
  10 min on 186k).
* GETMe (Vartziotis and Wipper): the driver in --getme DIR (default ../shared/peers/getme, or
  $QUADOPT_GETME_DIR; GPL, so it is built, never copied into this repository), built once with
  its build.sh into --out-dir, run as `getme_smooth getme IN OUT` on a valid input and
  `getme_smooth untangle+getme IN OUT` on one with inverted quads (or one GETMe's own test finds
  invalid), boundary and `fixed` vertices held. Its time is the driver's `seconds`: its own
  timer around the smoothing calls (GETMe's copy of the mesh and its quality evaluations
  included; no file IO, no set-up of the polygonal mesh); GETMe's internal stopwatches
  (`getme_seconds`, loops only) go to the JSON. One thread: built without TBB, its
  std::execution::par_unseq calls run serially. Skipped with a note when it cannot be built.
* DMO (Zint and Grosso, IMR 2018): the driver in --dmo DIR (default ../shared/peers/dmo, or
  $QUADOPT_DMO_DIR), built once with its build.sh into --out-dir, run as
  `OMP_NUM_THREADS=1 dmo_smooth --metric vsj IN OUT` (Verdict's quad scaled Jacobian, 100
  sweeps, boundary and `fixed` vertices held); its time is the driver's `seconds` (set-up and
  solve, no file IO). Skipped with a note when the directory or a compiler is missing, and
  above --dmo-max-quads.
* quadopt, once per preset in --presets (default fast,balanced,best): `quadopt optimize IN -o
  OUT --json --effort NAME`, or the flags --preset-flags NAME=FLAGS gives for that preset, with
  the default options otherwise (boundary `auto`: the boundary may slide along itself or snap;
  `fixed` vertices held); its time is the report's own `seconds` (no file IO). A note says when
  the report's "effort" is not the preset asked for. With --quadopt-fixed also a `--boundary
  fixed` run of every preset (the setting that holds exactly what the peers hold; not counted
  in the dominance).
GETMe and DMO read this script's copy of a file mesh (the same nodes bit for bit, checked):
their readers trust a CELLS size that some files get wrong (Mesquite's unstrquad).

Every output is evaluated by ONE evaluator (class Evaluator: a numpy implementation of quadopt's
signed scaled Jacobian, which equals Verdict's quad scaled Jacobian on every quad that is not
inverted), always against the input's orientation, so min, avg and inverted (quads with scaled
Jacobian <= 0) mean the same for every tool. `quadopt quality --json` is run on every file as a
cross-check; where the two differ (only when a tool flipped a whole component, since quadopt
orients each file by itself) a note says so. The script also checks, per output, that the quads
are the input's and that every held vertex is bit-identical to the input; a violation is
printed as a note and flagged in the table. Times are medians over --repeat runs (default 3, or
1 for meshes of 500k quads or more; DMO --dmo-repeat, default 1; a run that took more than 20 s
is not repeated); the gmsh runs of one optimizer must give bit-identical coordinates on every
repeat. The JSON file holds {"gmsh": version, "presets": {name: flags}, "rows": [...],
"dominance": {...}}.
"""

import argparse
import hashlib
import json
import math
import os
import resource
import shlex
import statistics
import subprocess
import sys
import time

import numpy as np

GMSH_VERSION = "4.15.2"
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GMSH_METHODS = ["Laplace2D", "Relocate2D", "UntangleMeshGeometry"]
# A run longer than this many seconds is not repeated (its time is far from any noise).
LONG_RUN = 20.0

# The plate of data/plate_10holes.vtk: 10 x 5 minus ten disks (x, y, r).
PLATE_W, PLATE_H = 10.0, 5.0
PLATE_DISKS = [(1.0, 1.0, 0.45), (1.1, 3.9, 0.5), (2.8, 2.5, 0.6), (4.4, 1.0, 0.4), (4.5, 3.9, 0.45),
               (6.0, 2.4, 0.55), (7.5, 1.0, 0.4), (7.6, 3.9, 0.5), (9.0, 2.5, 0.45), (4.35, 2.45, 0.3)]
# Quads per unit of (mesh size)^-2 for this plate with Mesh.RecombinationAlgorithm = 3 (measured).
QUADS_PER_INV_SIZE2 = 57.9


def note(msg):
    print(f"note: {msg}", file=sys.stderr, flush=True)


# --------------------------------------------------------------------------------------------
# Legacy VTK (ASCII) in and out
# --------------------------------------------------------------------------------------------


class Mesh:
    """Points (n x 3 float64), faces (m x 4 int, as in the file; a triangle has -1 in its fourth
    slot, quadopt's NO_VERTEX), fixed flags (n bools) or None. The attribute keeps its old name,
    `quads`: on a quad mesh every face is one."""

    def __init__(self, points, quads, fixed):
        self.points = points
        self.quads = quads
        self.fixed = fixed


def read_vtk(path):
    """Reads an ASCII legacy VTK UNSTRUCTURED_GRID (quads, type 9, and triangles, type 5; vertex
    and line cells are ignored) or POLYDATA (3- and 4-vertex POLYGONS) with an optional
    point-data array `fixed`. A triangle is stored with -1 as its fourth vertex."""
    with open(path) as f:
        lines = f.read().split("\n")
    if len(lines) < 4 or lines[2].strip().upper() != "ASCII":
        raise ValueError("not an ASCII legacy VTK file")
    tok = " ".join(lines[3:]).split()
    i, pts, cells, types, polys, fixed = 0, None, None, None, None, None
    section, count = None, 0

    def nums(k, conv=float):
        nonlocal i
        if i + k > len(tok):
            raise ValueError("truncated file")
        v = [conv(t) for t in tok[i : i + k]]
        i += k
        return v

    while i < len(tok):
        k = tok[i].upper()
        i += 1
        if k == "DATASET":
            if tok[i].upper() not in ("UNSTRUCTURED_GRID", "POLYDATA"):
                raise ValueError(f"dataset {tok[i]} not supported")
            i += 1
        elif k == "POINTS":
            n = int(tok[i])
            i += 2
            pts = np.array(nums(3 * n), dtype=np.float64).reshape(n, 3)
        elif k in ("CELLS", "POLYGONS"):
            ncells = int(tok[i])
            i += 2
            if tok[i].upper() == "OFFSETS":
                raise ValueError("VTK 5 OFFSETS layout not supported by this reader")
            # Walk the per-cell counts: some files give a wrong total size.
            data = []
            for _ in range(ncells):
                c = int(tok[i])
                data += nums(c + 1, int)
            if k == "CELLS":
                cells = data
            else:
                polys = data
        elif k == "CELL_TYPES":
            n = int(tok[i])
            i += 1
            types = nums(n, int)
        elif k in ("POINT_DATA", "CELL_DATA"):
            section, count = k, int(tok[i])
            i += 1
        elif k == "SCALARS":
            name = tok[i]
            i += 2
            ncomp = 1
            if i < len(tok) and tok[i].isdigit():
                ncomp = int(tok[i])
                i += 1
            if i < len(tok) and tok[i].upper() == "LOOKUP_TABLE":
                i += 2
            vals = nums(count * ncomp)
            if section == "POINT_DATA" and name == "fixed":
                fixed = np.array(vals).reshape(count, ncomp).any(axis=1)
        elif k == "FIELD":
            narr = int(tok[i + 1])
            i += 2
            for _ in range(narr):
                name, ncomp, ntup = tok[i], int(tok[i + 1]), int(tok[i + 2])
                i += 4
                vals = nums(ncomp * ntup)
                if section == "POINT_DATA" and name == "fixed":
                    fixed = np.array(vals).reshape(ntup, ncomp).any(axis=1)
        elif k == "METADATA":
            raise ValueError("METADATA blocks not supported by this reader")
        else:
            raise ValueError(f"unsupported VTK keyword {k!r}")
    if pts is None:
        raise ValueError("no POINTS")
    quads = []
    if polys is not None:
        j = 0
        while j < len(polys):
            if polys[j] == 3:
                quads.append(polys[j + 1 : j + 4] + [-1])
            elif polys[j] == 4:
                quads.append(polys[j + 1 : j + 5])
            else:
                raise ValueError(f"a polygon of {polys[j]} vertices (only triangles and quads)")
            j += polys[j] + 1
    if cells is not None:
        j = 0
        for t in types:
            n = cells[j]
            if t == 9:
                quads.append(cells[j + 1 : j + 5])
            elif t == 5:
                quads.append(cells[j + 1 : j + 4] + [-1])
            elif t not in (1, 2, 3, 4):
                raise ValueError(f"not a quad or quad-dominant mesh (VTK cell type {t})")
            j += n + 1
    if not quads:
        raise ValueError("no quads")
    if fixed is not None and len(fixed) != len(pts):
        raise ValueError("fixed array size differs from the point count")
    return Mesh(pts, np.array(quads, dtype=np.int64), fixed)


def write_vtk(path, mesh, title="quadopt bench_peers"):
    out = ["# vtk DataFile Version 3.0", title, "ASCII", "DATASET UNSTRUCTURED_GRID", f"POINTS {len(mesh.points)} double"]
    out += [f"{x!r} {y!r} {z!r}" for x, y, z in mesh.points.tolist()]
    tri = is_triangle(mesh.quads)
    out.append(f"CELLS {len(mesh.quads)} {5 * len(mesh.quads) - int(tri.sum())}")
    out += ["3 %d %d %d" % tuple(q[:3]) if t else "4 %d %d %d %d" % tuple(q) for q, t in zip(mesh.quads.tolist(), tri.tolist())]
    out.append(f"CELL_TYPES {len(mesh.quads)}")
    out += ["5" if t else "9" for t in tri.tolist()]
    if mesh.fixed is not None:
        out += [f"POINT_DATA {len(mesh.points)}", "SCALARS fixed int 1", "LOOKUP_TABLE default"]
        out += ["1" if f else "0" for f in mesh.fixed.tolist()]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


# --------------------------------------------------------------------------------------------
# Topology
# --------------------------------------------------------------------------------------------


def is_triangle(faces):
    """Per face (rows of an m x 4 array), whether it is a triangle (-1 fourth)."""
    return faces[:, 3] < 0


def face_vertices(f):
    """A face's vertices (a list of 4 ints, -1 fourth for a triangle) without the sentinel."""
    return f[:3] if f[3] < 0 else f


def reverse_faces(faces):
    """Every face reversed (a triangle keeps its -1 fourth)."""
    out = faces[:, ::-1].copy()
    tri = is_triangle(faces)
    out[tri] = np.stack([faces[tri, 2], faces[tri, 1], faces[tri, 0], faces[tri, 3]], axis=1)
    return out


def directed_edges(faces):
    """(E x 2 directed edges in each face's direction, face index of each edge): four per quad,
    three per triangle."""
    nxt = np.roll(faces, -1, axis=1)
    tri = is_triangle(faces)
    nxt[tri, 2] = faces[tri, 0]
    mask = faces >= 0
    e = np.stack([faces, nxt], axis=2)
    return e[mask], np.nonzero(mask)[0]


def boundary_edges(quads):
    """Edges used by exactly one face, as (a, b) in the face's direction; raises on an edge used
    by more than two faces."""
    count = {}
    for q in quads.tolist():
        q = face_vertices(q)
        for k in range(len(q)):
            a, b = q[k], q[(k + 1) % len(q)]
            key = (min(a, b), max(a, b))
            c = count.get(key)
            count[key] = (c[0] + 1, c[1]) if c else (1, (a, b))
    out = []
    for n, e in count.values():
        if n > 2:
            raise ValueError("non-manifold edge")
        if n == 1:
            out.append(e)
    return out


def boundary_loops(quads):
    """Boundary loops as directed vertex lists; raises when a boundary vertex has other than one
    outgoing boundary edge (a vertex where loops touch)."""
    nxt = {}
    for a, b in boundary_edges(quads):
        if a in nxt:
            raise ValueError(f"boundary vertex {a} lies on two loops")
        nxt[a] = b
    seen, loops = set(), []
    for start in sorted(nxt):
        if start in seen:
            continue
        lp, v = [], start
        while v not in seen:
            seen.add(v)
            lp.append(v)
            v = nxt.get(v)
            if v is None:
                raise ValueError("open boundary")
        if v != start:
            raise ValueError("boundary loops touch")
        loops.append(lp)
    return loops


def plane_frame(points):
    """Centre and orthonormal (e1, e2, normal) of the best-fit plane of the points."""
    c = points.mean(axis=0)
    _, _, vt = np.linalg.svd(points - c, full_matrices=False)
    return c, vt[0], vt[1], vt[2]


def loop_area(points2, lp):
    p = points2[lp]
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def held_vertices(mesh):
    """Boundary vertices and fixed vertices (what gmsh and DMO hold)."""
    held = np.zeros(len(mesh.points), dtype=bool)
    for a, b in boundary_edges(mesh.quads):
        held[a] = held[b] = True
    if mesh.fixed is not None:
        held |= mesh.fixed
    return held


# --------------------------------------------------------------------------------------------
# gmsh
# --------------------------------------------------------------------------------------------


def gmsh_start():
    import gmsh

    gmsh.initialize(["-noenv"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.Renumber", 0)
    return gmsh


def mesh_plate(gmsh, quads_wanted):
    """Meshes the ten-hole plate in the current session (see the module docs); returns the
    mesh size used."""
    size = math.sqrt(QUADS_PER_INV_SIZE2 / quads_wanted)
    occ = gmsh.model.occ
    outer = occ.addRectangle(0, 0, 0, PLATE_W, PLATE_H)
    occ.cut([(2, outer)], [(2, occ.addDisk(x, y, 0, r, r)) for x, y, r in PLATE_DISKS])
    occ.synchronize()
    for k, v in dict(MeshSizeMin=size, MeshSizeMax=size, MeshSizeFromCurvature=0, MeshSizeExtendFromBoundary=1,
                     Algorithm=6, RecombineAll=1, RecombinationAlgorithm=3, Smoothing=0, RandomSeed=1).items():
        gmsh.option.setNumber("Mesh." + k, v)
    gmsh.model.mesh.generate(2)
    return size


def components(n, quads):
    """Per vertex, the id of its connected component (vertices joined through quads)."""
    parent = list(range(n))

    def find(v):
        while parent[v] != v:
            parent[v] = parent[parent[v]]
            v = parent[v]
        return v

    for q in quads.tolist():
        for k in range(1, 4):
            if q[k] < 0:
                continue
            ra, rb = find(q[0]), find(q[k])
            if ra != rb:
                parent[ra] = rb
    return np.array([find(v) for v in range(n)], dtype=np.int64)


def import_mesh(gmsh, mesh):
    """Rebuilds `mesh` in the current (empty) session on plane surfaces of the built-in kernel,
    one per connected component (see the module docs). Node tags are vertex index + 1."""
    geo = gmsh.model.geo
    m = gmsh.model.mesh
    quads = mesh.quads
    loops = boundary_loops(quads)
    used = used_vertices(quads)
    c, e1, e2, _ = plane_frame(mesh.points[used])
    p2 = np.stack([(mesh.points - c) @ e1, (mesh.points - c) @ e2], axis=1)
    comp = components(len(mesh.points), quads)
    bnd_point = {}
    for lp in loops:
        for v in lp:
            bnd_point[v] = geo.addPoint(*mesh.points[v].tolist())
    line_nodes = []  # (line tag, a, b)
    surf_of = {}  # component id -> surface tag
    for cid in sorted({int(comp[v]) for v in used}):
        mine = [lp for lp in loops if comp[lp[0]] == cid]
        if not mine:
            raise ValueError("a component without boundary")
        mine.sort(key=lambda lp: -abs(loop_area(p2, lp)))  # the outer loop first
        curve_loops = []
        for lp in mine:
            lines = []
            for k in range(len(lp)):
                a, b = lp[k], lp[(k + 1) % len(lp)]
                t = geo.addLine(bnd_point[a], bnd_point[b])
                lines.append(t)
                line_nodes.append((t, a, b))
            curve_loops.append(geo.addCurveLoop(lines))
        surf_of[cid] = geo.addPlaneSurface(curve_loops)
    bset = set(bnd_point)
    fixed_inner = []
    if mesh.fixed is not None:
        fixed_inner = [int(v) for v in used if mesh.fixed[v] and int(v) not in bset]
    fixed_point = {v: geo.addPoint(*mesh.points[v].tolist()) for v in fixed_inner}
    geo.synchronize()
    for v, t in list(bnd_point.items()) + list(fixed_point.items()):
        m.addNodes(0, t, [v + 1], mesh.points[v].tolist())
    next_elem = 1
    for t, a, b in line_nodes:
        m.addElementsByType(t, 1, [next_elem], [a + 1, b + 1])
        next_elem += 1
    quad_comp = comp[quads[:, 0]]
    for cid, surf in surf_of.items():
        inner = [int(v) for v in used if comp[v] == cid and int(v) not in bset and int(v) not in fixed_point]
        if inner:
            xyz = mesh.points[inner].reshape(-1)
            par = gmsh.model.getParametrization(2, surf, xyz.tolist())
            m.addNodes(2, surf, [v + 1 for v in inner], xyz.tolist(), list(par))
        # Faces in the surface's orientation: quads (gmsh type 3), then triangles (type 2).
        qs = quads[quad_comp == cid]
        probe = mesh.points[face_vertices(qs[0].tolist())].mean(axis=0)
        sn = np.array(gmsh.model.getNormal(surf, list(gmsh.model.getParametrization(2, surf, probe.tolist()))))
        p = mesh.points[qs]
        tri = is_triangle(qs)
        p[tri, 3] = p[tri, 0]  # a triangle's diagonals: (c - a) x (a - b) is its doubled normal
        mesh_normal = np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1]).sum(axis=0)
        if float(mesh_normal @ sn) < 0:
            qs = reverse_faces(qs)
        for etype, sel in ((3, ~is_triangle(qs)), (2, is_triangle(qs))):
            f = qs[sel][:, : 4 if etype == 3 else 3]
            if len(f):
                m.addElementsByType(surf, etype, list(range(next_elem, next_elem + len(f))), (f.reshape(-1) + 1).tolist())
                next_elem += len(f)
    return held_vertices(mesh)


def used_vertices(faces):
    """The vertices used by some face, sorted."""
    return np.unique(faces[faces >= 0])


def gmsh_session_nodes(gmsh):
    """Surface nodes (the movable ones) with coordinates and parametric coordinates."""
    out = []
    for dim, tag in gmsh.model.getEntities(2):
        t, x, u = gmsh.model.mesh.getNodes(dim, tag, includeBoundary=False, returnParametricCoord=True)
        out.append((t.astype(np.int64), np.array(x), np.array(u)))
    return out


def gmsh_coords(gmsh, tag_index, n):
    """All node coordinates as an (n x 3) array indexed by vertex (tag_index maps tag -> vertex)."""
    tags, xyz, _ = gmsh.model.mesh.getNodes()
    out = np.full((n, 3), np.nan)
    out[tag_index[tags.astype(np.int64)]] = np.array(xyz).reshape(-1, 3)
    return out


def run_gmsh(mesh_source, repeat, out_dir, label, untangle_max_quads):
    """Runs the three gmsh optimizers. mesh_source is ("plate", quads_wanted) or ("file", Mesh).
    Returns (input Mesh, input path or None, {method: result dict}), writing the outputs."""
    gmsh = gmsh_start()
    results = {}
    try:
        gmsh.model.add(label)
        if mesh_source[0] == "plate":
            size = mesh_plate(gmsh, mesh_source[1])
            types, _, nodes = gmsh.model.mesh.getElements(2)
            if list(types) != [3]:
                raise RuntimeError(f"gmsh left element types {list(types)}, not all quads")
            tags, xyz, _ = gmsh.model.mesh.getNodes()
            tags = tags.astype(np.int64)
            quad_tags = np.array(nodes[0], dtype=np.int64).reshape(-1, 4)
            used = np.unique(quad_tags)  # the file holds the nodes of quads, in gmsh's tag order
            n = len(used)
            pos = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
            pos[tags] = np.arange(len(tags))
            # tag -> vertex; tags of nodes used by no quad map to the extra row n.
            tag_index_for_coords = np.full(int(tags.max()) + 1, n, dtype=np.int64)
            tag_index_for_coords[used] = np.arange(n)
            n_coords = n + 1
            points = np.array(xyz).reshape(-1, 3)[pos[used]]
            quads = tag_index_for_coords[quad_tags]
            p = points[quads]
            if np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1])[:, 2].sum() < 0:
                quads = quads[:, ::-1].copy()  # counter-clockwise in the file
            mesh = Mesh(points, quads, None)
            held = held_vertices(mesh)
            in_path = os.path.join(out_dir, f"{label}.vtk")
            write_vtk(in_path, mesh, f"ten-hole plate, gmsh mesh size {size!r} (tools/bench_peers.py)")
            back = read_vtk(in_path)  # what quadopt and DMO get: the same nodes, bit for bit
            if not (np.array_equal(back.points, mesh.points) and np.array_equal(back.quads, mesh.quads)):
                raise RuntimeError("the written plate differs from gmsh's mesh")
        else:
            mesh = mesh_source[1]
            held = import_mesh(gmsh, mesh)
            in_path = None
            n = len(mesh.points)
            tag_index_for_coords = np.arange(-1, n, dtype=np.int64)  # tag t -> vertex t - 1
            tag_index_for_coords[0] = n
            n_coords = n + 1
        used = used_vertices(mesh.quads)
        start = gmsh_session_nodes(gmsh)

        def coords():
            return gmsh_coords(gmsh, tag_index_for_coords, n_coords)[:n]

        def reset():
            for t, x, u in start:
                for k in range(len(t)):
                    gmsh.model.mesh.setNode(int(t[k]), x[3 * k : 3 * k + 3].tolist(), u[2 * k : 2 * k + 2].tolist())

        elem_before = [x.copy() for x in gmsh.model.mesh.getElements(2)[2]]
        for method in GMSH_METHODS:
            if method == "UntangleMeshGeometry" and len(mesh.quads) > untangle_max_quads:
                note(f"{label}: gmsh {method} skipped ({len(mesh.quads)} quads > --untangle-max-quads {untangle_max_quads})")
                continue
            times, cpu, first = [], [], None
            for r in range(repeat):
                if times and times[0] > LONG_RUN:
                    break
                reset()
                c0 = coords()
                if not np.array_equal(c0[used], mesh.points[used]):
                    raise RuntimeError("gmsh's nodes differ from the input before a run")
                t0, c0 = time.perf_counter(), time.process_time()
                gmsh.model.mesh.optimize(method)
                times.append(time.perf_counter() - t0)
                cpu.append(time.process_time() - c0)
                c = coords()
                if first is None:
                    first = c
                elif not np.array_equal(first[used], c[used]):
                    note(f"{label}: gmsh {method} gave different coordinates on repeat {r + 1}")
            after = gmsh.model.mesh.getElements(2)[2]
            if len(after) != len(elem_before) or not all(np.array_equal(x, y) for x, y in zip(after, elem_before)):
                note(f"{label}: gmsh {method} changed the connectivity")
            out = first.copy()
            unused = np.setdiff1d(np.arange(n), used)
            out[unused] = mesh.points[unused]
            out_path = os.path.join(out_dir, f"{label}.gmsh-{method}.vtk")
            write_vtk(out_path, Mesh(out, mesh.quads, mesh.fixed))
            results[method] = dict(seconds=statistics.median(times), times=times, cpu_seconds=cpu, cpu=statistics.median(cpu), output=out_path,
                                   held_moved=int(np.count_nonzero((out[held] != mesh.points[held]).any(axis=1))))
        reset()
    finally:
        gmsh.finalize()
    return mesh, in_path, results


# --------------------------------------------------------------------------------------------
# quadopt and the peers run as processes (DMO, GETMe)
# --------------------------------------------------------------------------------------------


def peer_copy(mesh, path):
    """Writes `mesh` to path in this script's plain layout and checks that it reads back bit for
    bit. GETMe and DMO get this copy of a file mesh: their readers trust a CELLS size that some
    files get wrong (Mesquite's unstrquad), which this script's reader walks around."""
    write_vtk(path, mesh)
    back = read_vtk(path)
    same_fixed = (back.fixed is None) == (mesh.fixed is None) and (mesh.fixed is None or np.array_equal(back.fixed, mesh.fixed))
    if not (np.array_equal(back.points, mesh.points) and np.array_equal(back.quads, mesh.quads) and same_fixed):
        raise RuntimeError("the peers' copy of the mesh differs from the file")
    return path


def quality(quadopt, path):
    r = subprocess.run([quadopt, "quality", "--json", path], capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(r.stderr.strip() or r.stdout.strip())
    j = json.loads(r.stdout)
    return dict(min=j["min"], avg=j["avg"], inverted=j["inverted"], quads=j["quads"])


class Evaluator:
    """The scaled Jacobian of every output, measured against the INPUT's orientation: quads
    made consistent across shared edges as quadopt does, then each connected component turned
    so that its total signed area in the input is positive; points projected onto the input's
    plane (x, y when z is constant). Per quad: the minimum over its corners of
    cross(next - p, prev - p) / (|next - p| |prev - p|), 0 for an edge shorter than 10 eps
    times the quad's bounding-box diagonal, a quad whose last two corners coincide measured as
    that triangle (quadopt's and Verdict's rules); per triangle (a -1 fourth vertex), Verdict's
    triangle scaled Jacobian: the minimum over its corners of the cross product over the product
    of the two edge lengths, times 2/sqrt(3) (1 for an equilateral triangle), signed the same
    way. A tool that flips a whole component thus shows inverted faces (quadopt quality, which
    orients each file by itself, would not)."""

    def __init__(self, mesh):
        used = used_vertices(mesh.quads)
        z = mesh.points[used, 2]
        if np.ptp(z) == 0:
            self.frame = None
        else:
            c, e1, e2, _ = plane_frame(mesh.points[used])
            self.frame = (c, e1, e2)
        quads = self._consistent(mesh.quads)
        p = self._project(mesh.points)
        comp = components(len(mesh.points), quads)[quads[:, 0]]
        area = self._areas(p, quads)
        for cid in np.unique(comp):
            sel = comp == cid
            if area[sel].sum() < 0:
                quads[sel] = reverse_faces(quads[sel])
        self.quads = quads
        self.tri = is_triangle(quads)

    @staticmethod
    def _consistent(quads):
        """Reverses quads so that every interior edge is run in opposite directions by its two
        quads (the minority of each component is reversed); raises if not orientable."""
        quads = quads.copy()
        e, face = directed_edges(quads)
        lo, hi = e.min(axis=1), e.max(axis=1)
        key = lo * (int(quads.max()) + 1) + hi
        order = np.argsort(key, kind="stable")
        k = key[order]
        dup = np.nonzero(k[1:] == k[:-1])[0]
        a, b = order[dup], order[dup + 1]
        same = e[a, 0] == e[b, 0]
        if not same.any():
            return quads
        adj = {}
        for qa, qb, sm in zip(face[a].tolist(), face[b].tolist(), same.tolist()):
            adj.setdefault(qa, []).append((qb, sm))
            adj.setdefault(qb, []).append((qa, sm))
        flip = {}
        for seed in range(len(quads)):
            if seed in flip:
                continue
            flip[seed] = False
            comp, head = [seed], 0
            while head < len(comp):
                q = comp[head]
                head += 1
                for nb, sm in adj.get(q, ()):
                    want = flip[q] ^ sm
                    if nb not in flip:
                        flip[nb] = want
                        comp.append(nb)
                    elif flip[nb] != want:
                        raise ValueError("mesh is not orientable")
            flipped = [q for q in comp if flip[q]]
            minority = flipped if 2 * len(flipped) <= len(comp) else [q for q in comp if not flip[q]]
            for q in minority:
                quads[q] = reverse_faces(quads[q : q + 1])[0]
        return quads

    def _project(self, points):
        if self.frame is None:
            return points[:, :2]
        c, e1, e2 = self.frame
        return np.stack([(points - c) @ e1, (points - c) @ e2], axis=1)

    @staticmethod
    def _areas(p, quads):
        q = quads.copy()
        tri = is_triangle(q)
        q[tri, 3] = q[tri, 0]  # a triangle as a quad with a repeated corner: the same area
        x, y = p[q][..., 0], p[q][..., 1]
        return 0.5 * (x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y).sum(axis=1)

    def scaled_jacobians(self, points):
        """Per face, its signed scaled Jacobian (quads and triangles as in the class docs)."""
        p = self._project(points)
        sj = np.empty(len(self.quads))
        sj[~self.tri] = self._quad_sj(p[self.quads[~self.tri]])
        sj[self.tri] = self._triangle_sj(p[self.quads[self.tri, :3]])
        return sj

    @staticmethod
    def _triangle_sj(p):
        """Verdict's triangle scaled Jacobian of each triangle (t x 3 x 2 corners), signed."""
        if len(p) == 0:
            return np.empty(0)
        a, b, c = p[:, 0], p[:, 1], p[:, 2]
        l0, l1, l2 = (np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1), np.linalg.norm(a - c, axis=1))
        big = np.maximum(np.maximum(l0 * l2, l0 * l1), l1 * l2)
        cross = (b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            sj = np.where(big > 0, cross * (2 / math.sqrt(3)) / big, 0.0)
        return np.clip(sj, -1.0, 1.0)

    @staticmethod
    def _quad_sj(p):
        """The quad scaled Jacobian of each quad (m x 4 x 2 corners), signed."""
        if len(p) == 0:
            return np.empty(0)
        e = np.roll(p, -1, axis=1) - p  # edge i: corner i -> i + 1
        ln = np.linalg.norm(e, axis=2)
        ej, lj = np.roll(e, 1, axis=1), np.roll(ln, 1, axis=1)  # edge into corner i
        with np.errstate(divide="ignore", invalid="ignore"):
            c = (ej[..., 0] * e[..., 1] - ej[..., 1] * e[..., 0]) / (ln * lj)
        sj = c.min(axis=1)
        diag = np.linalg.norm(p.max(axis=1) - p.min(axis=1), axis=1)
        short = (ln == 0) | (ln < 10 * np.finfo(float).eps * diag[:, None])
        sj[short.any(axis=1)] = 0.0
        tri = np.nonzero((p[:, 3] == p[:, 2]).all(axis=1))[0]
        for t in tri.tolist():
            a, b, cc = p[t, 0], p[t, 1], p[t, 2]
            ls = sorted([np.linalg.norm(b - a), np.linalg.norm(cc - b), np.linalg.norm(a - cc)])
            cr = (b - a)[0] * (cc - a)[1] - (b - a)[1] * (cc - a)[0]
            den = ls[2] * ls[1]
            sj[t] = cr / den * 2 / math.sqrt(3) if den > 1e-30 else 0.0
        return sj

    def edge_ratio(self, points):
        """Smallest shortest/longest edge ratio of a face: the scaled Jacobian does not see
        aspect ratio, so a quad squashed into a thin rectangle scores near 1 and only this shows it."""
        p = self._project(points)
        e, _ = directed_edges(self.quads)
        ln = np.full(self.quads.shape, np.nan)
        ln[self.quads >= 0] = np.linalg.norm(p[e[:, 1]] - p[e[:, 0]], axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            return float(np.nan_to_num(np.nanmin(ln, axis=1) / np.nanmax(ln, axis=1)).min())

    def stats(self, points):
        sj = self.scaled_jacobians(points)
        return dict(min=float(sj.min()), avg=float(sj.mean()), inverted=int(np.count_nonzero(sj <= 0)), quads=len(sj),
                    triangles=int(self.tri.sum()), edge_ratio=self.edge_ratio(points))


def child_cpu():
    u = resource.getrusage(resource.RUSAGE_CHILDREN)
    return u.ru_utime + u.ru_stime


def run_quadopt(quadopt, in_path, out_path, repeat, flags, io_cpu):
    """quadopt's own timing of the run (no IO); the process's CPU seconds less io_cpu (see
    quadopt_io_cpu) as its CPU time. The report's "effort" (the preset that ran, when the
    binary reports one) goes to the row."""
    times, cpu = [], []
    for _ in range(repeat):
        if times and times[0] > LONG_RUN:
            break
        c0 = child_cpu()
        r = subprocess.run([quadopt, "optimize", in_path, "-o", out_path, "--json", *flags], capture_output=True, text=True)
        cpu.append(child_cpu() - c0)
        if r.returncode != 0:
            raise RuntimeError(r.stderr.strip() or r.stdout.strip())
        j = json.loads(r.stdout)
        times.append(j["seconds"])
    return dict(seconds=statistics.median(times), times=times, process_cpu_seconds=cpu, io_cpu_seconds=io_cpu,
                cpu=max(0.0, statistics.median(cpu) - io_cpu), effort=j.get("effort"), quadopt_flags=list(flags), output=out_path)


def quadopt_io_cpu(quadopt, in_path, out_path):
    """CPU seconds of a quadopt run that only reads, sets up, does one sweep and writes (no
    untangling, no max-min stage): subtracted from each run's process CPU to take IO out."""
    c0 = child_cpu()
    subprocess.run([quadopt, "optimize", in_path, "-o", out_path, "--json", "--max-iter", "1",
                    "--boundary", "fixed", "--no-untangle", "--no-maxmin"], capture_output=True, text=True)
    return child_cpu() - c0


def preset_flags(presets, overrides):
    """quadopt's flags per preset: `--effort NAME`, or what --preset-flags NAME=FLAGS gives."""
    return {name: shlex.split(overrides[name]) if name in overrides else ["--effort", name] for name in presets}


def parse_preset_flags(items):
    """--preset-flags values (NAME=FLAGS) as {name: flags string}."""
    out = {}
    for it in items or []:
        name, eq, flags = it.partition("=")
        if not eq or not name.strip():
            sys.exit(f"error: --preset-flags wants NAME=FLAGS, got {it!r}")
        out[name.strip()] = flags
    return out


def has_effort_flag(quadopt):
    r = subprocess.run([quadopt, "optimize", "--help"], capture_output=True, text=True)
    return "--effort" in r.stdout


def build_peer(peer_dir, out_dir, exe_name, sources):
    """Builds a peer with its build.sh into out_dir (never inside the peer's directory, which
    may be read-only) unless the executable is newer than its build.sh and `sources`."""
    exe = os.path.join(out_dir, exe_name)
    src = [os.path.join(peer_dir, f) for f in ("build.sh", *sources)]
    if os.path.exists(exe) and all(os.path.getmtime(exe) >= os.path.getmtime(s) for s in src):
        return exe
    r = subprocess.run(["bash", os.path.join(peer_dir, "build.sh"), out_dir], capture_output=True, text=True)
    if r.returncode != 0 or not os.path.exists(exe):
        raise RuntimeError(f"build failed: {(r.stderr or r.stdout).strip()[-500:]}")
    return exe


def run_driver(cmd, cpu, env=None):
    """Runs a peer's driver, appending its CPU seconds to `cpu`; returns the process and the JSON
    report on its last stdout line (a RuntimeError when there is none)."""
    c0 = child_cpu()
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    cpu.append(child_cpu() - c0)
    try:
        return r, json.loads(r.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        raise RuntimeError(r.stderr.strip() or "no report")


def run_dmo(exe, in_path, out_path, repeat):
    times, cpu = [], []
    env = dict(os.environ, OMP_NUM_THREADS="1")
    for _ in range(repeat):
        r, j = run_driver([exe, "--metric", "vsj", in_path, out_path], cpu, env)
        if r.returncode != 0 or not j.get("ok"):
            raise RuntimeError(j.get("error") or r.stderr.strip())
        if j.get("threads") != 1:
            raise RuntimeError(f"DMO ran with {j.get('threads')} threads")
        times.append(j["seconds"])
    c0 = child_cpu()
    subprocess.run([exe, "--metric", "vsj", "--iters", "0", in_path, out_path + ".io.vtk"], capture_output=True, text=True, env=env)
    io = child_cpu() - c0
    return dict(seconds=statistics.median(times), times=times, process_cpu_seconds=cpu, io_cpu_seconds=io,
                cpu=max(0.0, statistics.median(cpu) - io), output=out_path)


class GetmeRefused(RuntimeError):
    """GETMe's driver failed; input_valid is GETMe's own verdict on the input (None: unknown)."""

    def __init__(self, msg, input_valid):
        super().__init__(msg)
        self.input_valid = input_valid


def run_getme(exe, in_path, out_path, repeat, mode):
    """GETMe's driver in `mode` (getme or untangle+getme); its time is the driver's own timer of
    the smoothing calls (`seconds`). No CPU time: the driver has no IO-only mode to subtract."""
    times, own, cpu = [], [], []
    for _ in range(repeat):
        if times and times[0] > LONG_RUN:
            break
        r, j = run_driver([exe, mode, in_path, out_path], cpu)
        if r.returncode != 0 or not j.get("ok"):
            raise GetmeRefused(j.get("error") or r.stderr.strip(), j.get("input_valid"))
        times.append(j["seconds"])
        own.append(j["getme_seconds"])
    return dict(seconds=statistics.median(times), times=times, getme_seconds=own, process_cpu_seconds=cpu,
                cpu=None, mode=mode, note=j.get("note", ""), output=out_path)


def run_getme_for(exe, in_path, out_path, repeat, inverted):
    """GETMe as a user would run it: `getme` on a valid input, `untangle+getme` on one with
    inverted quads; also `untangle+getme` when GETMe's own validity test (its mean ratio)
    refuses an input the evaluator finds valid."""
    if inverted:
        return run_getme(exe, in_path, out_path, repeat, "untangle+getme")
    try:
        return run_getme(exe, in_path, out_path, repeat, "getme")
    except GetmeRefused as e:
        if e.input_valid is not False:
            raise
        r = run_getme(exe, in_path, out_path, repeat, "untangle+getme")
        r["note"] = (r["note"] + "; " if r["note"] else "") + "GETMe found the input invalid: untangle+getme"
        return r


# --------------------------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------------------------


def parse_size(s):
    s = s.strip().lower()
    mult = 1
    if s.endswith("k"):
        mult, s = 1000, s[:-1]
    elif s.endswith("m"):
        mult, s = 1000000, s[:-1]
    return int(float(s) * mult)


def size_label(n):
    return f"{n // 1000000}m" if n % 1000000 == 0 else f"{n // 1000}k" if n % 1000 == 0 else str(n)


def check_output(mesh, path, must_hold):
    """Number of quads differing from the input's and of vertices in must_hold that moved."""
    out = read_vtk(path)
    if out.points.shape != mesh.points.shape:
        return dict(error="output has another vertex count")
    bad_quads = int(np.count_nonzero((out.quads != mesh.quads).any(axis=1))) if out.quads.shape == mesh.quads.shape else -1
    moved = int(np.count_nonzero((out.points[must_hold] != mesh.points[must_hold]).any(axis=1)))
    return dict(bad_quads=bad_quads, held_moved=moved)


def cross_check(label, name, mine, theirs):
    """Notes where quadopt's own evaluator disagrees with the script's."""
    if not (abs(mine["min"] - theirs["min"]) <= 1e-9 and abs(mine["avg"] - theirs["avg"]) <= 1e-9
            and mine["inverted"] == theirs["inverted"]):
        note(f"{label}: {name}: quadopt quality gives min/avg/inverted {theirs['min']:.6f}/{theirs['avg']:.6f}/"
             f"{theirs['inverted']}, measured against the input's orientation {mine['min']:.6f}/{mine['avg']:.6f}/"
             f"{mine['inverted']}")


def bench_mesh(args, label, source, quadopt, presets, dmo_exe, getme_exe):
    """All tools on one mesh (presets: {name: quadopt flags}); returns a list of row dicts."""
    out_dir = args.out_dir
    stem = label.replace("/", "_")
    rows = []
    if source[0] == "file":
        path = source[1]
        try:
            q_in = quality(quadopt, path)
        except RuntimeError as e:
            note(f"{label}: skipped, quadopt cannot read it ({str(e).splitlines()[0]})")
            return []
        try:
            mesh = read_vtk(path)
        except ValueError as e:
            note(f"{label}: skipped, this script cannot read it ({e})")
            return []
        if is_triangle(mesh.quads).any() and not args.quad_dominant:
            note(f"{label}: skipped, it has triangles (a quad-dominant mesh: see --quad-dominant)")
            return []
        nq = len(mesh.quads)
    else:
        nq = source[1]
        mesh, path, q_in = None, None, None
    repeat = args.repeat if args.repeat else (1 if nq >= 500000 else 3)

    # gmsh first: for a plate it also makes the mesh everyone else gets.
    gmsh_res = {}
    if not args.no_gmsh:
        try:
            t0 = time.perf_counter()
            gsrc = ("plate", source[1]) if source[0] == "plate" else ("file", mesh)
            m, p, gmsh_res = run_gmsh(gsrc, repeat, out_dir, stem, args.untangle_max_quads)
            if source[0] == "plate":
                mesh, path = m, p
            note(f"{label}: gmsh done in {time.perf_counter() - t0:.1f} s")
        except Exception as e:  # gmsh raises plain Exception; a mesh it cannot take is a note
            if source[0] == "plate":
                raise
            note(f"{label}: gmsh skipped ({e})")
    if mesh is None:
        raise RuntimeError("a plate needs gmsh to be meshed")
    if q_in is None:
        q_in = quality(quadopt, path)
    nq = len(mesh.quads)
    try:
        evaluator = Evaluator(mesh)
    except ValueError as e:
        note(f"{label}: skipped ({e})")
        return []
    q_quadopt = q_in
    q_in = evaluator.stats(mesh.points)
    cross_check(label, "input", q_in, q_quadopt)
    held = held_vertices(mesh)
    fixed = mesh.fixed if mesh.fixed is not None else np.zeros(len(mesh.points), dtype=bool)
    ntri = q_in["triangles"]
    rows.append(dict(mesh=label, quads=nq, triangles=ntri, tool="input", seconds=None,
                     **{k: q_in[k] for k in ("min", "avg", "inverted", "edge_ratio")}))

    runs = []  # (tool name, result dict, vertices that must not move)
    peer_path = path if source[0] == "plate" else peer_copy(mesh, os.path.join(out_dir, f"{stem}.peer-input.vtk"))
    for method in GMSH_METHODS:
        if method in gmsh_res:
            runs.append((f"gmsh {method}", gmsh_res[method], held))
    if getme_exe:
        try:
            r = run_getme_for(getme_exe, peer_path, os.path.join(out_dir, f"{stem}.getme.vtk"), repeat, q_in["inverted"])
            if r["note"]:
                note(f"{label}: GETMe: {r['note']}")
            runs.append(("GETMe", r, held))
        except RuntimeError as e:
            hint = ("; its driver reads quads only: give --getme a copy extended to triangles (see the module docs)"
                    if ntri and "cell type 5" in str(e) else "")
            note(f"{label}: GETMe skipped ({e}){hint}")
    if dmo_exe and ntri:
        note(f"{label}: DMO skipped (quad-only; {ntri} triangles)")
    elif dmo_exe and nq <= args.dmo_max_quads:
        try:
            runs.append(("DMO", run_dmo(dmo_exe, peer_path, os.path.join(out_dir, f"{stem}.dmo.vtk"), args.dmo_repeat), held))
        except RuntimeError as e:
            note(f"{label}: DMO skipped ({e})")
    elif dmo_exe:
        note(f"{label}: DMO skipped ({nq} quads > --dmo-max-quads {args.dmo_max_quads})")
    io_cpu = quadopt_io_cpu(quadopt, path, os.path.join(out_dir, f"{stem}.quadopt-io.vtk"))
    variants = [(f"quadopt {name}", f"{stem}.quadopt-{name}", flags, fixed) for name, flags in presets.items()]
    if args.quadopt_fixed:
        variants += [(f"quadopt {name} --boundary fixed", f"{stem}.quadopt-{name}-fixed", [*flags, "--boundary", "fixed"], held)
                     for name, flags in presets.items()]
    for name, out_stem, flags, must_hold in variants:
        try:
            r = run_quadopt(quadopt, path, os.path.join(out_dir, out_stem + ".vtk"), repeat, flags, io_cpu)
        except RuntimeError as e:
            note(f"{label}: {name} failed ({e})")
            continue
        if "--effort" in flags and r["effort"] != flags[flags.index("--effort") + 1]:
            note(f"{label}: {name}: the report says effort {r['effort']!r}")
        runs.append((name, r, must_hold))

    for name, r, must_hold in runs:
        chk = check_output(mesh, r["output"], must_hold)
        failed = []
        if chk.get("error"):
            failed.append(chk["error"])
        else:
            if chk["bad_quads"]:
                failed.append(f"{chk['bad_quads']} quads changed")
            if chk["held_moved"]:
                failed.append(f"{chk['held_moved']} held vertices moved")
        for f in failed:
            note(f"{label}: {name}: {f}")
        q = evaluator.stats(read_vtk(r["output"]).points)
        cross_check(label, name, q, quality(quadopt, r["output"]))
        rows.append(dict(mesh=label, quads=nq, triangles=ntri, tool=name, seconds=r["seconds"], times=r["times"], cpu=r["cpu"],
                         **{k: r[k] for k in ("cpu_seconds", "process_cpu_seconds", "getme_seconds", "mode", "effort", "quadopt_flags")
                            if r.get(k) is not None},
                         min=q["min"], avg=q["avg"], edge_ratio=q["edge_ratio"], inverted=q["inverted"], flags=failed))
    return rows


# The defect target (a scaled Jacobian) added to a sample model's perturbation in the
# quad-dominant set when the model's own targets are all positive: every perturbed mesh has
# inverted faces.
PERTURB_INVERT = -0.3

# CPU times below this (seconds) are within the noise of process accounting: no CPU ratio.
CPU_FLOOR = 1e-3

# An output whose smallest edge ratio (shortest over longest edge of a quad) falls below this
# fraction of the input's is "thin": it has squashed quads, which the scaled Jacobian scores well.
THIN = 0.1

# Dominance (see the module docs): a min or avg within QUALITY_SLACK of the peer's reaches it,
# and a time under TIME_FLOOR counts as TIME_FLOOR (below 1 ms the timers measure noise).
QUALITY_SLACK = 1e-3
TIME_FLOOR = 1e-3


def role(tool):
    """"input", "peer" (gmsh, GETMe, DMO), "preset" (quadopt as users run it; plain "quadopt" in
    JSON files written before the presets) or "other" (quadopt --boundary fixed)."""
    if tool == "input":
        return "input"
    if tool.startswith("gmsh ") or tool in ("GETMe", "DMO"):
        return "peer"
    if tool == "quadopt" or (tool.startswith("quadopt ") and " --" not in tool):
        return "preset"
    return "other"


def is_thin(row, input_row):
    r = row.get("edge_ratio")
    return r is not None and input_row is not None and r < THIN * input_row["edge_ratio"]


def by_mesh(rows):
    """{(mesh, quads): {tool: row}}, in the rows' order."""
    out = {}
    for r in rows:
        out.setdefault((r["mesh"], r["quads"]), {})[r["tool"]] = r
    return out


def reference_preset(tools):
    """The quadopt row the ratio columns divide by: the balanced preset (the default) if it ran,
    else the first preset that did."""
    presets = [r for name, r in tools.items() if role(name) == "preset"]
    return tools.get("quadopt balanced") or (presets[0] if presets else None)


def ratios(rows):
    """Per row, the reference preset's time over the peer's, wall-clock and CPU (None where
    not a peer, or either CPU time is missing or below CPU_FLOOR)."""
    refs = {key: reference_preset(tools) for key, tools in by_mesh(rows).items()}
    out = []
    for r in rows:
        q = refs.get((r["mesh"], r["quads"]))
        if q is None or role(r["tool"]) != "peer":
            out.append((None, None))
            continue
        wall = q["seconds"] / r["seconds"] if r["seconds"] > 0 else None
        qc, tc = q.get("cpu"), r.get("cpu")
        cpu = qc / tc if qc is not None and tc is not None and min(qc, tc) >= CPU_FLOOR else None
        out.append((wall, cpu))
    return out


def fmt_seconds(x):
    return "–" if x is None else (f"{x:.4f}" if x < 1 else f"{x:.2f}")


def tool_label(r):
    """The tool's name, with GETMe's mode when it untangled first and "(!)" after a failed check."""
    name = r["tool"] + (f" ({r['mode']})" if r.get("mode", "getme") != "getme" else "")
    return name + (" (!)" if r.get("flags") else "")


def fmt_faces(r):
    """The face count, with the triangles among them when there are any."""
    return f"{r['quads']} ({r['triangles']} tri)" if r.get("triangles") else f"{r['quads']}"


def fmt_rows(rows):
    inputs = {key: tools.get("input") for key, tools in by_mesh(rows).items()}
    faces = "faces" if any(r.get("triangles") for r in rows) else "quads"
    out = [f"| mesh | {faces} | tool | seconds | CPU s | min SJ | avg SJ | inverted | edge ratio | quadopt / tool (s) | quadopt / tool (CPU) |",
           "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for r, (wall, cpu) in zip(rows, ratios(rows)):
        thin = " thin" if r["tool"] != "input" and is_thin(r, inputs[(r["mesh"], r["quads"])]) else ""
        out.append(f"| {r['mesh']} | {fmt_faces(r)} | {tool_label(r)} | {fmt_seconds(r['seconds'])} | {fmt_seconds(r.get('cpu'))} | "
                   f"{r['min']:.3f} | {r['avg']:.3f} | {r['inverted']} | {r['edge_ratio']:.1e}{thin} | "
                   f"{'' if wall is None else f'{wall:.3g}'} | {'' if cpu is None else f'{cpu:.3g}'} |")
    return "\n".join(out)


def fmt_wide(rows):
    """One row per mesh: per tool "min / avg (inverted), seconds" (each tool's own timer, the
    time the dominance compares); a peer run that no preset dominates is marked "(not
    dominated)"."""
    tools = []
    for r in rows:
        if r["tool"] not in tools:
            tools.append(r["tool"])
    left = {(n["mesh"], n["peer"]) for n in dominance(rows)["not_dominated"]}
    faces = "faces" if any(r.get("triangles") for r in rows) else "quads"
    out = [f"| mesh | {faces} | " + " | ".join(tools) + " |", "| --- | ---: | " + " | ".join("---" for _ in tools) + " |"]
    for (mesh, nq), t in by_mesh(rows).items():
        first = next(iter(t.values()))
        cells = []
        for name in tools:
            r = t.get(name)
            if r is None:
                cells.append("–")
                continue
            c = f"{r['min']:.3f} / {r['avg']:.3f}"
            if r["inverted"]:
                c += f" ({r['inverted']} inv.)"
            if name != "input" and is_thin(r, t.get("input")):
                c += f" (thin {r['edge_ratio']:.0e})"
            if r.get("seconds") is not None:
                c += f", {fmt_seconds(r['seconds'])} s"
            if (mesh, name) in left:
                c += " (not dominated)"
            if r.get("flags"):
                c += " (!)"
            cells.append(c)
        out.append(f"| {mesh} | {fmt_faces(first)} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def misses(preset, peer):
    """What keeps a preset's row from dominating a peer's row (empty: it dominates)."""
    out = []
    if max(preset["seconds"], TIME_FLOOR) > max(peer["seconds"], TIME_FLOOR):
        out.append("slower")
    if preset["min"] < peer["min"] - QUALITY_SLACK:
        out.append("min")
    if preset["avg"] < peer["avg"] - QUALITY_SLACK:
        out.append("avg")
    if preset["inverted"] > peer["inverted"]:
        out.append("inverted")
    if preset.get("flags"):
        out.append("failed check")  # an output that changed the quads or moved a held vertex wins nothing
    return out


def run_summary(r):
    return dict(seconds=r["seconds"], min=r["min"], avg=r["avg"], inverted=r["inverted"])


def dominance(rows):
    """The dominance count over all meshes (see the module docs): per preset and in all, with
    the peer runs no preset dominates and the thin ones left out."""
    per_preset, thin, not_dominated = {}, [], []
    counted = dominated = 0
    for (mesh, _), tools in by_mesh(rows).items():
        presets = [r for name, r in tools.items() if role(name) == "preset"]
        for p in presets:
            per_preset.setdefault(p["tool"], 0)
        for peer in (r for name, r in tools.items() if role(name) == "peer"):
            if is_thin(peer, tools.get("input")):
                thin.append(dict(mesh=mesh, peer=peer["tool"], edge_ratio=peer["edge_ratio"]))
                continue
            counted += 1
            miss = {p["tool"]: misses(p, peer) for p in presets}
            for name, m in miss.items():
                per_preset[name] += not m
            if any(not m for m in miss.values()):
                dominated += 1
            else:
                not_dominated.append(dict(mesh=mesh, peer=peer["tool"], run=run_summary(peer),
                                          presets={p["tool"]: dict(run_summary(p), misses=miss[p["tool"]]) for p in presets}))
    return dict(dominated=dominated, counted=counted, thin=len(thin), peer_runs=counted + len(thin), per_preset=per_preset,
                not_dominated=not_dominated, thin_runs=thin)


def dominance_count(d):
    """The summary's numbers alone (--dominance-count)."""
    return {k: d[k] for k in ("dominated", "counted", "thin", "peer_runs", "per_preset")}


def fmt_run(r):
    return f"{fmt_seconds(r['seconds'])} s / {r['min']:.3f} / {r['avg']:.3f} / {r['inverted']}"


def fmt_dominance(d):
    out = [f"Dominance: {d['dominated']} of {d['counted']} counted peer runs dominated by some quadopt preset "
           f"({d['peer_runs']} peer runs, {d['thin']} left out as thin)"]
    out += [f"  {name}: dominates {n} of {d['counted']}" for name, n in d["per_preset"].items()]
    if d["thin_runs"]:
        out.append("  thin, left out: " + ", ".join(f"{t['mesh']} {t['peer']} ({t['edge_ratio']:.0e})" for t in d["thin_runs"]))
    if d["not_dominated"]:
        names = list(d["per_preset"])
        out += ["", "Not dominated (time / min SJ / avg SJ / inverted; what each preset misses):", "",
                "| mesh | peer | peer's run | " + " | ".join(names) + " |",
                "| --- | --- | --- | " + " | ".join("---" for _ in names) + " |"]
        for n in d["not_dominated"]:
            cells = [f"{fmt_run(n['presets'][p])}: {', '.join(n['presets'][p]['misses'])}" if p in n["presets"] else "–"
                     for p in names]
            out.append(f"| {n['mesh']} | {n['peer']} | {fmt_run(n['run'])} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0], formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.splitlines()[1:]))
    ap.add_argument("--sizes", default="10k,200k,1m",
                    help="synthetic plate sizes in quads, comma separated (k, m suffixes), or 'none' (default 10k,200k,1m)")
    ap.add_argument("--skip-1m", action="store_true", help="leave out synthetic sizes of 1M quads and more")
    ap.add_argument("--no-data", action="store_true", help="leave out the meshes in data/")
    ap.add_argument("--no-mesquite", action="store_true", help="leave out the Mesquite meshes")
    ap.add_argument("--only", help="only meshes whose label contains this string")
    ap.add_argument("--mesquite", default=os.path.join(ROOT, "..", "shared", "meshes", "mesquite"),
                    help="Mesquite mesh directory (default ../shared/meshes/mesquite from the repository)")
    ap.add_argument("--out-dir", default=os.path.join(ROOT, "target", "bench-peers"),
                    help="where meshes, outputs and the peers' builds go (default target/bench-peers, ignored by git)")
    target = os.environ.get("CARGO_TARGET_DIR") or os.path.join(ROOT, "target")
    ap.add_argument("--quadopt", default=os.path.join(target, "release", "quadopt"),
                    help="quadopt binary (default $CARGO_TARGET_DIR or target/, then release/quadopt: run cargo build --release)")
    ap.add_argument("--presets", default="fast,balanced,best",
                    help="quadopt presets to run, comma separated (default fast,balanced,best); each is a row 'quadopt NAME'")
    ap.add_argument("--preset-flags", action="append", metavar="NAME=FLAGS",
                    help="run preset NAME with these quadopt flags instead of --effort NAME (repeatable; "
                         "e.g. \"fast=--no-maxmin --max-iter 10\", \"balanced=\")")
    ap.add_argument("--quadopt-fixed", action="store_true",
                    help="also run every preset with --boundary fixed (holds what the peers hold; not counted in the dominance)")
    ap.add_argument("--getme", default=os.environ.get("QUADOPT_GETME_DIR", os.path.join(ROOT, "..", "shared", "peers", "getme")),
                    help="GETMe peer directory with build.sh (default $QUADOPT_GETME_DIR or ../shared/peers/getme)")
    ap.add_argument("--no-getme", action="store_true", help="do not run GETMe")
    ap.add_argument("--dmo", default=os.environ.get("QUADOPT_DMO_DIR", os.path.join(ROOT, "..", "shared", "peers", "dmo")),
                    help="DMO peer directory with build.sh (default $QUADOPT_DMO_DIR or ../shared/peers/dmo)")
    ap.add_argument("--no-dmo", action="store_true", help="do not run DMO")
    ap.add_argument("--dmo-max-quads", type=int, default=300000, help="skip DMO above this many quads (default 300000)")
    ap.add_argument("--dmo-repeat", type=int, default=1, help="DMO runs per mesh (default 1)")
    ap.add_argument("--untangle-max-quads", type=int, default=50000,
                    help="skip gmsh UntangleMeshGeometry above this many quads (default 50000: it takes minutes)")
    ap.add_argument("--no-gmsh", action="store_true", help="do not run gmsh's optimizers on file meshes")
    ap.add_argument("--repeat", type=int, help="runs per tool and mesh, median reported (default 3; 1 from 500k quads)")
    ap.add_argument("--wide", action="store_true",
                    help="one row per mesh (min / avg and each tool's own seconds per tool, peer runs no preset dominates marked) instead of one per tool")
    ap.add_argument("--json", metavar="PATH",
                    help="also write all rows (with every run's time) and the dominance summary as JSON to PATH ('-': stdout)")
    ap.add_argument("--from-json", metavar="PATH", help="print the table and the dominance of an earlier --json file instead of running")
    ap.add_argument("--quad-dominant", action="store_true",
                    help="run the quad-dominant set (sample models meshed with triangles kept, raw and perturbed; "
                         "data/*_mixed.vtk; Mesquite's polarMesh) instead of the quad meshes; DMO is quad-only and skipped")
    ap.add_argument("--dominance-count", action="store_true",
                    help="print only the dominance count, as one JSON line on stdout (for scripts)")
    ap.add_argument("--surfaces", action="store_true",
                    help="run the curved-surface set instead (tools/bench_surfaces.py: the surface samples, "
                         "their unperturbed meshes and Mesquite's curved meshes against gmsh's Laplace2D and "
                         "Relocate2D and OpenMesh's JacobiLaplaceSmootherT); --quadopt and --repeat apply")
    args = ap.parse_args()
    if args.json == "-" and args.dominance_count:
        ap.error("--json - and --dominance-count both want stdout")
    return args


def peer_exe(name, peer_dir, out_dir, build_dir, exe_name, source, default_dir=None):
    """A peer's executable, built with its build.sh into OUT_DIR/build_dir (a directory of its
    own for a peer directory other than default_dir, e.g. GETMe's copy extended to triangles,
    so that one build never stands in for another); None (with a note) when the peer is
    missing or its build fails."""
    if default_dir is not None and os.path.realpath(peer_dir) != os.path.realpath(default_dir):
        build_dir += "-" + hashlib.sha1(os.path.realpath(peer_dir).encode()).hexdigest()[:10]
    if not os.path.exists(os.path.join(peer_dir, "build.sh")):
        note(f"no {name} row: no {name} peer at {peer_dir} (--{name.lower()} DIR or QUADOPT_{name.upper()}_DIR)")
        return None
    try:
        return build_peer(os.path.abspath(peer_dir), os.path.join(os.path.abspath(out_dir), build_dir), exe_name, [source])
    except RuntimeError as e:
        note(f"no {name} row: {e}")
        return None


def mesh_list(args):
    """(label, source) of every mesh to run: ("plate", quads) or ("file", path)."""
    meshes = []
    if args.sizes.strip().lower() != "none":
        for s in args.sizes.split(","):
            n = parse_size(s)
            if args.skip_1m and n >= 1000000:
                continue
            meshes.append((f"plate10_{size_label(n)}", ("plate", n)))
    if not args.no_data:
        d = os.path.join(ROOT, "data")
        meshes += [(f[:-4], ("file", os.path.join(d, f))) for f in sorted(os.listdir(d)) if f.endswith(".vtk")]
    if not args.no_mesquite:
        if os.path.isdir(args.mesquite):
            for sub in sorted(os.listdir(args.mesquite)):
                d = os.path.join(args.mesquite, sub)
                if os.path.isdir(d):
                    meshes += [(f"mesquite/{sub}/{f[:-4]}", ("file", os.path.join(d, f))) for f in sorted(os.listdir(d)) if f.endswith(".vtk")]
        else:
            note(f"no Mesquite meshes at {args.mesquite}")
    if args.only:
        meshes = [m for m in meshes if args.only in m[0]]
    return meshes


def padded(faces):
    """Faces given as lists of 3 or 4 vertices as an m x 4 array (-1 fourth for a triangle)."""
    return np.array([list(f) + [-1] * (4 - len(f)) for f in faces], dtype=np.int64)


def quad_dominant_list(args):
    """(label, ("file", path)) of the quad-dominant set (--quad-dominant; see the module docs):
    per sample model of tools/make_samples.py, its gmsh mesh with the triangles kept (raw) and
    that mesh perturbed with inverted faces; data/*_mixed.vtk; Mesquite's polarMesh."""
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import make_samples as ms

    d = os.path.join(args.out_dir, "quad-dominant")
    os.makedirs(d, exist_ok=True)
    meshes = []
    for s in ms.SAMPLES:
        name = s["name"]
        if args.only and args.only not in f"qd/{name}" and args.only not in f"qd/{name}+perturbed":
            continue
        points = faces = None
        for rec in (1, 0):  # Blossom, then the simple recombination where Blossom leaves no triangle
            r = ms.gmsh_quads(s["build"], s["size"], 8, recombination=rec, mixed=True)
            if r is not None and any(len(f) == 3 for f in r[1]):
                points, faces = r
                break
        if faces is None:
            note(f"qd/{name}: skipped, gmsh left no triangle")
            continue
        if not all(ms.signed_area(points, f) > 0 for f in faces):
            note(f"qd/{name}: skipped, gmsh made an invalid face")
            continue
        fixed = None
        if s.get("fixed_outer"):
            _, _, bnd = ms.topology(len(points), faces)
            outer = set(ms.outer_loop(points, ms.boundary_loops(bnd)))
            fixed = np.array([v in outer for v in range(len(points))])
        defects = list(s["defects"]) if min(s["defects"]) < 0 else [PERTURB_INVERT] + list(s["defects"])
        try:
            moved = ms.perturb(points, faces, s["seed"], s["jitter"], s["slide"], defects, True)
        except Exception as e:  # the perturbation is make_samples.py's: a failure there is a note
            note(f"qd/{name}: no perturbed mesh ({e})")
            moved = None
        f4 = padded(faces)
        for label, pts in ((f"qd/{name}", points), (f"qd/{name}+perturbed", moved)):
            if pts is None:
                continue
            xyz = np.zeros((len(pts), 3))
            xyz[:, :2] = np.array(pts, dtype=np.float64)
            path = os.path.join(d, label.replace("/", "_") + ".vtk")
            write_vtk(path, Mesh(xyz, f4, fixed), f"{label}: gmsh quad-dominant mesh of make_samples.py's {name} (tools/bench_peers.py)")
            meshes.append((label, ("file", path)))
    data = os.path.join(ROOT, "data")
    meshes += [(f"data/{f[:-4]}", ("file", os.path.join(data, f))) for f in sorted(os.listdir(data)) if f.endswith("_mixed.vtk")]
    polar = os.path.join(args.mesquite, "untangled", "polarMesh.vtk")
    if os.path.exists(polar):
        meshes.append(("mesquite/untangled/polarMesh", ("file", polar)))
    else:
        note(f"no polarMesh at {polar}")
    if args.only:
        meshes = [m for m in meshes if args.only in m[0]]
    return meshes


def report(args, rows, record):
    """Prints the table and the dominance summary (or the count alone) and writes the JSON."""
    d = dominance(rows)
    if args.json:
        text = json.dumps(dict(record, rows=rows, dominance=d), indent=1)
        if args.json == "-":
            print(text)
        else:
            with open(args.json, "w") as f:
                f.write(text + "\n")
    if args.dominance_count:
        print(json.dumps(dominance_count(d)))
    elif args.json != "-":
        print(fmt_wide(rows) if args.wide else fmt_rows(rows))
        print()
        print(fmt_dominance(d))


def main():
    args = parse_args()
    if args.surfaces:
        cmd = [sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "bench_surfaces.py"),
               "--quadopt", args.quadopt]
        if args.repeat:
            cmd += ["--repeat", str(args.repeat)]
        if args.only:
            cmd += ["--only", args.only]
        sys.exit(subprocess.call(cmd))
    if args.from_json:
        with open(args.from_json) as f:
            record = json.load(f)
        args.json = None  # recomputed from the rows, never written back
        report(args, record.pop("rows"), record)
        return

    import gmsh

    if gmsh.__version__ != GMSH_VERSION:
        note(f"gmsh {gmsh.__version__} found, this comparison was made with {GMSH_VERSION}")
    quadopt = os.path.abspath(args.quadopt)
    if not os.access(quadopt, os.X_OK):
        sys.exit(f"error: no quadopt binary at {quadopt} (cargo build --release, or --quadopt BIN)")
    names = [p.strip() for p in args.presets.split(",") if p.strip()]
    overrides = parse_preset_flags(args.preset_flags)
    for name in sorted(set(overrides) - set(names)):
        note(f"--preset-flags {name}=...: {name} is not in --presets, not run")
    presets = preset_flags(names, overrides)
    if any(f[:1] == ["--effort"] for f in presets.values()) and not has_effort_flag(quadopt):
        sys.exit(f"error: {quadopt} has no --effort option: give --preset-flags NAME=FLAGS for every preset in --presets")
    os.makedirs(args.out_dir, exist_ok=True)
    if args.quad_dominant and not args.no_dmo:
        note("no DMO rows: DMO is quad-only (it takes no triangles)")
        args.no_dmo = True
    shared = os.path.join(ROOT, "..", "shared", "peers")
    dmo_exe = None if args.no_dmo else peer_exe("DMO", args.dmo, args.out_dir, "dmo-build", "dmo_smooth", "dmo_smooth.cpp",
                                                os.path.join(shared, "dmo"))
    getme_exe = None if args.no_getme else peer_exe("GETMe", args.getme, args.out_dir, "getme-build", "getme_smooth", "getme_smooth.cpp",
                                                    os.path.join(shared, "getme"))

    rows = []
    for label, source in quad_dominant_list(args) if args.quad_dominant else mesh_list(args):
        rows += bench_mesh(args, label, source, quadopt, presets, dmo_exe, getme_exe)
    report(args, rows, dict(gmsh=gmsh.__version__, presets=presets))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Sample meshes for quadopt (data/*.vtk), made reproducibly.

Usage:  pip install -r tools/requirements.txt      # gmsh==4.15.2 (pinned: the mesher decides the meshes)
        python3 tools/make_samples.py               # writes data/*.vtk, data/README.md, prints the table
        python3 tools/make_samples.py --check       # regenerates in memory, exit 1 if data/ differs
        python3 tools/make_samples.py --surfaces DIR   # only the surface samples (in data/ too; and their
                                                       # unperturbed *_clean meshes), into DIR; see
                                                       # "Surface samples" below

Each mesh imitates one of the models of Akram, Si and Chen's Table 1 (plates with circular and
square holes, irregular patches with notches, a maze-like wheel): the domain is built with gmsh's
OpenCASCADE kernel and meshed with quad-dominant recombination of an unstructured triangulation
(Frontal-Delaunay for quads, Mesh.Algorithm = 8, with Blossom recombination, the boundary given
an even number of edges; if a triangle is left, Frontal-Delaunay, Mesh.Algorithm = 6; failing
that, twice the size with every element split into quads, Mesh.SubdivisionAlgorithm = 1). Such
meshes are valid but mediocre (minimum scaled Jacobian 0.1 to 0.7, the lowest where a quad has
three vertices on a sharp boundary), so to reach the paper's poor inputs the vertices are then
perturbed with a fixed seed (every move is halved until no quad of the vertex's star falls below
the lowest defect target + 0.05, so inverted quads come from the defects only):

1. every interior vertex moves by a random vector in a disc of radius `jitter` times its shortest
   incident edge; boundary vertices in the middle of a straight boundary segment optionally move
   ALONG that segment (by at most `slide` times the shorter of their two boundary edges), so they
   stay on the true boundary (at most one of two boundary neighbours moves); vertices on curves
   and corners never move;
2. "defects": a few interior vertices, each in a star untouched by the previous defects, are moved
   along a random direction just far enough that the worst quad of their star reaches a chosen
   scaled Jacobian (bisection on the distance), so each mesh's input minimum is the number set
   below (0.55 ... -0.55, as in Table 1), with a handful of inverted quads where it is negative.

Connectivity is never changed: the meshes stay all-quad and manifold, and since only interior
vertices (and tangential moves along straight segments) were perturbed, a valid configuration with
the same boundary exists. Output: legacy VTK ASCII UNSTRUCTURED_GRID, cell type 9, coordinates with
repr() (round-trip precision), z = 0, quads counter-clockwise; two meshes carry a point-data int
array `fixed` marking their outer boundary. Everything is deterministic: gmsh runs single-threaded
with fixed options, the perturbations use random.Random(seed), nothing depends on time or dict
order. The quality printed is the signed 2D scaled Jacobian (quadopt's definition): per quad the
minimum over its corners of cross(e_next/|e_next|, e_prev/|e_prev|).

Quad-dominant samples (MIXED_SAMPLES, data/*_mixed.vtk): three of the models meshed in one gmsh
run without the all-quad fallbacks, keeping the triangles the recombination leaves (VTK cell
type 5 next to 9); a triangle's quality is Verdict's triangle scaled Jacobian (quadopt's). See
README_MIXED below.
"""

import argparse
import math
import os
import random
import sys

GMSH_VERSION = "4.15.2"

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "data")


# --------------------------------------------------------------------------------------------
# Geometry (gmsh OpenCASCADE)
# --------------------------------------------------------------------------------------------


def plate(occ, w, h, disks=(), squares=()):
    """A w x h rectangle minus circular holes (x, y, r) and square holes (x, y, side, angle_deg)."""
    outer = occ.addRectangle(0, 0, 0, w, h)
    tools = []
    for x, y, r in disks:
        tools.append((2, occ.addDisk(x, y, 0, r, r)))
    for x, y, s, a in squares:
        t = occ.addRectangle(x - s / 2, y - s / 2, 0, s, s)
        if a:
            occ.rotate([(2, t)], x, y, 0, 0, 0, 1, math.radians(a))
        tools.append((2, t))
    if tools:
        occ.cut([(2, outer)], tools)


def blob(occ, center, radii, notches=(), holes=()):
    """A closed B-spline curve through points at the given radii (equally spaced angles) minus
    polygonal notches (lists of (x, y)) and circular holes (x, y, r)."""
    cx, cy = center
    n = len(radii)
    pts = []
    for i, r in enumerate(radii):
        t = 2 * math.pi * i / n
        pts.append(occ.addPoint(cx + r * math.cos(t), cy + r * math.sin(t), 0))
    curve = occ.addBSpline(pts + [pts[0]])
    loop = occ.addCurveLoop([curve])
    surf = occ.addPlaneSurface([loop])
    tools = []
    for poly in notches:
        p = [occ.addPoint(x, y, 0) for x, y in poly]
        lines = [occ.addLine(p[i], p[(i + 1) % len(p)]) for i in range(len(p))]
        tools.append((2, occ.addPlaneSurface([occ.addCurveLoop(lines)])))
    for x, y, r in holes:
        tools.append((2, occ.addDisk(x, y, 0, r, r)))
    if tools:
        occ.cut([(2, surf)], tools)


def sector(occ, r_in, r_out, a0, a1):
    """The annular sector r_in <= r <= r_out, a0 <= angle <= a1 (radians), as a surface."""
    ring = occ.cut([(2, occ.addDisk(0, 0, 0, r_out, r_out))], [(2, occ.addDisk(0, 0, 0, r_in, r_in))])[0]
    # Keep the part inside the wedge: cut away its complement (a big polygon).
    big = 4 * r_out
    steps = 16
    span = 2 * math.pi - (a1 - a0)
    poly = [(0.0, 0.0)] + [
        (big * math.cos(a1 + span * k / steps), big * math.sin(a1 + span * k / steps)) for k in range(steps + 1)
    ]
    p = [occ.addPoint(x, y, 0) for x, y in poly]
    lines = [occ.addLine(p[i], p[(i + 1) % len(p)]) for i in range(len(p))]
    wedge = occ.addPlaneSurface([occ.addCurveLoop(lines)])
    return occ.cut(ring, [(2, wedge)])[0]


def mazewheel(occ):
    """A maze-like wheel: a disc with a central hole, three concentric ring walls with gaps, and
    radial walls sticking out of the rings into the corridors (dead ends)."""
    r_hole, r_out, t = 1.0, 5.0, 0.24
    body = occ.cut([(2, occ.addDisk(0, 0, 0, r_out, r_out))], [(2, occ.addDisk(0, 0, 0, r_hole, r_hole))])[0]
    walls = []
    # Ring walls at radius r, each with gaps of angular width g centred at the listed angles.
    rings = [(2.0, [30, 210]), (3.0, [120, 300]), (4.0, [75, 255])]
    g = math.radians(26)
    for r, gaps in rings:
        a = sorted(math.radians(x) for x in gaps)
        for k in range(len(a)):
            a0 = a[k] + g / 2
            a1 = a[(k + 1) % len(a)] - g / 2 + (2 * math.pi if k == len(a) - 1 else 0)
            walls += sector(occ, r - t / 2, r + t / 2, a0, a1)
    # Radial walls: from a ring wall outward (or inward) part of the way across the corridor.
    radial = [(2.0, 3.0, 100), (2.0, 1.0, 300), (3.0, 4.0, 200), (3.0, 2.0, 20), (4.0, 5.0, 160), (4.0, 3.0, 340)]
    for r_from, r_to, deg in radial:
        lo, hi = sorted((r_from, r_from + 0.62 * (r_to - r_from)))
        rect = occ.addRectangle(lo, -t / 2, 0, hi - lo, t)
        occ.rotate([(2, rect)], 0, 0, 0, 0, 0, 1, math.radians(deg))
        walls.append((2, rect))
    occ.cut(body, walls)


# --------------------------------------------------------------------------------------------
# Meshing
# --------------------------------------------------------------------------------------------


def gmsh_quads(build, size, algorithm, subdivide=False, recombination=1, mixed=False):
    """Meshes the geometry made by build(occ) with target size `size` and 2D algorithm
    `algorithm`, recombining with Blossom (Mesh.RecombinationAlgorithm = `recombination`, 1);
    returns (points, quads) with only the nodes used by quads, renumbered in gmsh's node order,
    quads counter-clockwise. An all-quad mesh needs an even number of boundary edges: when the
    1D mesh has an odd number, the longest curve gets one edge more. With `subdivide`, every
    element is split into quads (all-quad, four times as many). Returns None when triangles
    remain (only possible without `subdivide`). With `mixed` (quad-dominant samples), the
    boundary is left as the 1D mesher made it and the triangles the recombination leaves are
    kept: faces are then quads and triangles (3 vertices), all counter-clockwise."""
    import gmsh

    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.add("sample")
        occ = gmsh.model.occ
        build(occ)
        occ.removeAllDuplicates()
        occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMin", size)
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 1)
        gmsh.option.setNumber("Mesh.Algorithm", algorithm)
        gmsh.option.setNumber("Mesh.RecombineAll", 1)
        gmsh.option.setNumber("Mesh.RecombinationAlgorithm", recombination)
        gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 1 if subdivide else 0)
        gmsh.option.setNumber("Mesh.Smoothing", 1)
        gmsh.option.setNumber("Mesh.RandomSeed", 1)
        gmsh.model.mesh.generate(1)
        counts = {c: len(gmsh.model.mesh.getElements(1, c)[1][0]) for _, c in gmsh.model.getEntities(1)}
        if sum(counts.values()) % 2 and not mixed:
            longest = max(sorted(counts), key=lambda c: counts[c])
            gmsh.model.mesh.setTransfiniteCurve(longest, counts[longest] + 2)
            gmsh.model.mesh.clear()
            gmsh.model.mesh.generate(1)
        gmsh.model.mesh.generate(2)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        coord = {int(t): (float(xyz[3 * i]), float(xyz[3 * i + 1])) for i, t in enumerate(tags)}
        types, _, nodes = gmsh.model.mesh.getElements(2)
        quads = []
        for ty, nd in zip(types, nodes):
            if ty != 3 and not (mixed and ty == 2):
                return None
            k = 4 if ty == 3 else 3
            nd = [int(x) for x in nd]
            quads += [nd[k * i : k * i + k] for i in range(len(nd) // k)]
    finally:
        gmsh.finalize()
    used = sorted({v for q in quads for v in q})
    index = {t: i for i, t in enumerate(used)}
    points = [list(coord[t]) for t in used]
    quads = [[index[v] for v in q] for q in quads]
    for q in quads:
        if signed_area(points, q) < 0:
            q.reverse()
    return points, quads


def mesh_domain(build, size):
    """Frontal-Delaunay for quads (Mesh.Algorithm = 8) with Blossom recombination; if that
    leaves a triangle, Frontal-Delaunay (6); failing that, 6 at twice the size followed by
    subdivision into quads."""
    for algorithm in (8, 6):
        r = gmsh_quads(build, size, algorithm)
        if r is not None:
            return r
    return gmsh_quads(build, 2 * size, 6, subdivide=True)


# --------------------------------------------------------------------------------------------
# Quality and topology
# --------------------------------------------------------------------------------------------


def signed_area(p, q):
    a = 0.0
    k = len(q)
    for i in range(k):
        x0, y0 = p[q[i]]
        x1, y1 = p[q[(i + 1) % k]]
        a += x0 * y1 - x1 * y0
    return a / 2


def scaled_jacobian(p, q):
    """Signed 2D scaled Jacobian of a counter-clockwise quad (degenerate edge: 0), or of a
    triangle (3 vertices; see triangle_scaled_jacobian)."""
    if len(q) == 3:
        return triangle_scaled_jacobian(p, q)
    m = math.inf
    for i in range(4):
        x, y = p[q[i]]
        ax, ay = p[q[(i + 1) % 4]]
        bx, by = p[q[(i + 3) % 4]]
        e1 = (ax - x, ay - y)
        e2 = (bx - x, by - y)
        l1, l2 = math.hypot(*e1), math.hypot(*e2)
        if l1 == 0 or l2 == 0:
            return 0.0
        m = min(m, (e1[0] * e2[1] - e1[1] * e2[0]) / (l1 * l2))
    return m


def triangle_scaled_jacobian(p, t):
    """Verdict's triangle scaled Jacobian (quadopt's): twice the signed area over the largest
    product of two edge lengths, times 2/sqrt(3) (equilateral: 1); 0 when collapsed."""
    a, b, c = (p[v] for v in t)
    l0 = math.hypot(b[0] - a[0], b[1] - a[1])
    l1 = math.hypot(c[0] - b[0], c[1] - b[1])
    l2 = math.hypot(a[0] - c[0], a[1] - c[1])
    big = max(l0 * l2, l0 * l1, l1 * l2)
    if big == 0:
        return 0.0
    cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    return max(-1.0, min(1.0, cross * 2 / math.sqrt(3) / big))


def stats(p, quads):
    v = [scaled_jacobian(p, q) for q in quads]
    return min(v), sum(v) / len(v), max(v), sum(1 for x in v if x <= 0)


def topology(n, quads):
    """Per vertex: incident quads; boundary edges as a map v -> list of boundary neighbours."""
    vq = [[] for _ in range(n)]
    edges = {}
    for qi, q in enumerate(quads):
        for i in range(len(q)):
            vq[q[i]].append(qi)
            a, b = q[i], q[(i + 1) % len(q)]
            edges.setdefault((min(a, b), max(a, b)), []).append(qi)
    bnd = {}
    for (a, b), qs in edges.items():
        if len(qs) > 2:
            raise ValueError("non-manifold edge")
        if len(qs) == 1:
            bnd.setdefault(a, []).append(b)
            bnd.setdefault(b, []).append(a)
    for v, nb in bnd.items():
        if len(nb) != 2:
            raise ValueError(f"non-manifold boundary vertex {v}")
    return vq, edges, bnd


def boundary_loops(bnd):
    """Boundary loops as vertex lists (any direction), largest (by vertex count) first."""
    seen, loops = set(), []
    for start in sorted(bnd):
        if start in seen:
            continue
        lp, prev, v = [start], None, start
        seen.add(start)
        while True:
            a, b = bnd[v]
            nxt = a if a != prev else b
            if nxt == start:
                break
            lp.append(nxt)
            seen.add(nxt)
            prev, v = v, nxt
        loops.append(lp)
    return loops


def outer_loop(p, loops):
    def extent(lp):
        xs = [p[v][0] for v in lp]
        ys = [p[v][1] for v in lp]
        return (max(xs) - min(xs)) * (max(ys) - min(ys))

    return max(loops, key=extent)


# --------------------------------------------------------------------------------------------
# Perturbation
# --------------------------------------------------------------------------------------------


def perturb(points, quads, seed, jitter, slide, defects, triangles_first=False):
    """Perturbs a copy of `points` (see the module docs); returns the new points. With
    `triangles_first` (quad-dominant samples), the defects go first to vertices with a triangle
    in their star (in the same shuffled order), each moved towards the far edge of the first
    such triangle (by index) instead of in a random direction, so that triangles are among the
    worst faces."""
    rng = random.Random(seed)
    n = len(points)
    vq, edges, bnd = topology(n, quads)
    nbrs = [set() for _ in range(n)]
    for a, b in edges:
        nbrs[a].add(b)
        nbrs[b].add(a)
    h = [min(math.dist(points[v], points[u]) for u in nbrs[v]) for v in range(n)]
    p = [list(x) for x in points]

    # 1. Global jitter; straight-segment boundary vertices slide tangentially, at most one of
    # any two boundary neighbours, so each stays strictly between its (unmoved) neighbours.
    # A move that would put a quad of the vertex's star below `floor` is halved until it does
    # not (up to 4 times, then dropped), so inverted quads come from the defects only.
    floor = min(defects) + 0.05

    def try_move(v, dx, dy):
        x0, y0 = p[v]
        for _ in range(5):
            p[v][0], p[v][1] = x0 + dx, y0 + dy
            if min(scaled_jacobian(p, quads[q]) for q in vq[v]) >= floor:
                return True
            dx, dy = dx / 2, dy / 2
        p[v][0], p[v][1] = x0, y0
        return False

    slid = set()
    for v in range(n):
        rad, ang, s = math.sqrt(rng.random()), rng.uniform(0, 2 * math.pi), rng.uniform(-1, 1)
        if v not in bnd:
            try_move(v, jitter * h[v] * rad * math.cos(ang), jitter * h[v] * rad * math.sin(ang))
        elif slide > 0 and not slid.intersection(bnd[v]):
            a, b = bnd[v]
            pa, pb, pv = points[a], points[b], points[v]
            e1 = (pa[0] - pv[0], pa[1] - pv[1])
            e2 = (pb[0] - pv[0], pb[1] - pv[1])
            l1, l2 = math.hypot(*e1), math.hypot(*e2)
            cross = e1[0] * e2[1] - e1[1] * e2[0]
            if abs(cross) <= 1e-12 * l1 * l2 and e1[0] * e2[0] + e1[1] * e2[1] < 0:
                d = (pb[0] - pa[0], pb[1] - pa[1])
                t = slide * min(l1, l2) * s
                if d[0] == 0 or d[1] == 0:
                    # Axis-parallel segment: only the varying coordinate changes (exactly).
                    k = 0 if d[1] == 0 else 1
                    dx, dy = (math.copysign(t, d[0]), 0.0) if k == 0 else (0.0, math.copysign(t, d[1]))
                else:
                    ld = math.hypot(*d)
                    dx, dy = t * d[0] / ld, t * d[1] / ld
                if try_move(v, dx, dy):
                    slid.add(v)

    # 2. Defects: each pushes the worst quad of one interior vertex's star to a target value.
    touched = set()
    order = [v for v in range(n) if v not in bnd]
    rng.shuffle(order)
    if triangles_first:
        near = [v for v in order if any(len(quads[q]) == 3 for q in vq[v])]
        order = near + sorted(set(order) - set(near), key=order.index)
    it = iter(order)
    for target in defects:
        for v in it:
            star = set(vq[v])
            if star & touched:
                continue
            if min(scaled_jacobian(p, quads[q]) for q in star) <= target + 0.05:
                continue
            ang = rng.uniform(0, 2 * math.pi)
            dx, dy = math.cos(ang) * h[v], math.sin(ang) * h[v]
            tris = [quads[q] for q in sorted(star) if len(quads[q]) == 3]
            if triangles_first and tris:
                # Towards the far edge of a triangle of the star, which it can then invert.
                a, b = (u for u in tris[0] if u != v)
                mx, my = (p[a][0] + p[b][0]) / 2 - p[v][0], (p[a][1] + p[b][1]) / 2 - p[v][1]
                d = math.hypot(mx, my)
                dx, dy = mx / d * h[v], my / d * h[v]
            x0, y0 = p[v]

            def star_min(t):
                p[v][0], p[v][1] = x0 + t * dx, y0 + t * dy
                return min(scaled_jacobian(p, quads[q]) for q in star)

            t_hi = 0.9
            if star_min(t_hi) > target:
                p[v][0], p[v][1] = x0, y0
                continue
            lo, hi = 0.0, t_hi
            for _ in range(60):
                mid = (lo + hi) / 2
                if star_min(mid) > target:
                    lo = mid
                else:
                    hi = mid
            star_min(hi)
            # Every quad sharing a vertex with the star is off limits for later defects.
            for q in star:
                for u in quads[q]:
                    touched.update(vq[u])
            break
    return p


# --------------------------------------------------------------------------------------------
# The samples
# --------------------------------------------------------------------------------------------

SAMPLES = [
    # name, description, geometry, mesh size, seed, jitter, slide, defect targets, fixed outer
    dict(
        name="plate_1hole",
        what="plate with one circular hole (paper: 1 hole)",
        build=lambda occ: plate(occ, 4.0, 3.0, disks=[(2.0, 1.5, 0.7)]),
        size=0.66, seed=1, jitter=0.1, slide=0.0, defects=[0.558],
    ),
    dict(
        name="plate_2holes",
        what="plate with two circular holes (paper: 2 holes)",
        build=lambda occ: plate(occ, 5.0, 3.0, disks=[(1.35, 1.5, 0.65), (3.6, 1.45, 0.5)]),
        size=0.66, seed=2, jitter=0.35, slide=0.0, defects=[0.015, 0.2],
    ),
    dict(
        name="plate_2holes_2squares",
        what="plate with two circular and two square holes (paper: 2 holes 2 squares)",
        build=lambda occ: plate(
            occ, 6.0, 4.0, disks=[(1.5, 2.8, 0.6), (4.4, 1.2, 0.55)], squares=[(4.5, 2.9, 0.9, 0), (1.6, 1.1, 0.8, 30)]
        ),
        size=0.62, seed=3, jitter=0.4, slide=0.3, defects=[-0.556, -0.2, 0.1],
    ),
    dict(
        name="plate_3holes_1square",
        what="plate with three circular holes and a square hole (paper: 3 holes 1 square)",
        build=lambda occ: plate(
            occ, 6.0, 4.0, disks=[(1.3, 1.2, 0.55), (3.0, 2.9, 0.6), (4.8, 1.2, 0.5)], squares=[(4.8, 3.0, 0.8, 0)]
        ),
        size=0.62, seed=4, jitter=0.25, slide=0.0, defects=[0.554],
    ),
    dict(
        name="plate_3holes",
        what="plate with three circular holes of different sizes, outer boundary fixed (`fixed` array)",
        build=lambda occ: plate(occ, 7.0, 4.0, disks=[(1.5, 2.0, 0.9), (3.9, 1.3, 0.6), (5.5, 2.8, 0.45)]),
        size=0.5, seed=5, jitter=0.3, slide=0.0, defects=[0.3],
        fixed_outer=True,
    ),
    dict(
        name="plate_6holes_2squares",
        what="plate with six circular and two square holes (paper: 6 holes 2 squares)",
        build=lambda occ: plate(
            occ,
            9.0,
            5.0,
            disks=[(1.2, 1.2, 0.5), (3.0, 3.8, 0.6), (4.6, 1.4, 0.55), (6.4, 3.6, 0.5), (7.8, 1.3, 0.45), (1.3, 3.8, 0.4)],
            squares=[(3.0, 1.6, 0.8, 0), (6.3, 1.5, 0.9, 15)],
        ),
        size=0.53, seed=6, jitter=0.4, slide=0.3, defects=[-0.165, 0.05, 0.2],
    ),
    dict(
        name="plate_8holes",
        what="plate with eight circular holes (paper: 8 holes)",
        build=lambda occ: plate(
            occ,
            10.0,
            5.0,
            disks=[(1.3, 1.3, 0.55), (1.3, 3.7, 0.5), (3.7, 2.5, 0.75), (6.0, 1.2, 0.5),
                   (6.2, 3.8, 0.55), (8.5, 1.4, 0.6), (8.6, 3.8, 0.45), (4.9, 4.4, 0.3)],
        ),
        size=0.56, seed=8, jitter=0.4, slide=0.3, defects=[-0.513, -0.3, -0.1, 0.15],
    ),
    dict(
        name="plate_10holes",
        what="plate with ten circular holes, some close to each other (paper: 10 holes)",
        build=lambda occ: plate(
            occ,
            10.0,
            5.0,
            disks=[(1.0, 1.0, 0.45), (1.1, 3.9, 0.5), (2.8, 2.5, 0.6), (4.4, 1.0, 0.4), (4.5, 3.9, 0.45),
                   (6.0, 2.4, 0.55), (7.5, 1.0, 0.4), (7.6, 3.9, 0.5), (9.0, 2.5, 0.45), (4.35, 2.45, 0.3)],
        ),
        size=0.75, seed=10, jitter=0.45, slide=0.3, defects=[-0.098, 0.1],
    ),
    dict(
        name="patch_notched",
        what="irregular patch: curved outer boundary with three rectangular notches (paper: patch 5)",
        build=lambda occ: blob(
            occ,
            (0.0, 0.0),
            [2.0, 2.3, 1.9, 2.5, 2.2, 1.8, 2.4, 2.1, 1.9, 2.3],
            notches=[
                [(1.3, -0.25), (3.0, -0.25), (3.0, 0.25), (1.3, 0.25)],
                [(-0.3, 1.5), (0.3, 1.5), (0.3, 3.0), (-0.3, 3.0)],
                [(-3.0, -0.9), (-1.5, -0.9), (-1.5, -0.4), (-3.0, -0.4)],
            ],
        ),
        size=0.7, seed=55, jitter=0.4, slide=0.3, defects=[-0.156, 0.1],
    ),
    dict(
        name="patch_slotted",
        what="irregular patch: wavy outer boundary, V notches, a slot and a small hole (paper: patch 7)",
        build=lambda occ: blob(
            occ,
            (0.0, 0.0),
            [2.6, 2.9, 2.4, 3.1, 2.7, 2.3, 2.9, 3.2, 2.5, 2.8, 2.4, 3.0],
            notches=[
                [(1.2, 0.0), (3.5, -0.6), (3.5, 0.6)],
                [(-0.8, 1.6), (-1.6, 3.4), (0.0, 3.6)],
                [(-3.5, -0.2), (-1.2, -0.2), (-1.2, 0.2), (-3.5, 0.2)],
                [(0.3, -1.4), (0.9, -3.6), (-0.3, -3.6)],
            ],
            holes=[(0.6, 0.8, 0.35)],
        ),
        size=0.75, seed=77, jitter=0.4, slide=0.3, defects=[-0.529, -0.25, 0.05],
    ),
    dict(
        name="mazewheel",
        what="maze-like wheel: central hole, three ring walls with gaps, radial dead-end walls (paper: mazewheel 3)",
        build=mazewheel,
        size=0.48, seed=3, jitter=0.4, slide=0.3, defects=[-0.327, -0.15, 0.0, 0.2],
    ),
    dict(
        name="plate_1hole_fine",
        what="finer plate with one circular hole, outer boundary fixed (`fixed` array)",
        build=lambda occ: plate(occ, 8.0, 6.0, disks=[(4.0, 3.0, 1.4)]),
        size=0.15, seed=11, jitter=0.35, slide=0.0, defects=[0.25, 0.4],
        fixed_outer=True,
    ),
]


def model(name):
    """The sample called `name` (its geometry, size and perturbation settings)."""
    return next(s for s in SAMPLES if s["name"] == name)


# Quad-dominant samples: three of the models above meshed WITHOUT the all-quad fallbacks: one
# gmsh run (Mesh.Algorithm = 8, Frontal-Delaunay for quads; Mesh.SubdivisionAlgorithm = 0), the
# 1D mesh as gmsh made it (no extra edge for an even count), and the triangles the recombination
# leaves kept (VTK cell type 5 next to the quads' 9). Blossom (Mesh.RecombinationAlgorithm = 1)
# leaves triangles only where the boundary has an odd number of edges, which gmsh avoids on the
# plates and the wheel; there the simple recombination (Mesh.RecombinationAlgorithm = 0) is used,
# which leaves triangles wherever it finds no pair. Then the same seeded perturbation, with
# defects (some inverted faces) of their own, placed at triangles first (perturb's
# triangles_first).
MIXED_SAMPLES = [
    dict(
        model("plate_2holes"),
        name="plate_2holes_mixed",
        what="plate_2holes' plate, quads and triangles (simple recombination)",
        mixed=dict(algorithm=8, recombination=0), seed=2, defects=[-0.3, 0.1],
    ),
    dict(
        model("patch_notched"),
        name="patch_notched_mixed",
        what="patch_notched's patch, quads and triangles (Blossom, odd boundary)",
        mixed=dict(algorithm=8, recombination=1), seed=55, defects=[-0.2, 0.1],
    ),
    dict(
        model("mazewheel"),
        name="mazewheel_mixed",
        what="mazewheel's wheel, quads and triangles (simple recombination)",
        mixed=dict(algorithm=8, recombination=0), seed=3, defects=[-0.45, -0.2, 0.0, 0.2],
    ),
]


def make(sample):
    """Generates one sample: (points, faces, fixed flags or None); faces are quads, and for a
    quad-dominant sample (`mixed`) triangles too."""
    if sample.get("mixed"):
        m = sample["mixed"]
        points, quads = gmsh_quads(
            sample["build"], sample["size"], m["algorithm"], recombination=m["recombination"], mixed=True
        )
        assert any(len(q) == 3 for q in quads), "no triangle left: not a quad-dominant sample"
    else:
        points, quads = mesh_domain(sample["build"], sample["size"])
    n = len(points)
    _, _, bnd = topology(n, quads)
    assert all(signed_area(points, q) > 0 for q in quads), "mesher produced an invalid face"
    p = perturb(points, quads, sample["seed"], sample["jitter"], sample["slide"], sample["defects"],
                bool(sample.get("mixed")))
    fixed = None
    if sample.get("fixed_outer"):
        outer = set(outer_loop(points, boundary_loops(bnd)))
        fixed = [1 if v in outer else 0 for v in range(n)]
    return p, quads, fixed


def vtk_text(name, points, quads, fixed):
    out = ["# vtk DataFile Version 3.0", f"quadopt sample {name} (tools/make_samples.py)", "ASCII",
           "DATASET UNSTRUCTURED_GRID", f"POINTS {len(points)} double"]
    out += [f"{x!r} {y!r} 0.0" for x, y in points]
    out.append(f"CELLS {len(quads)} {sum(len(q) + 1 for q in quads)}")
    out += [f"{len(q)} " + " ".join(str(v) for v in q) for q in quads]
    out.append(f"CELL_TYPES {len(quads)}")
    out += ["9" if len(q) == 4 else "5" for q in quads]
    if fixed is not None:
        out += [f"POINT_DATA {len(points)}", "SCALARS fixed int 1", "LOOKUP_TABLE default"]
        out += [" ".join(str(f) for f in fixed[i : i + 20]) for i in range(0, len(fixed), 20)]
    return "\n".join(out) + "\n"


README_HEAD = """# Sample meshes

2D quad meshes (and quad-dominant ones, below) with boundaries like the models of the paper's
Table 1 (Akram, Si and Chen, 2021), with inputs as poor as the paper's: gmsh's quad-dominant
recombination of an unstructured triangulation, then interior vertices (and vertices on straight
boundary segments, along the segment only) perturbed with a fixed seed. Legacy VTK ASCII,
`UNSTRUCTURED_GRID`, quads (cell type 9) counter-clockwise, z = 0, coordinates with round-trip
precision. Quality: the signed 2D scaled Jacobian (quadopt's); inverted = quads with a
value <= 0. Made by tools/make_samples.py, which also wrote this file; tests/samples.rs
checks every method and boundary mode on all of them.

Regenerate (deterministic; gmsh pinned in tools/requirements.txt):

    pip install -r tools/requirements.txt
    python3 tools/make_samples.py            # writes data/*.vtk and this README, prints the table
    python3 tools/make_samples.py --check    # exit 1 if anything differs from the files here

| file | what | #V | #F | input min | input avg | inverted |
| --- | --- | ---: | ---: | ---: | ---: | ---: |
"""

README_MIXED = """
## Quad-dominant samples

Quads and triangles (cell types 9 and 5, both counter-clockwise): three of the models above
meshed by gmsh in one run, without the all-quad fallbacks above (Frontal-Delaunay for quads,
Mesh.Algorithm = 8; Mesh.SubdivisionAlgorithm = 0; the boundary's edge count left odd where the
1D mesher made it odd), keeping the triangles the recombination leaves. Blossom
(Mesh.RecombinationAlgorithm = 1) leaves triangles only where the boundary has an odd number of
edges, so it is used on patch_notched (33 boundary edges); on the plate and the wheel gmsh makes
the count even and Blossom gives all quads, so there the simple recombination
(Mesh.RecombinationAlgorithm = 0) is used. Then the same seeded perturbation as above (a
triangle's quality: Verdict's triangle scaled Jacobian, quadopt's), with defect targets of their
own, given first to vertices with a triangle in their star and pushing such a vertex towards the
far edge of that triangle (so triangles are among the worst faces; mazewheel_mixed has an
inverted one). #F counts all faces, #tri the triangles among them; min, avg and inverted are
over all faces.

| file | what | #V | #F | #tri | input min | input avg | inverted |
| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |
"""


# --------------------------------------------------------------------------------------------
# Surface samples (quad meshes on curved 3D surfaces; --surfaces OUTDIR)
# --------------------------------------------------------------------------------------------
#
# Three CAD models (gmsh OpenCASCADE) whose surfaces are meshed with the same recombination as
# the plates (mesh_surface: Mesh.Algorithm = 8, then 6, then 6 at twice the size with
# subdivision into quads; the sphere skips 8, with which gmsh 4.15.2 crashes on it;
# single-threaded, fixed seed; the quad-dominant bracket: one run of 8 with the simple
# recombination, keeping its triangles), then perturbed ALONG the surface
# (perturb_surface): only vertices classified on a CAD face move (those on CAD curves and
# points -- boundary loops, sharp edges, seams, feature corners -- never do), each by a random
# vector in the tangent plane of its face followed by gmsh.model.getClosestPoint onto that face,
# so every vertex stays on the exact CAD surface. As in perturb: a jitter whose moves are halved
# while they would put a face of the star below the lowest defect target + 0.05 (but at least
# 0.05, so that only the defects fold faces: one per negative target), then a few
# defects, each pushed by bisection along one tangent direction until the worst face of its star
# reaches the target (negative targets fold faces). Quality: the signed scaled Jacobian against
# the surface normal, per face the minimum over its corners of n . (e_next x e_prev) /
# (|e_next| |e_prev|), n the CAD face's unit normal at the point closest to the unperturbed
# face's centroid (oriented like the mesh); a triangle: 2/sqrt(3) n . cross / the largest
# product of two edge lengths. Faces are oriented consistently, outward (closed surfaces: positive
# volume; the open tube: away from its axis). Written with each sample: NAME_clean.vtk, the mesh
# before the perturbation (for tools/bench_surfaces.py). The functions mesh_surface and
# perturb_surface work in the caller's gmsh session, so that tools/bench_surfaces.py can run
# gmsh's own smoothers on the very same mesh with gmsh's parametrization.


def sphere(occ):
    """The unit sphere (one CAD face with a seam curve and two pole points)."""
    occ.addSphere(0, 0, 0, 1.0)


def bracket(occ):
    """An L-shaped bracket: a 3 x 2 x 2 box minus a box that leaves a 0.6 thick foot and leg; the
    inner bend (radius 0.4) and the outer bend and the foot's two outer vertical edges (0.5)
    filleted, a hole (radius 0.35) through the foot; all other edges sharp (90 degrees)."""
    body = occ.cut([(3, occ.addBox(0, 0, 0, 3.0, 2.0, 2.0))], [(3, occ.addBox(0.6, -1, 0.6, 3, 4, 2))])[0]

    def along_y(x, z):
        out = []
        for _, c in occ.getEntities(1):
            x0, y0, z0, x1, y1, z1 = occ.getBoundingBox(1, c)
            if abs(x0 - x) < 1e-3 and abs(x1 - x) < 1e-3 and abs(z0 - z) < 1e-3 and abs(z1 - z) < 1e-3:
                out.append(c)
        return out

    def along_z(x, y):
        out = []
        for _, c in occ.getEntities(1):
            x0, y0, z0, x1, y1, z1 = occ.getBoundingBox(1, c)
            if abs(x0 - x) < 1e-3 and abs(x1 - x) < 1e-3 and abs(y0 - y) < 1e-3 and abs(y1 - y) < 1e-3:
                out.append(c)
        return out

    inner, outer = along_y(0.6, 0.6), along_y(0.0, 0.0)
    body = occ.fillet([t for _, t in body], inner, [0.4])
    body = occ.fillet([t for _, t in body], outer + along_z(3.0, 0.0) + along_z(3.0, 2.0), [0.5])
    occ.cut(body, [(3, occ.addCylinder(1.9, 1.0, -1, 0, 0, 3, 0.35))])


def tube_with_holes(occ):
    """The lateral face of a cylinder (radius 1, height 3, open at both ends) with three holes
    through its wall: a bore along y (radius 0.35) through both sides at z = 1, and a hole
    (radius 0.3) through the x < 0 side only at z = 2.1; the seam (x = 1) stays whole."""
    cyl = occ.addCylinder(0, 0, 0, 0, 0, 3.0, 1.0)
    tools = [(3, occ.addCylinder(0, -2, 1.0, 0, 4, 0, 0.35)), (3, occ.addCylinder(0, 0, 2.1, -2, 0, 0, 0.3))]
    body = occ.cut([(3, cyl)], tools)[0]
    lateral = []
    for _, f in occ.getEntities(2):
        x0, y0, z0, x1, y1, z1 = occ.getBoundingBox(2, f)
        if z1 - z0 > 2.9 and x1 - x0 > 1.9:
            lateral.append(f)
    occ.remove(body)
    occ.remove([(2, f) for _, f in occ.getEntities(2) if f not in lateral], recursive=True)


def cross3(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot3(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def sub3(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def unit3(a):
    d = math.sqrt(dot3(a, a))
    return (a[0] / d, a[1] / d, a[2] / d)


def face_vector(p, f):
    """The area vector of a face (half the sum of the cross products of consecutive corners)."""
    s = [0.0, 0.0, 0.0]
    k = len(f)
    for i in range(k):
        c = cross3(p[f[i]], p[f[(i + 1) % k]])
        s[0] += c[0] / 2
        s[1] += c[1] / 2
        s[2] += c[2] / 2
    return s


def surface_scaled_jacobian(p, f, n):
    """Signed scaled Jacobian of face f against the unit normal n (see above; degenerate: 0)."""
    k = len(f)
    if k == 3:
        a, b, c = (p[v] for v in f)
        l0, l1, l2 = math.dist(a, b), math.dist(b, c), math.dist(c, a)
        big = max(l0 * l2, l0 * l1, l1 * l2)
        if big == 0:
            return 0.0
        cross = dot3(n, cross3(sub3(b, a), sub3(c, a)))
        return max(-1.0, min(1.0, cross * 2 / math.sqrt(3) / big))
    m = math.inf
    for i in range(4):
        x = p[f[i]]
        e1, e2 = sub3(p[f[(i + 1) % 4]], x), sub3(p[f[(i + 3) % 4]], x)
        l1, l2 = math.sqrt(dot3(e1, e1)), math.sqrt(dot3(e2, e2))
        if l1 == 0 or l2 == 0:
            return 0.0
        m = min(m, dot3(n, cross3(e1, e2)) / (l1 * l2))
    return m


def surface_stats(p, faces, normals):
    v = [surface_scaled_jacobian(p, f, n) for f, n in zip(faces, normals)]
    return min(v), sum(v) / len(v), max(v), sum(1 for x in v if x <= 0)


def orient_faces(points, faces):
    """Reverses faces in place so that neighbours agree (each edge used in both directions) and
    each connected piece faces outward: the sum over its faces of area vector . (centroid -
    the piece's vertex mean) positive (3 x the volume for a closed piece)."""
    edge_faces = {}
    for fi, f in enumerate(faces):
        for i in range(len(f)):
            a, b = f[i], f[(i + 1) % len(f)]
            edge_faces.setdefault((min(a, b), max(a, b)), []).append(fi)
    seen = [False] * len(faces)
    for start in range(len(faces)):
        if seen[start]:
            continue
        seen[start], piece, queue = True, [start], [start]
        while queue:
            fi = queue.pop()
            f = faces[fi]
            for i in range(len(f)):
                a, b = f[i], f[(i + 1) % len(f)]
                for g in edge_faces[(min(a, b), max(a, b))]:
                    if seen[g]:
                        continue
                    h = faces[g]
                    # Consistent when g runs b -> a.
                    if any(h[j] == a and h[(j + 1) % len(h)] == b for j in range(len(h))):
                        h.reverse()
                    seen[g] = True
                    piece.append(g)
                    queue.append(g)
        vs = sorted({v for fi in piece for v in faces[fi]})
        c0 = [sum(points[v][k] for v in vs) / len(vs) for k in range(3)]
        flux = 0.0
        for fi in piece:
            f = faces[fi]
            c = [sum(points[v][k] for v in f) / len(f) for k in range(3)]
            flux += dot3(face_vector(points, f), sub3(c, c0))
        if flux < 0:
            for fi in piece:
                faces[fi].reverse()


def surface_attempt(gmsh, build, size, algorithm, subdivide=False, recombination=1, mixed=False):
    """One meshing of the model build(occ) in the current gmsh session (cleared first): True
    when it gives what was asked (all quads; with `mixed`, quads and at least one triangle)."""
    gmsh.clear()
    gmsh.model.add("surface")
    occ = gmsh.model.occ
    build(occ)
    occ.synchronize()
    for k, v in dict(MeshSizeMin=size, MeshSizeMax=size, MeshSizeFromCurvature=0, MeshSizeExtendFromBoundary=1,
                     Algorithm=algorithm, RecombineAll=1, RecombinationAlgorithm=recombination,
                     SubdivisionAlgorithm=1 if subdivide else 0, Smoothing=1, RandomSeed=1).items():
        gmsh.option.setNumber("Mesh." + k, v)
    gmsh.model.mesh.generate(2)
    types = set()
    for _, s in gmsh.model.getEntities(2):
        types.update(int(t) for t in gmsh.model.mesh.getElements(2, s)[0])
    return types == {2, 3} if mixed else types == {3}


def mesh_surface(gmsh, sample):
    """Meshes a surface sample in the current gmsh session (initialized by the caller, which
    keeps the mesh and the model). Returns a dict: points (lists [x, y, z], the nodes used by
    2D elements in tag order), faces (vertex lists, oriented, see orient_faces), tags (the gmsh
    node tag of each vertex), where (per vertex: the CAD face it is classified on, or None on a
    CAD curve or point), face_surface (the CAD face of each face), normals (per face, see the
    section's notes)."""
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    m = sample.get("mixed")
    if m:
        ok = surface_attempt(gmsh, sample["build"], sample["size"], m["algorithm"], recombination=m["recombination"],
                             mixed=True)
        assert ok, "not a quad-dominant mesh"
    elif not any(surface_attempt(gmsh, sample["build"], sample["size"], a) for a in sample.get("algorithms", (8, 6))):
        assert surface_attempt(gmsh, sample["build"], 2 * sample["size"], 6, subdivide=True)
    coord, where = {}, {}
    for dim, ent in gmsh.model.getEntities():
        if dim > 2:
            continue
        tags, xyz, _ = gmsh.model.mesh.getNodes(dim, ent)
        for i, t in enumerate(tags):
            coord[int(t)] = [float(xyz[3 * i]), float(xyz[3 * i + 1]), float(xyz[3 * i + 2])]
            where[int(t)] = ent if dim == 2 else None
    raw, face_surface = [], []
    for _, s in gmsh.model.getEntities(2):
        types, _, nodes = gmsh.model.mesh.getElements(2, s)
        for ty, nd in zip(types, nodes):
            k = 4 if ty == 3 else 3
            nd = [int(x) for x in nd]
            for i in range(len(nd) // k):
                raw.append(nd[k * i : k * i + k])
                face_surface.append(s)
    used = sorted({v for f in raw for v in f})
    index = {t: i for i, t in enumerate(used)}
    points = [coord[t] for t in used]
    faces = [[index[v] for v in f] for f in raw]
    orient_faces(points, faces)
    normals = []
    for f, s in zip(faces, face_surface):
        c = [sum(points[v][k] for v in f) / len(f) for k in range(3)]
        _, uv = gmsh.model.getClosestPoint(2, s, c)
        n = unit3([float(x) for x in gmsh.model.getNormal(s, list(uv))])
        normals.append(n if dot3(n, face_vector(points, f)) > 0 else (-n[0], -n[1], -n[2]))
    return dict(points=points, faces=faces, tags=used, where=[where[t] for t in used], face_surface=face_surface,
                normals=normals)


def perturb_surface(gmsh, mesh, seed, jitter, defects):
    """Perturbs a copy of mesh["points"] along the CAD surface (see the section's notes) in the
    session that made `mesh`; returns (points, params): params maps each moved vertex to its
    parametric coordinates (u, v) on its CAD face."""
    rng = random.Random(seed)
    points, faces, normals, where = mesh["points"], mesh["faces"], mesh["normals"], mesh["where"]
    n = len(points)
    vq, edges, _ = topology(n, faces)
    nbrs = [set() for _ in range(n)]
    for a, b in edges:
        nbrs[a].add(b)
        nbrs[b].add(a)
    h = [min(math.dist(points[v], points[u]) for u in nbrs[v]) for v in range(n)]
    p = [list(x) for x in points]
    params = {}
    frames = {}

    def frame(v):
        """Two unit tangents of v's CAD face at v's unperturbed position."""
        if v not in frames:
            _, uv = gmsh.model.getClosestPoint(2, where[v], points[v])
            nv = unit3([float(x) for x in gmsh.model.getNormal(where[v], list(uv))])
            axis = min(range(3), key=lambda k: abs(nv[k]))
            e = [0.0, 0.0, 0.0]
            e[axis] = 1.0
            t1 = unit3(cross3(nv, e))
            frames[v] = (t1, cross3(nv, t1))
        return frames[v]

    def place(v, x):
        """Puts v at the point of its CAD face closest to x."""
        xyz, uv = gmsh.model.getClosestPoint(2, where[v], x)
        p[v][0], p[v][1], p[v][2] = float(xyz[0]), float(xyz[1]), float(xyz[2])
        params[v] = (float(uv[0]), float(uv[1]))

    def star_min(v):
        return min(surface_scaled_jacobian(p, faces[q], normals[q]) for q in vq[v])

    def restore(v, x0, uv0):
        p[v][0], p[v][1], p[v][2] = x0
        if uv0 is None:
            params.pop(v, None)
        else:
            params[v] = uv0

    floor = max(min(defects) + 0.05, 0.05)
    for v in range(n):
        rad, ang = math.sqrt(rng.random()), rng.uniform(0, 2 * math.pi)
        if where[v] is None:
            continue
        t1, t2 = frame(v)
        a, b = jitter * h[v] * rad * math.cos(ang), jitter * h[v] * rad * math.sin(ang)
        x0, uv0 = tuple(p[v]), params.get(v)
        for _ in range(5):
            place(v, [x0[k] + a * t1[k] + b * t2[k] for k in range(3)])
            if star_min(v) >= floor:
                break
            a, b = a / 2, b / 2
        else:
            restore(v, x0, uv0)

    touched = set()
    order = [v for v in range(n) if where[v] is not None]
    rng.shuffle(order)
    it = iter(order)
    for target in defects:
        for v in it:
            star = set(vq[v])
            if star & touched:
                continue
            if star_min(v) <= target + 0.05:
                continue
            ang = rng.uniform(0, 2 * math.pi)
            t1, t2 = frame(v)
            d = [h[v] * (math.cos(ang) * t1[k] + math.sin(ang) * t2[k]) for k in range(3)]
            x0, uv0 = tuple(p[v]), params.get(v)

            def at(t):
                place(v, [x0[k] + t * d[k] for k in range(3)])
                return star_min(v)

            t_hi = 0.9
            if at(t_hi) > target:
                restore(v, x0, uv0)
                continue
            lo, hi = 0.0, t_hi
            for _ in range(60):
                mid = (lo + hi) / 2
                if at(mid) > target:
                    lo = mid
                else:
                    hi = mid
            at(hi)
            for q in star:
                for u in faces[q]:
                    touched.update(vq[u])
            break
    return p, params


SURFACE_SAMPLES = [
    dict(
        name="sphere_surface",
        what="unit sphere, closed, all quads",
        build=sphere, size=0.15, algorithms=(6,), seed=101, jitter=0.35, defects=[-0.3, -0.05, 0.25],
    ),
    dict(
        name="bracket_surface",
        what="L bracket: three filleted edges, sharp edges and corners, a hole through the foot; closed, all quads",
        build=bracket, size=0.23, seed=102, jitter=0.35, defects=[-0.4, -0.1, 0.15],
    ),
    dict(
        name="cylinder_holes_surface",
        what="open tube (lateral face of a cylinder) with three holes through its wall, all quads",
        build=tube_with_holes, size=0.2, seed=103, jitter=0.35, defects=[-0.25, 0.05, 0.2],
    ),
    dict(
        name="bracket_surface_mixed",
        what="bracket_surface's bracket, quads and triangles (simple recombination)",
        build=bracket, size=0.17, seed=104, jitter=0.35, defects=[-0.3, 0.1],
        mixed=dict(algorithm=8, recombination=0),
    ),
]


def make_surface(sample):
    """Generates one surface sample in a gmsh session of its own: (clean points, perturbed
    points, faces, normals)."""
    import gmsh

    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        mesh = mesh_surface(gmsh, sample)
        p, _ = perturb_surface(gmsh, mesh, sample["seed"], sample["jitter"], sample["defects"])
    finally:
        gmsh.finalize()
    return mesh["points"], p, mesh["faces"], mesh["normals"]


def vtk_text_3d(name, points, faces):
    out = ["# vtk DataFile Version 3.0", f"quadopt sample {name} (tools/make_samples.py)", "ASCII",
           "DATASET UNSTRUCTURED_GRID", f"POINTS {len(points)} double"]
    out += [f"{x!r} {y!r} {z!r}" for x, y, z in points]
    out.append(f"CELLS {len(faces)} {sum(len(f) + 1 for f in faces)}")
    out += [f"{len(f)} " + " ".join(str(v) for v in f) for f in faces]
    out.append(f"CELL_TYPES {len(faces)}")
    out += ["9" if len(f) == 4 else "5" for f in faces]
    return "\n".join(out) + "\n"


def write_surfaces(outdir, only=None):
    """Writes the surface samples (NAME.vtk) and their unperturbed meshes (NAME_clean.vtk) to
    outdir, printing their quality."""
    os.makedirs(outdir, exist_ok=True)
    print(f"{'name':24} {'#V':>5} {'#F':>5} {'min':>9} {'avg':>9} {'max':>9} {'inverted':>8}  (clean min, avg)")
    for s in SURFACE_SAMPLES:
        if only and s["name"] != only:
            continue
        clean, p, faces, normals = make_surface(s)
        lo, avg, hi, inv = surface_stats(p, faces, normals)
        clo, cavg, _, _ = surface_stats(clean, faces, normals)
        tri = sum(1 for f in faces if len(f) == 3)
        line = f"{s['name']:24} {len(p):5} {len(faces):5} {lo:9.4f} {avg:9.4f} {hi:9.4f} {inv:8}  ({clo:.4f}, {cavg:.4f})"
        print(line + (f"  ({tri} triangles)" if tri else ""))
        with open(os.path.join(outdir, s["name"] + ".vtk"), "w") as f:
            f.write(vtk_text_3d(s["name"], p, faces))
        with open(os.path.join(outdir, s["name"] + "_clean.vtk"), "w") as f:
            f.write(vtk_text_3d(s["name"] + "_clean", clean, faces))


README_SURFACES = """
## Surface samples

Quad meshes on curved surfaces in 3D (cell types 9 and 5; faces oriented consistently, outward):
three CAD models of gmsh's OpenCASCADE kernel -- a unit sphere; an L bracket with filleted and
sharp edges, sharp corners and a hole; an open tube with three holes through its wall -- and the
bracket quad-dominant, meshed with recombination and then perturbed along the surface: only
vertices inside a CAD face move, each in its tangent plane and back onto the exact CAD surface,
until one face per negative defect target folds over. Quality: the scaled Jacobian signed
against the CAD surface's normal at the point closest to each face's unperturbed centroid
(`quadopt quality` signs it against the faceted input surface's normals instead, and its numbers
differ slightly); inverted = folded faces. `python3 tools/make_samples.py --surfaces DIR` writes
these with their unperturbed meshes (`NAME_clean.vtk`, for tools/bench_surfaces.py).

| file | what | #V | #F | #tri | input min | input avg | inverted |
| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="compare with the files in data/ instead of writing")
    ap.add_argument("--only", help="generate only this sample")
    ap.add_argument("--surfaces", metavar="OUTDIR",
                    help="write only the surface samples (and their unperturbed *_clean meshes) to OUTDIR")
    args = ap.parse_args()
    import gmsh

    if gmsh.__version__ != GMSH_VERSION:
        print(f"warning: gmsh {gmsh.__version__} found, the samples were made with {GMSH_VERSION}", file=sys.stderr)
    if args.surfaces:
        write_surfaces(args.surfaces, args.only)
        return
    os.makedirs(DATA, exist_ok=True)
    print(f"{'name':24} {'#V':>5} {'#F':>5} {'min':>9} {'avg':>9} {'max':>9} {'inverted':>8}")
    differ = 0
    readme = README_HEAD

    def emit(path, text):
        nonlocal differ
        if args.check:
            old = open(path).read() if os.path.exists(path) else None
            if old != text:
                print(f"  differs from {path}")
                differ += 1
        else:
            with open(path, "w") as f:
                f.write(text)

    for s in SAMPLES + MIXED_SAMPLES:
        if s is MIXED_SAMPLES[0]:
            readme += README_MIXED
        if args.only and s["name"] != args.only:
            continue
        p, q, fixed = make(s)
        lo, avg, hi, inv = stats(p, q)
        tri = sum(1 for f in q if len(f) == 3)
        line = f"{s['name']:24} {len(p):5} {len(q):5} {lo:9.4f} {avg:9.4f} {hi:9.4f} {inv:8}"
        print(line + (f"  ({tri} triangles)" if tri else ""))
        counts = f"{len(p)} | {len(q)} | {tri}" if s.get("mixed") else f"{len(p)} | {len(q)}"
        readme += f"| {s['name']}.vtk | {s['what']} | {counts} | {lo:.4f} | {avg:.4f} | {inv} |\n"
        emit(os.path.join(DATA, s["name"] + ".vtk"), vtk_text(s["name"], p, q, fixed))
    readme += README_SURFACES
    for s in SURFACE_SAMPLES:
        if args.only and s["name"] != args.only:
            continue
        _, p, faces, normals = make_surface(s)
        lo, avg, hi, inv = surface_stats(p, faces, normals)
        tri = sum(1 for f in faces if len(f) == 3)
        line = f"{s['name']:24} {len(p):5} {len(faces):5} {lo:9.4f} {avg:9.4f} {hi:9.4f} {inv:8}"
        print(line + (f"  ({tri} triangles)" if tri else ""))
        readme += f"| {s['name']}.vtk | {s['what']} | {len(p)} | {len(faces)} | {tri} | {lo:.4f} | {avg:.4f} | {inv} |\n"
        emit(os.path.join(DATA, s["name"] + ".vtk"), vtk_text_3d(s["name"], p, faces))
    if not args.only:
        emit(os.path.join(DATA, "README.md"), readme)
    if differ:
        sys.exit(1)


if __name__ == "__main__":
    main()

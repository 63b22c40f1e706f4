#!/usr/bin/env python3
"""Peer comparison on curved surfaces: quadopt's presets against gmsh, OpenMesh and vcglib smoothers.

quadopt's presets against gmsh's Laplace2D and Relocate2D, OpenMesh's JacobiLaplaceSmootherT and
vcglib's LaplacianReproject and SmoothReprojectPCA (QuadWild's), on quad (and quad-dominant)
meshes of curved 3D surfaces.

Usage:  python3 -m venv VENV && VENV/bin/pip install -r tools/requirements.txt   # gmsh 4.15.2, vtk, numpy
        apt-get install libopenmesh-dev g++ pkg-config        # for the OpenMesh peer (else skipped)
        apt-get install libeigen3-dev                         # for the vcglib peers (else skipped)
        VENV/bin/python tools/bench_surfaces.py --quadopt target/release/quadopt [--out DIR]
            [--only NAME,...] [--real DIR] [--vcglib DIR] [--meshlab-src TARBALL] [--build DIR]

Meshes: the surface samples of tools/make_samples.py (sphere_surface, bracket_surface,
cylinder_holes_surface, bracket_surface_mixed), regenerated here in the gmsh session that also
runs gmsh's smoothers, each also unperturbed (NAME_clean), and Mesquite's untangled
bias-sphere-quads, quads_on_sphere_529 and paraboloid (--mesquite DIR), and the real meshes of
--real DIR (default ../shared/meshes/real; skipped with a note if absent): every surface/*.vtk and
every mixed/*.vtk that is not planar (planar ones are tools/bench_peers.py's); a mesh that is
planar or not orientable (surface/mfem_mobius-strip, which quadopt refuses) gets a "skipped" row
saying why. The real meshes and Mesquite's have no CAD model: gmsh's smoothers and the CAD
distance are for the CAD samples only. --only NAME,... keeps the meshes whose name contains one
of the NAMEs. Each input is written to OUT/inputs/ (the samples bit for bit as `make_samples.py
--surfaces` writes them, the others as plain copies), the outputs to OUT/outputs/, the rows to
OUT/bench_surfaces.json.

Tools (each timed by its own timer around the smoothing step alone, no meshing or file IO; the
median over --repeat runs):
  * gmsh Laplace2D, Relocate2D (CAD samples only): gmsh.model.mesh.optimize(METHOD) in the session
    that meshed the CAD model, after the sample's perturbation has been applied with
    gmsh.model.mesh.setNode (coordinates and the parametric coordinates getClosestPoint gave), so
    gmsh smooths with its parametrization; before each run every node gets its coordinates and
    parametric coordinates back. Nodes on CAD curves and points stay (gmsh's rule).
  * OpenMesh Jacobi (10 and 100 iterations; tools/peers/openmesh_jacobi.cpp, built with g++ into
    --build DIR): JacobiLaplaceSmootherT, initialize(Tangential, C0) + smooth(N), i.e. uniform
    Laplace with each move projected onto the input's tangent plane at the vertex; boundary
    vertices held, and (--features, 45 degrees) every vertex on an edge whose dihedral angle
    exceeds 45 degrees, as quadopt holds feature curves to their polylines.
  * vcglib LaplacianReproject (5 and 100 steps), SmoothReprojectPCA (30 and 100 steps)
    (tools/peers/vcglib/vcglib_polygonal.cpp, GPL, its own folder; built with g++ and Eigen into
    --build DIR against vcglib's headers in --vcglib DIR, default ../vcglib_src, extracted there
    from MeshLab 2025.07's source tarball --meshlab-src when absent; skipped with a note when
    either is missing): vcg::PolygonalAlgorithm<PolyMesh> on the mesh's quads and triangles as
    polygons, the call alone timed (it builds its guide surface, the input fan-triangulated
    around each face's barycentre, and a grid on it, inside). LaplacianReproject(m, N, 0.5,
    OnlyOnSelected=true): per step, area-weighted Laplace damped by 0.5 (each vertex goes half way
    to the mean of its faces' other vertices), then half way (vcglib's fixed 0.5) to its closest
    point on the guide surface; damping 0.5 and OnlyOnSelected as QuadWild's QuadRetopology calls
    it, 5 steps its default, 100 vcglib's. SmoothReprojectPCA(m, N, fixS=true, 0.5, SharpDeg=0,
    WeightByQuality=false, FixB=true): per step, one SmoothPCA step (each face's regular template
    polygon fitted onto it, averaged per vertex by inverse area, blended with 0.1 of Laplace,
    damped by 0.5) and a half-way reprojection; damping 0.5 and 30 steps as QuadWild's final
    smoothing (MultiCostraintSmooth) runs its SmoothPCA steps, 100 vcglib's default. Held, as
    for OpenMesh: boundary vertices and (--features) every vertex on an edge whose dihedral angle
    exceeds 45 degrees, by vcglib's selection (LaplacianReproject moves only the selected
    vertices, the held ones unselected; SmoothReprojectPCA with fixS holds the selected ones, the
    held ones selected). SharpDeg stays 0: vcglib's own sharp-edge rule would let those vertices
    slide along the line of a sharp edge instead.
  * quadopt PRESET (fast, balanced, best): `quadopt optimize IN -o OUT --json --effort PRESET`
    (plus --quadopt-flags), its report's "seconds" plus "setup_seconds" (the features, patches
    and reference trees it builds first, as the peers' times include their set-up). A failed run is reported as an error row and
    the benchmark goes on.

Measures (numpy, of every input and output):
  * verdict min / avg: Verdict's 3D quad scaled Jacobian (vtkMeshQuality's QuadScaledJacobian:
    corners' cross products against the quad's centre normal (e0 - e2) x (e1 - e3), over the
    edge lengths) and triangle scaled Jacobian (unsigned in 3D, as Verdict has no normal there);
    checked against vtkMeshQuality on the first mesh. inv: faces with a value <= 0.
  * signed min / avg (inv): the measure quadopt ranks by, from `quadopt quality OUT --reference
    IN --json` for every tool's output alike: per face the minimum over its corners of
    n . ((v_next - v) x (v_prev - v)) / (|v_next - v| |v_prev - v|), n the normal of the face's
    smooth patch of the input surface at the corner (the input's area-weighted vertex normals over
    that patch, interpolated over its triangles; patches are cut by the feature curves, so a
    corner next to a sharp edge is measured against its own side); a triangle: 2/sqrt(3)
    n . ((b - a) x (c - a)) / the largest product of two edge lengths. inv: faces with a value
    <= 0.
  * dist: the largest distance of a vertex to the reference (vtkStaticCellLocator), over the
    input's mean edge length ("dist_abs" in the JSON). The reference is a chordal approximation:
    a vertex on the exact curved surface is up to a sagitta away from it.
  * CAD dist (CAD samples only): the largest distance of a vertex to the exact CAD surfaces of
    its incident faces (untrimmed; gmsh.model.getClosestPoint), over the same length.
Every tool's output (every peer's and every preset's) is ranked in both measures, Verdict's and
the signed one. The table, one per mesh: tool, verdict min / avg (inv), signed min / avg (inv),
dist, CAD dist (CAD samples), seconds, and the measures in which the peer run is dominated.
Dominance, in each measure (signed, verdict) apart: a peer run (gmsh, OpenMesh, vcglib, on one
mesh) is dominated when some quadopt preset on the same mesh ran, took no more seconds (times
under 1 ms count as 1 ms) and has that measure's min and avg at least the peer's (less 1e-3);
"dominated N of M peer runs" is printed per measure.
"""

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)

import make_samples  # noqa: E402  (the surface samples, their meshing and perturbation)

GMSH_METHODS = ["Laplace2D", "Relocate2D"]
PRESETS = ["fast", "balanced", "best"]
OPENMESH_ITERS = [10, 100]
MESQUITE = os.path.join(ROOT, "..", "shared", "meshes", "mesquite", "untangled")
MESQUITE_MESHES = ["bias-sphere-quads", "quads_on_sphere_529", "paraboloid"]
REAL = os.path.join(ROOT, "..", "shared", "meshes", "real")
REAL_SETS = ["surface", "mixed"]  # real/planar is tools/bench_peers.py's
MESHLAB_SRC = os.path.join(ROOT, "..", "shared", "meshlab", "meshlab-2025.07-src.tar.xz")
VCGLIB = os.path.join(ROOT, "..", "vcglib_src")
# vcglib's polygon smoothers (tools/peers/vcglib/): (tool name, driver --method, steps, damping).
VCGLIB_RUNS = [("LaplacianReproject", "laplacian", 5, 0.5), ("LaplacianReproject", "laplacian", 100, 0.5),
               ("SmoothReprojectPCA", "pca", 30, 0.5), ("SmoothReprojectPCA", "pca", 100, 0.5)]
TOL = 1e-3
MIN_SECONDS = 1e-3
OUT_INPUTS = [""]  # the inputs' directory (error messages name it; the table leaves it out)


def note(msg):
    print(f"note: {msg}", file=sys.stderr, flush=True)


# --------------------------------------------------------------------------------------------
# Meshes: points (n x 3), faces (m x 4, -1 fourth for a triangle)
# --------------------------------------------------------------------------------------------


def read_vtk(path):
    """Legacy VTK ASCII UNSTRUCTURED_GRID or POLYDATA: points and the triangles and quads (other
    cells ignored). Walks the per-cell counts (some files give a wrong CELLS size)."""
    tok = open(path).read().split()
    i, pts, faces = 0, None, []
    types, cells = None, None
    while i < len(tok):
        k = tok[i].upper()
        if k == "POINTS":
            n = int(tok[i + 1])
            pts = np.array(tok[i + 3 : i + 3 + 3 * n], dtype=np.float64).reshape(n, 3)
            i += 3 + 3 * n
        elif k in ("CELLS", "POLYGONS"):
            m = int(tok[i + 1])
            i += 3
            cells = []
            for _ in range(m):
                c = int(tok[i])
                cells.append([int(x) for x in tok[i + 1 : i + 1 + c]])
                i += c + 1
            if k == "POLYGONS":
                types = [9 if len(c) == 4 else 5 if len(c) == 3 else 0 for c in cells]
        elif k == "CELL_TYPES":
            m = int(tok[i + 1])
            types = [int(x) for x in tok[i + 2 : i + 2 + m]]
            i += 2 + m
        elif k in ("POINT_DATA", "CELL_DATA"):
            break
        else:
            i += 1
    for c, t in zip(cells, types):
        if t == 9:
            faces.append(c)
        elif t == 5:
            faces.append(c + [-1])
    return pts, np.array(faces, dtype=np.int64)


def write_vtk(path, points, faces, title):
    out = ["# vtk DataFile Version 3.0", title, "ASCII", "DATASET UNSTRUCTURED_GRID", f"POINTS {len(points)} double"]
    out += [f"{x!r} {y!r} {z!r}" for x, y, z in points.tolist()]
    tri = faces[:, 3] < 0
    out.append(f"CELLS {len(faces)} {5 * len(faces) - int(tri.sum())}")
    out += ["3 %d %d %d" % tuple(f[:3]) if t else "4 %d %d %d %d" % tuple(f) for f, t in zip(faces.tolist(), tri.tolist())]
    out.append(f"CELL_TYPES {len(faces)}")
    out += ["5" if t else "9" for t in tri.tolist()]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def write_off(path, points, faces):
    out = ["OFF", f"{len(points)} {len(faces)} 0"]
    out += [f"{x!r} {y!r} {z!r}" for x, y, z in points.tolist()]
    out += ["3 %d %d %d" % tuple(f[:3]) if f[3] < 0 else "4 %d %d %d %d" % tuple(f) for f in faces.tolist()]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def _normal_angle(points, t, u):
    """Per row, the angle (0 to pi) between the normals of triangles t and u (k x 3 vertex
    indices); pi where either has no area."""
    def n(t):
        return np.cross(points[t[:, 1]] - points[t[:, 0]], points[t[:, 2]] - points[t[:, 0]])

    m, k = n(t), n(u)
    ang = np.arctan2(np.linalg.norm(np.cross(m, k), axis=1), np.einsum("ij,ij->i", m, k))
    zero = ((m * m).sum(axis=1) == 0) | ((k * k).sum(axis=1) == 0)
    return np.where(zero, math.pi, ang)


def triangles(points, faces):
    """The faces as triangles, as quadopt's reference surface (src/surface/reference.rs) has
    them: a quad [a, b, c, d] split along the diagonal whose two triangles' normals make the
    smaller angle, a-c ([a, b, c], [a, c, d]) unless b-d ([a, b, d], [b, c, d]) is better by more
    than 1e-12 radians; triangles as they are, all in face order."""
    tri = faces[:, 3] < 0
    a, b, c, d = faces[:, 0], faces[:, 1], faces[:, 2], faces[:, 3]
    ac1, ac2 = np.stack([a, b, c], 1), np.stack([a, c, d], 1)
    bd1, bd2 = np.stack([a, b, d], 1), np.stack([b, c, d], 1)
    q = ~tri
    use_bd = np.zeros(len(faces), dtype=bool)
    if q.any():
        use_bd[q] = _normal_angle(points, bd1[q], bd2[q]) < _normal_angle(points, ac1[q], ac2[q]) - 1e-12
    first = np.where(use_bd[:, None], bd1, ac1)
    second = np.where(use_bd[:, None], bd2, ac2)
    out = np.empty((len(faces), 2, 3), dtype=np.int64)
    out[:, 0], out[:, 1] = first, second
    keep = np.ones((len(faces), 2), dtype=bool)
    keep[tri, 1] = False
    return out[keep]


def mean_edge_length(points, faces):
    e = set()
    for f in faces.tolist():
        f = f[:3] if f[3] < 0 else f
        for i in range(len(f)):
            a, b = f[i], f[(i + 1) % len(f)]
            e.add((min(a, b), max(a, b)))
    e = np.array(sorted(e))
    return float(np.linalg.norm(points[e[:, 0]] - points[e[:, 1]], axis=1).mean())


def orientable(faces):
    """Whether the faces can be oriented consistently (a Moebius strip cannot): flips propagated
    across the edges with two faces, one connected piece at a time."""
    by_edge = {}
    for i, f in enumerate(faces.tolist()):
        f = f[:3] if f[3] < 0 else f
        for k in range(len(f)):
            a, b = f[k], f[(k + 1) % len(f)]
            by_edge.setdefault((min(a, b), max(a, b)), []).append((i, a < b))
    nbrs = [[] for _ in range(len(faces))]
    for uses in by_edge.values():
        if len(uses) == 2:
            (i, di), (j, dj) = uses
            nbrs[i].append((j, di == dj))  # same direction: one of the two must flip
            nbrs[j].append((i, di == dj))
    flip = [None] * len(faces)
    for seed in range(len(faces)):
        if flip[seed] is not None:
            continue
        flip[seed], todo = False, [seed]
        while todo:
            i = todo.pop()
            for j, differ in nbrs[i]:
                want = flip[i] != differ
                if flip[j] is None:
                    flip[j] = want
                    todo.append(j)
                elif flip[j] != want:
                    return False
    return True


def planar(points, faces, tol=1e-9):
    """Whether the used vertices lie in one plane (to tol times their extent)."""
    p = points[np.unique(faces[faces >= 0])]
    s = np.linalg.svd(p - p.mean(axis=0), compute_uv=False)
    return bool(s[-1] <= tol * s[0])


def orientation_conflicts(faces):
    """Interior edges used twice in the same direction (0 for a consistently oriented mesh)."""
    seen, bad = set(), 0
    for f in faces.tolist():
        f = f[:3] if f[3] < 0 else f
        for i in range(len(f)):
            d = (f[i], f[(i + 1) % len(f)])
            bad += d in seen
            seen.add(d)
    return bad


# --------------------------------------------------------------------------------------------
# Quality
# --------------------------------------------------------------------------------------------


def _unit(v):
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.divide(v, n, out=np.zeros_like(v), where=n > 0)


def verdict_scaled_jacobian(points, faces):
    """Verdict's quad scaled Jacobian (3D) and triangle scaled Jacobian (unsigned in 3D)."""
    out = np.empty(len(faces))
    tri = faces[:, 3] < 0
    if (~tri).any():
        p = points[faces[~tri]]  # q x 4 x 3
        e = np.roll(p, -1, axis=1) - p  # e[i] = p[i+1] - p[i]
        ln = np.linalg.norm(e, axis=2)
        cn = np.cross(np.roll(e, 1, axis=1), e)  # corner i: e[i-1] x e[i]
        centre = _unit(np.cross(e[:, 0] - e[:, 2], e[:, 1] - e[:, 3]))
        area = np.einsum("qj,qij->qi", centre, cn)
        lprod = np.roll(ln, 1, axis=1) * ln
        with np.errstate(divide="ignore", invalid="ignore"):
            sj = np.where(lprod > 0, area / lprod, 0.0).min(axis=1)
        sj[(ln == 0).any(axis=1)] = 0.0
        out[~tri] = sj
    if tri.any():
        out[tri] = _tri_sj(points[faces[tri, :3]], None)
    return out


def _tri_sj(p, n):
    """Triangle scaled Jacobian of t x 3 x 3 corners; against unit normals n (t x 3) when given,
    else unsigned."""
    a, b, c = p[:, 0], p[:, 1], p[:, 2]
    l0, l1, l2 = (np.linalg.norm(x, axis=1) for x in (b - a, c - b, a - c))
    big = np.maximum(np.maximum(l0 * l2, l0 * l1), l1 * l2)
    cr = np.cross(b - a, c - a)
    j = np.linalg.norm(cr, axis=1) if n is None else np.einsum("ij,ij->i", cr, n)
    with np.errstate(divide="ignore", invalid="ignore"):
        v = np.where(big > 0, j * 2 / math.sqrt(3) / big, 0.0)
    return np.clip(v, -1.0, 1.0)


class Reference:
    """The input surface, triangulated, with a cell locator and area-weighted vertex normals."""

    def __init__(self, points, faces):
        import vtk
        from vtk.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray

        self.vtk = vtk
        t = triangles(points, faces)
        self.points, self.tris = points, t
        cr = np.cross(points[t[:, 1]] - points[t[:, 0]], points[t[:, 2]] - points[t[:, 0]])
        vn = np.zeros_like(points)
        for k in range(3):
            np.add.at(vn, t[:, k], cr)
        self.vn = _unit(vn)
        pd = vtk.vtkPolyData()
        vp = vtk.vtkPoints()
        vp.SetData(numpy_to_vtk(np.ascontiguousarray(points), deep=True))
        pd.SetPoints(vp)
        ca = vtk.vtkCellArray()
        ca.SetData(numpy_to_vtkIdTypeArray(np.arange(0, 3 * len(t) + 1, 3, dtype=np.int64), deep=True),
                   numpy_to_vtkIdTypeArray(t.astype(np.int64).ravel(), deep=True))
        pd.SetPolys(ca)
        self.pd = pd
        self.loc = vtk.vtkStaticCellLocator()
        self.loc.SetDataSet(pd)
        self.loc.BuildLocator()
        self.h = mean_edge_length(points, faces)

    def closest(self, x):
        """(closest point, triangle index, squared distance)."""
        c = [0.0, 0.0, 0.0]
        cid, sub, d2 = self.vtk.reference(0), self.vtk.reference(0), self.vtk.reference(0.0)
        self.loc.FindClosestPoint(list(map(float, x)), c, cid, sub, d2)
        return np.array(c), int(cid), float(d2)

    def normal(self, x):
        c, t, _ = self.closest(x)
        a, b, d = self.points[self.tris[t]]
        # Barycentric coordinates of c in (a, b, d).
        v0, v1, v2 = b - a, d - a, c - a
        d00, d01, d11, d20, d21 = v0 @ v0, v0 @ v1, v1 @ v1, v2 @ v0, v2 @ v1
        den = d00 * d11 - d01 * d01
        if den <= 0:
            w = np.array([1 / 3, 1 / 3, 1 / 3])
        else:
            wb = (d11 * d20 - d01 * d21) / den
            wd = (d00 * d21 - d01 * d20) / den
            w = np.array([1 - wb - wd, wb, wd])
        n = w @ self.vn[self.tris[t]]
        ln = np.linalg.norm(n)
        return n / ln if ln > 0 else n

    def max_distance(self, points):
        return max(math.sqrt(self.closest(x)[2]) for x in points)


def signed_scaled_jacobian(points, faces, ref):
    """The scaled Jacobian against the reference surface's normal (see the module docs)."""
    tri = faces[:, 3] < 0
    cen = np.array([points[f[:3] if f[3] < 0 else f].mean(axis=0) for f in faces])
    n = np.array([ref.normal(c) for c in cen])
    out = np.empty(len(faces))
    if (~tri).any():
        p = points[faces[~tri]]
        nx = np.roll(p, -1, axis=1) - p
        pv = np.roll(p, 1, axis=1) - p
        lp = np.linalg.norm(nx, axis=2) * np.linalg.norm(pv, axis=2)
        num = np.einsum("qj,qij->qi", n[~tri], np.cross(nx, pv))
        with np.errstate(divide="ignore", invalid="ignore"):
            out[~tri] = np.where(lp > 0, num / lp, 0.0).min(axis=1)
    if tri.any():
        out[tri] = _tri_sj(points[faces[tri, :3]], n[tri])
    return out


def measure(points, faces, ref, path, reference_path, quadopt):
    """Verdict's measure and the distance from the reference here; the signed measure from
    `quadopt quality PATH --reference INPUT` (each corner against the normal of its face's
    smooth patch of the input surface), so that every tool is ranked by the measure quadopt
    reports."""
    v = verdict_scaled_jacobian(points, faces)
    r = subprocess.run([quadopt, "quality", path, "--reference", reference_path, "--json"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"quadopt quality {path}: {r.stderr.strip()}")
    q = json.loads(r.stdout)
    d = ref.max_distance(points[np.unique(faces[faces >= 0])])
    return dict(verdict_min=float(v.min()), verdict_avg=float(v.mean()), verdict_inverted=int((v <= 0).sum()),
                signed_min=q["min"], signed_avg=q["avg"], inverted=q["inverted"],
                dist_abs=d, dist_rel=d / ref.h)


def vtk_cross_check(points, faces):
    """Largest difference between verdict_scaled_jacobian and vtkMeshQuality's."""
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    ug = vtk.vtkUnstructuredGrid()
    vp = vtk.vtkPoints()
    for x in points.tolist():
        vp.InsertNextPoint(x)
    ug.SetPoints(vp)
    for f in faces.tolist():
        if f[3] < 0:
            ug.InsertNextCell(vtk.VTK_TRIANGLE, 3, f[:3])
        else:
            ug.InsertNextCell(vtk.VTK_QUAD, 4, f)
    mq = vtk.vtkMeshQuality()
    mq.SetInputData(ug)
    mq.SetQuadQualityMeasureToScaledJacobian()
    mq.SetTriangleQualityMeasureToScaledJacobian()
    mq.Update()
    theirs = vtk_to_numpy(mq.GetOutput().GetCellData().GetArray("Quality"))
    return float(np.abs(theirs - verdict_scaled_jacobian(points, faces)).max())


# --------------------------------------------------------------------------------------------
# The tools
# --------------------------------------------------------------------------------------------


def gmsh_entity_nodes(gmsh):
    """Every node's (tag, coordinates, parametric coordinates), per entity (as gmsh classifies)."""
    out = []
    for dim, ent in gmsh.model.getEntities():
        if dim > 2:
            continue
        # Node by node: some nodes (of subdivided meshes) have no parametric coordinates, and
        # getNodes then returns fewer of them, not aligned with the tags.
        for t in gmsh.model.mesh.getNodes(dim, ent, includeBoundary=False)[0]:
            xyz, uv, _, _ = gmsh.model.mesh.getNode(int(t))
            out.append((int(t), [float(x) for x in xyz], [float(x) for x in uv]))
    return out


def run_cad_sample(sample, clean, repeat, out_dir):
    """Meshes (and unless `clean` perturbs) a surface sample in a gmsh session, writes it to
    out_dir/inputs, runs gmsh's smoothers on it; returns (input path, {method: result})."""
    import gmsh

    name = sample["name"] + ("_clean" if clean else "")
    results = {}
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        mesh = make_samples.mesh_surface(gmsh, sample)
        gmsh.option.setNumber("Mesh.Renumber", 0)
        p = mesh["points"]
        if not clean:
            p, params = make_samples.perturb_surface(gmsh, mesh, sample["seed"], sample["jitter"], sample["defects"])
            for v, uv in sorted(params.items()):
                gmsh.model.mesh.setNode(mesh["tags"][v], p[v], list(uv))
        in_path = os.path.join(out_dir, "inputs", name + ".vtk")
        with open(in_path, "w") as f:
            f.write(make_samples.vtk_text_3d(name, p, mesh["faces"]))
        points = np.array(p, dtype=np.float64)
        index = {t: i for i, t in enumerate(mesh["tags"])}
        start = gmsh_entity_nodes(gmsh)

        def coords():
            tags, xyz, _ = gmsh.model.mesh.getNodes()
            c = points.copy()
            xyz = np.array(xyz).reshape(-1, 3)
            for k, t in enumerate(tags.tolist()):
                if t in index:
                    c[index[t]] = xyz[k]
            return c

        def reset():
            for t, x, uv in start:
                gmsh.model.mesh.setNode(t, x, uv)

        if not np.array_equal(coords(), points):
            raise RuntimeError("gmsh's nodes differ from the written input")
        faces = np.array([f if len(f) == 4 else f + [-1] for f in mesh["faces"]], dtype=np.int64)
        for method in GMSH_METHODS:
            times, first = [], None
            for r in range(repeat):
                reset()
                t0 = time.perf_counter()
                gmsh.model.mesh.optimize(method)
                times.append(time.perf_counter() - t0)
                c = coords()
                if first is None:
                    first = c
                elif not np.array_equal(first, c):
                    note(f"{name}: gmsh {method} gave different coordinates on repeat {r + 1}")
            out_path = os.path.join(out_dir, "outputs", f"{name}.gmsh-{method}.vtk")
            write_vtk(out_path, first, faces, f"{name}, gmsh {method} (tools/bench_surfaces.py)")
            results[f"gmsh {method}"] = dict(seconds=statistics.median(times), times=times, output=out_path)
        reset()
    finally:
        gmsh.finalize()
    return in_path, results, mesh["face_surface"]


def cad_distances(sample, face_surface, faces, outputs):
    """Per output (a list of point arrays): the largest distance of a vertex to the exact CAD
    model, each vertex measured against the (untrimmed) CAD surfaces of its incident faces
    (gmsh.model.getClosestPoint), in a gmsh session that rebuilds the sample's geometry (the
    same entity tags as when it was meshed)."""
    import gmsh

    by_surface = {}
    for f, srf in zip(faces.tolist(), face_surface):
        by_surface.setdefault(srf, set()).update(v for v in f if v >= 0)
    by_surface = {srf: np.array(sorted(vs)) for srf, vs in by_surface.items()}
    out = []
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("cad")
        sample["build"](gmsh.model.occ)
        gmsh.model.occ.synchronize()
        for points in outputs:
            d = np.full(len(points), np.inf)
            for srf, vs in by_surface.items():
                x = points[vs]
                c = np.array(gmsh.model.getClosestPoint(2, srf, x.ravel().tolist())[0]).reshape(-1, 3)
                d[vs] = np.minimum(d[vs], np.linalg.norm(c - x, axis=1))
            out.append(float(d[np.isfinite(d)].max()))
    finally:
        gmsh.finalize()
    return out


def build_openmesh(build_dir):
    src = os.path.join(HERE, "peers", "openmesh_jacobi.cpp")
    exe = os.path.join(build_dir, "openmesh_jacobi")
    if os.path.exists(exe) and os.path.getmtime(exe) >= os.path.getmtime(src):
        return exe
    os.makedirs(build_dir, exist_ok=True)
    flags = subprocess.run(["pkg-config", "--cflags", "--libs", "openmesh"], capture_output=True, text=True)
    libs = flags.stdout.split() if flags.returncode == 0 else ["-lOpenMeshCore"]
    r = subprocess.run(["g++", "-O2", "-std=c++17", "-o", exe, src, *libs, "-lOpenMeshTools"], capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"building the OpenMesh driver failed: {r.stderr.strip()[-400:]}")
    return exe


def vcglib_headers(vcglib_dir, tarball):
    """The directory of vcglib's headers: vcglib_dir, extracted there first from MeshLab's source
    tarball (its src/vcglib) when it has no vcglib. Never inside the repository (GPL)."""
    header = os.path.join("vcg", "complex", "algorithms", "polygonal_algorithms.h")
    if os.path.exists(os.path.join(vcglib_dir, header)):
        return vcglib_dir
    target = os.path.abspath(vcglib_dir)
    if os.path.commonpath([target, ROOT]) == ROOT:
        raise RuntimeError(f"{vcglib_dir} is inside the repository; extract vcglib outside it (--vcglib)")
    if not os.path.exists(tarball):
        raise RuntimeError(f"no vcglib in {vcglib_dir} and no {tarball} to extract it from")
    import tarfile

    note(f"extracting vcglib from {tarball} into {vcglib_dir}")
    with tarfile.open(tarball, "r:xz") as tar:
        for m in tar:
            parts = m.name.split("/")
            # meshlab-COMMIT/src/vcglib/...: keep what follows src/vcglib/.
            if len(parts) > 3 and parts[1:3] == ["src", "vcglib"] and (m.isfile() or m.isdir()):
                m.name = "/".join(parts[3:])
                tar.extract(m, target, filter="data")
    if not os.path.exists(os.path.join(vcglib_dir, header)):
        raise RuntimeError(f"{tarball} has no src/vcglib/{header}")
    return vcglib_dir


def eigen_include():
    flags = subprocess.run(["pkg-config", "--cflags-only-I", "eigen3"], capture_output=True, text=True)
    dirs = [f[2:] for f in flags.stdout.split()] if flags.returncode == 0 else []
    for d in dirs + ["/usr/include/eigen3", "/usr/local/include/eigen3"]:
        if os.path.exists(os.path.join(d, "Eigen", "Core")):
            return d
    raise RuntimeError("Eigen not found (apt-get install libeigen3-dev)")


def build_vcglib(build_dir, vcglib_dir, tarball):
    src = os.path.join(HERE, "peers", "vcglib", "vcglib_polygonal.cpp")
    exe = os.path.join(build_dir, "vcglib_polygonal")
    if os.path.exists(exe) and os.path.getmtime(exe) >= os.path.getmtime(src):
        return exe
    os.makedirs(build_dir, exist_ok=True)
    inc = [vcglib_headers(vcglib_dir, tarball), eigen_include()]
    r = subprocess.run(["g++", "-O2", "-std=c++17", *[f"-I{d}" for d in inc], "-o", exe, src],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"building the vcglib driver failed: {r.stderr.strip()[-400:]}")
    return exe


def run_driver(cmd, xyz, faces, out_path, title):
    """Runs a peer driver that writes the output positions to xyz and its report as the last line
    of its stdout; writes the output mesh to out_path; returns the report."""
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        msg = (r.stderr.strip() or f"exit {r.returncode}").splitlines()
        raise RuntimeError(msg[-1] if msg else f"exit {r.returncode}")
    rep = json.loads(r.stdout.strip().splitlines()[-1])
    write_vtk(out_path, np.loadtxt(xyz).reshape(-1, 3), faces, title)
    return rep


def run_openmesh(exe, off, faces, name, iters, repeat, features, out_dir):
    xyz = os.path.join(out_dir, "outputs", f"{name}.openmesh-{iters}.xyz")
    cmd = [exe, off, xyz, "--iters", str(iters), "--repeat", str(repeat)]
    if features is not None:
        cmd += ["--features", str(features)]
    out_path = os.path.join(out_dir, "outputs", f"{name}.openmesh-{iters}.vtk")
    rep = run_driver(cmd, xyz, faces, out_path,
                     f"{name}, OpenMesh JacobiLaplaceSmootherT x{iters} (tools/bench_surfaces.py)")
    return dict(seconds=rep["seconds"], times=rep["times"], feature_edges=rep["feature_edges"], output=out_path)


def run_vcglib(exe, off, faces, name, run, repeat, features, out_dir):
    algorithm, method, steps, damp = run
    stem = os.path.join(out_dir, "outputs", f"{name}.vcglib-{method}-{steps}")
    cmd = [exe, off, stem + ".xyz", "--method", method, "--iters", str(steps), "--damp", str(damp),
           "--repeat", str(repeat)]
    if features is not None:
        cmd += ["--features", str(features)]
    rep = run_driver(cmd, stem + ".xyz", faces, stem + ".vtk",
                     f"{name}, vcglib {algorithm} x{steps} (tools/bench_surfaces.py)")
    return dict(seconds=rep["seconds"], times=rep["times"], damp=damp, feature_edges=rep["feature_edges"],
                held=rep["held"], output=stem + ".vtk")


def run_quadopt(quadopt, in_path, name, preset, repeat, extra, out_dir):
    out_path = os.path.join(out_dir, "outputs", f"{name}.quadopt-{preset}.vtk")
    times = []
    for _ in range(repeat):
        cmd = [quadopt, "optimize", in_path, "-o", out_path, "--json", "--effort", preset, *extra]
        t0 = time.perf_counter()
        r = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        if r.returncode != 0:
            msg = (r.stderr.strip() or r.stdout.strip() or f"exit {r.returncode}").splitlines()
            raise RuntimeError(msg[-1] if msg else f"exit {r.returncode}")
        try:
            report = json.loads(r.stdout)
            # The run and the set-up it needs (features, patches, reference trees), as the peers'
            # times include theirs.
            times.append(float(report["seconds"]) + float(report.get("setup_seconds", 0.0)))
        except (ValueError, KeyError):
            times.append(wall)
        if times[0] > 20:
            break
    return dict(seconds=statistics.median(times), times=times, output=out_path)


# --------------------------------------------------------------------------------------------
# The benchmark
# --------------------------------------------------------------------------------------------


def bench_mesh(args, name, in_path, tool_results, exes, cad=None):
    """Runs the peer drivers (exes: "openmesh", "vcglib", None when not built) and quadopt's
    presets on one mesh, measures the input and every tool's output (with tool_results, the
    outputs already made); returns the rows. With `cad` (the sample and its faces' CAD surfaces),
    also each vertex's distance to the CAD model."""
    points, faces = read_vtk(in_path)
    ref = Reference(points, faces)
    bad = orientation_conflicts(faces)
    if bad:
        note(f"{name}: {bad} edges used twice in the same direction (inconsistent orientation)")
    base = dict(mesh=name, faces=len(faces), triangles=int((faces[:, 3] < 0).sum()), vertices=len(points),
                mean_edge=ref.h)
    rows = [dict(base, tool="input", seconds=None, **measure(points, faces, ref, in_path, in_path, args.quadopt))]
    results = dict(tool_results)
    off = os.path.join(args.out, "outputs", f"{name}.off")
    write_off(off, points, faces)
    peer_runs = []  # (tool, function running it)
    if exes["openmesh"]:
        peer_runs += [(f"OpenMesh Jacobi x{it}", lambda it=it: run_openmesh(
            exes["openmesh"], off, faces, name, it, args.repeat, args.features, args.out)) for it in OPENMESH_ITERS]
    if exes["vcglib"]:
        peer_runs += [(f"vcglib {run[0]} x{run[2]}", lambda run=run: run_vcglib(
            exes["vcglib"], off, faces, name, run, args.repeat, args.features, args.out)) for run in VCGLIB_RUNS]
    for tool, run in peer_runs:
        try:
            results[tool] = run()
        except (RuntimeError, ValueError) as e:
            results[tool] = dict(error=str(e))
    for preset in PRESETS:
        try:
            results[f"quadopt {preset}"] = run_quadopt(args.quadopt, in_path, name, preset, args.repeat,
                                                       args.quadopt_flags.split(), args.out)
        except RuntimeError as e:
            results[f"quadopt {preset}"] = dict(error=str(e))
    for tool, res in results.items():
        row = dict(base, tool=tool, **{k: v for k, v in res.items() if k != "output"})
        if "error" not in res:
            out_points, out_faces = read_vtk(res["output"])
            if not np.array_equal(out_faces, faces):
                row["error"] = "the output's faces differ from the input's"
            else:
                try:
                    row.update(measure(out_points, out_faces, ref, res["output"], in_path, args.quadopt))
                except RuntimeError as e:
                    row["error"] = str(e)
            row["output"] = res["output"]
            row["_points"] = out_points
        rows.append(row)
    if cad is not None:
        measured = [r for r in rows if "error" not in r]
        pts = [r.pop("_points", points) for r in measured]
        for r, d in zip(measured, cad_distances(cad[0], cad[1], faces, pts)):
            r["cad_dist_abs"], r["cad_dist_rel"] = d, d / ref.h
    for r in rows:
        r.pop("_points", None)
    return rows


MEASURES = ["signed", "verdict"]


def dominance(rows):
    """Per peer run: the quadopt presets that dominate it in each measure (see the module docs)."""
    out = []
    for r in rows:
        if r["tool"] == "input" or r["tool"].startswith("quadopt") or "error" in r or "skipped" in r:
            continue
        d = dict(mesh=r["mesh"], peer=r["tool"])
        for m in MEASURES:
            d[m] = [q["tool"] for q in rows if q["mesh"] == r["mesh"] and q["tool"].startswith("quadopt")
                    and "error" not in q and max(q["seconds"], MIN_SECONDS) <= max(r["seconds"], MIN_SECONDS)
                    and q[f"{m}_min"] >= r[f"{m}_min"] - TOL and q[f"{m}_avg"] >= r[f"{m}_avg"] - TOL]
        out.append(d)
    return out


def fmt_seconds(s):
    return "" if s is None else f"{s:.4f}" if s >= 0.01 else f"{s:.2e}"


def table(rows, dom):
    """One compact table per mesh; "dominated" names the measures in which a quadopt preset
    dominates the peer run."""
    by_peer = {(d["mesh"], d["peer"]): d for d in dom}
    inputs = os.path.join(os.path.abspath(OUT_INPUTS[0]), "")
    out = []
    for mesh in dict.fromkeys(r["mesh"] for r in rows):
        mr = [r for r in rows if r["mesh"] == mesh]
        r0 = mr[0]
        tri = f" ({r0['triangles']} triangles)" if r0.get("triangles") else ""
        out.append(f"### {mesh}: {r0.get('faces', '?')} faces{tri}, {r0.get('vertices', '?')} vertices")
        if "skipped" in r0:
            out += [f"skipped: {r0['skipped']}", ""]
            continue
        cad = any("cad_dist_rel" in r for r in mr)
        out += ["| tool | verdict min / avg (inv) | signed min / avg (inv) | dist | " + ("CAD dist | " if cad else "")
                + "seconds | dominated |",
                "| --- | ---: | ---: | ---: | " + ("---: | " if cad else "") + "---: | --- |"]
        for r in mr:
            if "error" in r:
                err = r["error"].replace(inputs, "").replace("|", "/")[:110]
                out.append(f"| {r['tool']} | error: {err} | | | " + ("| " if cad else "") + "| |")
                continue
            d = by_peer.get((mesh, r["tool"]))
            dominated = "" if d is None else ", ".join(m for m in MEASURES if d[m]) or "no"
            out.append(f"| {r['tool']} | {r['verdict_min']:.4f} / {r['verdict_avg']:.4f} ({r['verdict_inverted']}) | "
                       f"{r['signed_min']:.4f} / {r['signed_avg']:.4f} ({r['inverted']}) | {r['dist_rel']:.2e} | "
                       + (f"{format(r['cad_dist_rel'], '.2e') if 'cad_dist_rel' in r else ''} | " if cad else "")
                       + f"{fmt_seconds(r['seconds'])} | {dominated} |")
        out.append("")
    return "\n".join(out)


def real_meshes(real_dir, wanted):
    """The real meshes on curved surfaces (real_dir/surface, and real_dir/mixed unless planar):
    [(name, path, None or why it is skipped)]."""
    out = []
    for sub in REAL_SETS:
        d = os.path.join(real_dir, sub)
        for fn in sorted(os.listdir(d)) if os.path.isdir(d) else []:
            name = fn[:-4]
            if not fn.endswith(".vtk") or not wanted(name):
                continue
            points, faces = read_vtk(os.path.join(d, fn))
            why = None
            if planar(points, faces):
                why = f"planar ({sub}/; planar meshes are tools/bench_peers.py's)"
            elif not orientable(faces):
                why = "not orientable (quadopt refuses it: a curved surface's measure is signed by its orientation)"
            out.append((name, os.path.join(d, fn), why))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quadopt", required=True, help="the quadopt binary")
    ap.add_argument("--out", default=os.path.join(ROOT, "target", "bench-surfaces"), help="output directory (inputs, outputs, JSON)")
    ap.add_argument("--mesquite", default=MESQUITE, help="directory of Mesquite's untangled meshes")
    ap.add_argument("--real", default=REAL,
                    help="directory of real meshes (its surface/ and mixed/ subdirectories; default ../shared/meshes/real)")
    ap.add_argument("--build", default=os.path.join(ROOT, "target", "surface-peers"),
                    help="where the peer drivers (OpenMesh, vcglib) are built")
    ap.add_argument("--vcglib", default=VCGLIB,
                    help="vcglib's source tree (extracted there from --meshlab-src if absent; outside the repository)")
    ap.add_argument("--meshlab-src", default=MESHLAB_SRC, help="MeshLab's source tarball (src/vcglib inside)")
    ap.add_argument("--repeat", type=int, default=5, help="runs per tool (the median time is reported)")
    ap.add_argument("--features", type=float, default=45.0,
                    help="OpenMesh, vcglib: hold vertices on edges with a larger dihedral angle (degrees; negative: none)")
    ap.add_argument("--quadopt-flags", default="", help="extra flags for every quadopt run")
    ap.add_argument("--only", help="only the meshes whose name contains one of these (comma-separated)")
    args = ap.parse_args()
    if args.features < 0:
        args.features = None
    only = [w for w in (args.only or "").split(",") if w]

    def wanted(name):
        return not only or any(w in name for w in only)

    os.makedirs(os.path.join(args.out, "inputs"), exist_ok=True)
    OUT_INPUTS[0] = os.path.join(args.out, "inputs")
    os.makedirs(os.path.join(args.out, "outputs"), exist_ok=True)
    exes = {}
    for peer, build in (("openmesh", lambda: build_openmesh(args.build)),
                        ("vcglib", lambda: build_vcglib(args.build, args.vcglib, args.meshlab_src))):
        try:
            exes[peer] = build()
        except (RuntimeError, OSError) as e:
            note(f"{peer} peers skipped: {e}")
            exes[peer] = None

    meshes = []  # (name, input path, gmsh results, CAD or None)
    skipped = []  # rows of the meshes not run
    for s in make_samples.SURFACE_SAMPLES:
        for clean in (False, True):
            name = s["name"] + ("_clean" if clean else "")
            if not wanted(name):
                continue
            in_path, res, face_surface = run_cad_sample(s, clean, args.repeat, args.out)
            meshes.append((name, in_path, res, (s, face_surface)))
    copies = []  # (name, source, title)
    for m in MESQUITE_MESHES:
        path = os.path.join(args.mesquite, m + ".vtk")
        if not wanted(m):
            continue
        if not os.path.exists(path):
            note(f"{path} not found, skipped")
            continue
        copies.append((m, path, f"Mesquite {m} (tools/bench_surfaces.py copy)"))
    if os.path.isdir(args.real):
        for name, path, why in real_meshes(args.real, wanted):
            if why is None:
                copies.append((name, path, f"{name} (tools/bench_surfaces.py copy)"))
                continue
            note(f"{name} skipped: {why}")
            points, faces = read_vtk(path)
            skipped.append(dict(mesh=name, faces=len(faces), triangles=int((faces[:, 3] < 0).sum()),
                                vertices=len(points), tool="input", skipped=why))
    else:
        note(f"{args.real} not found, the real meshes skipped")
    for name, path, title in copies:
        # A plain copy (this script's layout), which every tool reads the same.
        points, faces = read_vtk(path)
        in_path = os.path.join(args.out, "inputs", name + ".vtk")
        write_vtk(in_path, points, faces, title)
        meshes.append((name, in_path, {}, None))

    rows, checked = [], False
    for name, in_path, res, cad in meshes:
        if not checked:
            p, f = read_vtk(in_path)
            diff = vtk_cross_check(p, f)
            note(f"verdict scaled Jacobian vs vtkMeshQuality on {name}: largest difference {diff:.2e}")
            checked = True
        rows += bench_mesh(args, name, in_path, res, exes, cad)
        print(f"done {name}", file=sys.stderr, flush=True)
    rows += skipped
    dom = dominance(rows)
    print(table(rows, dom))
    counts = {m: sum(1 for d in dom if d[m]) for m in MEASURES}
    for m in MEASURES:
        print(f"dominance ({m} measure): dominated {counts[m]} of {len(dom)} peer runs")
    for d in dom:
        missing = [m for m in MEASURES if not d[m]]
        if missing:
            print(f"  not dominated ({', '.join(missing)}): {d['mesh']} / {d['peer']}")
    with open(os.path.join(args.out, "bench_surfaces.json"), "w") as f:
        json.dump(dict(rows=rows, dominance=dom, dominated=counts, peer_runs=len(dom), repeat=args.repeat,
                       features=args.features, quadopt=args.quadopt, quadopt_flags=args.quadopt_flags,
                       vcglib_runs=VCGLIB_RUNS), f, indent=1)


if __name__ == "__main__":
    main()

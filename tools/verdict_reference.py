#!/usr/bin/env python3
"""Reference values of Verdict's quad and triangle scaled Jacobians (VTK) for tests/verdict.rs.

Usage:  python3 -m venv /tmp/venv && /tmp/venv/bin/pip install vtk
        /tmp/venv/bin/python tools/verdict_reference.py            # writes tests/data/verdict_quads.csv
        /tmp/venv/bin/python tools/verdict_reference.py --check    # only compares with the committed CSV
        /tmp/venv/bin/python tools/verdict_reference.py --triangles          # verdict_triangles.csv
        /tmp/venv/bin/python tools/verdict_reference.py --triangles --check
        /tmp/venv/bin/python tools/verdict_reference.py --3d                  # verdict_quads_3d.csv
        /tmp/venv/bin/python tools/verdict_reference.py --3d --triangles      # verdict_triangles_3d.csv
        (add --check to either to compare with the committed CSV)

The 3D modes are described in the section "Faces in 3D" at the end of this docstring.
The triangle mode is described in the section "Triangles" at the end of this docstring.

The output is deterministic (fixed seed, no dependence on dict order or time); rerunning the script
with the same VTK version reproduces the committed file byte for byte. The committed file was made
with VTK 9.7.2 (pip wheel); `vtkMeshQuality` with `SetQuadQualityMeasureToScaledJacobian` calls
`vtkverdict::quad_scaled_jacobian`.

CSV columns
-----------
kind              shape family: square, rectangle, rhombus, parallelogram, trapezoid, kite, dart,
                  bowtie, near_degenerate, degenerate, collapsed, tiny, and random_convex,
                  random_dart (one reflex corner), random_bowtie (self-intersecting); a ``_cw``
                  suffix marks a quad whose net signed area is negative (given clockwise).
rule              how quadopt's value relates to Verdict's on this row (see below).
x0,y0,...,x3,y3   the corners in the order given to both libraries (z = 0), printed with repr()
                  so they parse back to the same doubles.
verdict_sj        vtkMeshQuality's scaled Jacobian of that quad.
verdict_sj_big    vtkMeshQuality's value for the same quad scaled by 2**32 about the origin (an
                  exact scaling in binary floating point, so the shape is identical).

What Verdict computes (VTK 9.7.2, read from the binary and checked on every row by `model()`)
---------------------------------------------------------------------------------------------
1. If the last two points are bit-identical (``is_collapsed_quad``), the quad is measured as the
   triangle (p0, p1, p2) with ``tri_scaled_jacobian``: |2 * area| * 2/sqrt(3) divided by the largest
   product of two edge lengths. This value is UNSIGNED (no normal callback is installed by VTK),
   and it is not clamped, so an equilateral triangle can give 1.0000000000000002.
2. Otherwise the edges are divided by the diagonal of the quad's bounding box, and if any
   normalized edge is shorter than 2.220446049250313e-15 (10 * DBL_EPSILON) the result is 0. The
   threshold is relative to the quad's size; Verdict's old absolute VERDICT_DBL_MIN = 1e-30 test is
   no longer what decides.
3. The quad's own normal is n = (e0 - e2) x (e1 - e3) (the "principal axes"); in the plane
   n_z = 4 * signed area. ``VerdictVector::normalize`` sets vectors of length <= 4.440892098500626e-15
   (20 * DBL_EPSILON) to zero. That threshold is ABSOLUTE, so every quad with |area| <= 1.11e-15
   (a square of side < 3.3e-8, in whatever units the mesh uses) scores 0, and so does every quad
   with zero net area (a symmetric bowtie, all four points on a line).
4. Otherwise the value is min over the corners of sign(area) * cross(next - p, prev - p) /
   (|next - p| |prev - p|): the signed corner values against the quad's own normal.

How quadopt's signed definition relates (docs/method.md, "Scaled Jacobian in the plane")
----------------------------------------------------------------------------------------
quadopt measures every corner against +z (the mesh's normal once its orientation is fixed):
sj(q) = min_i c_i with c_i = cross(next - p, prev - p) / (|next - p| |prev - p|). Hence:

* area > 0 (counter-clockwise, including darts and bowties whose net area is positive):
  quadopt == Verdict.                                                          rule ``equal``
* area < 0 (clockwise): Verdict measures against -z, so Verdict(q) == quadopt(reversed q), with
  reversed q = (p1, p0, p3, p2) (this reversal keeps a collapsed pair last). For quadopt itself
  quadopt(q) = min_i c_i <= -max_i c_i = -Verdict(q).                          rule ``reversed``
  NOTE: quadopt(q) == -Verdict(q) only when all four |c_i| are equal (rectangles, rhombi,
  parallelograms) and for collapsed triangles; for a clockwise convex trapezoid quadopt gives
  -max|c_i| (the worst fold) while Verdict gives +min|c_i|.                      rule ``negated``
  marks the rows where quadopt(q) == -Verdict(q) is expected as well.
* collapsed (p2 == p3): quadopt's triangle value is signed, Verdict's is |.|: ``equal`` for a
  counter-clockwise triangle, ``negated`` for a clockwise one.
* exactly zero-length edge (not the collapsed pair): both give 0.               rule ``equal``
* edge shorter than 10 * DBL_EPSILON of the bounding-box diagonal: Verdict gives 0; quadopt
  should as well.                                                               rule ``short_edge``
* zero net area with nonzero edges (symmetric bowtie, collinear points): Verdict has no normal and
  gives 0; quadopt still sees the corners turning both ways and gives a value <= 0 (inverted or
  degenerate against the mesh normal). A deliberate, documented divergence.     rule ``zero_area``
* 0 < |area| <= 1.11e-15 (tiny quads): Verdict gives 0 because of its absolute normalization
  threshold; quadopt stays scale invariant and gives Verdict's value for the same quad scaled by
  2**32 (column verdict_sj_big). A deliberate, documented divergence.           rule ``tiny_area``

Self-intersecting ("bowtie") quads: Verdict does not detect self-intersection. It uses the sign of
the NET signed area (the two lobes cancel partially), so a bowtie gets the value of rule 4 (always
negative: each lobe has a corner turning the wrong way) or 0 when the lobes cancel exactly. They
are included: with nonzero net area they obey the same ``equal`` / ``reversed`` rules as every
other quad, and the exact-cancellation case is covered by ``zero_area`` rows.

Rows whose classification would depend on roundoff (area within a factor 4 of Verdict's threshold,
an edge ratio within a factor 4 of 10 * DBL_EPSILON, or a net area that is not clearly nonzero
relative to the quad's size) are dropped, so every row's rule is unambiguous.

Triangles (``--triangles``, tests/data/verdict_triangles.csv)
=============================================================
``vtkMeshQuality`` with ``SetTriangleQualityMeasureToScaledJacobian`` on VTK_TRIANGLE cells calls
``vtkverdict::tri_scaled_jacobian``. Same seed policy: rerunning reproduces the file byte for byte.

CSV columns: kind, rule, x0,y0,x1,y1,x2,y2 (repr()), verdict_sj, verdict_sj_big (the triangle
scaled by 2**32 about the origin, exact). ``kind`` is the shape family (equilateral, right,
right_isosceles, obtuse, needle, cap, nearly_collapsed, degenerate, tiny, huge, random) with a
``_cw`` suffix when the triangle's exact signed area is negative (given clockwise).

What Verdict computes (VTK 9.7.2, checked on every row by ``tri_model()`` to 1e-13): with
e0 = p1 - p0, e1 = p2 - p0, e2 = p2 - p1, the Jacobian is |(e1 - e0) x (e2 - e0)| (= |2 * area|,
UNSIGNED: VTK installs no normal callback, so a clockwise triangle in the plane gets the same
positive value as its counter-clockwise twin), and the result is that times 2/sqrt(3) divided by
the largest product of two edge lengths; 0 for a tiny triangle (ABSOLUTE). ``tri_model()`` models
that cut-off as a largest product below VERDICT_DBL_MIN = 1e-30, which classifies every planar
row as VTK does; VTK 9.7.2 in fact divides the edges by the bounding-box diagonal first and cuts
off at a diagonal below about 2.2e-15 (see "Triangles" under the 3D mode below), which differs
only in a band no planar row falls in. Not clamped: an equilateral triangle can give
1.0000000000000002.

quadopt (src/quality.rs, ``triangle_scaled_jacobian``) computes the same ratio SIGNED against +z
(the mesh normal), clamped to [-1, 1], on edges scaled by a power of two first (scale invariant).
Rules:

* ``equal``: area > 0 (counter-clockwise): quadopt == Verdict.
* ``negated``: area < 0 (clockwise): quadopt(t) == -Verdict(t), and quadopt(reversed t) ==
  Verdict(t). (A triangle has one value, not a minimum over corners, so unlike a quad both hold.)
* ``zero_area``: exactly zero area (collinear or repeated points): Verdict's value is 0 up to
  roundoff of its cross product, quadopt's as well (|value| <= 1e-15 for both).
* ``tiny_area``: nonzero area but largest edge product < 1e-30 / 4: Verdict gives 0; quadopt is
  scale invariant and gives sign(area) * (Verdict's value for the triangle scaled by 2**32,
  ``verdict_sj_big``). A deliberate, documented divergence, as for tiny quads.

Rows are dropped when their classification would depend on roundoff: a largest edge product
within a factor 4 of 1e-30 (at either scale), or a nonzero area below 1e-12 of the largest edge
product (the sign of the computed cross product could be roundoff).

Faces in 3D (``--3d``, tests/data/verdict_quads_3d.csv and ``--3d --triangles``,
tests/data/verdict_triangles_3d.csv; read by tests/verdict_3d.rs)
=========================================================================================
The same filters on non-planar quads and 3D triangles (VTK_QUAD, VTK_TRIANGLE cells with z), with
their own seed (SEED_3D), so the planar files above are untouched by this mode.

Quads: CSV columns kind, rule, x0,y0,z0,...,x3,y3,z3 (repr()), verdict_sj, verdict_sj_big (the quad
scaled by 2**32 about the origin, exact). ``kind``: planar shapes (square, rhombus, trapezoid, kite,
dart, bowtie, random) rotated into a random orientation (``planar_*``), ``lifted`` (a square with
one corner lifted by h), ``twisted`` (a saddle: opposite corners lifted by +h and -h), ``folded``
(a planar quad with corner 3 rotated about the diagonal 0-2 by 10 to 175 degrees), ``bent`` (both
halves of a square turned about the diagonal 1-3), ``near_planar`` (random convex quads with out
of plane noise 1e-12 to 1e-3), ``random3d`` (four random points), ``degenerate``, ``collapsed``,
``tiny``, ``huge``; at random orientations, scales 1e-3 to 1e3 and offsets.

What Verdict computes on a quad in 3D (VTK 9.7.2, checked on every row by ``model_3d()`` to 1e-13
relative; Verdict's source: V_QuadMetric.cpp, signed_corner_areas and quad_scaled_jacobian):
1. last two points bit-identical: the triangle (p0, p1, p2) as below (unsigned).
2. an edge shorter than 10 * DBL_EPSILON of the diagonal of the 3D bounding box: 0.
3. the centre normal n = (e0 - e2) x (e1 - e3), e_i = p_(i+1) - p_i, normalized; 0 when
   |n| <= 20 * DBL_EPSILON (ABSOLUTE, as in the plane: every quad with |n| = 4 |projected area|
   below 4.4e-15 scores 0).
4. min over the corners of n_hat . (e_(i-1) x e_i) / (|e_(i-1)| |e_i|): each corner's normal
   measured against the quad's own centre normal, not clamped. A quad folded across a diagonal
   scores positive as long as every corner normal makes an angle below 90 degrees with n (a
   square folded by 175 degrees still scores 0.0436).

Rules: ``equal`` (quadopt's quality3d::verdict_scaled_jacobian == VTK up to roundoff);
``short_edge`` (both 0); ``zero_normal`` (the exact centre normal is zero, e.g. a symmetric
bowtie or four collinear points: both 0); ``tiny_area`` (0 < |n| <= 20 DBL_EPSILON / 4: VTK gives 0,
quadopt is scale invariant and gives VTK's value for the quad scaled by 2**32, verdict_sj_big).
Verdict computes |n| as the square root of the sum of squares, which overflows when |n| exceeds
about 1e154 (edges beyond about 1e77): VTK then gives 0 (and for triangles when the bounding-box
diagonal overflows, coordinates beyond about 1e154); quadopt scales first and does not. Such rows
are not generated (the ``huge`` ones are scaled by 2**60 to 2**180). Rows whose rule would depend
on roundoff (|n| within a factor 4 of the threshold at VTK's scale or
at quadopt's, edges near the short-edge cut-off, or |n| below 1e-9 of the squared bounding-box
diagonal) are dropped.

Triangles: CSV columns kind, rule, x0,y0,z0,...,x2,y2,z2, verdict_sj, verdict_sj_big. Verdict
(VTK 9.7.2 as measured; V_TriMetric.cpp tri_scaled_jacobian_impl): the edges e0 = p1 - p0,
e1 = p2 - p0, e2 = p2 - p1 are divided by the diagonal of the bounding box (by 1 when that
diagonal is below 10 DBL_EPSILON), then |(e1 - e0) x (e2 - e0)| * 2/sqrt(3) / (largest product of
two edge lengths), unsigned, not clamped; 0 when that product is below 10 DBL_EPSILON, which in
effect means a bounding-box diagonal below 2.2e-15 (absolute). NOTE: the description of the
planar triangle above (an unscaled absolute 1e-30 cut-off) fits every planar row but is not what
VTK 9.7.2 does: it scales like this, so a triangle with a diagonal in [1e-15, 2.2e-15) gives 0
there too, and one with coordinates beyond about 1e154 gives 0 (the diagonal overflows).
Rules: ``equal``, ``zero_area`` (exactly collinear: both 0 up to roundoff), ``tiny_area``
(bounding-box diagonal below 2.2e-15 / 2: VTK 0, quadopt = verdict_sj_big).
"""

import argparse
import csv
import io
import math
import os
import random
import sys
from fractions import Fraction

import vtk

SEED = 20240611
EPS10 = 2.220446049250313e-15  # 10 * DBL_EPSILON: Verdict's relative edge threshold
NORMAL_MIN = 4.440892098500626e-15  # 20 * DBL_EPSILON: VerdictVector::normalize threshold
BIG = 2.0**32

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "tests", "data", "verdict_quads.csv")
OUT_TRIANGLES = os.path.join(HERE, "..", "tests", "data", "verdict_triangles.csv")
VERDICT_DBL_MIN = 1.0e-30  # tri_scaled_jacobian's absolute cut-off on the largest edge product


# ---------------------------------------------------------------------------------------------
# Verdict through VTK


def verdict_faces(faces, cell_type, quad_measure):
    """Scaled Jacobian of every face (all quads or all triangles; points as (x, y, z)) through
    vtkMeshQuality: one unstructured grid, one run. The coordinates must reach Verdict as the
    same doubles."""
    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()
    grid = vtk.vtkUnstructuredGrid()
    for f in faces:
        ids = vtk.vtkIdList()
        for p in f:
            ids.InsertNextId(pts.InsertNextPoint(*p))
        grid.InsertNextCell(cell_type, ids)
    grid.SetPoints(pts)
    k = 0
    for f in faces:
        for p in f:
            assert pts.GetPoint(k) == tuple(p)
            k += 1
    m = vtk.vtkMeshQuality()
    m.SetInputData(grid)
    if quad_measure:
        m.SetQuadQualityMeasureToScaledJacobian()
    else:
        m.SetTriangleQualityMeasureToScaledJacobian()
    m.Update()
    arr = m.GetOutput().GetCellData().GetArray("Quality")
    return [arr.GetValue(i) for i in range(len(faces))]


def verdict_values(quads):
    """Scaled Jacobian of every planar quad through vtkMeshQuality."""
    return verdict_faces([[(x, y, 0.0) for x, y in q] for q in quads], vtk.VTK_QUAD, True)


# ---------------------------------------------------------------------------------------------
# Exact geometry (Fractions: every double is an exact rational) and a float model of Verdict


def exact_area2(q):
    """Twice the signed (shoelace) area, exactly."""
    f = [(Fraction(x), Fraction(y)) for x, y in q]
    return sum(f[i][0] * f[(i + 1) % 4][1] - f[(i + 1) % 4][0] * f[i][1] for i in range(4))


def exact_len2(a, b):
    return (Fraction(b[0]) - Fraction(a[0])) ** 2 + (Fraction(b[1]) - Fraction(a[1])) ** 2


def bbox_diag2(q):
    xs = [Fraction(x) for x, _ in q]
    ys = [Fraction(y) for _, y in q]
    return (max(xs) - min(xs)) ** 2 + (max(ys) - min(ys)) ** 2


def corner_values(q):
    """quadopt's signed corner values (against +z), in floats."""
    out = []
    for i in range(4):
        p, n, v = q[i], q[(i + 1) % 4], q[(i + 3) % 4]
        e1 = (n[0] - p[0], n[1] - p[1])
        e2 = (v[0] - p[0], v[1] - p[1])
        out.append((e1[0] * e2[1] - e1[1] * e2[0]) / (math.hypot(*e1) * math.hypot(*e2)))
    return out


def tri_sj_unsigned(a, b, c):
    e0 = (b[0] - a[0], b[1] - a[1])
    e1 = (c[0] - b[0], c[1] - b[1])
    e2 = (a[0] - c[0], a[1] - c[1])
    l0, l1, l2 = math.hypot(*e0), math.hypot(*e1), math.hypot(*e2)
    m = max(l0 * l1, l1 * l2, l0 * l2)
    if m < 1e-30:
        return 0.0
    jac = abs(e0[0] * (c[1] - a[1]) - e0[1] * (c[0] - a[0]))
    return jac * (2.0 / math.sqrt(3.0)) / m


def model(q):
    """Verdict's quad scaled Jacobian as described in the module docstring (floats)."""
    if q[2] == q[3]:
        return tri_sj_unsigned(q[0], q[1], q[2])
    cs = math.sqrt(float(bbox_diag2(q)))
    if cs < EPS10:
        cs = 1.0
    for i in range(4):
        a, b = q[i], q[(i + 1) % 4]
        if math.hypot((b[0] - a[0]) / cs, (b[1] - a[1]) / cs) < EPS10:
            return 0.0
    n = 2.0 * float(exact_area2(q))  # (e0 - e2) x (e1 - e3) = 4 * area = 2 * area2
    if abs(n) <= NORMAL_MIN:
        return 0.0
    s = 1.0 if n > 0 else -1.0
    return min(s * c for c in corner_values(q))


def classify(q):
    """The rule of a quad, or None when it would depend on roundoff (row dropped)."""
    a2 = exact_area2(q)
    if q[2] == q[3]:
        tri2 = a2  # the shoelace of (p0, p1, p2, p2) is the triangle's doubled area
        return "equal" if tri2 >= 0 else "negated"
    edges2 = [exact_len2(q[i], q[(i + 1) % 4]) for i in range(4)]
    d2 = bbox_diag2(q)
    if min(edges2) == 0:
        return "equal"  # exact zero-length edge: both 0
    ratio2 = min(edges2) / d2
    t2 = Fraction(EPS10) ** 2
    if ratio2 < t2 / 16:
        return "short_edge"
    if ratio2 < t2 * 16:
        return None
    n = 2 * abs(a2)
    if a2 == 0:
        return "zero_area"
    if n < Fraction(NORMAL_MIN) / 4:
        return "tiny_area" if a2 > 0 else None
    if n < Fraction(NORMAL_MIN) * 4:
        return None
    # Net area not clearly nonzero relative to the size: the sign Verdict sees is roundoff.
    if abs(a2) < Fraction(1, 10**9) * d2:
        return None
    return "equal" if a2 > 0 else "reversed"


# ---------------------------------------------------------------------------------------------
# The quads


def transform(q, angle, scale, tx, ty):
    c, s = math.cos(angle), math.sin(angle)
    return [(scale * (c * x - s * y) + tx, scale * (s * x + c * y) + ty) for x, y in q]


def reverse(q):
    """Same quad, clockwise <-> counter-clockwise, keeping a collapsed pair last."""
    return [q[1], q[0], q[3], q[2]]


def rotate_start(q, k):
    return q[k:] + q[:k]


def build(rng):
    rows = []  # (kind, quad)

    def add(kind, q, both=True, starts=True):
        """Add q (ccw) in a few placements, and its clockwise twin."""
        q = [(float(x), float(y)) for x, y in q]
        rows.append((kind, q))
        if starts:
            rows.append((kind, rotate_start(q, 1 + rng.randrange(3))))
        for _ in range(2):
            t = transform(
                q, rng.uniform(0, 2 * math.pi), 10 ** rng.uniform(-3, 3), rng.uniform(-50, 50), rng.uniform(-50, 50)
            )
            rows.append((kind, t))
        if both:
            rows.append((kind + "_cw", reverse(q)))
            t = transform(q, rng.uniform(0, 2 * math.pi), 10 ** rng.uniform(-2, 2), rng.uniform(-5, 5), 0.0)
            rows.append((kind + "_cw", reverse(t)))

    h = math.sqrt(3.0) / 2.0
    add("square", [(0, 0), (1, 0), (1, 1), (0, 1)])
    add("square", [(-1, -1), (1, -1), (1, 1), (-1, 1)])
    add("rectangle", [(0, 0), (5, 0), (5, 0.1), (0, 0.1)])
    add("rectangle", [(0, 0), (1e-3, 0), (1e-3, 7), (0, 7)])
    add("rhombus", [(0, 0), (1, 0), (1.5, h), (0.5, h)])
    add("rhombus", [(0, 0), (1, 0), (1 + math.cos(0.2), math.sin(0.2)), (math.cos(0.2), math.sin(0.2))])
    add("parallelogram", [(0, 0), (3, 0), (4, 1), (1, 1)])
    add("parallelogram", [(0, 0), (2, 0.5), (2.5, 2.5), (0.5, 2)])
    add("trapezoid", [(0, 0), (2, 0), (1, 1), (0, 1)])
    add("trapezoid", [(0, 0), (4, 0), (3, 1), (1, 1)])
    add("trapezoid", [(0, 0), (1, 0), (0.99, 1), (0.01, 1)])
    add("kite", [(0, 0), (1, -0.5), (3, 0), (1, 0.5)])
    add("kite", [(0, -1), (2, 0), (0, 1), (-0.5, 0)])
    add("dart", [(0, 0), (1, 0), (0.5, 0.2), (0, 1)])
    add("dart", [(0, 0), (2, 1), (4, 0), (2, 3)])
    add("dart", [(0, 0), (1, 0), (0.4, 0.4), (0, 1)])
    add("dart", [(0, 0), (1, 0), (0.5, 0.499), (0, 1)])  # reflex corner just past 180 degrees
    add("kite", [(0, 0), (1, 0), (0.5, 0.501), (0, 1)])  # convex, nearly flat corner
    # Bowties: net area positive / negative / exactly zero.
    add("bowtie", [(0, 0), (2, 2), (2, 0), (0, 1)][::-1])
    add("bowtie", [(0, 0), (3, 1), (3, 0), (0, 2)])
    add("bowtie", [(0, 0), (1, 2), (1, 0), (0, 1)])
    for q in ([(0, 0), (1, 1), (1, 0), (0, 1)], [(0, 0), (2, 1), (2, 0), (0, 1)], [(0, 0), (1, 0), (0, 1), (1, 1)]):
        rows.append(("bowtie", [(float(x), float(y)) for x, y in q]))
    # All four points on a line (zero area): Verdict 0.
    rows.append(("degenerate", [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (3.0, 0.0)]))
    rows.append(("degenerate", [(0.0, 0.0), (2.0, 1.0), (1.0, 0.5), (3.0, 1.5)]))
    # Exactly repeated points (not the collapsed pair): zero-length edge, both 0.
    for q in (
        [(0, 0), (0, 0), (1, 1), (0, 1)],
        [(0, 0), (1, 0), (1, 0), (0, 1)],
        [(0, 0), (1, 0), (1, 1), (0, 0)],
        [(2, 2), (2, 2), (2, 2), (2, 2)],
        [(0, 0), (0, 0), (1, 1), (1, 1)],
    ):
        rows.append(("degenerate", [(float(x), float(y)) for x, y in q]))
    # Collapsed quads (last two points equal): measured as the triangle (p0, p1, p2).
    add("collapsed", [(0, 0), (1, 0), (0.5, h), (0.5, h)], starts=False)
    add("collapsed", [(0, 0), (1, 0), (0, 1), (0, 1)], starts=False)
    add("collapsed", [(0, 0), (4, 0), (1, 0.3), (1, 0.3)], starts=False)
    add("collapsed", [(0, 0), (1, 0), (2, 1e-9), (2, 1e-9)], starts=False)
    rows.append(("collapsed", [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, 0.0)]))  # flat triangle
    rows.append(("collapsed", [(0.0, 0.0), (0.0, 0.0), (2.0, 1.0), (2.0, 1.0)]))  # two pairs
    # Near-degenerate: one short edge, still well above Verdict's relative threshold.
    for e in (1e-3, 1e-6, 1e-9, 1e-12, 1e-13):
        add("near_degenerate", [(0, 0), (e, 0), (1, 1), (0, 1)], both=False)
        add("near_degenerate", [(0, 0), (1, 0), (1, 1), (1 - e, 1)], both=False, starts=False)
    add("near_degenerate", [(0, 0), (1, 0), (1, 1e-9), (0, 1e-9)])  # sliver rectangle
    # Short edges below 10 * DBL_EPSILON of the size: Verdict 0 (the threshold is relative).
    for e in (1e-16, 1e-20, 1e-29, 1e-31, 1e-300):
        rows.append(("degenerate", [(0.0, 0.0), (e, 0.0), (1.0, 1.0), (0.0, 1.0)]))
    for e, s in ((1e-12, 1e6), (1e-6, 1e10), (1.0, 1e17)):
        rows.append(("degenerate", [(e, 0.0), (s, 0.0), (s, s), (0.0, 0.0)]))
        rows.append(("degenerate", [(0.0, 0.0), (s, 0.0), (s, s), (0.0, e)]))
    rows.append(("degenerate", [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (1.0, math.nextafter(1.0, 2.0))]))  # p3 ~ p2
    # Tiny quads (|area| <= 1.1e-15): Verdict 0 by its absolute threshold; dyadic scale factors
    # keep the shapes exact.
    for kind, q in list(rows[:40]):
        if kind.endswith("_cw") or rng.random() < 0.6:
            continue
        k = rng.choice([-30, -31, -32])  # undone exactly by BIG = 2**32
        rows.append(("tiny", [(math.ldexp(x, k), math.ldexp(y, k)) for x, y in q]))
    rows.append(("tiny", [(1.0, 1.0), (1.0 + 2**-30, 1.0), (1.0 + 2**-30, 1.0 + 2**-30), (1.0, 1.0 + 2**-30)]))
    # Random quads: points around a circle with jitter (mostly convex, some darts) and
    # fully random points (every kind, including bowties), both orientations as they come.
    for _ in range(120):
        angles = sorted(rng.uniform(0, 2 * math.pi) for _ in range(4))
        r = [rng.uniform(0.2, 1.0) for _ in range(4)]
        q = [(r[i] * math.cos(angles[i]), r[i] * math.sin(angles[i])) for i in range(4)]
        if rng.random() < 0.3:
            q = q[::-1]
        q = transform(q, 0.0, 10 ** rng.uniform(-4, 4), rng.uniform(-100, 100), rng.uniform(-100, 100))
        rows.append(("random", q))
    for _ in range(120):
        q = [(rng.uniform(-1, 1), rng.uniform(-1, 1)) for _ in range(4)]
        rows.append(("random", q))
    return rows


def final_kind(kind, q):
    """The family name, with ``_cw`` when the quad's net area is negative; random quads get their
    geometric kind (convex, dart: one reflex corner, bowtie: self-intersecting)."""
    a2 = exact_area2(q)
    kind = kind.removesuffix("_cw")
    if kind == "random":
        sign = 1 if a2 >= 0 else -1
        flipped = sum(1 for v in corner_values(q) if sign * v < 0)
        kind = "random_" + {0: "convex", 1: "dart"}.get(flipped, "bowtie")
    return kind + ("_cw" if a2 < 0 else "")


# ---------------------------------------------------------------------------------------------
# Triangles (--triangles)


def verdict_triangle_values(tris):
    """Scaled Jacobian of every planar triangle through vtkMeshQuality."""
    return verdict_faces([[(x, y, 0.0) for x, y in t] for t in tris], vtk.VTK_TRIANGLE, False)


def tri_exact_area2(t):
    """Twice the signed area, exactly."""
    (ax, ay), (bx, by), (cx, cy) = [(Fraction(x), Fraction(y)) for x, y in t]
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


def tri_max_product2(t):
    """The square of the largest product of two edge lengths, exactly."""
    l2 = [exact_len2(t[i], t[(i + 1) % 3]) for i in range(3)]
    return max(l2[0] * l2[1], l2[1] * l2[2], l2[0] * l2[2])


def tri_model(t):
    """Verdict's tri_scaled_jacobian as described in the docstring, step by step in floats."""
    a, b, c = t
    e0 = (b[0] - a[0], b[1] - a[1])
    e1 = (c[0] - a[0], c[1] - a[1])
    e2 = (c[0] - b[0], c[1] - b[1])
    first = (e1[0] - e0[0], e1[1] - e0[1])
    second = (e2[0] - e0[0], e2[1] - e0[1])
    jac = abs(first[0] * second[1] - first[1] * second[0])
    l0, l1, l2 = [math.sqrt(e[0] * e[0] + e[1] * e[1]) for e in (e0, e1, e2)]
    m = max(l0 * l1, max(l1 * l2, l0 * l2))
    if m < VERDICT_DBL_MIN:
        return 0.0
    return jac * (2.0 / math.sqrt(3.0)) / m


def tri_classify(t):
    """The rule of a triangle, or None when it would depend on roundoff (row dropped)."""
    a2 = tri_exact_area2(t)
    if a2 == 0:
        return "zero_area"
    m2 = tri_max_product2(t)
    lo, hi = Fraction(VERDICT_DBL_MIN / 4) ** 2, Fraction(VERDICT_DBL_MIN * 4) ** 2
    if lo <= m2 <= hi or lo <= m2 * Fraction(BIG) ** 4 <= hi:
        return None
    if a2 * a2 < Fraction(1, 10**24) * m2:
        return None  # |2 area| < 1e-12 * largest product: the computed sign may be roundoff
    if m2 < lo:
        return "tiny_area"
    return "equal" if a2 > 0 else "negated"


def tri_build(rng):
    rows = []  # (kind, triangle)

    def add(kind, t, placements=2, both=True):
        """Add t (ccw) as given, from another first corner, in a few random placements, and its
        clockwise twin (given and placed)."""
        t = [(float(x), float(y)) for x, y in t]
        rows.append((kind, t))
        k = 1 + rng.randrange(2)
        rows.append((kind, t[k:] + t[:k]))
        for _ in range(placements):
            rows.append(
                (
                    kind,
                    transform(
                        t,
                        rng.uniform(0, 2 * math.pi),
                        10 ** rng.uniform(-3, 3),
                        rng.uniform(-50, 50),
                        rng.uniform(-50, 50),
                    ),
                )
            )
        if both:
            rows.append((kind, [t[0], t[2], t[1]]))
            p = transform(t, rng.uniform(0, 2 * math.pi), 10 ** rng.uniform(-2, 2), rng.uniform(-5, 5), 0.0)
            rows.append((kind, [p[1], p[0], p[2]]))

    h = math.sqrt(3.0) / 2.0
    add("equilateral", [(0, 0), (1, 0), (0.5, h)], placements=4)
    add("equilateral", [(-1, -1), (1, -1), (0, -1 + 2 * h)])
    add("right_isosceles", [(0, 0), (1, 0), (0, 1)])
    add("right_isosceles", [(0, 0), (2, 0), (1, 1)])
    add("right", [(0, 0), (4, 0), (0, 3)])
    add("right", [(0, 0), (math.sqrt(3.0), 0), (0, 1)])
    add("right", [(0, 0), (10, 0), (0, 0.1)])
    for deg in (100, 120, 135, 150, 170, 179):
        a = math.radians(deg)
        add("obtuse", [(0, 0), (1, 0), (math.cos(a), math.sin(a))])
    add("obtuse", [(0, 0), (4, 0), (2, 1)])
    add("obtuse", [(0, 0), (3, 0), (-1, 0.5)])
    for e in (1e-2, 1e-4, 1e-6, 1e-9):
        add("needle", [(0, 0), (1, 0), (0.5, e)], placements=1)  # isosceles sliver, apex angle ~180
        add("needle", [(0, 0), (1, 0), (1, e)], placements=1)  # one short edge
        add("needle", [(0, 0), (1, 0), (1 + e, e)], placements=1)  # two long edges, tiny angle
    for e in (1e-3, 1e-6, 1e-9):
        add("cap", [(0, 0), (1, 0), (0.3, e)], placements=1)
    for e in (1e-10, 1e-11, 2**-36):
        add("nearly_collapsed", [(0, 0), (1, 0), (0.25, e)], placements=1)
        add("nearly_collapsed", [(0, 0), (1, 0), (3, e)], placements=0)
    # Exactly zero area: collinear points, repeated points, a single point.
    for t in (
        [(0, 0), (1, 0), (2, 0)],
        [(0, 0), (2, 0), (1, 0)],
        [(0, 0), (2, 1), (4, 2)],
        [(0.5, 0.25), (1.5, 0.75), (3.5, 1.75)],
        [(0, 0), (0, 0), (1, 1)],
        [(0, 0), (1, 1), (1, 1)],
        [(2, 2), (2, 2), (2, 2)],
        [(0, 0), (3, 0), (3, 0)],
    ):
        rows.append(("degenerate", [(float(x), float(y)) for x, y in t]))
    # Tiny triangles (largest edge product < 1e-30): Verdict 0 by its absolute threshold;
    # dyadic factors keep the shapes exact, and 2**32 brings them above the threshold.
    shapes = [t for kind, t in rows[:60] if kind in ("equilateral", "right_isosceles", "right", "obtuse")]
    for t in rng.sample(shapes, 12):
        k = rng.choice([-56, -60, -64, -70])
        rows.append(("tiny", [(math.ldexp(x, k), math.ldexp(y, k)) for x, y in t]))
    rows.append(("tiny", [(1.0, 1.0), (1.0 + 2**-52, 1.0), (1.0, 1.0 + 2**-52)]))
    # Huge coordinates: nothing overflows in Verdict below about 1e150.
    for t in rng.sample(shapes, 6):
        k = rng.choice([100, 200, 300])
        rows.append(("huge", [(math.ldexp(x, k), math.ldexp(y, k)) for x, y in t]))
    # Random triangles, both orientations as they come.
    for _ in range(150):
        t = [(rng.uniform(-1, 1), rng.uniform(-1, 1)) for _ in range(3)]
        t = transform(t, 0.0, 10 ** rng.uniform(-4, 4), rng.uniform(-100, 100), rng.uniform(-100, 100))
        rows.append(("random", t))
    return rows


def triangle_csv(rng):
    """The triangle reference CSV's text and a one-line summary."""
    rows = []
    dropped = 0
    for kind, t in tri_build(rng):
        rule = tri_classify(t)
        if rule is None:
            print(f"dropped (ambiguous): {kind} {t}")
            dropped += 1
            continue
        a2 = tri_exact_area2(t)
        rows.append((kind + ("_cw" if a2 < 0 else ""), rule, t))

    tris = [t for _, _, t in rows]
    values = verdict_triangle_values(tris)
    big = verdict_triangle_values([[(x * BIG, y * BIG) for x, y in t] for t in tris])

    for i, ((kind, rule, t), v, b) in enumerate(zip(rows, values, big)):
        m = tri_model(t)
        if not abs(m - v) <= 1e-13 * max(1.0, abs(v)):
            sys.exit(f"row {i} ({kind}, {rule}): model {m!r} != vtk {v!r} for {t}")
        if v < 0.0:
            sys.exit(f"row {i} ({kind}, {rule}): vtk gave {v!r} < 0, the docstring says unsigned")
        if rule == "zero_area" and not (v <= 1e-15 and b <= 1e-15):
            sys.exit(f"row {i} ({kind}, {rule}): vtk gave {v!r}, {b!r}, expected 0")
        if rule == "tiny_area" and not (v == 0.0 and b > 0.0):
            sys.exit(f"row {i} ({kind}, {rule}): vtk gave {v!r}, {b!r}, expected 0 and > 0")

    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["kind", "rule", "x0", "y0", "x1", "y1", "x2", "y2", "verdict_sj", "verdict_sj_big"])
    for (kind, rule, t), v, b in zip(rows, values, big):
        w.writerow([kind, rule] + [repr(c) for p in t for c in p] + [repr(v), repr(b)])
    counts = {}
    for _, rule, _ in rows:
        counts[rule] = counts.get(rule, 0) + 1
    summary = f"{len(rows)} triangles ({dropped} ambiguous dropped), vtk {vtk.vtkVersion.GetVTKVersion()}: {counts}"
    return buf.getvalue(), summary


def quad_csv(rng):
    """The quad reference CSV's text and a one-line summary."""
    rows = []
    dropped = 0
    for kind, q in build(rng):
        rule = classify(q)
        if rule is None:
            print(f"dropped (ambiguous): {kind} {q}")
            dropped += 1
            continue
        # Clockwise parallelograms and triangles: quadopt == -Verdict exactly as well.
        if rule == "reversed" and kind.split("_")[0] in ("square", "rectangle", "rhombus", "parallelogram"):
            rule = "negated"
        rows.append((final_kind(kind, q), rule, q))

    quads = [q for _, _, q in rows]
    values = verdict_values(quads)
    big = verdict_values([[(x * BIG, y * BIG) for x, y in q] for q in quads])

    # The description of Verdict in the docstring must hold on every row.
    for i, ((kind, rule, q), v) in enumerate(zip(rows, values)):
        m = model(q)
        if not abs(m - v) <= 1e-13 * max(1.0, abs(v)):
            sys.exit(f"row {i} ({kind}, {rule}): model {m!r} != vtk {v!r} for {q}")
        if rule in ("short_edge", "zero_area", "tiny_area") and v != 0.0:
            sys.exit(f"row {i} ({kind}, {rule}): vtk gave {v!r}, expected 0")

    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["kind", "rule", "x0", "y0", "x1", "y1", "x2", "y2", "x3", "y3", "verdict_sj", "verdict_sj_big"])
    for (kind, rule, q), v, b in zip(rows, values, big):
        w.writerow([kind, rule] + [repr(c) for p in q for c in p] + [repr(v), repr(b)])
    counts = {}
    for _, rule, _ in rows:
        counts[rule] = counts.get(rule, 0) + 1
    summary = f"{len(rows)} rows ({dropped} ambiguous dropped), vtk {vtk.vtkVersion.GetVTKVersion()}: {counts}"
    return buf.getvalue(), summary


# ---------------------------------------------------------------------------------------------
# Faces in 3D (--3d)

SEED_3D = 20261206
OUT_3D = os.path.join(HERE, "..", "tests", "data", "verdict_quads_3d.csv")
OUT_TRIANGLES_3D = os.path.join(HERE, "..", "tests", "data", "verdict_triangles_3d.csv")


def sub3(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross3(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot3(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm3(a):
    return math.sqrt(dot3(a, a))


def exact3(p):
    return tuple(Fraction(c) for c in p)


def bbox_diag2_3d(f):
    e = [exact3(p) for p in f]
    return sum((max(p[k] for p in e) - min(p[k] for p in e)) ** 2 for k in range(3))


def exact_centre_normal(q):
    e = [exact3(p) for p in q]
    ed = [sub3(e[(i + 1) % 4], e[i]) for i in range(4)]
    return cross3(sub3(ed[0], ed[2]), sub3(ed[1], ed[3]))


def tri_model_3d(t):
    """Verdict's tri_scaled_jacobian in 3D, step by step in floats (edges divided by the diagonal
    of the bounding box unless it is below 10 DBL_EPSILON, as for quads)."""
    a, b, c = t
    cs = math.sqrt(float(bbox_diag2_3d(t)))
    if cs < EPS10:
        cs = 1.0
    e0, e1, e2 = [(d[0] / cs, d[1] / cs, d[2] / cs) for d in (sub3(b, a), sub3(c, a), sub3(c, b))]
    jac = norm3(cross3(sub3(e1, e0), sub3(e2, e0)))
    l0, l1, l2 = norm3(e0), norm3(e1), norm3(e2)
    m = max(l0 * l1, max(l1 * l2, l0 * l2))
    if m < EPS10:
        return 0.0
    return jac * (2.0 / math.sqrt(3.0)) / m


def model_3d(q):
    """Verdict's quad_scaled_jacobian in 3D as described in the docstring (floats)."""
    if q[2] == q[3]:
        return tri_model_3d(q[:3])
    cs = math.sqrt(float(bbox_diag2_3d(q)))
    if cs < EPS10:
        cs = 1.0
    e = [sub3(q[(i + 1) % 4], q[i]) for i in range(4)]
    for d in e:
        if norm3((d[0] / cs, d[1] / cs, d[2] / cs)) < EPS10:
            return 0.0
    n = cross3(sub3(e[0], e[2]), sub3(e[1], e[3]))
    ln = norm3(n)
    if ln <= NORMAL_MIN:
        return 0.0
    n = (n[0] / ln, n[1] / ln, n[2] / ln)
    return min(dot3(n, cross3(e[(i + 3) % 4], e[i])) / (norm3(e[i]) * norm3(e[(i + 3) % 4])) for i in range(4))


def unit_scale_exponent(vectors):
    """k with 2**k <= the largest absolute component < 2**(k+1) (quadopt's edge scaling)."""
    m = max(abs(c) for v in vectors for c in v)
    return math.frexp(m)[1] - 1 if m > 0 else 0


def classify_3d(q):
    """The rule of a 3D quad, or None when it would depend on roundoff (row dropped)."""
    if q[2] == q[3]:
        a2 = tri_exact_cross2(q[:3])
        if a2 == 0:
            return "zero_normal"
        return tri_classify_3d(q[:3]) and "equal"
    e = [exact3(p) for p in q]
    edges2 = [dot3(d, d) for d in (sub3(e[(i + 1) % 4], e[i]) for i in range(4))]
    d2 = bbox_diag2_3d(q)
    if min(edges2) == 0:
        return "equal"
    ratio2 = min(edges2) / d2
    t2 = Fraction(EPS10) ** 2
    if ratio2 < t2 / 16:
        return "short_edge"
    if ratio2 < t2 * 16:
        return None
    n = exact_centre_normal(q)
    n2 = dot3(n, n)
    if n2 == 0:
        return "zero_normal"
    if n2 > Fraction(2) ** 1000:
        return None  # |n|^2 overflows in Verdict's normalize: VTK gives 0, quadopt does not
    if n2 < Fraction(1, 10**18) * d2 * d2:
        return None  # the centre normal's direction would be roundoff
    lo, hi = Fraction(NORMAL_MIN / 4) ** 2, Fraction(NORMAL_MIN * 4) ** 2
    # quadopt's scale: edges scaled by a power of two so the largest component is in [1, 2).
    k = unit_scale_exponent([sub3(q[(i + 1) % 4], q[i]) for i in range(4)])
    n2_scaled = n2 * Fraction(2) ** (-4 * k)
    if lo <= n2_scaled <= hi or lo <= n2 * Fraction(BIG) ** 4 <= hi:
        return None
    if n2 < lo:
        return "tiny_area"
    if n2 <= hi:
        return None
    return "equal"


def tri_exact_cross2(t):
    a, b, c = [exact3(p) for p in t]
    n = cross3(sub3(b, a), sub3(c, a))
    return dot3(n, n)


def tri_classify_3d(t):
    """The rule of a 3D triangle, or None when it would depend on roundoff (row dropped)."""
    n2 = tri_exact_cross2(t)
    if n2 == 0:
        return "zero_area"
    a, b, c = [exact3(p) for p in t]
    l2 = [dot3(d, d) for d in (sub3(b, a), sub3(c, b), sub3(a, c))]
    m2 = max(l2[0] * l2[1], l2[1] * l2[2], l2[0] * l2[2])
    if n2 < Fraction(1, 10**24) * m2:
        return None
    d2 = bbox_diag2_3d(t)
    t2 = Fraction(EPS10) ** 2
    if t2 / 4 <= d2 <= t2 * 4 or t2 / 4 <= d2 * Fraction(BIG) ** 2 <= t2 * 4:
        return None
    return "tiny_area" if d2 < t2 else "equal"


def random_rotation(rng):
    """A uniformly random rotation matrix (from a random unit quaternion)."""
    while True:
        w, x, y, z = (rng.gauss(0, 1) for _ in range(4))
        s = math.sqrt(w * w + x * x + y * y + z * z)
        if s > 1e-3:
            break
    w, x, y, z = w / s, x / s, y / s, z / s
    return (
        (1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
        (2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
        (2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)),
    )


def place_3d(f, rng, scale_range=(-3, 3), offset=50.0):
    r = random_rotation(rng)
    s = 10 ** rng.uniform(*scale_range)
    t = [rng.uniform(-offset, offset) for _ in range(3)]
    return [tuple(s * dot3(r[k], p) + t[k] for k in range(3)) for p in f]


def lift(f):
    return [(float(p[0]), float(p[1]), float(p[2]) if len(p) > 2 else 0.0) for p in f]


def build_3d(rng):
    rows = []

    def add(kind, q, placements=3):
        q = lift(q)
        rows.append((kind, q))
        k = 1 + rng.randrange(3)
        rows.append((kind, q[k:] + q[:k]))
        for _ in range(placements):
            rows.append((kind, place_3d(q, rng)))

    h = math.sqrt(3.0) / 2.0
    planar = {
        "square": [(0, 0), (1, 0), (1, 1), (0, 1)],
        "rectangle": [(0, 0), (5, 0), (5, 0.1), (0, 0.1)],
        "rhombus": [(0, 0), (1, 0), (1.5, h), (0.5, h)],
        "parallelogram": [(0, 0), (3, 0), (4, 1), (1, 1)],
        "trapezoid": [(0, 0), (4, 0), (3, 1), (1, 1)],
        "kite": [(0, -1), (2, 0), (0, 1), (-0.5, 0)],
        "dart": [(0, 0), (1, 0), (0.5, 0.2), (0, 1)],
        "bowtie": [(0, 0), (3, 1), (3, 0), (0, 2)],
    }
    for name, q in planar.items():
        add("planar_" + name, q)
        add("planar_" + name + "_cw", q[::-1], placements=1)
    for hh in (0.01, 0.1, 0.5, 1.0, 3.0):
        add("lifted", [(0, 0, 0), (1, 0, 0), (1, 1, hh), (0, 1, 0)])
        add("twisted", [(0, 0, 0), (1, 0, hh), (1, 1, 0), (0, 1, hh)])
        add("twisted", [(0, 0, hh), (1, 0, -hh), (1, 1, hh), (0, 1, -hh)], placements=1)
    # Folded: corner 3 of a planar quad turned about the diagonal 0-2 by an angle.
    for base in ([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 0), (2, 0), (2.5, 1), (0.2, 1.3)]):
        p0, p2, p3 = lift([base[0]])[0], lift([base[2]])[0], lift([base[3]])[0]
        axis = sub3(p2, p0)
        la = norm3(axis)
        u = (axis[0] / la, axis[1] / la, axis[2] / la)
        for deg in (10, 45, 80, 95, 120, 150, 175):
            a = math.radians(deg)
            v = sub3(p3, p0)
            par = dot3(v, u)
            along = (u[0] * par, u[1] * par, u[2] * par)
            perp = sub3(v, along)
            w = cross3(u, perp)
            r = tuple(p0[k] + along[k] + math.cos(a) * perp[k] + math.sin(a) * w[k] for k in range(3))
            add("folded", lift(base[:3]) + [r], placements=2)
    # Bent: both halves of a square turned about the diagonal 1-3, by +-a/2 each.
    for deg in (20, 60, 100, 140, 170):
        c, z = 0.5 * math.cos(math.radians(deg) / 2), math.sqrt(0.5) * math.sin(math.radians(deg) / 2)
        add("bent", [(0.5 - c, 0.5 - c, z), (1, 0, 0), (0.5 + c, 0.5 + c, z), (0, 1, 0)], placements=2)
    # Near-planar: random convex quads with small out-of-plane noise.
    for _ in range(40):
        angles = sorted(rng.uniform(0, 2 * math.pi) for _ in range(4))
        r = [rng.uniform(0.3, 1.0) for _ in range(4)]
        eps = 10 ** rng.uniform(-12, -3)
        q = [(r[i] * math.cos(angles[i]), r[i] * math.sin(angles[i]), eps * rng.uniform(-1, 1)) for i in range(4)]
        rows.append(("near_planar", place_3d(q, rng)))
    # Random points in 3D.
    for _ in range(80):
        q = [tuple(rng.uniform(-1, 1) for _ in range(3)) for _ in range(4)]
        rows.append(("random3d", place_3d(q, rng, scale_range=(-4, 4), offset=100.0)))
    for _ in range(40):
        rows.append(("random3d", [tuple(rng.uniform(-1, 1) for _ in range(3)) for _ in range(4)]))
    # Degenerate, with exact coordinates: zero-length edges, zero centre normal, short edges.
    for q in (
        [(0, 0, 0), (0, 0, 0), (1, 1, 1), (0, 1, 0)],
        [(0, 0, 0), (1, 0, 2), (1, 0, 2), (0, 1, 0)],
        [(0, 0, 0), (1, 1, 1), (2, 2, 2), (3, 3, 3)],  # collinear: zero normal
        [(0, 0, 0), (1, 0, 1), (1, 0, 0), (0, 0, 1)],  # symmetric bowtie in the xz plane
        [(0, 0, 0), (1, 1, 0), (1, 1, 1), (0, 0, 1)],  # symmetric bowtie in a diagonal plane
        [(0, 0, 0), (1e-20, 0, 0), (1, 1, 1), (0, 1, 0)],  # short edge
        [(0, 0, 0), (1, 0, 0), (1, 1, 1), (1e-17, 0, 0)],
    ):
        rows.append(("degenerate", lift(q)))
    # Collapsed quads (last two points equal): Verdict's triangle.
    add("collapsed", [(0, 0, 0), (1, 0, 1), (0, 1, 1), (0, 1, 1)], placements=0)
    add("collapsed", [(0, 0, 0), (1, 0, 0), (0.5, 0.5, h), (0.5, 0.5, h)], placements=0)
    rows.append(("collapsed", lift([(0, 0, 0), (1, 1, 1), (2, 2, 2), (2, 2, 2)])))
    for kind, q in list(rows[:60]):
        if q[2] == q[3]:
            continue
        # Tiny (dyadic, undone exactly by 2**32) and huge copies of a few shapes.
        if rng.random() < 0.25:
            k = rng.choice([-30, -31, -32])
            rows.append(("tiny", [tuple(math.ldexp(c, k) for c in p) for p in q]))
        elif rng.random() < 0.15:
            k = rng.choice([60, 120, 180])  # beyond about 2**250 Verdict's centre normal overflows
            rows.append(("huge", [tuple(math.ldexp(c, k) for c in p) for p in q]))
    return rows


def tri_build_3d(rng):
    rows = []

    def add(kind, t, placements=3):
        t = lift(t)
        rows.append((kind, t))
        rows.append((kind, [t[0], t[2], t[1]]))
        for _ in range(placements):
            rows.append((kind, place_3d(t, rng)))

    h = math.sqrt(3.0) / 2.0
    add("equilateral", [(0, 0), (1, 0), (0.5, h)], placements=5)
    add("equilateral", [(1, 0, 0), (0, 1, 0), (0, 0, 1)])
    add("right_isosceles", [(0, 0, 0), (1, 0, 0), (0, 0, 1)])
    add("right", [(0, 0), (4, 0), (0, 3)])
    for deg in (100, 135, 170, 179):
        a = math.radians(deg)
        add("obtuse", [(0, 0), (1, 0), (math.cos(a), math.sin(a))])
    for e in (1e-3, 1e-6, 1e-9):
        add("needle", [(0, 0, 0), (1, 0, 0), (0.5, e, e)], placements=1)
        add("needle", [(0, 0, 0), (1, 1, 1), (1, 1, 1 + e)], placements=1)
    for t in (
        [(0, 0, 0), (1, 1, 1), (2, 2, 2)],
        [(0, 0, 0), (2, 4, 6), (1, 2, 3)],
        [(0, 0, 0), (0, 0, 0), (1, 2, 3)],
        [(1, 2, 3), (1, 2, 3), (1, 2, 3)],
    ):
        rows.append(("degenerate", lift(t)))
    shapes = [t for kind, t in rows[:40] if kind in ("equilateral", "right_isosceles", "right", "obtuse")]
    for t in rng.sample(shapes, 10):
        k = rng.choice([-56, -60, -64])
        rows.append(("tiny", [tuple(math.ldexp(c, k) for c in p) for p in t]))
    for t in rng.sample(shapes, 5):
        k = rng.choice([100, 200, 300])
        rows.append(("huge", [tuple(math.ldexp(c, k) for c in p) for p in t]))
    for _ in range(120):
        t = [tuple(rng.uniform(-1, 1) for _ in range(3)) for _ in range(3)]
        rows.append(("random3d", place_3d(t, rng, scale_range=(-4, 4), offset=100.0)))
    return rows


def csv_3d(rng, triangles):
    """The 3D reference CSV's text (quads or triangles) and a one-line summary."""
    n = 3 if triangles else 4
    rows, dropped = [], 0
    for kind, f in (tri_build_3d if triangles else build_3d)(rng):
        rule = (tri_classify_3d if triangles else classify_3d)(f)
        if rule is None:
            print(f"dropped (ambiguous): {kind} {f}")
            dropped += 1
            continue
        rows.append((kind, rule, f))
    faces = [f for _, _, f in rows]
    cell = vtk.VTK_TRIANGLE if triangles else vtk.VTK_QUAD
    values = verdict_faces(faces, cell, not triangles)
    big = verdict_faces([[tuple(c * BIG for c in p) for p in f] for f in faces], cell, not triangles)
    model = (lambda f: tri_model_3d(f)) if triangles else model_3d
    for i, ((kind, rule, f), v, b) in enumerate(zip(rows, values, big)):
        m = model(f)
        if not abs(m - v) <= 1e-13 * max(1.0, abs(v)):
            sys.exit(f"row {i} ({kind}, {rule}): model {m!r} != vtk {v!r} for {f}")
        if rule in ("short_edge", "zero_normal") and abs(v) > 1e-15:
            sys.exit(f"row {i} ({kind}, {rule}): vtk gave {v!r}, expected 0")
        if rule == "zero_area" and not (v <= 1e-15 and b <= 1e-15):
            sys.exit(f"row {i} ({kind}, {rule}): vtk gave {v!r}, {b!r}, expected 0")
        if rule == "tiny_area" and not (v == 0.0 and b != 0.0):
            sys.exit(f"row {i} ({kind}, {rule}): vtk gave {v!r}, {b!r}, expected 0 and nonzero")
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["kind", "rule"] + [f"{c}{k}" for k in range(n) for c in "xyz"] + ["verdict_sj", "verdict_sj_big"])
    for (kind, rule, f), v, b in zip(rows, values, big):
        w.writerow([kind, rule] + [repr(c) for p in f for c in p] + [repr(v), repr(b)])
    counts = {}
    for _, rule, _ in rows:
        counts[rule] = counts.get(rule, 0) + 1
    what = "triangles" if triangles else "quads"
    summary = f"{len(rows)} 3D {what} ({dropped} ambiguous dropped), vtk {vtk.vtkVersion.GetVTKVersion()}: {counts}"
    return buf.getvalue(), summary


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="compare with the committed CSV instead of writing")
    ap.add_argument("--triangles", action="store_true", help="triangles (verdict_triangles.csv) instead of quads")
    ap.add_argument("--3d", dest="three_d", action="store_true", help="faces in 3D (verdict_*_3d.csv)")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    if args.out is None:
        if args.three_d:
            args.out = OUT_TRIANGLES_3D if args.triangles else OUT_3D
        else:
            args.out = OUT_TRIANGLES if args.triangles else OUT

    if args.three_d:
        text, summary = csv_3d(random.Random(SEED_3D), args.triangles)
    else:
        rng = random.Random(SEED)
        text, summary = (triangle_csv if args.triangles else quad_csv)(rng)
    print(summary)
    if args.check:
        with open(args.out) as f:
            if f.read() != text:
                sys.exit(f"{args.out} differs from what this script generates")
        print("committed CSV is up to date")
    else:
        os.makedirs(os.path.dirname(args.out), exist_ok=True)
        with open(args.out, "w") as f:
            f.write(text)
        print(f"wrote {os.path.normpath(args.out)}")


if __name__ == "__main__":
    main()

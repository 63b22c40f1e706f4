#!/usr/bin/env python3
"""Writes the small test meshes of cpp_tests/data/ (run from anywhere; deterministic).

- plate_hole.obj / plate_hole.off: a square plate [-1, 1]^2 with a circular hole of radius 0.4,
  an O-grid of 16 x 5 quads; interior vertices jittered, boundary vertices moved along the
  square's sides and around the circle, so both the interior and the boundary have work to do.
- jittered_grid.off / jittered_grid.obj: an 8 x 8 grid on [0, 8]^2, jittered, with one interior
  vertex dragged across its neighbour's edge so that quads are inverted.
- mixed.obj: two quads and a triangle (the adapters take it and keep the triangle).
- mixed_grid.obj / mixed_grid.off: a quad-dominant mesh, an 8 x 8 grid on [0, 8]^2 with every
  fifth cell (i + 2 j = 0 mod 5) split into two triangles, jittered like jittered_grid, with one
  interior vertex dragged so that quads and a triangle are inverted.

- quarter_cylinder.obj: a mesh on a curved surface, an 8 x 6 grid of quads on a quarter of the
  cylinder x^2 + y^2 = 4 (angle 0 to pi/2, height 0 to 3); interior vertices jittered along the
  cylinder (angle and height), boundary vertices along their side (the straight sides in
  height, the arcs in angle), the vertical line i = 4 in height only (a straight line, ends
  included, that the tests mark as a feature curve), and vertex (2, 3) dragged by 1.1 cells in angle.

Coordinates are float32 values (see f32) written with 17 significant digits, so every reader
loads them bit for bit.
"""
import math
import os
import random
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def f32(x):
    """Rounds to the nearest float32 value: OpenMesh's readers parse coordinates as float, so
    coordinates that are exactly representable in float load bit for bit into both float and
    double OpenMesh meshes, and into quadopt's own readers."""
    return struct.unpack("f", struct.pack("f", x))[0]


def fmt(x):
    return "%.17g" % x


def write_obj(path, points, faces, comment):
    with open(path, "w") as f:
        f.write("# %s\n" % comment)
        for p in points:
            f.write("v %s %s %s\n" % (fmt(p[0]), fmt(p[1]), fmt(0.0)))
        for q in faces:
            f.write("f %s\n" % " ".join(str(i + 1) for i in q))


def write_obj3(path, points, faces, comment):
    with open(path, "w") as f:
        f.write("# %s\n" % comment)
        for p in points:
            f.write("v %s %s %s\n" % (fmt(p[0]), fmt(p[1]), fmt(p[2])))
        for q in faces:
            f.write("f %s\n" % " ".join(str(i + 1) for i in q))


def quarter_cylinder(rng, na=8, nz=6, radius=2.0, dz=0.5):
    """The quarter cylinder of the module's docstring: vertex j * (na + 1) + i at angle
    i * (pi / 2) / na and height j * dz, jittered; quads counter-clockwise seen from outside."""
    da = (math.pi / 2) / na
    points = []
    for j in range(nz + 1):
        for i in range(na + 1):
            a, z = i * da, j * dz
            side = i in (0, na)
            arc = j in (0, nz)
            if not side and not arc and i != 4:
                a += rng.uniform(-0.25, 0.25) * da
            if not arc:
                z += rng.uniform(-0.25, 0.25) * dz
            elif not side and i != 4:
                a += rng.uniform(-0.25, 0.25) * da
            if (i, j) == (2, 3):
                a += 1.1 * da
            points.append((f32(radius * math.cos(a)), f32(radius * math.sin(a)), f32(z)))
    quads = []
    for j in range(nz):
        for i in range(na):
            v = j * (na + 1) + i
            quads.append((v, v + 1, v + na + 2, v + na + 1))
    return points, quads


def write_off(path, points, faces):
    with open(path, "w") as f:
        f.write("OFF\n")  # OpenMesh's OFF reader accepts no comment lines
        f.write("%d %d 0\n" % (len(points), len(faces)))
        for p in points:
            f.write("%s %s %s\n" % (fmt(p[0]), fmt(p[1]), fmt(0.0)))
        for q in faces:
            f.write("%d %s\n" % (len(q), " ".join(str(i) for i in q)))


def min_sj(points, q):
    """Signed scaled Jacobian of a counter-clockwise quad (minimum over its corners), or of a
    triangle (Verdict's: twice its signed area over the largest product of two edge lengths,
    times 2/sqrt(3); 1 for an equilateral one)."""
    if len(q) == 3:
        (ax, ay), (bx, by), (cx, cy) = (points[v] for v in q)
        cross = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
        la, lb, lc = math.hypot(bx - ax, by - ay), math.hypot(cx - bx, cy - by), math.hypot(ax - cx, ay - cy)
        return cross / max(la * lb, lb * lc, lc * la) * 2 / math.sqrt(3)
    best = 1.0
    for c in range(4):
        p = points[q[c]]
        a = points[q[(c + 1) % 4]]
        b = points[q[(c + 3) % 4]]
        ux, uy = a[0] - p[0], a[1] - p[1]
        vx, vy = b[0] - p[0], b[1] - p[1]
        best = min(best, (ux * vy - uy * vx) / (math.hypot(ux, uy) * math.hypot(vx, vy)))
    return best


def plate(rng):
    n_theta, n_rings = 16, 6  # 6 rings of vertices = 5 layers of quads
    points = []
    for r in range(n_rings):
        t = r / (n_rings - 1)
        for k in range(n_theta):
            theta = 2 * math.pi * k / n_theta
            if r == 0:  # the hole: move around the circle
                theta += rng.uniform(-0.25, 0.25) * 2 * math.pi / n_theta
            cx, cy = 0.4 * math.cos(theta), 0.4 * math.sin(theta)
            d = max(abs(math.cos(theta)), abs(math.sin(theta)))
            sx, sy = math.cos(theta) / d, math.sin(theta) / d
            if r == n_rings - 1 and k % 4 != 2:  # the square's sides (k = 2, 6, 10, 14: corners)
                if abs(sx) == 1.0 or abs(abs(sx) - 1.0) < 1e-12:
                    sx = math.copysign(1.0, sx)
                    sy += rng.uniform(-0.12, 0.12)
                else:
                    sy = math.copysign(1.0, sy)
                    sx += rng.uniform(-0.12, 0.12)
            elif r == n_rings - 1:
                sx, sy = math.copysign(1.0, sx), math.copysign(1.0, sy)
            x, y = (1 - t) * cx + t * sx, (1 - t) * cy + t * sy
            if 0 < r < n_rings - 1:
                x += rng.uniform(-0.06, 0.06)
                y += rng.uniform(-0.06, 0.06)
            points.append((f32(x), f32(y)))
    quads = []
    for r in range(n_rings - 1):
        for k in range(n_theta):
            a = r * n_theta + k
            b = r * n_theta + (k + 1) % n_theta
            quads.append((a, a + n_theta, b + n_theta, b))  # counter-clockwise
    assert all(min_sj(points, q) > 0 for q in quads)
    return points, quads


def jittered_points(rng, n):
    """An n x n grid of unit cells, interior vertices jittered, boundary ones slid along their
    side, rounded to f32."""
    points = []
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = float(i), float(j)
            interior_x = 0 < i < n
            interior_y = 0 < j < n
            if interior_x and interior_y:
                x += rng.uniform(-0.25, 0.25)
                y += rng.uniform(-0.25, 0.25)
            elif interior_x:  # bottom / top side: slide along x
                x += rng.uniform(-0.2, 0.2)
            elif interior_y:  # left / right side: slide along y
                y += rng.uniform(-0.2, 0.2)
            points.append((f32(x), f32(y)))
    return points


def drag_right(points, n, i, j):
    """Drags vertex (i, j) past its right-hand neighbour, so its faces fold over."""
    v = j * (n + 1) + i
    points[v] = (f32(points[v + 1][0] + 0.35), f32(points[v][1] + 0.1))


def grid(rng):
    n = 8
    points = jittered_points(rng, n)
    drag_right(points, n, 3, 4)
    quads = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            quads.append((a, a + 1, a + n + 2, a + n + 1))
    inverted = sum(1 for q in quads if min_sj(points, q) <= 0)
    assert inverted >= 1, inverted
    return points, quads


def mixed_grid(rng):
    """The jittered grid's construction with every fifth cell split into two triangles."""
    n = 8
    points = jittered_points(rng, n)
    faces = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            if (i + 2 * j) % 5 == 0:
                faces.append((a, a + 1, a + n + 2))
                faces.append((a, a + n + 2, a + n + 1))
            else:
                faces.append((a, a + 1, a + n + 2, a + n + 1))
    # Vertex (3, 2): its faces fold over, the triangle of the split cell (3, 1) among them.
    drag_right(points, n, 3, 2)
    inverted = [f for f in faces if min_sj(points, f) <= 0]
    assert any(len(f) == 3 for f in inverted) and any(len(f) == 4 for f in inverted), inverted
    return points, faces


def main():
    rng = random.Random(20240611)
    points, quads = plate(rng)
    c = "plate with a hole: %d vertices, %d quads (cpp_tests/data/make_data.py)" % (len(points), len(quads))
    write_obj(os.path.join(HERE, "plate_hole.obj"), points, quads, c)
    write_off(os.path.join(HERE, "plate_hole.off"), points, quads)
    points, quads = grid(rng)
    c = "jittered 8x8 grid with inverted quads: %d vertices, %d quads (cpp_tests/data/make_data.py)" % (
        len(points), len(quads))
    write_off(os.path.join(HERE, "jittered_grid.off"), points, quads)
    write_obj(os.path.join(HERE, "jittered_grid.obj"), points, quads, c)
    mixed = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (0.0, 1.0), (1.0, 1.0), (2.0, 1.0), (1.0, 2.0)]
    write_obj(os.path.join(HERE, "mixed.obj"), mixed, [(0, 1, 4, 3), (1, 2, 5, 4), (3, 4, 6)],
              "two quads and a triangle (cpp_tests/data/make_data.py)")
    points, faces = mixed_grid(random.Random(20261206))
    c = "quad-dominant 8x8 grid with inverted faces: %d vertices, %d quads, %d triangles (cpp_tests/data/make_data.py)" % (
        len(points), sum(len(f) == 4 for f in faces), sum(len(f) == 3 for f in faces))
    write_off(os.path.join(HERE, "mixed_grid.off"), points, faces)
    write_obj(os.path.join(HERE, "mixed_grid.obj"), points, faces, c)
    points, quads = quarter_cylinder(random.Random(20261207))
    c = "quarter cylinder x^2 + y^2 = 4, 8x6 quads, jittered: %d vertices, %d quads (cpp_tests/data/make_data.py)" % (
        len(points), len(quads))
    write_obj3(os.path.join(HERE, "quarter_cylinder.obj"), points, quads, c)


if __name__ == "__main__":
    main()

"""Every error case: bad meshes raise MeshError (a ValueError) with the library's message, wrong
shapes and dtypes TypeError, bad options ValueError; nothing is returned and the caller's
arrays are never written, on success or failure. Non-contiguous, Fortran-ordered, read-only and
any-dtype arrays are accepted and give the float64 array's result."""

import numpy as np
import pytest

import quadopt
from helpers import bits, bumpy, jittered_grid


@pytest.fixture
def mesh():
    return jittered_grid(6, 5, jitter=0.35, seed=1)


def untouched(*arrays):
    """Snapshots of arrays, and a check that they still hold the same bytes and flags."""
    saved = [(a, a.copy(), a.flags.writeable) for a in arrays]

    def check():
        for a, copy, writeable in saved:
            assert a.dtype == copy.dtype and a.shape == copy.shape and a.flags.writeable == writeable
            assert a.tobytes() == copy.tobytes(), "the caller's array was written"

    return check


def test_mesh_error_is_a_value_error():
    assert issubclass(quadopt.MeshError, ValueError)
    assert quadopt.MeshError.__module__ == "quadopt"


def test_nan_and_infinite_coordinates(mesh):
    points, faces = mesh
    for bad in (np.nan, np.inf, -np.inf):
        p = points.copy()
        p[7, 1] = bad
        check = untouched(p, faces)
        with pytest.raises(quadopt.MeshError, match="vertex 7 has a non-finite coordinate"):
            quadopt.optimize(p, faces)
        with pytest.raises(quadopt.MeshError, match="vertex 7 has a non-finite coordinate"):
            quadopt.quality(p, faces)
        check()
    p3 = bumpy(points)
    p3[9, 2] = np.nan
    with pytest.raises(quadopt.MeshError, match="vertex 9 has a non-finite"):
        quadopt.optimize(p3, faces)


def test_index_out_of_range(mesh):
    points, faces = mesh
    f = faces.copy()
    f[3, 2] = len(points)
    with pytest.raises(quadopt.MeshError, match=f"quad 3 corner 2 refers to vertex {len(points)}, but there are only"):
        quadopt.optimize(points, f)
    f[3, 2] = 2**40
    with pytest.raises(quadopt.MeshError, match=f"refers to vertex {2**40}"):
        quadopt.optimize(points, f)
    f[3, 2] = -3
    with pytest.raises(quadopt.MeshError, match="face 3 corner 2 is -3"):
        quadopt.optimize(points, f)
    # -1 marks a triangle in the fourth corner only.
    f = faces.copy()
    f[2, 1] = -1
    with pytest.raises(quadopt.MeshError, match="face 2 corner 1 is -1"):
        quadopt.optimize(points, f)
    with pytest.raises(quadopt.MeshError, match="refers to vertex 99"):
        quadopt.optimize(points, [[0, 1, 8, 7], [1, 2, 99]])


def test_a_pentagon_and_other_face_sizes(mesh):
    points, faces = mesh
    polygon = [list(f) for f in faces]
    polygon[4] = [0, 1, 2, 9, 8]
    with pytest.raises(quadopt.MeshError, match="face 4 has 5 vertices; only triangles and quads are supported"):
        quadopt.optimize(points, polygon)
    polygon[4] = [0, 1]
    with pytest.raises(quadopt.MeshError, match="face 4 has 2 vertices"):
        quadopt.quality(points, polygon)
    with pytest.raises(quadopt.MeshError, match="face 0 has 5 vertices"):
        quadopt.optimize(points, np.zeros((3, 5), dtype=np.int64))
    with pytest.raises(quadopt.MeshError, match="face 0 has 0 vertices"):
        quadopt.optimize(points, np.zeros((3, 0), dtype=np.int64))
    with pytest.raises(quadopt.MeshError, match="the mesh has no quads"):
        quadopt.optimize(points, np.zeros((0, 0), dtype=np.int64))


def test_other_invalid_meshes(mesh):
    points, faces = mesh
    with pytest.raises(quadopt.MeshError, match="the mesh has no quads"):
        quadopt.optimize(points, np.zeros((0, 4), dtype=np.int64))
    with pytest.raises(quadopt.MeshError, match="uses vertex 1 more than once"):
        quadopt.optimize(points, [[0, 1, 1, 7]])
    # Three quads on one edge.
    p = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0], [2, 1], [1, -1], [0, -1]], dtype=float)
    with pytest.raises(quadopt.MeshError, match="non-manifold"):
        quadopt.optimize(p, [[0, 1, 2, 3], [1, 4, 5, 2], [1, 0, 7, 6], [0, 1, 6, 7]])
    # A closed planar mesh: a flattened cube.
    cube = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=float)
    cube_faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    with pytest.raises(quadopt.MeshError, match="closed"):
        quadopt.optimize(cube[:, :2], cube_faces)
    # ... the same cube in 3D is a closed surface, optimized on it.
    assert quadopt.optimize(cube, cube_faces).report["surface"] is True


def test_fixed_errors(mesh):
    points, faces = mesh
    with pytest.raises(quadopt.MeshError, match="3 fixed flags were given for 42 vertices"):
        quadopt.optimize(points, faces, fixed=np.array([True, False, True]))
    with pytest.raises(quadopt.MeshError, match="fixed index 1 is vertex 42, but there are only 42 vertices"):
        quadopt.optimize(points, faces, fixed=[3, 42])
    with pytest.raises(quadopt.MeshError, match="is vertex -1"):
        quadopt.optimize(points, faces, fixed=[-1])
    with pytest.raises(TypeError, match="fixed"):
        quadopt.optimize(points, faces, fixed=np.array([0.5, 1.0]))
    with pytest.raises(TypeError, match="fixed"):
        quadopt.optimize(points, faces, fixed=np.zeros((2, 2), dtype=bool))
    # An empty list fixes nothing.
    same = quadopt.optimize(points, faces, fixed=[])
    np.testing.assert_array_equal(bits(same.points), bits(quadopt.optimize(points, faces).points))


def test_wrong_shapes_and_dtypes(mesh):
    points, faces = mesh
    bad_points = [points[:, :1], np.zeros((5, 4)), points.ravel(), points[None], points.astype(complex),
                  points.astype(object), points > 1, "points", [[0, 0], [1]], None]
    for p in bad_points:
        with pytest.raises(TypeError, match="points"):
            quadopt.optimize(p, faces)
        with pytest.raises(TypeError, match="points"):
            quadopt.quality(p, faces)
    bad_faces = [faces.astype(float), faces.ravel(), faces[None], faces > 2, "faces", 7, None,
                 [[0, 1, 2.5, 3]], [[0, 1, 8, "7"]], [3]]
    for f in bad_faces:
        with pytest.raises(TypeError, match="faces"):
            quadopt.optimize(points, f)
    with pytest.raises(TypeError, match="feature_edges"):
        quadopt.optimize(bumpy(points), faces, feature_edges=np.array([[0, 1, 2]]))
    with pytest.raises(TypeError, match="feature_edges"):
        quadopt.optimize(bumpy(points), faces, feature_edges=np.array([[0.0, 1.0]]))


def test_bad_options(mesh):
    points, faces = mesh
    cases = [
        ({"effort": "slow"}, ValueError, "unknown effort 'slow' \\(expected fast, balanced or best\\)"),
        ({"boundary": "glued"}, ValueError, "unknown boundary mode 'glued'"),
        ({"method": "magic"}, ValueError, "unknown method 'magic'"),
        ({"feature_angle": 200.0}, ValueError, "invalid option feature_angle_deg: 200 is not in \\[0, 180\\]"),
        ({"feature_angle": float("nan")}, ValueError, "feature_angle"),
        ({"max_iterations": 0}, ValueError, "max_iterations: must be at least 1"),
        ({"threads": 0}, ValueError, "threads"),
        ({"effort": 3}, TypeError, "effort"),
        ({"max_iterations": -1}, ValueError, "max_iterations: must be at least 1"),
        ({"max_iterations": 2.5}, TypeError, "max_iterations"),
        ({"threads": "2"}, TypeError, "threads"),
        ({"progress": 5}, TypeError, "progress"),
    ]
    for options, kind, message in cases:
        with pytest.raises(kind, match=message):
            quadopt.optimize(points, faces, **options)
    with pytest.raises(TypeError):
        quadopt.optimize(points, faces, "fast")  # options are keyword-only


def test_feature_edges_errors(mesh):
    points, faces = mesh
    with pytest.raises(ValueError, match="feature_edges apply to meshes on curved surfaces; this mesh is planar"):
        quadopt.optimize(points, faces, feature_edges=[[0, 1]])
    with pytest.raises(ValueError, match="marked edge 1, vertices \\(0, 8\\), is not an edge of the mesh"):
        quadopt.optimize(bumpy(points), faces, feature_edges=[[0, 1], [0, 8]])
    with pytest.raises(ValueError, match="marked edge 0 has vertex -4"):
        quadopt.optimize(bumpy(points), faces, feature_edges=[[-4, 1]])
    # No edge at all is fine anywhere.
    quadopt.optimize(points, faces, feature_edges=np.zeros((0, 2), dtype=int))


def variants(a):
    """The same values as strided, Fortran-ordered, read-only, list and other-dtype arrays."""
    wide = np.zeros((a.shape[0] * 2, a.shape[1] + 3), dtype=a.dtype)
    wide[::2, 1:1 + a.shape[1]] = a
    strided = wide[::2, 1:1 + a.shape[1]]
    assert not strided.flags.c_contiguous and np.array_equal(strided, a)
    readonly = a.copy()
    readonly.flags.writeable = False
    yield "strided", strided
    yield "fortran", np.asfortranarray(a)
    yield "readonly", readonly
    yield "list", a.tolist()
    yield "big-endian", a.astype(a.dtype.newbyteorder(">"))


def test_non_contiguous_read_only_and_other_dtypes_give_the_same_result(mesh):
    points, faces = mesh
    want = quadopt.optimize(points, faces)
    for name, p in variants(points):
        for fname, f in variants(faces):
            got = quadopt.optimize(p, f)
            np.testing.assert_array_equal(bits(got.points), bits(want.points), err_msg=f"{name} points, {fname} faces")
            assert got.report["output"] == want.report["output"]
    # Integer coordinates and float32 ones are converted to float64 (as numpy converts them).
    grid = np.array([[x, y] for y in range(4) for x in range(4)])
    grid_faces = np.array([[j * 4 + i, j * 4 + i + 1, j * 4 + i + 5, j * 4 + i + 4] for j in range(3) for i in range(3)])
    for dtype in (np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint16, np.uint32, np.uint64, np.float16,
                  np.float32, np.longdouble):
        for fdtype in (np.int32, np.uint16, np.int64, np.uint64):
            got = quadopt.optimize(grid.astype(dtype), grid_faces.astype(fdtype))
            want = quadopt.optimize(grid.astype(dtype).astype(np.float64), grid_faces)
            np.testing.assert_array_equal(bits(got.points), bits(want.points), err_msg=f"{dtype} {fdtype}")
    p32 = (points + 0.1).astype(np.float32)
    np.testing.assert_array_equal(bits(quadopt.optimize(p32, faces).points),
                                  bits(quadopt.optimize(p32.astype(np.float64), faces).points))


def test_the_callers_arrays_are_never_written(mesh):
    points, faces = mesh
    fixed = np.array([5, 9])
    mask = np.zeros(len(points), dtype=bool)
    mask[[10, 11]] = True
    for p in (points, bumpy(points)):
        check = untouched(p, faces, fixed, mask)
        r = quadopt.optimize(p, faces, fixed=fixed)
        assert r.report["moved"] > 0 and not np.shares_memory(r.points, p)
        r2 = quadopt.optimize(p, faces, fixed=mask)
        r2.points[:] = 0  # the result is the caller's to change
        quadopt.quality(p, faces)
        check()
    # A read-only result of a previous run can go in again.
    again = quadopt.optimize(points, faces).points
    again.flags.writeable = False
    quadopt.optimize(again, faces)


def test_nothing_is_returned_on_error_and_the_next_call_works(mesh):
    points, faces = mesh
    bad = points.copy()
    bad[3] = np.nan
    for _ in range(3):
        with pytest.raises(quadopt.MeshError):
            quadopt.optimize(bad, faces)
    ok = quadopt.optimize(points, faces)
    assert ok.report["output"]["inverted"] == 0

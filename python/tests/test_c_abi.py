"""Bit-identity with the C ABI: ``quadopt_optimize`` and ``quadopt_quality`` of the shared
library (``libquadopt.so``, loaded with ctypes) on the same arrays give the points and the
statistics ``quadopt.optimize`` and ``quadopt.quality`` give."""

import ctypes

import numpy as np
import pytest

import quadopt
from helpers import bits, bumpy, jittered_grid, library_path, read_sample, sample_paths

NO_VERTEX = 0xFFFFFFFF
METHODS = {"ep": 0, "laplace": 1, "cotan": 2, "angle": 3}
BOUNDARIES = {"auto": 0, "fixed": 1, "slide": 2, "snap": 3}
EFFORTS = {"balanced": 0, "fast": 1, "best": 2}


class Options(ctypes.Structure):
    """include/quadopt.h's QuadoptOptions."""

    _fields_ = [
        ("struct_size", ctypes.c_uint32), ("method", ctypes.c_uint32), ("boundary", ctypes.c_uint32),
        ("max_iterations", ctypes.c_uint32), ("lambda_", ctypes.c_double), ("tau", ctypes.c_double),
        ("feature_angle_deg", ctypes.c_double), ("guard_floor", ctypes.c_double),
        ("max_boundary_deviation", ctypes.c_double), ("tau_absolute", ctypes.c_uint8), ("guard", ctypes.c_uint8),
        ("untangle", ctypes.c_uint8), ("keep_best", ctypes.c_uint8), ("stop_rule", ctypes.c_uint32),
        ("progress", ctypes.c_void_p), ("progress_user_data", ctypes.c_void_p), ("max_min", ctypes.c_uint32),
        ("reserved1", ctypes.c_uint32), ("effort", ctypes.c_uint32), ("reserved2", ctypes.c_uint32),
    ]


class Quality(ctypes.Structure):
    _fields_ = [("min", ctypes.c_double), ("avg", ctypes.c_double), ("max", ctypes.c_double),
                ("inverted", ctypes.c_size_t)]


@pytest.fixture(scope="module")
def lib():
    path = library_path()
    if not path.exists():
        pytest.fail(f"{path} is missing: build it with `cargo build --release --lib` (or set QUADOPT_LIBRARY)")
    lib = ctypes.CDLL(str(path))
    lib.quadopt_options_init.argtypes = [ctypes.POINTER(Options), ctypes.c_size_t]
    lib.quadopt_optimize.argtypes = [ctypes.c_void_p, ctypes.c_uint32, ctypes.c_size_t, ctypes.c_void_p,
                                     ctypes.c_size_t, ctypes.c_void_p, ctypes.POINTER(Options), ctypes.c_void_p]
    lib.quadopt_quality.argtypes = [ctypes.c_void_p, ctypes.c_uint32, ctypes.c_size_t, ctypes.c_void_p,
                                    ctypes.c_size_t, ctypes.POINTER(Quality), ctypes.c_void_p, ctypes.c_size_t]
    lib.quadopt_last_error.restype = ctypes.c_char_p
    return lib


def c_faces(faces):
    return np.ascontiguousarray(np.where(np.asarray(faces) < 0, NO_VERTEX, faces), dtype=np.uint32)


def c_optimize(lib, points, faces, fixed=None, effort="balanced", boundary="auto", method="ep",
               feature_angle=45.0, max_iterations=None):
    coords = np.array(points, dtype=np.float64, order="C")
    quads = c_faces(faces)
    o = Options()
    assert lib.quadopt_options_init(ctypes.byref(o), ctypes.sizeof(o)) == 0
    o.method, o.boundary, o.effort = METHODS[method], BOUNDARIES[boundary], EFFORTS[effort]
    o.feature_angle_deg = feature_angle
    if max_iterations is not None:
        o.max_iterations = max_iterations
    flags = None
    if fixed is not None:
        mask = np.zeros(len(coords), dtype=np.uint8)
        mask[fixed] = 1
        flags = mask
    status = lib.quadopt_optimize(coords.ctypes.data, coords.shape[1], len(coords), quads.ctypes.data, len(quads),
                                  None if flags is None else flags.ctypes.data, ctypes.byref(o), None)
    assert status == 0, lib.quadopt_last_error().decode()
    return coords


OPTIONS = [{}, {"effort": "fast", "boundary": "fixed"}, {"effort": "best", "method": "laplace", "boundary": "snap"},
           {"max_iterations": 5, "feature_angle": 20.0}]


@pytest.mark.parametrize("options", OPTIONS, ids=lambda o: ",".join(f"{k}={v}" for k, v in o.items()) or "defaults")
@pytest.mark.parametrize("sample", sample_paths(), ids=lambda p: p.stem)
def test_samples_match_the_c_abi(lib, sample, options):
    points, faces, fixed = read_sample(sample)
    want = c_optimize(lib, points, faces, fixed, **options)
    got = quadopt.optimize(points, faces, fixed=fixed, **options)
    np.testing.assert_array_equal(bits(got.points), bits(want))


@pytest.mark.parametrize("seed", range(4))
def test_random_meshes_match_the_c_abi_in_2d_and_3d(lib, seed):
    points, faces = jittered_grid(12, 9, jitter=0.4, seed=seed, triangles=0.3 * (seed % 2))
    np.testing.assert_array_equal(bits(quadopt.optimize(points, faces).points), bits(c_optimize(lib, points, faces)))
    surface = bumpy(points)
    np.testing.assert_array_equal(bits(quadopt.optimize(surface, faces).points),
                                  bits(c_optimize(lib, surface, faces)))


@pytest.mark.parametrize("sample", sample_paths(), ids=lambda p: p.stem)
def test_quality_matches_the_c_abi(lib, sample):
    points, faces, _ = read_sample(sample)
    coords = np.ascontiguousarray(points)
    quads = c_faces(faces)
    per_face = np.zeros(len(faces))
    q = Quality()
    status = lib.quadopt_quality(coords.ctypes.data, 3, len(coords), quads.ctypes.data, len(quads), ctypes.byref(q),
                                 per_face.ctypes.data, len(per_face))
    assert status == 0, lib.quadopt_last_error().decode()
    mine = quadopt.quality(points, faces)
    np.testing.assert_array_equal(bits(mine.values), bits(per_face))
    assert (mine.summary["min"], mine.summary["avg"], mine.summary["max"], mine.summary["inverted"]) == (
        q.min, q.avg, q.max, q.inverted)

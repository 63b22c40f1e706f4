"""Bit-identity with the CLI: ``quadopt.optimize`` and ``quadopt.quality`` on arrays give what
``quadopt optimize --json`` and ``quadopt quality --json`` give on a file holding the same mesh
(points, report and per-face quality, compared bit for bit; the report without its times)."""

import json

import numpy as np
import pytest

import quadopt
from helpers import (bits, bumpy, cli_optimize, cli_quality, is_planar_z, jittered_grid, read_sample,
                     sample_paths, stable)

OPTION_SETS = [
    {},
    {"effort": "fast", "boundary": "fixed"},
    {"effort": "best", "boundary": "slide", "method": "laplace"},
    {"boundary": "snap", "method": "angle", "feature_angle": 30.0},
    {"method": "cotan", "max_iterations": 7},
]


def same_report(got, want):
    assert json.dumps(stable(got), sort_keys=True) == json.dumps(stable(want), sort_keys=True)


def check_against_cli(tmp_path, points, faces, fixed=None, feature_edges=None, **options):
    want_points, want_report, want_quality = cli_optimize(tmp_path, points, faces, fixed, feature_edges, **options)
    r = quadopt.optimize(points, faces, fixed=fixed, feature_edges=feature_edges, **options)
    assert r.points.dtype == np.float64 and r.points.shape == points.shape
    d = points.shape[1]
    np.testing.assert_array_equal(bits(r.points), bits(want_points[:, :d]))
    np.testing.assert_array_equal(bits(r.quality), bits(want_quality))
    same_report(r.report, want_report)
    return r, want_report


@pytest.mark.parametrize("options", OPTION_SETS, ids=lambda o: ",".join(f"{k}={v}" for k, v in o.items()) or "defaults")
@pytest.mark.parametrize("sample", sample_paths(), ids=lambda p: p.stem)
def test_samples_match_the_cli_bit_for_bit(tmp_path, sample, options):
    points, faces, fixed = read_sample(sample)
    r, report = check_against_cli(tmp_path, points, faces, fixed, **options)
    assert report["moved"] > 0
    if is_planar_z(points):
        assert "surface" not in report
        # The same mesh as an (n, 2) array: the same run (a 2D file is the plane z = 0).
        if np.all(points[:, 2] == 0):
            flat = quadopt.optimize(points[:, :2].copy(), faces, fixed=fixed, **options)
            np.testing.assert_array_equal(bits(flat.points), bits(r.points[:, :2]))
            np.testing.assert_array_equal(bits(flat.quality), bits(r.quality))
            same_report(flat.report, r.report)
    else:
        assert report["surface"] is True


@pytest.mark.parametrize("seed", range(6))
def test_random_planar_meshes_match_the_cli(tmp_path, seed):
    rng = np.random.default_rng(100 + seed)
    points, faces = jittered_grid(
        int(rng.integers(4, 14)), int(rng.integers(4, 14)), jitter=float(rng.uniform(0.05, 0.45)), seed=seed,
        triangles=[0.0, 0.3][seed % 2], holes=[(3.0, 3.0, 1.2)] if seed % 3 == 0 else ())
    options = OPTION_SETS[seed % len(OPTION_SETS)]
    check_against_cli(tmp_path, points, faces, **options)


@pytest.mark.parametrize("seed", range(4))
def test_random_surfaces_match_the_cli(tmp_path, seed):
    points, faces = jittered_grid(8, 7, jitter=0.3, seed=seed, triangles=0.25 * (seed % 2))
    surface = bumpy(points)
    r, report = check_against_cli(tmp_path, surface, faces, **OPTION_SETS[seed % 3])
    assert report["surface"] is True


def test_a_tilted_plane_matches_the_cli(tmp_path):
    points, faces = jittered_grid(9, 6, jitter=0.35, seed=7)
    c, s = np.cos(0.4), np.sin(0.4)
    rotation = np.array([[1, 0, 0], [0, c, -s], [0, s, c]]) @ np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    tilted = np.column_stack([points, np.zeros(len(points))]) @ rotation.T + [3.0, -2.0, 5.0]
    r, report = check_against_cli(tmp_path, tilted, faces)
    assert "surface" not in report and report["moved"] > 0
    # Unmoved vertices (the corners) keep their input bits.
    unmoved = np.all(r.points == tilted, axis=1)
    assert unmoved.sum() == len(points) - report["moved"]


def test_fixed_as_mask_or_indices_matches_the_cli(tmp_path):
    points, faces = jittered_grid(10, 8, jitter=0.3, seed=3)
    chosen = np.array([12, 25, 40, 41, 60])
    mask = np.zeros(len(points), dtype=bool)
    mask[chosen] = True
    by_index, _ = check_against_cli(tmp_path, points, faces, fixed=chosen)
    by_mask = quadopt.optimize(points, faces, fixed=mask)
    by_list = quadopt.optimize(points, faces, fixed=chosen.tolist())
    for other in (by_mask, by_list):
        np.testing.assert_array_equal(bits(other.points), bits(by_index.points))
        same_report(other.report, by_index.report)
    np.testing.assert_array_equal(bits(by_index.points[chosen]), bits(points[chosen]))


def test_feature_edges_on_a_surface_match_the_cli(tmp_path):
    points, faces = jittered_grid(10, 8, jitter=0.25, seed=5)
    surface = bumpy(points, amplitude=0.3)
    row = 4 * 11  # the vertices of grid row 4: a curve across the sheet
    edges = np.array([[row + i, row + i + 1] for i in range(10)])
    r, report = check_against_cli(tmp_path, surface, faces, feature_edges=edges)
    plain = quadopt.optimize(surface, faces)
    assert report["feature_curves"] > plain.report["feature_curves"]


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_any_number_of_threads_matches_the_cli(tmp_path, threads):
    points, faces = jittered_grid(20, 15, jitter=0.4, seed=11, triangles=0.2)
    r, _ = check_against_cli(tmp_path, points, faces, threads=threads)
    default = quadopt.optimize(points, faces)
    np.testing.assert_array_equal(bits(r.points), bits(default.points))


@pytest.mark.parametrize("sample", sample_paths(), ids=lambda p: p.stem)
def test_quality_matches_the_cli(tmp_path, sample):
    points, faces, _ = read_sample(sample)
    want = cli_quality(tmp_path, points, faces)
    q = quadopt.quality(points, faces)
    assert json.dumps(stable(q.summary), sort_keys=True) == json.dumps(stable(want), sort_keys=True)
    assert len(q.values) == len(faces)
    assert sum(q.summary["histogram"]) == len(faces)
    if want.get("surface"):
        assert q.verdict is not None and len(q.verdict) == len(faces)
        assert q.verdict.min() == want["verdict"]["min"]
    else:
        assert q.verdict is None
    assert q.values.min() == want["min"]


@pytest.mark.parametrize("sample", [p for p in sample_paths() if "surface" in p.stem], ids=lambda p: p.stem)
def test_quality_against_a_reference_matches_the_cli(tmp_path, sample):
    points, faces, fixed = read_sample(sample)
    optimized = quadopt.optimize(points, faces, fixed=fixed).points
    from helpers import run_cli, write_vtk
    write_vtk(tmp_path / "ref.vtk", points, faces)
    write_vtk(tmp_path / "out.vtk", optimized, faces)
    want = json.loads(run_cli(["quality", tmp_path / "out.vtk", "--reference", tmp_path / "ref.vtk", "--json"]).stdout)
    got = quadopt.quality(optimized, faces, reference=points)
    assert json.dumps(stable(got.summary), sort_keys=True) == json.dumps(stable(want), sort_keys=True)
    assert "surface_fidelity" in got.summary
    flat, flat_faces = jittered_grid(4, 4, jitter=0.2, seed=1)
    with pytest.raises(ValueError, match="reference measures a mesh on a curved surface; this mesh is planar"):
        quadopt.quality(flat, flat_faces, reference=flat)

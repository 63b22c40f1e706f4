"""``quadopt.optimize_mesh`` and meshio: round trips through VTU and MSH files (meshio reads,
quadopt optimizes, meshio writes and reads back), compared bit for bit with the CLI optimizing
the same file; gmsh physical groups as meshio carries them (``--fix-physical`` and
``--feature-physical``); cells other than quads and triangles kept as they are."""

import json

import numpy as np
import pytest

import quadopt
from helpers import bits, bumpy, jittered_grid, run_cli

meshio = pytest.importorskip("meshio")


def surface_faces(mesh):
    return [b for b in mesh.cells if b.type in ("quad", "triangle")]


def quality_of(mesh):
    return np.concatenate([np.ravel(q) for b, q in zip(mesh.cells, mesh.cell_data["scaled_jacobian"])
                           if b.type in ("quad", "triangle")])


def cli_run(tmp_path, src, suffix, *args):
    out = tmp_path / f"cli_out{suffix}"
    report = json.loads(run_cli(["optimize", src, "-o", out, "--json", *args]).stdout)
    return meshio.read(out), report


@pytest.mark.parametrize("triangles", [0.0, 0.25])
def test_vtu_round_trip_matches_the_cli(tmp_path, triangles):
    src = tmp_path / "in.vtu"
    run_cli(["generate", "--quads", "3000", "--holes", "4", "--jitter", "0.4", "--seed", "7",
             "--triangles", repr(triangles), "-o", src])
    mesh = meshio.read(src)
    before = mesh.points.copy()
    out, report = quadopt.optimize_mesh(mesh, return_report=True)
    assert mesh.points.tobytes() == before.tobytes() and "scaled_jacobian" not in mesh.cell_data
    path = tmp_path / "py.vtu"
    meshio.write(path, out)
    back = meshio.read(path)
    want, want_report = cli_run(tmp_path, src, ".vtu")
    np.testing.assert_array_equal(bits(back.points), bits(want.points))
    np.testing.assert_array_equal(bits(quality_of(back)), bits(quality_of(want)))
    assert [b.type for b in back.cells] == [b.type for b in want.cells]
    for a, b in zip(surface_faces(back), surface_faces(want)):
        np.testing.assert_array_equal(a.data, b.data)
    assert report["moved"] == want_report["moved"] and report["output"] == want_report["output"]


def gmsh_plate(path, all_quads=False):
    """A plate with two holes meshed by gmsh and recombined (quad-dominant, or with
    ``all_quads`` subdivided into quads only), with physical groups."""
    gmsh = pytest.importorskip("gmsh")
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        occ = gmsh.model.occ
        plate = occ.addRectangle(0, 0, 0, 6, 4)
        holes = [occ.addDisk(2, 2, 0, 0.9, 0.9), occ.addDisk(4.4, 1.8, 0, 0.6, 0.6)]
        (surface,), _ = occ.cut([(2, plate)], [(2, h) for h in holes])
        occ.synchronize()
        curves = [c for _, c in gmsh.model.getBoundary([surface], oriented=False)]
        circles = [c for c in curves if gmsh.model.getType(1, c) != "Line"]
        gmsh.model.addPhysicalGroup(2, [surface[1]], name="plate")
        gmsh.model.addPhysicalGroup(1, circles, name="holes")
        gmsh.model.addPhysicalGroup(1, [c for c in curves if c not in circles], name="outer")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.35)
        gmsh.option.setNumber("Mesh.RecombineAll", 1)
        gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 0)
        gmsh.option.setNumber("Mesh.Smoothing", 0)
        if all_quads:
            gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 1)
        gmsh.model.mesh.generate(2)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


def test_msh_from_gmsh_with_a_fixed_physical_group_matches_the_cli(tmp_path):
    src = tmp_path / "plate.msh"
    gmsh_plate(src)
    mesh = meshio.read(src)
    assert "line" in [b.type for b in mesh.cells], "gmsh's boundary lines are kept as other cells"
    out, report = quadopt.optimize_mesh(mesh, fix_physical=["holes"], return_report=True)
    want, want_report = cli_run(tmp_path, src, ".msh", "--fix-physical", "holes")
    np.testing.assert_array_equal(bits(out.points), bits(want.points))
    np.testing.assert_array_equal(bits(quality_of(out)), bits(quality_of(want)))
    assert report["moved"] == want_report["moved"] and report["loop_modes"] == want_report["loop_modes"]
    # The holes' nodes did not move; other cells are there as they were, with their data.
    holes_tag = mesh.field_data["holes"][0]
    for b, tags in zip(mesh.cells, mesh.cell_data["gmsh:physical"]):
        if b.type == "line":
            nodes = np.unique(b.data[tags == holes_tag])
            np.testing.assert_array_equal(bits(out.points[nodes]), bits(mesh.points[nodes]))
    assert [(b.type, len(b.data)) for b in out.cells] == [(b.type, len(b.data)) for b in mesh.cells]
    for a, b in zip(out.cell_data["gmsh:physical"], mesh.cell_data["gmsh:physical"]):
        np.testing.assert_array_equal(a, b)
    lines = [q for b, q in zip(out.cells, out.cell_data["scaled_jacobian"]) if b.type == "line"]
    assert all(np.isnan(q).all() for q in lines)
    # Without the group the holes move: the group made the difference.
    free = quadopt.optimize_mesh(mesh)
    assert not np.array_equal(free.points, out.points)
    with pytest.raises(ValueError, match="fix_physical nowhere: no physical group of that name"):
        quadopt.optimize_mesh(mesh, fix_physical=["nowhere"])


def test_msh_round_trip_matches_the_cli(tmp_path):
    """gmsh's MSH 4.1 in, meshio's binary MSH 4.1 out and back. (meshio 5.3.5 cannot write a
    quad-dominant gmsh mesh back: its 4.1 writer refuses a quad block and a triangle block of one
    gmsh entity, its 2.2 reader splits what its writer wrote, and under numpy 2 it writes float
    cell data in ASCII MSH as "np.float64(...)": hence an all-quad mesh, in binary.)"""
    src = tmp_path / "plate_quads.msh"
    gmsh_plate(src, all_quads=True)
    mesh = meshio.read(src)
    assert {b.type for b in mesh.cells} == {"line", "quad"}
    out, report = quadopt.optimize_mesh(mesh, return_report=True)
    want, want_report = cli_run(tmp_path, src, ".msh")
    np.testing.assert_array_equal(bits(out.points), bits(want.points))
    np.testing.assert_array_equal(bits(quality_of(out)), bits(quality_of(want)))
    path = tmp_path / "py.msh"
    meshio.write(path, out, file_format="gmsh", binary=True)
    back = meshio.read(path)
    np.testing.assert_array_equal(bits(back.points), bits(out.points))
    np.testing.assert_array_equal(bits(quality_of(back)), bits(quality_of(out)))
    # The CLI reads what meshio wrote and measures what the run reported.
    measured = json.loads(run_cli(["quality", path, "--json"]).stdout)
    assert (measured["min"], measured["avg"], measured["quads"]) == (
        report["output"]["min"], report["output"]["avg"], report["quads"])
    assert report["output"] == want_report["output"]


def test_a_feature_curve_of_a_surface_msh_matches_the_cli(tmp_path):
    """A curved sheet with a physical curve across it, written by meshio as MSH 2.2 (with the
    curve's line elements and $PhysicalNames), optimized with the curve as a feature."""
    points, faces = jittered_grid(10, 8, jitter=0.25, seed=5)
    surface = bumpy(points, amplitude=0.3)
    row = 4 * 11
    lines = np.array([[row + i, row + i + 1] for i in range(10)])
    mesh = meshio.Mesh(surface, [("line", lines), ("quad", faces)],
                       cell_data={"gmsh:physical": [np.full(len(lines), 7), np.full(len(faces), 1)],
                                  "gmsh:geometrical": [np.full(len(lines), 1), np.full(len(faces), 1)]},
                       field_data={"crease": np.array([7, 1]), "sheet": np.array([1, 2])})
    src = tmp_path / "sheet.msh"
    meshio.write(src, mesh, file_format="gmsh22", binary=False)
    read = meshio.read(src)
    out, report = quadopt.optimize_mesh(read, feature_physical=["crease"], return_report=True)
    want, want_report = cli_run(tmp_path, src, ".msh", "--feature-physical", "crease")
    np.testing.assert_array_equal(bits(out.points), bits(want.points))
    np.testing.assert_array_equal(bits(quality_of(out)), bits(quality_of(want)))
    assert report["surface"] is True and report["feature_curves"] == want_report["feature_curves"]
    plain = quadopt.optimize_mesh(read, return_report=True)[1]
    assert report["feature_curves"] > plain["feature_curves"]


def test_a_fixed_point_data_array_pins_its_vertices(tmp_path):
    points, faces = jittered_grid(8, 8, jitter=0.4, seed=2)
    fixed = np.zeros(len(points), dtype=np.int32)
    fixed[[20, 30, 40]] = 1
    mesh = meshio.Mesh(np.column_stack([points, np.zeros(len(points))]), [("quad", faces)],
                       point_data={"fixed": fixed})
    src = tmp_path / "fixed.vtu"
    meshio.write(src, mesh)
    out = quadopt.optimize_mesh(meshio.read(src))
    want, _ = cli_run(tmp_path, src, ".vtu")
    np.testing.assert_array_equal(bits(out.points), bits(want.points))
    np.testing.assert_array_equal(bits(out.points[[20, 30, 40]]), bits(mesh.points[[20, 30, 40]]))
    np.testing.assert_array_equal(out.point_data["fixed"], fixed)


def test_a_mesh_without_faces_is_refused():
    mesh = meshio.Mesh(np.zeros((3, 3)), [("line", np.array([[0, 1], [1, 2]]))])
    with pytest.raises(quadopt.MeshError, match="no quad or triangle cells"):
        quadopt.optimize_mesh(mesh)

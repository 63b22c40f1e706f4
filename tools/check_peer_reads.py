#!/usr/bin/env python3
"""Checks that the tools users open quadopt's output with read it as quadopt wrote it: VTK
(what ParaView is built on) reads every VTU encoding, gmsh reads MSH 4.1 ASCII and binary.

Usage:  python3 -m venv /tmp/venv && /tmp/venv/bin/pip install -r tools/requirements.txt
        /tmp/venv/bin/python tools/check_peer_reads.py path/to/quadopt [MESH]

`quadopt optimize MESH` (default: the bundled data/patch_notched.vtk) writes a legacy VTK
file, the reference (ASCII, shortest round-trip doubles, so its numbers are exact), then the
same run as

  VTU   ascii, binary (inline base64) and appended raw, each with and without zlib
  MSH   4.1 ASCII and 4.1 binary

VTK's vtkXMLUnstructuredGridReader must read each VTU with the reference's points, quads,
`scaled_jacobian` cell array and `fixed` and `corner` point arrays, bit for bit (ASCII VTU
included: quadopt writes shortest round-trip doubles); gmsh must read each MSH with the
reference's nodes, quads and the three views. Prints one line per file; exits 1 on any
difference.
"""

import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")


def read_legacy_vtk(path):
    """Points, quads and the scalar arrays of quadopt's ASCII legacy VTK output."""
    words = open(path).read().split()
    out = {"cell": {}, "point": {}}
    i, section = 0, None
    while i < len(words):
        w = words[i]
        if w == "POINTS":
            n = int(words[i + 1])
            xs = [float(x) for x in words[i + 3:i + 3 + 3 * n]]
            out["points"] = [xs[3 * k:3 * k + 3] for k in range(n)]
            i += 3 + 3 * n
        elif w == "CELLS":
            n = int(words[i + 1])
            cells = [int(x) for x in words[i + 3:i + 3 + 5 * n]]
            out["quads"] = [cells[5 * k + 1:5 * k + 5] for k in range(n)]
            i += 3 + 5 * n
        elif w in ("CELL_DATA", "POINT_DATA"):
            section, count = ("cell" if w == "CELL_DATA" else "point"), int(words[i + 1])
            i += 2
        elif w == "SCALARS":
            name = words[i + 1]
            values = words[i + 6:i + 6 + count]  # SCALARS name type 1 LOOKUP_TABLE default
            out[section][name] = [float(v) for v in values]
            i += 6 + count
        else:
            i += 1
    return out


def check_vtu(path, ref):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    if reader.GetErrorCode() != 0:
        return [f"VTK's reader failed (error code {reader.GetErrorCode()})"]
    grid = reader.GetOutput()
    problems = []
    points = vtk_to_numpy(grid.GetPoints().GetData()).tolist()
    if points != ref["points"]:
        problems.append(f"points differ ({len(points)} read, {len(ref['points'])} expected)")
    cells = grid.GetCells()
    conn = vtk_to_numpy(cells.GetConnectivityArray()).tolist()
    offsets = vtk_to_numpy(cells.GetOffsetsArray()).tolist()
    quads = [conn[a:b] for a, b in zip(offsets, offsets[1:])]
    types = {grid.GetCellType(c) for c in range(grid.GetNumberOfCells())}
    if quads != ref["quads"] or types != {9}:
        problems.append(f"quads differ ({len(quads)} read, cell types {sorted(types)})")
    for where, data in (("cell", grid.GetCellData()), ("point", grid.GetPointData())):
        for name, want in ref[where].items():
            array = data.GetArray(name)
            if array is None:
                problems.append(f"no {where} array {name!r}")
            elif [float(v) for v in vtk_to_numpy(array).tolist()] != want:
                problems.append(f"{where} array {name!r} differs")
    return problems


def check_msh(path, ref):
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(path)
        problems = []
        tags, coords, _ = gmsh.model.mesh.getNodes()
        nodes = dict((int(t), list(coords[3 * k:3 * k + 3])) for k, t in enumerate(tags))
        if nodes != {k + 1: p for k, p in enumerate(ref["points"])}:
            problems.append(f"nodes differ ({len(nodes)} read, {len(ref['points'])} expected)")
        _, quad_nodes = gmsh.model.mesh.getElementsByType(3)
        quads = [[int(n) - 1 for n in quad_nodes[k:k + 4]] for k in range(0, len(quad_nodes), 4)]
        if quads != ref["quads"]:
            problems.append(f"quads differ ({len(quads)} read, {len(ref['quads'])} expected)")
        views = {gmsh.option.getString(f"View[{gmsh.view.getIndex(v)}].Name"): v for v in gmsh.view.getTags()}
        for name, want in list(ref["cell"].items()) + list(ref["point"].items()):
            if name not in views:
                problems.append(f"no view {name!r} (views: {sorted(views)})")
                continue
            _, vtags, data, _, _ = gmsh.view.getModelData(views[name], 0)
            got = [float(d[0]) for _, d in sorted(zip(vtags, data))]
            if got != want:
                problems.append(f"view {name!r} differs")
        return problems
    finally:
        gmsh.finalize()


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    quadopt = os.path.abspath(sys.argv[1])
    mesh = sys.argv[2] if len(sys.argv) == 3 else os.path.join(ROOT, "data", "patch_notched.vtk")
    outputs = [("ref.vtk", [])]
    for encoding in ("ascii", "binary", "appended"):
        outputs.append((f"{encoding}.vtu", ["--encoding", encoding]))
        if encoding != "ascii":
            outputs.append((f"{encoding}_zlib.vtu", ["--encoding", encoding, "--zlib"]))
    outputs += [("ascii.msh", []), ("binary.msh", ["--encoding", "binary"])]
    failed = False
    with tempfile.TemporaryDirectory() as tmp:
        for name, flags in outputs:
            path = os.path.join(tmp, name)
            subprocess.run([quadopt, "optimize", mesh, "-o", path, *flags], check=True, stdout=subprocess.DEVNULL)
        ref = read_legacy_vtk(os.path.join(tmp, "ref.vtk"))
        assert ref["points"] and ref["quads"] and "scaled_jacobian" in ref["cell"] and "fixed" in ref["point"]
        for name, _ in outputs[1:]:
            path = os.path.join(tmp, name)
            reader = "vtk" if name.endswith(".vtu") else "gmsh"
            problems = check_vtu(path, ref) if reader == "vtk" else check_msh(path, ref)
            for p in problems:
                print(f"{name} ({reader}): {p}", file=sys.stderr)
            if not problems:
                print(f"{name}: {reader} reads {len(ref['points'])} points, {len(ref['quads'])} quads and "
                      f"{', '.join(list(ref['cell']) + list(ref['point']))} as written")
            failed |= bool(problems)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()

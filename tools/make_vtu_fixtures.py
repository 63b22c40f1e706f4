#!/usr/bin/env python3
"""VTU fixtures written by VTK itself, for tests/io_vtu.rs.

Usage:  python3 -m venv /tmp/venv && /tmp/venv/bin/pip install vtk
        /tmp/venv/bin/python tools/make_vtu_fixtures.py          # writes tests/data/vtu/

One small quad mesh (a 3 x 2 grid with two moved interior-free vertices, an unused vertex and
a `fixed` point array, plus a cell array that readers must skip) is written by
vtkXMLUnstructuredGridWriter in each data mode ParaView can produce:

  ascii.vtu                 format="ascii"
  binary.vtu                format="binary" (inline base64), no compression
  binary_zlib.vtu           inline base64, vtkZLibDataCompressor
  appended_raw.vtu          <AppendedData encoding="raw">, no compression
  appended_base64.vtu       <AppendedData encoding="base64">
  appended_zlib.vtu         appended raw + zlib: what ParaView writes by default
  appended_zlib_small_blocks.vtu   zlib with 64-byte blocks (several blocks per array)
  big_endian_uint32.vtu     appended raw, BigEndian, UInt32 headers
  float32_int32.vtu         Float32 points and Int32 connectivity, appended raw + zlib

expected.txt holds what every file must read as: the points (Python repr, exact doubles), the
quads and the fixed flags. The Float32 file's points are the float32 roundings of these.
The mesh is deterministic, so rerunning the script with the same VTK version reproduces the
files byte for byte; the committed files were made with VTK 9.7.2 (pip wheel).
"""

import os
import sys

import vtk
from vtk.util import numpy_support  # noqa: F401  (checks numpy is present)

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "tests", "data", "vtu")


def mesh():
    """Points (x, y, z) and quads of a 3 x 2 grid, two vertices moved, one vertex unused."""
    points = []
    for j in range(3):
        for i in range(4):
            points.append([i * 0.5, j * 0.75, 0.0])
    points[5] = [0.5 + 0.1, 0.75 - 1.0 / 3.0, 0.0]  # values with no short decimal form
    points[6] = [1.0 + 2.0 ** -30, 0.75 + 1e-9, 0.0]
    points.append([7.0, 7.0, 0.0])  # used by no quad: must be kept in place
    quads = []
    for j in range(2):
        for i in range(3):
            a = j * 4 + i
            quads.append([a, a + 1, a + 5, a + 4])
    fixed = [1 if (p[0] in (0.0, 1.5) or p[1] in (0.0, 1.5)) else 0 for p in points[:12]] + [0]
    return points, quads, fixed


def grid(float32=False, int32=False):
    points, quads, fixed = mesh()
    pts = vtk.vtkPoints()
    pts.SetDataTypeToFloat() if float32 else pts.SetDataTypeToDouble()
    for p in points:
        pts.InsertNextPoint(p)
    g = vtk.vtkUnstructuredGrid()
    g.SetPoints(pts)
    if int32:
        cells = vtk.vtkCellArray()
        cells.Use32BitStorage()
        for q in quads:
            cells.InsertNextCell(4, q)
        g.SetCells(vtk.VTK_QUAD, cells)
    else:
        g.Allocate(len(quads))
        for q in quads:
            g.InsertNextCell(vtk.VTK_QUAD, 4, q)
    f = vtk.vtkUnsignedCharArray()
    f.SetName("fixed")
    for v in fixed:
        f.InsertNextValue(v)
    g.GetPointData().AddArray(f)
    other = vtk.vtkDoubleArray()  # a point array the reader must skip
    other.SetName("temperature")
    other.SetNumberOfComponents(2)
    for i in range(len(points)):
        other.InsertNextTuple2(i * 0.5, -i)
    g.GetPointData().AddArray(other)
    q = vtk.vtkDoubleArray()  # a cell array the reader must skip
    q.SetName("scaled_jacobian")
    for i in range(len(quads)):
        q.InsertNextValue(1.0 - i / 10.0)
    g.GetCellData().AddArray(q)
    return g


def write(name, mode, compress=False, block=None, big_endian=False, uint32=False, **kw):
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(os.path.join(OUT, name))
    w.SetInputData(grid(**kw))
    {"ascii": w.SetDataModeToAscii, "binary": w.SetDataModeToBinary,
     "appended": w.SetDataModeToAppended}[mode]()
    w.SetEncodeAppendedData(mode == "appended" and name.startswith("appended_base64"))
    if compress:
        w.SetCompressorTypeToZLib()
        if block:
            w.SetBlockSize(block)
    else:
        w.SetCompressorTypeToNone()
    w.SetByteOrderToBigEndian() if big_endian else w.SetByteOrderToLittleEndian()
    w.SetHeaderTypeToUInt32() if uint32 else w.SetHeaderTypeToUInt64()
    if not w.Write():
        sys.exit(f"VTK could not write {name}")


def main():
    os.makedirs(OUT, exist_ok=True)
    write("ascii.vtu", "ascii")
    write("binary.vtu", "binary")
    write("binary_zlib.vtu", "binary", compress=True)
    write("appended_raw.vtu", "appended")
    write("appended_base64.vtu", "appended")
    write("appended_zlib.vtu", "appended", compress=True)
    write("appended_zlib_small_blocks.vtu", "appended", compress=True, block=64)
    write("big_endian_uint32.vtu", "appended", big_endian=True, uint32=True)
    write("float32_int32.vtu", "appended", compress=True, float32=True, int32=True)
    points, quads, fixed = mesh()
    with open(os.path.join(OUT, "expected.txt"), "w") as f:
        f.write(f"# written by tools/make_vtu_fixtures.py with VTK {vtk.vtkVersion.GetVTKVersion()}\n")
        for p in points:
            f.write("point " + " ".join(repr(float(c)) for c in p) + "\n")
        for q in quads:
            f.write("quad " + " ".join(str(v) for v in q) + "\n")
        f.write("fixed " + " ".join(str(v) for v in fixed) + "\n")


if __name__ == "__main__":
    main()

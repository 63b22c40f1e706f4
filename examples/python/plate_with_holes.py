"""A plate with holes, from gmsh to a VTU file with the quality and a picture before and after.

gmsh meshes the plate and recombines its triangles into quads (a quad-dominant mesh: quads
and a few triangles), meshio reads the MSH file, quadopt optimizes it (the holes' physical
group is kept fixed, to show how gmsh's physical groups are honoured), meshio writes the result
as a VTU file with each face's scaled Jacobian as cell data, and matplotlib draws the mesh
before and after, faces coloured by their scaled Jacobian.

    python examples/python/plate_with_holes.py [--out DIR] [--size H]

Needs gmsh, meshio and matplotlib (pip install gmsh meshio matplotlib) besides quadopt; runs
without a display.
"""

import argparse
import os
from pathlib import Path

import numpy as np


def mesh_plate(path: Path, size: float) -> None:
    """A 10 x 6 plate with five holes, meshed by gmsh and recombined into quads, written to
    ``path`` (MSH 4.1) with physical groups "plate", "outer" and "holes"."""
    import gmsh

    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("plate")
        occ = gmsh.model.occ
        plate = occ.addRectangle(0, 0, 0, 10, 6)
        holes = [occ.addDisk(x, y, 0, r, r) for x, y, r in
                 [(2.5, 3, 1.2), (5.5, 1.8, 0.8), (5.2, 4.3, 0.9), (7.9, 3.1, 1.0), (8.9, 5.1, 0.45)]]
        (surface,), _ = occ.cut([(2, plate)], [(2, h) for h in holes])
        occ.synchronize()
        curves = [c for _, c in gmsh.model.getBoundary([surface], oriented=False)]
        outer = [c for c in curves if gmsh.model.getType(1, c) == "Line"]
        circles = [c for c in curves if c not in outer]
        gmsh.model.addPhysicalGroup(2, [surface[1]], name="plate")
        gmsh.model.addPhysicalGroup(1, outer, name="outer")
        gmsh.model.addPhysicalGroup(1, circles, name="holes")
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", size)
        # Frontal-Delaunay, then the simple recombination without smoothing: quads of all
        # shapes and some triangles left over, what a mesher gives before any clean-up.
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.RecombineAll", 1)
        gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 0)
        gmsh.option.setNumber("Mesh.Smoothing", 0)
        gmsh.model.mesh.generate(2)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


def faces_of(mesh):
    """The quad and triangle cells of a meshio mesh as one list of faces."""
    return [list(f) for b in mesh.cells if b.type in ("quad", "triangle") for f in b.data]


def draw(path: Path, before, after, quality_before, quality_after) -> None:
    """The mesh before and after side by side, faces coloured by scaled Jacobian."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    fig, axes = plt.subplots(1, 2, figsize=(13, 4.6), constrained_layout=True)
    for ax, mesh, q, title in zip(axes, (before, after), (quality_before, quality_after), ("gmsh", "quadopt")):
        polygons = [mesh.points[f, :2] for f in faces_of(mesh)]
        pc = PolyCollection(polygons, array=q, cmap="RdYlGn", clim=(0, 1), edgecolors="k", linewidths=0.3)
        ax.add_collection(pc)
        ax.set_xlim(-0.2, 10.2)
        ax.set_ylim(-0.2, 6.2)
        ax.set_aspect("equal")
        ax.set_title(f"{title}: min {q.min():.3f}, avg {q.mean():.3f}, {(q <= 0).sum()} inverted")
        ax.axis("off")
    fig.colorbar(pc, ax=axes, shrink=0.8, label="scaled Jacobian")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("plate_with_holes_out"), help="output directory")
    parser.add_argument("--size", type=float, default=0.3, help="gmsh's mesh size")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    import meshio
    import quadopt

    msh = args.out / "plate.msh"
    mesh_plate(msh, args.size)
    before = meshio.read(msh)
    optimized, report = quadopt.optimize_mesh(before, fix_physical=["holes"], return_report=True)
    vtu = args.out / "plate_optimized.vtu"
    meshio.write(vtu, optimized)

    q_before = quadopt.quality(before.points, faces_of(before)).values
    q_after = np.concatenate([q for b, q in zip(optimized.cells, optimized.cell_data["scaled_jacobian"])
                              if b.type in ("quad", "triangle")])
    png = args.out / "plate_before_after.png"
    draw(png, before, optimized, q_before, q_after)

    quads = report["quads"]
    triangles = report.get("triangles", 0)
    print(f"gmsh: {len(before.points)} vertices, {quads} quads and {triangles} triangles ({msh})")
    for name in ("input", "output"):
        s = report[name]
        print(f"{name:6}: min {s['min']:.4f}, avg {s['avg']:.4f}, {s['inverted']} inverted")
    print(f"quadopt: {report['iterations']} sweeps, {report['moved']} vertices moved, "
          f"{report['corners']} corners kept, boundary modes {report['loop_modes']}")
    print(f"wrote {vtu} (cell data: {', '.join(optimized.cell_data)})")
    print(f"wrote {png}")


if __name__ == "__main__":
    main()

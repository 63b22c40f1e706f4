#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Draws the README's before/after picture of a sample run through the filter in pymeshlab.

    PY plugins/meshlab/tests/before_after.py PLUGIN QUADOPT [SAMPLE] [OUT.png]

PY: a python with pymeshlab and matplotlib (e.g. target/meshlab-test/venv/bin/python after
`pip install matplotlib`); PLUGIN: the path scripts/meshlab-plugin prints; QUADOPT: the
command-line tool (for the input's per-face values). SAMPLE defaults to data/mazewheel_mixed.vtk,
OUT to docs/images/meshlab_mazewheel_mixed.png. The faces are coloured by MeshLab's per-face
quality as the filter leaves it (the output) and by quadopt's values of the input; pymeshlab
cannot render offscreen without an OpenGL context, so matplotlib draws them.
"""
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_filter import FILTER, ROOT, read_vtk, write_obj  # noqa: E402


def main():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    import pymeshlab
    from matplotlib.collections import PolyCollection

    plugin, cli = sys.argv[1], sys.argv[2]
    sample = sys.argv[3] if len(sys.argv) > 3 else os.path.join(ROOT, "data", "mazewheel_mixed.vtk")
    out = sys.argv[4] if len(sys.argv) > 4 else os.path.join(ROOT, "docs", "images", "meshlab_mazewheel_mixed.png")
    pts, faces, _ = read_vtk(sample)
    tmp = tempfile.mkdtemp(prefix="quadopt-picture-")
    q_in = os.path.join(tmp, "q.vtk")
    subprocess.run([cli, "quality", sample, "-o", q_in], check=True, stdout=subprocess.DEVNULL)
    before = read_vtk(q_in)[2]["scaled_jacobian"]

    pymeshlab.load_plugin(plugin)
    obj = os.path.join(tmp, "m.obj")
    write_obj(obj, pts, faces)
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(obj)
    report = ms.apply_filter(FILTER)
    m = ms.current_mesh()
    moved = m.vertex_matrix()
    per_tri = m.face_scalar_array()
    first = np.cumsum([0] + [len(c) - 2 for c in faces])[:-1]
    after = per_tri[first]  # every triangle of a polygon holds its value

    fig, axes = plt.subplots(1, 2, figsize=(10, 5.2), dpi=90)
    cmap = plt.get_cmap("RdYlGn")
    for ax, xyz, q, title in (
            (axes[0], pts, before, "input: min %.3f, avg %.3f, %d inverted" % (
                report["input_min"], report["input_avg"], report["input_inverted"])),
            (axes[1], moved, after, "after the filter: min %.3f, avg %.3f, %d inverted" % (
                report["output_min"], report["output_avg"], report["output_inverted"]))):
        polys = [xyz[c][:, :2] for c in faces]
        coll = PolyCollection(polys, array=np.clip(q, 0, 1), cmap=cmap, edgecolors="k", linewidths=0.3)
        coll.set_clim(0, 1)
        ax.add_collection(coll)
        bad = [p for p, v in zip(polys, q) if v <= 0]
        if bad:
            ax.add_collection(PolyCollection(bad, facecolors="none", edgecolors="b", linewidths=1.2, hatch="///"))
        ax.set_aspect("equal")
        ax.autoscale_view()
        ax.set_axis_off()
        ax.set_title(title, fontsize=10)
    cb = fig.colorbar(coll, ax=axes, orientation="horizontal", fraction=0.04, pad=0.03)
    cb.set_label("scaled Jacobian per face (after: MeshLab's per-face quality as the filter left it; <= 0 hatched)", fontsize=9)
    fig.suptitle("%s in pymeshlab: apply_coord_quadopt_quad_quality (%d quads, %d triangles, %.1f ms)" % (
        os.path.basename(sample), report["quads"], report["triangles"], 1000 * report["seconds"]), fontsize=11)
    fig.savefig(out, bbox_inches="tight")
    # A palette image: a tenth of the size, no visible difference on these flat colours.
    from PIL import Image
    Image.open(out).convert("RGB").quantize(colors=256, method=Image.Quantize.FASTOCTREE).save(out, optimize=True)
    print(out)


if __name__ == "__main__":
    main()

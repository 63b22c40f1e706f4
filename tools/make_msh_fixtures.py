#!/usr/bin/env python3
"""MSH fixtures written by gmsh itself, for tests/io_msh.rs; and a check that gmsh reads what
quadopt writes.

Usage:  python3 -m venv /tmp/venv && /tmp/venv/bin/pip install gmsh
        /tmp/venv/bin/python tools/make_msh_fixtures.py            # writes tests/data/msh/
        /tmp/venv/bin/python tools/make_msh_fixtures.py --check-read FILE.msh EXPECTED.txt
                                       # gmsh opens FILE.msh (ours); its nodes, quads and
                                       # views must equal EXPECTED.txt (exit 1 if not)

The mesh: a 2 x 1 plate with a hole of radius 0.25, all quads (recombined, then subdivided),
with physical curves "wall" (the left edge) and "hole" (the circle), a physical point
"corner" (the origin) and a physical surface "domain". It is written as

  plate_v41_binary.msh    Mesh.Binary=1, MSH 4.1 (what `gmsh -bin` writes)
  plate_v41_ascii.msh     MSH 4.1 ASCII
  plate_v22_ascii.msh     MSH 2.2 ASCII (physical tags on the elements)
  plate_v22_binary.msh    MSH 2.2 binary (not read: the reader must say so)

and plate_expected.txt lists what they hold: `node TAG X Y Z` (Python repr, exact doubles, in
the files' node order), `quad TAG TAG TAG TAG`, `group DIM TAG NAME NODE_TAGS...` for the
point and curve groups. Deterministic for one gmsh version (4.15.2 for the committed files).

--check-read's EXPECTED.txt has the same `node` and `quad` lines (what quadopt wrote) and
`view NAME VALUES...` lines (per node or per element, in tag order).
"""

import os
import sys

import gmsh

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "tests", "data", "msh")


def build():
    gmsh.model.add("plate")
    occ = gmsh.model.occ
    rect = occ.addRectangle(0, 0, 0, 2, 1)
    disk = occ.addDisk(1, 0.5, 0, 0.25, 0.25)
    occ.cut([(2, rect)], [(2, disk)])
    occ.synchronize()
    left = hole = origin = None
    for dim, tag in gmsh.model.getEntities(1):
        x0, y0, _, x1, y1, _ = gmsh.model.getBoundingBox(dim, tag)
        if x1 < 1e-6:
            left = tag
        if x0 > 0.5 and x1 < 1.5 and y0 > 0.1:
            hole = tag
    for dim, tag in gmsh.model.getEntities(0):
        x0, y0, _, _, _, _ = gmsh.model.getBoundingBox(dim, tag)
        if abs(x0) < 1e-6 and abs(y0) < 1e-6:
            origin = tag
    assert None not in (left, hole, origin)
    gmsh.model.addPhysicalGroup(1, [left], tag=11, name="wall")
    gmsh.model.addPhysicalGroup(1, [hole], tag=12, name="hole")
    gmsh.model.addPhysicalGroup(0, [origin], tag=13, name="corner")
    gmsh.model.addPhysicalGroup(2, [s for _, s in gmsh.model.getEntities(2)], tag=14, name="domain")
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.3)
    gmsh.option.setNumber("Mesh.RecombineAll", 1)
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 1)  # all quads
    gmsh.model.mesh.generate(2)


def write(name, version, binary):
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.option.setNumber("Mesh.Binary", 1 if binary else 0)
    gmsh.write(os.path.join(OUT, name))


def expected():
    lines = [f"# written by tools/make_msh_fixtures.py with gmsh {gmsh.__version__}"]
    tags, coords, _ = gmsh.model.mesh.getNodes()
    for i, t in enumerate(tags):
        lines.append(f"node {t} " + " ".join(repr(float(c)) for c in coords[3 * i:3 * i + 3]))
    _, nodes = gmsh.model.mesh.getElementsByType(3)
    for i in range(0, len(nodes), 4):
        lines.append("quad " + " ".join(str(n) for n in nodes[i:i + 4]))
    for dim, tag in gmsh.model.getPhysicalGroups():
        if dim <= 1:
            ns, _ = gmsh.model.mesh.getNodesForPhysicalGroup(dim, tag)
            name = gmsh.model.getPhysicalName(dim, tag)
            lines.append(f"group {dim} {tag} {name} " + " ".join(str(n) for n in sorted(ns)))
    return "\n".join(lines) + "\n"


def check_read(path, expected_path):
    """gmsh opens `path`; its nodes, quads and views must be exactly those of expected."""
    gmsh.open(path)
    want = {"node": [], "quad": [], "view": {}}
    for line in open(expected_path):
        w = line.split()
        if not w or w[0].startswith("#"):
            continue
        if w[0] == "node":
            want["node"].append((int(w[1]), [float(x) for x in w[2:5]]))
        elif w[0] == "quad":
            want["quad"].append([int(x) for x in w[1:5]])
        elif w[0] == "view":
            want["view"][w[1]] = [float(x) for x in w[2:]]
    tags, coords, _ = gmsh.model.mesh.getNodes()
    got = {int(t): list(coords[3 * i:3 * i + 3]) for i, t in enumerate(tags)}
    problems = []
    if got != dict(want["node"]):
        problems.append(f"nodes differ ({len(got)} read, {len(want['node'])} expected)")
    _, nodes = gmsh.model.mesh.getElementsByType(3)
    quads = [[int(n) for n in nodes[i:i + 4]] for i in range(0, len(nodes), 4)]
    if quads != want["quad"]:
        problems.append(f"quads differ ({len(quads)} read, {len(want['quad'])} expected)")
    views = {gmsh.option.getString(f"View[{gmsh.view.getIndex(v)}].Name"): v for v in gmsh.view.getTags()}
    for name, values in want["view"].items():
        if name not in views:
            problems.append(f"no view {name!r} (views: {sorted(views)})")
            continue
        kind, vtags, data, _, _ = gmsh.view.getModelData(views[name], 0)
        by_tag = sorted(zip(vtags, (d[0] for d in data)))
        if [v for _, v in by_tag] != values:
            problems.append(f"view {name!r} differs")
    for p in problems:
        print(f"{path}: {p}", file=sys.stderr)
    return not problems


def main():
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    if len(sys.argv) == 4 and sys.argv[1] == "--check-read":
        ok = check_read(sys.argv[2], sys.argv[3])
        gmsh.finalize()
        sys.exit(0 if ok else 1)
    os.makedirs(OUT, exist_ok=True)
    build()
    write("plate_v41_binary.msh", 4.1, True)
    write("plate_v41_ascii.msh", 4.1, False)
    write("plate_v22_ascii.msh", 2.2, False)
    write("plate_v22_binary.msh", 2.2, True)
    with open(os.path.join(OUT, "plate_expected.txt"), "w") as f:
        f.write(expected())
    gmsh.finalize()


if __name__ == "__main__":
    main()

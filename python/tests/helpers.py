"""What the tests share: the CLI (``target/release/quadopt``, built by cargo) run on a file that
holds exactly the arrays given to Python, legacy VTK files written and read without rounding,
and meshes to test on (the bundled samples and random ones)."""

import json
import os
import subprocess
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "data"
NO_VERTEX = -1


def cli_path() -> Path:
    """The CLI: $QUADOPT_CLI, else the release build of this checkout (cargo's target dir)."""
    if os.environ.get("QUADOPT_CLI"):
        return Path(os.environ["QUADOPT_CLI"])
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return target / "release" / "quadopt"


def library_path() -> Path:
    """The C ABI's shared library: $QUADOPT_LIBRARY, else beside the CLI."""
    if os.environ.get("QUADOPT_LIBRARY"):
        return Path(os.environ["QUADOPT_LIBRARY"])
    return cli_path().parent / "libquadopt.so"


def bits(a: np.ndarray) -> np.ndarray:
    """The bit patterns of a float64 array (NaNs and signed zeros compared exactly)."""
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


def write_vtk(path: Path, points: np.ndarray, faces: np.ndarray, fixed=None) -> None:
    """A legacy ASCII VTK file of the mesh, every coordinate written with repr (shortest round
    trip: the CLI reads back the very bits); a 2D mesh is written in the plane z = 0, as a 2D
    file is read."""
    points = np.asarray(points, dtype=np.float64)
    faces = np.asarray(faces)
    lines = ["# vtk DataFile Version 3.0", "quadopt python test", "ASCII", "DATASET UNSTRUCTURED_GRID",
             f"POINTS {len(points)} double"]
    for p in points:
        xyz = list(p) + [0.0] * (3 - len(p))
        lines.append(" ".join(repr(float(c)) for c in xyz))
    corners = [[int(v) for v in f if v != NO_VERTEX] for f in faces]
    lines.append(f"CELLS {len(corners)} {sum(len(c) + 1 for c in corners)}")
    lines += [" ".join(map(str, [len(c)] + c)) for c in corners]
    lines.append(f"CELL_TYPES {len(corners)}")
    lines += ["9" if len(c) == 4 else "5" for c in corners]
    if fixed is not None:
        mask = np.zeros(len(points), dtype=bool)
        mask[np.asarray(fixed)] = True
        lines += [f"POINT_DATA {len(points)}", "SCALARS fixed int 1", "LOOKUP_TABLE default"]
        lines += ["1" if f else "0" for f in mask]
    Path(path).write_text("\n".join(lines) + "\n")


def read_vtk(path: Path):
    """A legacy ASCII VTK file (the samples', the CLI's): points (n, 3), faces (m, 4) with -1
    for a triangle's fourth corner, and the cell and point data arrays by name."""
    tokens = Path(path).read_text().split("\n")
    points = faces = None
    cell_data, point_data = {}, {}
    section = None
    i = 0
    while i < len(tokens):
        line = tokens[i].split()
        i += 1
        if not line:
            continue
        key = line[0]
        if key == "POINTS":
            n = int(line[1])
            values = []
            while len(values) < 3 * n:
                values += [float(t) for t in tokens[i].split()]
                i += 1
            points = np.array(values, dtype=np.float64).reshape(n, 3)
        elif key == "CELLS":
            m = int(line[1])
            faces = np.full((m, 4), NO_VERTEX, dtype=np.int64)
            for f in range(m):
                c = [int(t) for t in tokens[i].split()]
                i += 1
                faces[f, : c[0]] = c[1:]
        elif key in ("CELL_DATA", "POINT_DATA"):
            section = cell_data if key == "CELL_DATA" else point_data
            count = int(line[1])
        elif key == "SCALARS":
            i += 1  # LOOKUP_TABLE
            values = []
            while len(values) < count:
                values += [float(t) for t in tokens[i].split()]
                i += 1
            section[line[1]] = np.array(values, dtype=np.float64)
    return points, faces, cell_data, point_data


def sample_paths():
    return sorted(DATA.glob("*.vtk"))


def read_sample(name_or_path):
    path = Path(name_or_path)
    if not path.is_absolute():
        path = DATA / path
    points, faces, _, point_data = read_vtk(path)
    fixed = point_data.get("fixed")
    return points, faces, None if fixed is None else np.flatnonzero(fixed)


def is_planar_z(points: np.ndarray) -> bool:
    return points.shape[1] == 2 or bool(np.all(points[:, 2] == points[0, 2]))


def cli_options(effort="balanced", boundary="auto", method="ep", feature_angle=45.0, max_iterations=None,
                threads=None):
    args = ["--effort", effort, "--boundary", boundary, "--method", method, "--feature-angle", repr(feature_angle)]
    if max_iterations is not None:
        args += ["--max-iter", str(max_iterations)]
    if threads is not None:
        args = ["--threads", str(threads)] + args
    return args


def run_cli(args, check=True):
    r = subprocess.run([str(cli_path())] + [str(a) for a in args], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError(f"quadopt {' '.join(map(str, args))} failed: {r.stderr}")
    return r


def cli_optimize(tmp_path: Path, points, faces, fixed=None, feature_edges=None, **options):
    """``quadopt optimize --json`` on a VTK file of the mesh: (points (n, 3), report, quality)."""
    src, out = tmp_path / "cli_in.vtk", tmp_path / "cli_out.vtk"
    write_vtk(src, points, faces, fixed)
    args = ["optimize", src, "-o", out, "--json"] + cli_options(**options)
    if feature_edges is not None:
        edges = tmp_path / "edges.txt"
        edges.write_text("".join(f"{a} {b}\n" for a, b in np.asarray(feature_edges)))
        args += ["--feature-edges", edges]
    report = json.loads(run_cli(args).stdout)
    new_points, _, cell_data, _ = read_vtk(out)
    return new_points, report, cell_data["scaled_jacobian"]


def cli_quality(tmp_path: Path, points, faces):
    src = tmp_path / "cli_quality.vtk"
    write_vtk(src, points, faces)
    return json.loads(run_cli(["quality", src, "--json"]).stdout)


#: Keys of a report that are times (never equal from one run to the next), or the CLI's file names.
UNSTABLE = {"seconds", "setup_seconds", "input_file", "output_file", "picture_file", "file"}


def stable(report):
    """A report without its times and file names (recursively)."""
    if isinstance(report, dict):
        return {k: stable(v) for k, v in report.items() if k not in UNSTABLE}
    if isinstance(report, list):
        return [stable(v) for v in report]
    return report


def jittered_grid(nx, ny, jitter, seed, triangles=0.0, holes=()):
    """A random mesh: an nx-by-ny grid of unit quads whose interior vertices are moved by up to
    ``jitter`` per axis (0.3 and more folds quads), a fraction ``triangles`` of the quads split
    along a diagonal, and the quads whose centre lies in one of ``holes`` ((cx, cy, r)) removed
    (the vertices left unused stay in the mesh)."""
    rng = np.random.default_rng(seed)
    xs, ys = np.meshgrid(np.arange(nx + 1, dtype=float), np.arange(ny + 1, dtype=float))
    points = np.column_stack([xs.ravel(), ys.ravel()])
    interior = (xs.ravel() > 0) & (xs.ravel() < nx) & (ys.ravel() > 0) & (ys.ravel() < ny)
    points[interior] += rng.uniform(-jitter, jitter, size=(interior.sum(), 2))
    faces = []
    for j in range(ny):
        for i in range(nx):
            if any((i + 0.5 - cx) ** 2 + (j + 0.5 - cy) ** 2 < r * r for cx, cy, r in holes):
                continue
            a, b, c, d = j * (nx + 1) + i, j * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i
            if rng.uniform() < triangles:
                faces += [[a, b, c, NO_VERTEX], [a, c, d, NO_VERTEX]]
            else:
                faces.append([a, b, c, d])
    return points, np.array(faces, dtype=np.int64)


def bumpy(points2d, amplitude=0.15, frequency=0.7):
    """A 2D mesh lifted onto a curved surface z = a sin(fx) cos(fy)."""
    x, y = points2d[:, 0], points2d[:, 1]
    return np.column_stack([x, y, amplitude * np.sin(frequency * x) * np.cos(frequency * y)])

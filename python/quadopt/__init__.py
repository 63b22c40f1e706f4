"""quadopt: quality optimization of quad and quad-dominant meshes, planar or on curved surfaces.

Vertices move, connectivity never changes, and the scaled Jacobian (Verdict's definition) of
the faces goes up, while the boundary, its corners and any vertex you pin stay where they must.
The Python package of the Rust library: numpy arrays in and out, the same results as the
``quadopt`` command line tool and the C ABI, bit for bit.

>>> import numpy as np, quadopt
>>> points = np.array([[x, y] for y in range(3) for x in range(3)], dtype=float)
>>> points[4] = [1.6, 1.5]                  # the centre vertex dragged off-centre
>>> faces = np.array([[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]])
>>> result = quadopt.optimize(points, faces, boundary="fixed")
>>> bool(result.report["output"]["min"] > result.report["input"]["min"])
True
>>> np.round(result.points[4], 3)
array([1., 1.])

Functions: :func:`optimize` (arrays), :func:`quality` (the measure alone),
:func:`optimize_mesh` (a ``meshio.Mesh``). Errors: :class:`MeshError` (a mesh that cannot be
used; a ``ValueError``), ``TypeError`` for arrays of the wrong shape or dtype, ``ValueError``
for an option out of range, :class:`CancelledError` when the progress callback says stop.
"""

import numbers
from typing import Any, Callable, Dict, NamedTuple, Optional, Sequence, Union

import numpy as np

from . import _quadopt
from ._quadopt import CancelledError, MeshError, Progress

__all__ = [
    "optimize",
    "quality",
    "optimize_mesh",
    "OptimizeResult",
    "QualityResult",
    "Progress",
    "MeshError",
    "CancelledError",
    "__version__",
]

__version__ = _quadopt._library_version()

#: The element types read as they are (any other real dtype is converted to float64 first).
_NATIVE_REALS = (np.float64, np.float32, np.int64, np.int32, np.int16, np.int8,
                 np.uint64, np.uint32, np.uint16, np.uint8)
_NATIVE_INTS = _NATIVE_REALS[2:]


class OptimizeResult(NamedTuple):
    """What :func:`optimize` returns.

    Attributes:
        points: the new coordinates, a float64 array of the input's shape ((n, 2) or (n, 3));
            a vertex that did not move keeps its input coordinates bit for bit.
        report: the run's report, a dict with the keys and values ``quadopt optimize --json``
            prints (without the file names): ``input`` and ``output`` statistics (``min``,
            ``avg``, ``max``, ``inverted``), ``iterations``, ``moved``, ``converged``, ... and,
            on a curved surface, ``surface`` (True), Verdict's statistics and the distances
            from the input surface.
        quality: each face's scaled Jacobian after the run (float64, one per face, in the input's
            order); on a curved surface the signed measure the optimizer ranks by.
    """

    points: np.ndarray
    report: Dict[str, Any]
    quality: np.ndarray


class QualityResult(NamedTuple):
    """What :func:`quality` returns.

    Attributes:
        values: each face's scaled Jacobian (float64, one per face); on a curved surface the
            signed measure (each corner against the surface's normal there, so a fold counts as
            inverted).
        summary: what ``quadopt quality --json`` prints (without the file name): ``min``,
            ``avg``, ``max``, ``inverted``, ``vertices``, ``quads``, ``histogram`` (11 bins:
            ``<= 0``, then tenths), with triangles ``triangles``, ``faces`` and ``by_kind``; on
            a curved surface ``surface`` (True) and ``verdict`` (Verdict's 3D statistics).
        verdict: on a curved surface, each face's Verdict 3D scaled Jacobian (what VTK's
            vtkMeshQuality gives); None for a planar mesh, where the two measures agree on
            every face that is not folded.
    """

    values: np.ndarray
    summary: Dict[str, Any]
    verdict: Optional[np.ndarray]


def _real_array(a: Any, name: str, kinds: str, what: str) -> np.ndarray:
    """``a`` as a numpy array of one of ``kinds`` (numpy kind letters), without a copy when it
    is one already; TypeError otherwise."""
    if not isinstance(a, np.ndarray):
        try:
            a = np.asarray(a)
        except (ValueError, TypeError) as e:
            raise TypeError(f"{name}: {what} is needed ({e})") from None
    if a.dtype.kind not in kinds:
        raise TypeError(f"{name}: {what} is needed, not an array of dtype {a.dtype}")
    return a


def _points(points: Any) -> np.ndarray:
    a = _real_array(points, "points", "fiu", "an (n, 2) or (n, 3) array of real numbers")
    if a.ndim != 2 or a.shape[1] not in (2, 3):
        raise TypeError(f"points: an (n, 2) or (n, 3) array is needed, not shape {a.shape}")
    if not (a.dtype.isnative and a.dtype.type in _NATIVE_REALS):
        a = a.astype(np.float64)  # float16, long double, another byte order
    return a


def _index_array(a: np.ndarray) -> np.ndarray:
    if not (a.dtype.isnative and a.dtype.type in _NATIVE_INTS):
        a = a.astype(np.int64)
    return a


def _faces(faces: Any) -> Any:
    if isinstance(faces, np.ndarray):
        if faces.dtype.kind not in "iu":
            raise TypeError(f"faces: an (m, 4) array of integers is needed, not an array of dtype {faces.dtype}")
        if faces.ndim != 2:
            raise TypeError(f"faces: an (m, 4) array of integers is needed, not shape {faces.shape}")
        return _index_array(faces)
    if isinstance(faces, (str, bytes)) or not hasattr(faces, "__iter__"):
        raise TypeError(
            "faces: an (m, 4) array of integers or a sequence of sequences of 3 or 4 indices is needed, "
            f"not {type(faces).__name__}"
        )
    return faces  # a sequence of faces: read face by face


def _fixed(fixed: Any) -> Optional[np.ndarray]:
    if fixed is None:
        return None
    a = fixed if isinstance(fixed, np.ndarray) else np.asarray(fixed)
    if a.size == 0:
        return np.zeros(0, dtype=np.int64)
    if a.dtype.kind not in "biu" or a.ndim != 1:
        raise TypeError(
            f"fixed: a boolean mask or a 1D array of vertex indices is needed, not {a.dtype} of shape {a.shape}"
        )
    return a if a.dtype.kind == "b" else _index_array(a)


def _feature_edges(edges: Any) -> Optional[np.ndarray]:
    if edges is None:
        return None
    a = edges if isinstance(edges, np.ndarray) else np.asarray(edges)
    if a.size == 0:
        return np.zeros((0, 2), dtype=np.int64)
    if a.dtype.kind not in "iu" or a.ndim != 2 or a.shape[1] != 2:
        raise TypeError(f"feature_edges: a (k, 2) array of vertex indices is needed, not {a.dtype} of shape {a.shape}")
    return _index_array(a)


def _count(value: Any, option: str) -> Optional[int]:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{option}: a whole number is needed, not {type(value).__name__}")
    if value < 1:
        raise ValueError(f"invalid option {option}: must be at least 1, not {value}")
    return int(value)


def _name(value: Any, option: str) -> str:
    if not isinstance(value, str):
        raise TypeError(f"{option}: a string is needed, not {type(value).__name__}")
    return value


class _TqdmBar:
    """A tqdm bar of the sweeps (``progress=True``)."""

    def __init__(self, tqdm: Any) -> None:
        self._tqdm = tqdm
        self._bar: Any = None

    def __call__(self, p: Progress) -> None:
        if self._bar is None:
            self._bar = self._tqdm(total=p.max_iterations, unit="sweep", desc="quadopt", leave=False)
        self._bar.total = p.max_iterations
        self._bar.n = p.iteration
        self._bar.set_postfix_str(f"pass {p.pass_}/{p.passes}", refresh=False)
        self._bar.refresh()

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()


def _progress(progress: Any) -> Any:
    if progress is None or progress is False:
        return None
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            return None  # no tqdm: no bar
        return _TqdmBar(tqdm)
    if not callable(progress):
        raise TypeError(f"progress: a callable, True or None is needed, not {type(progress).__name__}")
    return progress


def optimize(
    points: Any,
    faces: Any,
    *,
    fixed: Any = None,
    feature_edges: Any = None,
    effort: str = "balanced",
    boundary: str = "auto",
    method: str = "ep",
    feature_angle: float = 45.0,
    max_iterations: Optional[int] = None,
    threads: Optional[int] = None,
    progress: Union[None, bool, Callable[[Progress], Optional[bool]]] = None,
) -> OptimizeResult:
    """Optimizes a mesh: moves its vertices to raise the faces' scaled Jacobians.

    Connectivity, corners, fixed vertices and the boundary are kept; a planar mesh is optimized
    in its plane, any other on its surface (every vertex stays on the input surface, a vertex of
    a feature curve on its curve). The result is the one ``quadopt optimize`` gives for a file
    holding the same mesh with the same options, bit for bit.

    Args:
        points: an (n, 2) or (n, 3) array of vertex coordinates, of any real or integer dtype
            (converted to float64); strided and read-only arrays are fine. Never modified.
        faces: an (m, 4) integer array of vertex indices (from 0), -1 in the fourth column for
            a triangle (an (m, 3) array is all triangles), or a sequence of sequences of 3 or 4
            indices. Faces may be given clockwise or counter-clockwise.
        fixed: the vertices that must not move: a boolean mask (one flag per vertex) or an
            array of vertex indices.
        feature_edges: for a mesh on a curved surface, more feature edges to keep (a (k, 2)
            array of vertex pairs, each an edge of the mesh): their vertices only slide along
            them. Sharp edges (dihedral angle above ``feature_angle``) are found anyway.
        effort: "fast" (a few guarded sweeps, no max-min stage), "balanced" or "best".
        boundary: "auto" (the better of slide and snap per vertex), "slide", "snap" or
            "fixed"; on a surface, "fixed" keeps the feature curves' vertices in place.
        method: the interior smoothing: "ep" (embedded polygon), "laplace", "cotan" or "angle".
        feature_angle: degrees; boundary vertices turning by more are corners (never moved), and
            on a surface edges whose faces meet at more are feature edges.
        max_iterations: the sweep cap (default 1000; a preset may stop sooner by itself).
        threads: worker threads (default: one per core); the result is the same on any number.
        progress: a callable called after every sweep with a :class:`Progress`; returning False
            stops the run (:class:`CancelledError`), and an exception it raises stops the run
            and is raised. ``True`` shows a tqdm bar when tqdm is installed.

    Returns:
        An :class:`OptimizeResult`: ``points`` (a new float64 array), ``report`` (a dict, the keys
        of ``quadopt optimize --json``) and ``quality`` (each face's scaled Jacobian).

    Raises:
        MeshError: the mesh cannot be used (an index out of range, a NaN coordinate, a face of
            five vertices, a non-manifold edge, a closed planar mesh, ...); nothing is returned.
        TypeError: an array of the wrong shape or dtype.
        ValueError: an option out of range (``feature_angle`` outside [0, 180], ...).
        KeyboardInterrupt: Ctrl-C stops the run within a sweep.

    The run releases the GIL: other Python threads run meanwhile.

    >>> import numpy as np, quadopt
    >>> points = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1.4, 1.3], [2, 1],
    ...                    [0, 2], [1, 2], [2, 2]])
    >>> faces = [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]]
    >>> r = quadopt.optimize(points, faces, boundary="fixed")
    >>> r.report["moved"], r.report["output"]["inverted"]
    (1, 0)
    >>> bool(r.quality.min() > 0.99)
    True
    """
    bar = _progress(progress)
    try:
        new_points, report, values = _quadopt.optimize(
            _points(points),
            _faces(faces),
            _fixed(fixed),
            _feature_edges(feature_edges),
            _name(effort, "effort"),
            _name(boundary, "boundary"),
            _name(method, "method"),
            float(feature_angle),
            _count(max_iterations, "max_iterations"),
            _count(threads, "threads"),
            bar,
        )
    finally:
        if isinstance(bar, _TqdmBar):
            bar.close()
    return OptimizeResult(new_points, report, values)


def quality(points: Any, faces: Any, *, reference: Any = None) -> QualityResult:
    """The scaled Jacobian of each face, and the summary ``quadopt quality --json`` prints.

    ``points`` and ``faces`` as for :func:`optimize`. A planar mesh gets the signed scaled
    Jacobian (Verdict's definition, signed against the mesh's orientation); a mesh on a curved
    surface gets both measures: the signed one the optimizer ranks by (``values``) and Verdict's
    3D one (``verdict``). The signed one is taken against the mesh's own surface, or with
    ``reference`` (the points of the mesh it was optimized from: the same faces) against that
    mesh's surface, as ``quadopt quality --reference`` does; the summary then has the distances
    from it (``surface_fidelity``), and its statistics are those :func:`optimize` reports.

    >>> import numpy as np, quadopt
    >>> q = quadopt.quality(np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0.5]]),
    ...                     [[0, 1, 2, 3], [1, 4, 2]])
    >>> q.values.round(3)
    array([1.   , 0.924])
    >>> q.summary["quads"], q.summary["triangles"], q.summary["inverted"]
    (1, 1, 0)
    """
    faces = _faces(faces)
    ref = None if reference is None else _points(reference)
    values, summary, verdict = _quadopt.quality(_points(points), faces, ref)
    return QualityResult(values, summary, verdict)


def _physical_nodes(mesh: Any, names: Sequence[str], dims: Sequence[int], option: str) -> Dict[str, np.ndarray]:
    """The nodes of the elements of each gmsh physical group in ``names`` (points and curves,
    of the dimensions ``dims``), as meshio carries them: ``field_data`` maps a name to its tag
    and dimension, ``cell_data["gmsh:physical"]`` gives each element's tag."""
    field_data = getattr(mesh, "field_data", None) or {}
    tags = mesh.cell_data.get("gmsh:physical")
    nodes: Dict[str, np.ndarray] = {}
    for name in names:
        groups = [(int(v[0]), int(v[1])) for n, v in field_data.items() if n == name and int(v[1]) in dims]
        if not groups or tags is None:
            known = sorted(n for n, v in field_data.items() if int(v[1]) in dims)
            has = f"the mesh has: {', '.join(known)}" if known else "the mesh has none"
            raise ValueError(f"{option} {name}: no physical group of that name ({has})")
        found = []
        for block, block_tags in zip(mesh.cells, tags):
            dim = {"vertex": 0, "line": 1}.get(block.type)
            if dim is None:
                continue
            for tag, group_dim in groups:
                if dim == group_dim:
                    found.append(np.asarray(block.data)[np.asarray(block_tags) == tag].ravel())
        nodes[name] = np.unique(np.concatenate(found)) if found else np.zeros(0, dtype=np.int64)
    return nodes


def _edges_within(faces: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """The mesh's edges (each once) with both vertices in ``nodes``."""
    inside = np.zeros(int(faces.max(initial=-1)) + 2, dtype=bool)
    inside[nodes[nodes < len(inside) - 1]] = True
    edges = []
    for f in faces:
        corners = [v for v in f if v >= 0]
        for a, b in zip(corners, corners[1:] + corners[:1]):
            if inside[a] and inside[b]:
                edges.append((min(a, b), max(a, b)))
    return np.array(sorted(set(edges)), dtype=np.int64).reshape(-1, 2)


def optimize_mesh(
    mesh: Any,
    *,
    fix_physical: Sequence[str] = (),
    feature_physical: Sequence[str] = (),
    return_report: bool = False,
    **options: Any,
) -> Any:
    """Optimizes a ``meshio.Mesh``: returns a new mesh, the input left as it was.

    The quad and triangle cells are optimized together (in the order of their cell blocks);
    any other cells (lines, vertices, ...) are kept as they are. The new mesh has the input's
    cells, point data, cell data and field data, the moved points, and the scaled Jacobian of
    each face as cell data ``scaled_jacobian`` (NaN for other cells), as ``quadopt optimize``
    writes it. A point-data array ``fixed`` (nonzero = fixed), as quadopt's files carry it,
    pins its vertices.

    Gmsh physical groups, as meshio reads them from an MSH file (``field_data`` and
    ``cell_data["gmsh:physical"]``), are honoured as the CLI's ``--fix-physical`` and
    ``--feature-physical`` do: ``fix_physical`` names physical points and curves whose nodes
    never move; ``feature_physical`` names physical curves whose edges are feature edges (a mesh
    on a curved surface).

    ``options`` are :func:`optimize`'s (``effort``, ``boundary``, ``method``, ...). With
    ``return_report=True``, returns ``(mesh, report)``.

    >>> import meshio, numpy as np, quadopt
    >>> m = meshio.Mesh(np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1.4, 1.3, 0],
    ...                           [2, 1, 0], [0, 2, 0], [1, 2, 0], [2, 2, 0]], dtype=float),
    ...                 [("quad", np.array([[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]]))])
    >>> out = quadopt.optimize_mesh(m, boundary="fixed")
    >>> bool(out.cell_data["scaled_jacobian"][0].min() > 0.99)
    True
    """
    import meshio

    surface_types = {"quad": 4, "triangle": 3}
    blocks = [b for b in mesh.cells if b.type in surface_types]
    if not blocks:
        raise MeshError("the mesh has no quad or triangle cells")
    faces = np.full((sum(len(b.data) for b in blocks), 4), -1, dtype=np.int64)
    row = 0
    for b in blocks:
        data = np.asarray(b.data)
        faces[row:row + len(data), : data.shape[1]] = data
        row += len(data)
    points = np.asarray(mesh.points)
    n = len(points)
    fixed = np.zeros(n, dtype=bool)
    given = mesh.point_data.get("fixed")
    if given is not None:
        fixed |= np.asarray(given).reshape(n, -1)[:, 0] != 0
    for nodes in _physical_nodes(mesh, list(fix_physical), (0, 1), "fix_physical").values():
        fixed[nodes] = True
    feature_edges = None
    if feature_physical:
        groups = _physical_nodes(mesh, list(feature_physical), (1,), "feature_physical")
        feature_edges = np.concatenate([_edges_within(faces, g) for g in groups.values()])
    result = optimize(
        points,
        faces,
        fixed=fixed if fixed.any() else None,
        feature_edges=feature_edges,
        **options,
    )
    cell_data = {k: [np.copy(v) for v in vs] for k, vs in mesh.cell_data.items()}
    per_block = []
    row = 0
    for b in mesh.cells:
        if b.type in surface_types:
            per_block.append(result.quality[row:row + len(b.data)])
            row += len(b.data)
        else:
            per_block.append(np.full(len(b.data), np.nan))
    cell_data["scaled_jacobian"] = per_block
    out = meshio.Mesh(
        result.points,
        [meshio.CellBlock(b.type, np.copy(b.data)) for b in mesh.cells],
        point_data={k: np.copy(v) for k, v in mesh.point_data.items()},
        cell_data=cell_data,
        field_data={k: np.copy(v) for k, v in (getattr(mesh, "field_data", None) or {}).items()},
    )
    return (out, result.report) if return_report else out

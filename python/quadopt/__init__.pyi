# Type stubs of the quadopt package (the documentation is in __init__.py's docstrings).
from typing import Any, Callable, Dict, Literal, NamedTuple, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

from ._quadopt import CancelledError as CancelledError
from ._quadopt import MeshError as MeshError
from ._quadopt import Progress as Progress

__version__: str

Effort = Literal["fast", "balanced", "best"]
Boundary = Literal["auto", "slide", "snap", "fixed"]
Method = Literal["ep", "embedded-polygon", "laplace", "laplacian", "cotan", "cotangent", "angle", "angle-based"]
#: An (n, 2) or (n, 3) array of real numbers.
Points = npt.ArrayLike
#: An (m, 4) integer array (-1 in the fourth column for a triangle), an (m, 3) one, or a
#: sequence of sequences of 3 or 4 vertex indices.
Faces = Union[npt.ArrayLike, Sequence[Sequence[int]]]
ProgressCallback = Callable[[Progress], Optional[bool]]

class OptimizeResult(NamedTuple):
    points: npt.NDArray[np.float64]
    report: Dict[str, Any]
    quality: npt.NDArray[np.float64]

class QualityResult(NamedTuple):
    values: npt.NDArray[np.float64]
    summary: Dict[str, Any]
    verdict: Optional[npt.NDArray[np.float64]]

def optimize(
    points: Points,
    faces: Faces,
    *,
    fixed: Optional[npt.ArrayLike] = ...,
    feature_edges: Optional[npt.ArrayLike] = ...,
    effort: Effort = ...,
    boundary: Boundary = ...,
    method: Method = ...,
    feature_angle: float = ...,
    max_iterations: Optional[int] = ...,
    threads: Optional[int] = ...,
    progress: Union[None, bool, ProgressCallback] = ...,
) -> OptimizeResult: ...
def quality(points: Points, faces: Faces, *, reference: Optional[Points] = ...) -> QualityResult: ...
@overload
def optimize_mesh(
    mesh: Any,
    *,
    fix_physical: Sequence[str] = ...,
    feature_physical: Sequence[str] = ...,
    return_report: Literal[False] = ...,
    effort: Effort = ...,
    boundary: Boundary = ...,
    method: Method = ...,
    feature_angle: float = ...,
    max_iterations: Optional[int] = ...,
    threads: Optional[int] = ...,
    progress: Union[None, bool, ProgressCallback] = ...,
) -> Any: ...
@overload
def optimize_mesh(
    mesh: Any,
    *,
    fix_physical: Sequence[str] = ...,
    feature_physical: Sequence[str] = ...,
    return_report: Literal[True],
    effort: Effort = ...,
    boundary: Boundary = ...,
    method: Method = ...,
    feature_angle: float = ...,
    max_iterations: Optional[int] = ...,
    threads: Optional[int] = ...,
    progress: Union[None, bool, ProgressCallback] = ...,
) -> Tuple[Any, Dict[str, Any]]: ...

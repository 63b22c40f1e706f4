# Type stubs of the extension module (the Rust half; quadopt/__init__.py wraps it).
from typing import Any, Dict, List, Optional, Tuple

import numpy as np
import numpy.typing as npt

NO_VERTEX: int

class MeshError(ValueError): ...
class CancelledError(Exception): ...

class Progress:
    """The progress of a run, passed to the ``progress`` callable after every sweep."""

    @property
    def iteration(self) -> int: ...
    @property
    def max_iterations(self) -> int: ...
    @property
    def pass_(self) -> int: ...
    @property
    def passes(self) -> int: ...
    @property
    def energy(self) -> float: ...
    @property
    def energy_change(self) -> float: ...

def optimize(
    points: npt.NDArray[Any],
    faces: Any,
    fixed: Optional[npt.NDArray[Any]],
    feature_edges: Optional[npt.NDArray[Any]],
    effort: str,
    boundary: str,
    method: str,
    feature_angle: float,
    max_iterations: Optional[int],
    threads: Optional[int],
    progress: Any,
) -> Tuple[npt.NDArray[np.float64], Dict[str, Any], npt.NDArray[np.float64]]: ...
def quality(
    points: npt.NDArray[Any], faces: Any, reference: Optional[npt.NDArray[Any]] = ...
) -> Tuple[npt.NDArray[np.float64], Dict[str, Any], Optional[npt.NDArray[np.float64]]]: ...
def _time_rust_run(points: npt.NDArray[Any], faces: Any, effort: str, repeat: int) -> List[float]: ...
def _library_version() -> str: ...

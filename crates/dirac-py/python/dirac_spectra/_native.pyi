# Type stubs of the compiled module (crates/dirac-py/src/lib.rs). Users call the wrappers in
# dirac_spectra; these take C-contiguous float64 (n, 3) positions and int64 (m, 3) faces.
from typing import Any, Callable

import numpy as np

# The options object of a solve, read by attribute.
from ._spectrum import _Request

class NativeError(Exception):
    """args = (kind, message, details); translated by dirac_spectra.errors."""

DEFAULT_FLAT_TOLERANCE: float
DEFAULT_MERGE_DISTANCE: float
OPERATORS: list[str]

def read_mesh(path: str) -> tuple[np.ndarray, np.ndarray]: ...
def write_mesh(path: str, vertices: np.ndarray, faces: np.ndarray) -> None: ...

# Both return {"vertices", "faces", "vertex_origin", "face_origin": arrays, "report": JSON text,
# "summary": text}; faces need not be valid (negative indices count as out of range).
def repair(vertices: np.ndarray, faces: np.ndarray, merge_distance: float) -> dict[str, Any]: ...
def read_and_repair(path: str, merge_distance: float) -> dict[str, Any]: ...
def default_mesh() -> tuple[np.ndarray, np.ndarray]: ...
def spectrum(
    vertices: np.ndarray,
    faces: np.ndarray,
    request: _Request,
    eigenvectors: bool,
    progress: Callable[[dict[str, int]], object] | None,
    relative_to: np.ndarray | None = None,
) -> dict[str, Any]: ...
def eigenproblem(
    vertices: np.ndarray,
    faces: np.ndarray,
    request: _Request,
    form: str,
    relative_to: np.ndarray | None = None,
) -> dict[str, Any]: ...
def geodesic_distance(vertices: np.ndarray, faces: np.ndarray, sources: list[int]) -> np.ndarray: ...
def potential_well(vertices: np.ndarray, faces: np.ndarray, well: Any) -> np.ndarray: ...
def laplacian(vertices: np.ndarray, faces: np.ndarray) -> tuple[dict[str, Any], np.ndarray]: ...
def kernel_signature(
    kind: str,
    eigenvalues: np.ndarray,
    eigenvectors: np.ndarray,
    times: np.ndarray | None,
    count: int,
) -> tuple[np.ndarray, np.ndarray]: ...
def wave_kernel_signature(
    eigenvalues: np.ndarray,
    eigenvectors: np.ndarray,
    energies: np.ndarray | None,
    sigma: float | None,
    count: int,
) -> tuple[np.ndarray, np.ndarray, float]: ...
def segmentation_descriptor(
    eigenvalues: np.ndarray, eigenvectors: np.ndarray
) -> tuple[np.ndarray, np.ndarray]: ...

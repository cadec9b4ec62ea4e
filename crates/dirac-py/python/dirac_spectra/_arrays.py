"""Checking and converting the arrays users pass: any real dtype for positions, any integer dtype
for faces, C or Fortran order; the native code receives C-contiguous float64 and int64."""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt


def _shape_error(name: str, expected: str, array: np.ndarray) -> ValueError:
    return ValueError(f"{name} must have shape {expected}, got shape {array.shape}")


def vertices(V: npt.ArrayLike, name: str = "V") -> np.ndarray:
    """``V`` as C-contiguous float64 ``(n, 3)``."""
    array = np.asarray(V)
    if not (np.issubdtype(array.dtype, np.floating) or np.issubdtype(array.dtype, np.integer)):
        raise TypeError(
            f"{name} must hold real numbers (a float dtype such as float64), got dtype {array.dtype}"
        )
    if array.ndim != 2 or array.shape[1] != 3:
        raise _shape_error(name, "(n, 3): one row of x, y, z per vertex", array)
    return np.ascontiguousarray(array, dtype=np.float64)


def faces(F: npt.ArrayLike, name: str = "F") -> np.ndarray:
    """``F`` as C-contiguous int64 ``(m, 3)``."""
    array = np.asarray(F)
    if not np.issubdtype(array.dtype, np.integer):
        hint = ""
        if np.issubdtype(array.dtype, np.floating):
            hint = f"; convert whole numbers with {name}.astype(np.int64)"
        raise TypeError(
            f"{name} must hold vertex indices (an integer dtype such as int64), "
            f"got dtype {array.dtype}{hint}"
        )
    if array.ndim != 2 or array.shape[1] != 3:
        raise _shape_error(name, "(m, 3): three vertex indices per triangle", array)
    if array.dtype == np.uint64 and array.size and array.max() > np.iinfo(np.int64).max:
        face = int(np.argmax(array.max(axis=1) > np.iinfo(np.int64).max))
        raise ValueError(f"{name}[{face}] holds a vertex index beyond the int64 range")
    return np.ascontiguousarray(array, dtype=np.int64)


def eigenvalues(values: npt.ArrayLike) -> np.ndarray:
    """Eigenvalues as C-contiguous float64 ``(k,)``."""
    array = np.asarray(values)
    if not np.issubdtype(array.dtype, np.floating) and not np.issubdtype(array.dtype, np.integer):
        raise TypeError(f"eigenvalues must be real numbers, got dtype {array.dtype}")
    if array.ndim != 1:
        raise _shape_error("eigenvalues", "(k,)", array)
    return np.ascontiguousarray(array, dtype=np.float64)


def eigenvectors(vectors: npt.ArrayLike, k: int) -> np.ndarray:
    """Quaternionic eigenvectors as C-contiguous float64 ``(n, k, 4)``."""
    array = np.asarray(vectors)
    if not np.issubdtype(array.dtype, np.floating):
        raise TypeError(f"eigenvectors must be real (float) arrays, got dtype {array.dtype}")
    if array.ndim != 3 or array.shape[1] != k or array.shape[2] != 4:
        raise _shape_error("eigenvectors", f"(n, {k}, 4): (w, x, y, z) per vertex and mode", array)
    return np.ascontiguousarray(array, dtype=np.float64)


def samples(values: Any, name: str) -> np.ndarray | None:
    """Optional 1-D float64 samples (times or energies)."""
    if values is None:
        return None
    array = np.atleast_1d(np.asarray(values, dtype=np.float64))
    if array.ndim != 1:
        raise _shape_error(name, "(count,)", array)
    return np.ascontiguousarray(array)

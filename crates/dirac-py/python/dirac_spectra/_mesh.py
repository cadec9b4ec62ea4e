"""Mesh files and the built-in mesh."""

from __future__ import annotations

import os

import numpy as np
import numpy.typing as npt

from . import _arrays, _native
from ._repair import read_and_repair
from .errors import translated


def read_mesh(
    path: str | os.PathLike[str], repair: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """``(V, F)`` of a ``.obj``, ``.off``, ``.ply`` or ``.stl`` file (PLY and STL ASCII or binary;
    STL corners with equal coordinates welded): float64 ``(n, 3)`` positions and int64 ``(m, 3)``
    triangles. The mesh is validated: a file that is not a manifold, consistently oriented
    triangle mesh raises ``MeshError`` naming the element.

    With ``repair=True`` the file is repaired instead (:func:`dirac_spectra.repair`, default
    tolerance) and the repaired ``(V, F)`` returned; the report and the maps back to the file's
    numbering are dropped, so use :func:`dirac_spectra.read_and_repair` to keep them."""
    if repair:
        repaired = read_and_repair(path)
        return repaired.vertices, repaired.faces
    return translated()(_native.read_mesh)(os.fspath(path))


def write_mesh(path: str | os.PathLike[str], V: npt.ArrayLike, F: npt.ArrayLike) -> None:
    """Writes ``(V, F)`` as OBJ or binary PLY, by the extension of ``path``."""
    vertices, faces = _arrays.vertices(V), _arrays.faces(F)
    translated()(_native.write_mesh)(os.fspath(path), vertices, faces)


def default_mesh() -> tuple[np.ndarray, np.ndarray]:
    """Keenan Crane's *spot* (2930 vertices, closed, genus 0; public domain), the mesh the
    ``dirac`` command line uses when given none."""
    return _native.default_mesh()

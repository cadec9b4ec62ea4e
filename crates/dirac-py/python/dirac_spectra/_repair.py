"""Repair of meshes as downloaded (``dirac::repair``): merged vertices, degenerate and duplicate
faces dropped, non-manifold edges and vertices split, faces oriented consistently."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from . import _arrays, _native
from .errors import translated

DEFAULT_MERGE_DISTANCE: float = _native.DEFAULT_MERGE_DISTANCE
"""Vertices closer than this times the bounding-box diagonal are merged (``1e-9``)."""


@dataclass(frozen=True)
class Repaired:
    """A repaired mesh and what was done to get it.

    ``vertices`` float64 ``(n, 3)`` and ``faces`` int64 ``(m, 3)`` form a valid mesh (what
    :func:`spectrum` accepts). ``vertex_origin`` int64 ``(n,)`` gives, for each output vertex,
    the input vertex it came from (the smallest of those merged into it), so per-vertex data
    carries over as ``data[vertex_origin]``; ``face_origin`` int64 ``(m,)`` the input face of
    each output face (per-face labels: ``labels[face_origin]``). ``report`` maps each step to
    ``{"count": int, "examples": list}`` (the first five elements affected, input numbering;
    pairs as two-element lists), as ``dirac`` writes it in JSON; ``summary`` is the report as
    text, one line per change (``"nothing to repair"`` when there was none).
    """

    vertices: np.ndarray
    faces: np.ndarray
    vertex_origin: np.ndarray
    face_origin: np.ndarray
    report: dict[str, dict[str, Any]]
    summary: str

    @property
    def changed(self) -> bool:
        """Whether the repair changed anything."""
        return any(step["count"] for step in self.report.values())


def _repaired(raw: dict[str, Any]) -> Repaired:
    return Repaired(
        vertices=raw["vertices"],
        faces=raw["faces"],
        vertex_origin=raw["vertex_origin"],
        face_origin=raw["face_origin"],
        report=json.loads(raw["report"]),
        summary=raw["summary"],
    )


def repair(
    V: npt.ArrayLike, F: npt.ArrayLike, merge_distance: float = DEFAULT_MERGE_DISTANCE
) -> Repaired:
    """Repairs the mesh ``(V, F)``, which need not be valid: faces naming a missing vertex (any
    index ``< 0`` or ``≥ n``) or a non-finite coordinate are dropped; vertices closer than
    ``merge_distance`` times the bounding-box diagonal are merged (``0``: only identical ones);
    faces repeating a vertex, duplicating an earlier face, of zero area or with a degenerate
    angle are dropped; non-manifold edges and vertices are split; each connected component is
    oriented consistently (the orientation of the larger area wins); unused vertices are dropped.
    Repairing a repaired mesh changes nothing. See docs/USER_GUIDE.md, "Repair".

    Raises ``MeshError`` when no face is left, when a component is not orientable (``face``
    names an input face) or when the result is still invalid, and ``OptionsError`` for a
    negative or non-finite ``merge_distance``."""
    vertices, faces = _arrays.vertices(V), _arrays.faces(F)
    raw = translated()(_native.repair)(vertices, faces, float(merge_distance))
    return _repaired(raw)


@translated()
def _read_and_repair(path: str, merge_distance: float) -> dict[str, Any]:
    return _native.read_and_repair(path, merge_distance)


def read_and_repair(
    path: str | os.PathLike[str], merge_distance: float = DEFAULT_MERGE_DISTANCE
) -> Repaired:
    """Reads a ``.obj``, ``.off``, ``.ply`` or ``.stl`` file without validating it and repairs it
    as :func:`repair` does; indices in the report and the origins are those of the file (for STL,
    of its vertices after equal corners are welded)."""
    return _repaired(_read_and_repair(os.fspath(path), float(merge_distance)))

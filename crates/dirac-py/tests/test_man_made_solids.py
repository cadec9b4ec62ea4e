"""Closed man-made solids, the shapes of CAD models: prisms capped by fans of thin triangles or
around a centre, a cube whose faces are flat grids, a cone, a toothed extrusion. Every Dirac
operator's spectrum and kernel are checked against a dense scipy solve of the same pencil whose
kernel is found numerically, knowing nothing of flat vertices, pieces or rulings."""

from __future__ import annotations

import numpy as np
import pytest

import dirac_spectra as ds
from pencils import by_magnitude, dense_reference
from test_linear_kernel import ring_faces


def prism(section: np.ndarray, rings: int, caps: str) -> tuple[np.ndarray, np.ndarray]:
    """The counter-clockwise polygon ``section`` extruded to height 1 through ``rings`` rings,
    closed at both ends by a fan from the first corner (``caps="fan"``: thin triangles, as CAD
    exporters write them), around an added centre vertex (``caps="centre"``), or left open
    (``caps="none"``)."""
    around = len(section)
    V = [[x, y, z] for z in np.linspace(0, 1, rings) for x, y in section]
    F = ring_faces(rings, around).tolist()
    ends = [] if caps == "none" else [(0, False), (rings - 1, True)]
    for ring, upward in ends:
        first = ring * around
        if caps == "fan":
            cap = [[first, first + i, first + i + 1] for i in range(1, around - 1)]
        else:
            V.append([*section.mean(axis=0), ring / (rings - 1)])
            cap = [[first + i, first + (i + 1) % around, len(V) - 1] for i in range(around)]
        F += cap if upward else [t[::-1] for t in cap]
    return np.array(V, dtype=float), np.array(F)


def polygon(radii: list[float]) -> np.ndarray:
    """Corners at equal angles and the given distances from the centre, counter-clockwise."""
    angle = 2 * np.pi * np.arange(len(radii)) / len(radii)
    return np.stack([radii * np.cos(angle), radii * np.sin(angle)], axis=1)


def cut(section: np.ndarray, cuts: int) -> np.ndarray:
    """The polygon ``section`` with each side cut into ``cuts`` equal edges: flat panels with
    columns of vertices between their creases once extruded."""
    following = np.roll(section, -1, axis=0)
    steps = np.arange(cuts)[:, np.newaxis, np.newaxis] / cuts
    return (section + steps * (following - section)).transpose(1, 0, 2).reshape(-1, 2)


def cube(cuts: int) -> tuple[np.ndarray, np.ndarray]:
    """The unit cube, each face a flat grid of ``cuts × cuts`` quads split in two."""
    index: dict[tuple[float, ...], int] = {}
    F = []
    steps = np.linspace(0, 1, cuts + 1)
    for axis in range(3):
        u, w = [a for a in range(3) if a != axis]
        for side in (0.0, 1.0):
            outward = np.zeros(3)
            outward[axis] = 2 * side - 1
            for i in range(cuts):
                for j in range(cuts):
                    quad = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = np.zeros(3)
                        p[axis], p[u], p[w] = side, steps[i + di], steps[j + dj]
                        quad.append(index.setdefault(tuple(p), len(index)))
                    corner = np.array(list(index))[quad]
                    turn = np.cross(corner[1] - corner[0], corner[2] - corner[0]) @ outward
                    a, b, c, d = quad if turn > 0 else quad[::-1]
                    F += [[a, b, c], [a, c, d]]
    return np.array(list(index), dtype=float), np.array(F)


def cone(around: int) -> tuple[np.ndarray, np.ndarray]:
    """A cone of height 1.5 over the unit circle, closed by a disc around its centre."""
    angle = 2 * np.pi * np.arange(around) / around
    V = np.vstack([np.stack([np.cos(angle), np.sin(angle), 0 * angle], 1), [0, 0, 1.5], [0, 0, 0]])
    F = [[i, (i + 1) % around, around] for i in range(around)]
    F += [[(i + 1) % around, i, around + 1] for i in range(around)]
    return V, np.array(F)


SOLIDS = {
    "hexagonal prism, centred caps": prism(polygon([1.0] * 6), 3, "centre"),
    "12-gon prism, fan caps": prism(polygon([1.0] * 12), 2, "fan"),
    "toothed prism, fan caps": prism(polygon([1.0, 1.3] * 6), 3, "fan"),
    "elliptic prism, centred caps": prism(polygon([1.0] * 16) * [2.0, 0.7], 4, "centre"),
    "hexagonal prism of panels cut twice, centred caps": prism(cut(polygon([1.0] * 6), 2), 3, "centre"),
    "cube of 5 × 5 grids": cube(5),
    "cone": cone(16),
}


OPERATORS = [("relative-dirac", None), ("extrinsic-dirac", None), ("squared", None),
             ("family", 0.5), ("laplace", None)]


@pytest.mark.parametrize("operator, tau", OPERATORS)
@pytest.mark.parametrize("name", list(SOLIDS))
def test_the_spectra_of_man_made_solids_match_scipy(name, operator, tau):
    V, F = SOLIDS[name]
    k = 8
    got = ds.spectrum(V, F, k=k, operator=operator, tau=tau, eigenvectors=False)
    dimension, reference = dense_reference(V, F, operator, tau)
    assert got.kernel_dimension == dimension, name
    listed = np.count_nonzero(got.eigenvalues == 0)  # the kernel, where listed by default
    np.testing.assert_allclose(
        by_magnitude(np.repeat(got.eigenvalues[listed:], 4)),
        by_magnitude(reference)[: 4 * (k - listed)],
        rtol=1e-9,
        err_msg=name,
    )

"""Man-made shapes built here with numpy, independently of the package: extrusions of polygons
(prisms, open tubes of flat panels), cubes of flat grids, cones, a ribbon."""

from __future__ import annotations

import numpy as np


def ring_faces(rings: int, around: int) -> np.ndarray:
    """Two triangles per quad between consecutive rings of ``around`` vertices each, closed
    around, counter-clockwise seen from outside for rings ordered by increasing angle."""
    F = []
    for j in range(rings - 1):
        for i in range(around):
            a, b = j * around + i, j * around + (i + 1) % around
            F += [[a, b, b + around], [a, b + around, a + around]]
    return np.array(F)


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
    return voxels([(0, 0, 0)], cuts)


def cone(around: int) -> tuple[np.ndarray, np.ndarray]:
    """A cone of height 1.5 over the unit circle, closed by a disc around its centre."""
    angle = 2 * np.pi * np.arange(around) / around
    V = np.vstack([np.stack([np.cos(angle), np.sin(angle), 0 * angle], 1), [0, 0, 1.5], [0, 0, 0]])
    F = [[i, (i + 1) % around, around] for i in range(around)]
    F += [[(i + 1) % around, i, around + 1] for i in range(around)]
    return V, np.array(F)


def revolve(profile: list[tuple[float, float]], around: int, bottom: str) -> tuple[np.ndarray, np.ndarray]:
    """The surface of revolution of the polyline ``profile`` of ``(radius, height)`` points
    about the z axis, ``around`` vertices per ring: a band of two triangles per quad between
    consecutive rings (a cone frustum or a cylinder, creased where the profile turns), open at
    the top and closed at the bottom around a centre (``bottom="centre"``) or left open
    (``"none"``); counter-clockwise seen from outside for a profile of increasing height."""
    angle = 2 * np.pi * np.arange(around) / around
    V = [[r * np.cos(t), r * np.sin(t), z] for r, z in profile for t in angle]
    F = ring_faces(len(profile), around).tolist()
    if bottom == "centre":
        V.append([0.0, 0.0, profile[0][1]])
        F += [[(i + 1) % around, i, len(V) - 1] for i in range(around)]
    return np.array(V, dtype=float), np.array(F)


def rounded_square(segments: int, half_side: float = 1.0, radius: float = 0.3) -> np.ndarray:
    """A counter-clockwise square section whose corners are quarter circles of ``segments``
    edges each: flat sides tangent to cylindrical fillets once extruded, as CAD rounds edges."""
    points = []
    for corner, (cx, cy) in enumerate([(1, 1), (-1, 1), (-1, -1), (1, -1)]):
        centre = np.array([cx, cy]) * (half_side - radius)
        for step in range(segments + 1):
            t = np.pi / 2 * (corner + step / segments)
            points.append(centre + radius * np.array([np.cos(t), np.sin(t)]))
    return np.array(points)


def voxels(cells: list[tuple[int, int, int]], cuts: int) -> tuple[np.ndarray, np.ndarray]:
    """The boundary of a union of unit cubes (integer corners ``cells``), each exposed face a
    flat grid of ``cuts × cuts`` quads split in two: an L-bracket, a frame with a hole, stairs.
    Cells meeting only along an edge or at a corner would make it non-manifold."""
    filled = set(cells)
    # Corners by their coordinates rounded (sums of cells and steps), each kept as first met.
    index: dict[tuple[float, ...], int] = {}
    V = []
    F = []
    steps = np.linspace(0, 1, cuts + 1)
    for cell in cells:
        for axis in range(3):
            u, w = [a for a in range(3) if a != axis]
            for side in (0, 1):
                neighbour = list(cell)
                neighbour[axis] += 2 * side - 1
                if tuple(neighbour) in filled:
                    continue
                outward = np.zeros(3)
                outward[axis] = 2 * side - 1
                for i in range(cuts):
                    for j in range(cuts):
                        quad, corner = [], []
                        for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                            p = np.array(cell, dtype=float)
                            p[axis] += side
                            p[u] += steps[i + di]
                            p[w] += steps[j + dj]
                            key = tuple(np.round(p, 12))
                            if key not in index:
                                index[key] = len(V)
                                V.append(p)
                            quad.append(index[key])
                            corner.append(p)
                        turn = np.cross(corner[1] - corner[0], corner[2] - corner[0]) @ outward
                        a, b, c, d = quad if turn > 0 else quad[::-1]
                        F += [[a, b, c], [a, c, d]]
    return np.array(V, dtype=float), np.array(F)


def ribbon(segments: int) -> tuple[np.ndarray, np.ndarray]:
    """A ribbon one quad wide along a wavy curve, rising and falling: ``segments`` quads split
    in two, so ``2 (segments + 1)`` vertices carry only ``2 segments`` rows of ``D_N``."""
    t = np.linspace(0, 1, segments + 1)
    near = np.stack([4 * t, np.sin(3 * t), np.zeros_like(t)], axis=1)
    far = np.stack([4 * t, np.sin(3 * t) + 0.1, 0.5 + 0.2 * np.cos(5 * t)], axis=1)
    i = np.arange(segments)
    F = np.concatenate([np.stack([i, i + 1, segments + 1 + i], axis=1),
                        np.stack([i + 1, segments + 2 + i, segments + 1 + i], axis=1)])
    return np.vstack([near, far]), F

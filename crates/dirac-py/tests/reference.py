"""Meshes and operators built with numpy and scipy alone, independently of the package: the
references of the tests, and of `benches/python/eigs_vs_scipy.py`."""

from __future__ import annotations

import numpy as np
import scipy.sparse


def icosphere(subdivisions: int) -> tuple[np.ndarray, np.ndarray]:
    """A unit icosphere: the icosahedron, each triangle split in four ``subdivisions`` times."""
    t = (1.0 + 5.0**0.5) / 2.0
    V = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
         [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    F = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
         [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
         [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    V = [np.array(v, dtype=float) / np.linalg.norm(v) for v in V]
    for _ in range(subdivisions):
        midpoint: dict[tuple[int, int], int] = {}

        def middle(a: int, b: int) -> int:
            key = (min(a, b), max(a, b))
            if key not in midpoint:
                m = V[a] + V[b]
                V.append(m / np.linalg.norm(m))
                midpoint[key] = len(V) - 1
            return midpoint[key]

        refined = []
        for a, b, c in F:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            refined += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        F = refined
    return np.array(V), np.array(F, dtype=np.int64)


def cotangent_laplacian(V: np.ndarray, F: np.ndarray) -> tuple[scipy.sparse.csc_array, np.ndarray]:
    """L_ij = −(cot α_ij + cot β_ij)/2, L_ii = −Σ_j L_ij, and barycentric masses (area/3)."""
    n = len(V)
    rows, cols, vals = [], [], []
    mass = np.zeros(n)
    for corner in range(3):
        i, j, k = F[:, corner], F[:, (corner + 1) % 3], F[:, (corner + 2) % 3]
        u, w = V[j] - V[i], V[k] - V[i]
        cross = np.linalg.norm(np.cross(u, w), axis=1)
        cot = np.einsum("ij,ij->i", u, w) / cross  # the angle at i, opposite edge jk
        rows += [j, k]
        cols += [k, j]
        vals += [-cot / 2, -cot / 2]
        mass += np.bincount(i, weights=cross / 6, minlength=n)
    off = scipy.sparse.csc_array(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    )
    return (off - scipy.sparse.diags_array(np.asarray(off.sum(axis=1)).ravel())).tocsc(), mass

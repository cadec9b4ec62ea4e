"""Meshes built here with numpy, independently of the package, and the paths of the repository."""

from __future__ import annotations

import os
import pathlib

import numpy as np
import pytest

REPOSITORY = pathlib.Path(__file__).resolve().parents[3]


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


def torus(around: int, tube: int, R: float = 1.0, r: float = 0.4) -> tuple[np.ndarray, np.ndarray]:
    """A torus of ``around × tube`` quads, each split in two counter-clockwise triangles."""
    u = 2 * np.pi * np.arange(around) / around
    v = 2 * np.pi * np.arange(tube) / tube
    U, W = np.meshgrid(u, v, indexing="ij")
    V = np.stack([(R + r * np.cos(W)) * np.cos(U), (R + r * np.cos(W)) * np.sin(U),
                  r * np.sin(W)], axis=-1).reshape(-1, 3)
    index = lambda i, j: (i % around) * tube + (j % tube)  # noqa: E731
    F = []
    for i in range(around):
        for j in range(tube):
            a, b, c, d = index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)
            F += [[a, b, c], [a, c, d]]
    return V, np.array(F, dtype=np.int64)


def grid(nx: int, ny: int) -> tuple[np.ndarray, np.ndarray]:
    """A flat unit square of ``nx × ny`` quads in the plane z = 0."""
    x, y = np.meshgrid(np.linspace(0, 1, nx + 1), np.linspace(0, 1, ny + 1), indexing="ij")
    V = np.stack([x, y, np.zeros_like(x)], axis=-1).reshape(-1, 3)
    F = []
    for i in range(nx):
        for j in range(ny):
            a, b = i * (ny + 1) + j, (i + 1) * (ny + 1) + j
            F += [[a, b, b + 1], [a, b + 1, a + 1]]
    return V, np.array(F, dtype=np.int64)


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A uniformly random rotation matrix (QR of a Gaussian matrix, determinant +1)."""
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q @ np.diag(np.sign(np.diag(r)))
    return q if np.linalg.det(q) > 0 else -q


def quaternion_product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton products of (…, 4) arrays (w, x, y, z)."""
    aw, ax, ay, az = np.moveaxis(a, -1, 0)
    bw, bx, by, bz = np.moveaxis(b, -1, 0)
    return np.stack([aw * bw - ax * bx - ay * by - az * bz,
                     aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw], axis=-1)


def conjugate(q: np.ndarray) -> np.ndarray:
    return q * np.array([1.0, -1.0, -1.0, -1.0])


@pytest.fixture(scope="session")
def sphere() -> tuple[np.ndarray, np.ndarray]:
    return icosphere(3)  # 642 vertices


@pytest.fixture(scope="session")
def bumpy_sphere() -> tuple[np.ndarray, np.ndarray]:
    """The icosphere of 642 vertices with radial noise of 2%: no symmetry, so no eigenvalue
    is degenerate beyond the quaternionic multiplicity (which ARPACK may otherwise miss)."""
    V, F = icosphere(3)
    rng = np.random.default_rng(11)
    return V * (1 + 0.02 * rng.uniform(-1, 1, (len(V), 1))), F


@pytest.fixture(scope="session")
def small_torus() -> tuple[np.ndarray, np.ndarray]:
    return torus(24, 12)


@pytest.fixture(scope="session")
def dirac_binary() -> pathlib.Path:
    """The `dirac` command line: $DIRAC_BIN (set by `cargo xtask test`) or target/release."""
    path = pathlib.Path(os.environ.get("DIRAC_BIN", REPOSITORY / "target" / "release" / "dirac"))
    if not path.is_file():
        pytest.skip(f"no dirac binary at {path}: build it with cargo build --release -p dirac-cli")
    return path

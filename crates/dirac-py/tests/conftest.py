"""Meshes built here with numpy, independently of the package, and the paths of the repository."""

from __future__ import annotations

import os
import pathlib

import numpy as np
import pytest
from reference import icosphere

REPOSITORY = pathlib.Path(__file__).resolve().parents[3]


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

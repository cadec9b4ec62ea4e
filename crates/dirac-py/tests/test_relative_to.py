"""``spectrum(..., relative_to=V2)``: the relative Dirac operator ``D_{f1,f2}`` of two surfaces
with the same faces, checked against identities it must satisfy (``f2 = f1`` is the extrinsic
Dirac operator; scaling ``f2`` by ``c`` scales every eigenvalue by ``c``; a rotated and moved
``f2`` has the same spectrum), against scipy's dense solve of its matrices, and its typed
errors."""

from __future__ import annotations

import numpy as np
import pytest

import dirac_spectra as ds
from conftest import grid, torus
from pencils import by_magnitude, dense_reference
from solids import ribbon


def rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """The rotation matrix about ``axis`` by ``angle`` (Rodrigues)."""
    a = axis / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def test_relative_to_itself_is_the_extrinsic_dirac_operator():
    V, F = torus(24, 10)
    got = ds.spectrum(V, F, k=8, relative_to=V).eigenvalues
    want = ds.spectrum(V, F, k=8, operator="extrinsic-dirac").eigenvalues
    np.testing.assert_allclose(got, want, rtol=1e-9)


def test_scaling_and_moving_the_second_surface():
    V, F = torus(24, 10)
    W = V * (1 + 0.2 * np.sin(3 * V[:, [0]]))
    base = ds.spectrum(V, F, k=8, relative_to=W).eigenvalues
    scaled = ds.spectrum(V, F, k=8, relative_to=2.5 * W).eigenvalues
    np.testing.assert_allclose(scaled, 2.5 * base, rtol=1e-8)
    moved = W @ rotation(np.array([1.0, 2.0, -0.5]), 0.7).T + np.array([3.0, -1.0, 2.0])
    np.testing.assert_allclose(
        ds.spectrum(V, F, k=8, relative_to=moved).eigenvalues, base, rtol=1e-8
    )
    plain = ds.spectrum(V, F, k=8).eigenvalues
    assert abs(plain[0] - base[0]) > 1e-3 * abs(base[0])


@pytest.mark.parametrize("operator", ["relative-dirac", "squared"])
@pytest.mark.parametrize("surface", ["torus", "ribbon"])
def test_the_relative_spectrum_matches_scipy_on_its_matrices(surface, operator):
    # `operator_matrices(..., relative_to=W)` gives the pencil `spectrum(..., relative_to=W)`
    # solves; the ribbon's rows are freed from end to end for `D_{f,W}` too (its second kernel
    # dimension was missed: relative Dirac stopped as singular, squared listed 2e-16).
    V, F = torus(16, 8) if surface == "torus" else ribbon(30)
    W = V * (1 + 0.2 * np.sin(3 * V[:, [0]])) + 0.1 * np.cos(2 * V[:, [1, 2, 0]])
    got = ds.spectrum(V, F, k=8, operator=operator, relative_to=W, eigenvectors=False)
    dimension, reference = dense_reference(V, F, operator, relative_to=W)
    assert got.kernel_dimension == dimension
    ours = by_magnitude(np.repeat(got.eigenvalues, 4))
    np.testing.assert_allclose(np.abs(ours), np.abs(by_magnitude(reference)[: len(ours)]), rtol=1e-9)
    with pytest.raises(ds.OptionsError, match="Gauss map"):
        ds.operator_matrices(V, F, "laplace", relative_to=W)


def test_errors_are_typed():
    V, F = torus(24, 10)
    with pytest.raises(ds.OptionsError, match="Gauss map"):
        ds.spectrum(V, F, k=4, operator="laplace", relative_to=V)
    # A reference short of a vertex is named as such, not as a face of an invalid mesh.
    with pytest.raises(ds.MeshError, match="same triangulation") as error:
        ds.spectrum(V, F, k=4, relative_to=V[:-1])
    assert "240 and 239 vertices" in str(error.value)
    assert "repair" not in str(error.value)


def test_a_planar_reference_adds_a_linear_function_to_the_kernel():
    # Relative to its own flattening W, D_{f,W} annihilates the linear functions u·W of the
    # plane besides the constants: the kernel has one more dimension, removed like the
    # constant, and the spectrum keeps the identities of the relative operator (scaling W by c
    # scales every eigenvalue by c; moving W rigidly out of its plane changes none).
    W, F = grid(6, 5)
    V = W.copy()
    V[:, 2] = 0.3 * np.sin(3 * W[:, 0]) * np.cos(2 * W[:, 1])
    base = ds.spectrum(V, F, k=6, relative_to=W)
    assert (base.kernel_dimension, base.kernel_linear_functions) == (2, 1)
    scaled = ds.spectrum(V, F, k=6, relative_to=1.7 * W).eigenvalues
    np.testing.assert_allclose(scaled, 1.7 * base.eigenvalues, rtol=1e-8)
    moved = W @ rotation(np.array([1.0, -2.0, 0.5]), 0.9).T + np.array([0.5, 1.0, -2.0])
    np.testing.assert_allclose(
        ds.spectrum(V, F, k=6, relative_to=moved).eigenvalues, base.eigenvalues, rtol=1e-8
    )

"""Pieces on which every face is parallel to one direction ``u`` (a plane, an open prism): the
extrinsic Dirac operator ``D_f`` annihilates the linear function ``u f`` there besides the
constants. The package removes it like the constants; its spectrum is checked against a dense
scipy solve of the same pencil whose kernel is found numerically, knowing nothing of pieces,
directions or linear functions."""

from __future__ import annotations

import numpy as np
import pytest

import dirac_spectra as ds
from conftest import grid
from pencils import by_magnitude, dense_reference
from solids import cut, polygon, prism, ring_faces


def tube(segments: int, rings: int, flare: float) -> tuple[np.ndarray, np.ndarray]:
    """An open tube around the z axis of radius ``1 + flare z²``: a prism for ``flare = 0``."""
    angle = 2 * np.pi * np.arange(segments) / segments
    V = np.array(
        [
            [(1 + flare * z * z) * np.cos(a), (1 + flare * z * z) * np.sin(a), z]
            for z in 0.5 * np.arange(rings)
            for a in angle
        ]
    )
    return V, ring_faces(rings, segments)


def warped_grid() -> tuple[np.ndarray, np.ndarray]:
    """The grid moved within its plane, irregularly."""
    V, F = grid(6, 5)
    V = V + np.stack([0.3 * V[:, 1] ** 2, 0.1 * V[:, 0] * V[:, 1], 0 * V[:, 0]], axis=1)
    return V, F


@pytest.mark.parametrize(
    "name, mesh, kernel",
    [
        ("plane", grid(6, 5), 2),
        ("warped plane", warped_grid(), 2),
        ("open prism", tube(6, 5, 0.0), 2),
        ("flared tube", tube(6, 5, 0.3), 1),
    ],
)
def test_the_extrinsic_dirac_spectrum_matches_scipy(name, mesh, kernel):
    V, F = mesh
    k = 8
    got = ds.spectrum(V, F, k=k, operator="extrinsic-dirac")
    dimension, reference = dense_reference(V, F, "extrinsic-dirac")
    assert dimension == kernel == got.kernel_dimension, name
    assert got.kernel_linear_functions == kernel - 1
    np.testing.assert_allclose(
        by_magnitude(np.repeat(got.eigenvalues, 4)),
        by_magnitude(reference)[: 4 * k],
        rtol=1e-9,
        err_msg=name,
    )


def test_the_relative_dirac_spectrum_of_a_tube_of_flat_panels_matches_scipy():
    """Along each crease the triangles of vertex normals have two equal corners, whose rows of
    ``D_N`` ask only equal values there: the kernel is a constant and a linear function per
    crease (12 on a hexagon), not one constant, and the spectrum matches scipy's."""
    V, F = prism(cut(polygon([1.0] * 6), 3), 5, "none")
    k = 12  # the ±λ of a hexagon come 12 at once
    got = ds.spectrum(V, F, k=k, operator="relative-dirac")
    dimension, reference = dense_reference(V, F, "relative-dirac")
    assert dimension == got.kernel_dimension == 12
    assert got.kernel_linear_functions == 6
    np.testing.assert_allclose(
        by_magnitude(np.repeat(got.eigenvalues, 4)),
        by_magnitude(reference)[: 4 * k],
        rtol=1e-9,
    )


def test_rulings_tied_at_single_vertices_carry_a_basis_of_the_kernel():
    """Cut twice, each panel has one column of vertices between its creases, tied to the rest
    only where the crease normals turn at the boundary: the kernel is larger than a constant
    and a linear function (scipy finds 6). The package removes a basis of it (6 functions of
    rulings) and its spectrum matches scipy's."""
    V, F = prism(cut(polygon([1.0] * 6), 2), 5, "none")
    k = 12
    got = ds.spectrum(V, F, k=k, operator="relative-dirac")
    dimension, reference = dense_reference(V, F, "relative-dirac")
    assert dimension == got.kernel_dimension == got.kernel_ruling_functions == 6
    np.testing.assert_allclose(
        by_magnitude(np.repeat(got.eigenvalues, 4)),
        by_magnitude(reference)[: 4 * k],
        rtol=1e-9,
    )

"""Closed man-made solids, the shapes of CAD models: prisms capped by fans of thin triangles or
around a centre, a cube whose faces are flat grids, a cone, a toothed extrusion. Every
operator's spectrum and kernel are checked against a dense scipy solve of the same pencil whose
kernel is found numerically, knowing nothing of flat vertices, pieces or rulings."""

from __future__ import annotations

import numpy as np
import pytest

import dirac_spectra as ds
from pencils import OPERATORS, by_magnitude, dense_reference
from solids import cone, cube, cut, polygon, prism

SOLIDS = {
    "hexagonal prism, centred caps": prism(polygon([1.0] * 6), 3, "centre"),
    "12-gon prism, fan caps": prism(polygon([1.0] * 12), 2, "fan"),
    "toothed prism, fan caps": prism(polygon([1.0, 1.3] * 6), 3, "fan"),
    "elliptic prism, centred caps": prism(polygon([1.0] * 16) * [2.0, 0.7], 4, "centre"),
    "hexagonal prism of panels cut twice, centred caps": prism(cut(polygon([1.0] * 6), 2), 3, "centre"),
    "cube of 5 × 5 grids": cube(5),
    "cone": cone(16),
}


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

"""Man-made solids, the shapes of CAD models: prisms capped by fans of thin triangles or
around a centre, a cube whose faces are flat grids, a cone, a toothed extrusion, a vase of
conical and cylindrical bands, unions of cubes (an L-bracket, stairs, a frame with a hole),
a rounded square extruded (flat sides tangent to cylindrical fillets), an open cut of a
cylinder with a jagged boundary, a ribbon one quad wide. Every operator's spectrum and kernel
are checked against a dense scipy solve of the same pencil whose kernel is found numerically,
knowing nothing of flat vertices, pieces, rulings or freed rows."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import dirac_spectra as ds
from pencils import OPERATORS, by_magnitude, dense_reference
from solids import cone, cube, cut, polygon, prism, revolve, ribbon, rounded_square, voxels

# An open surface cut from a CAD cylinder (manifold3d), committed with the Rust tests.
JAGGED_CUT = Path(__file__).parents[2] / "dirac/tests/data/jagged_cylinder_cut.obj"

VASE = [(0.5, 0.0), (1.0, 0.3), (1.0, 0.8), (0.6, 1.0), (0.7, 1.3)]

SOLIDS = {
    "hexagonal prism, centred caps": prism(polygon([1.0] * 6), 3, "centre"),
    "12-gon prism, fan caps": prism(polygon([1.0] * 12), 2, "fan"),
    "toothed prism, fan caps": prism(polygon([1.0, 1.3] * 6), 3, "fan"),
    "elliptic prism, centred caps": prism(polygon([1.0] * 16) * [2.0, 0.7], 4, "centre"),
    "hexagonal prism of panels cut twice, centred caps": prism(cut(polygon([1.0] * 6), 2), 3, "centre"),
    # Open: every panel's modes are constrained, and the constraints of neighbouring panels
    # share entries, one chained group over the whole tube.
    "16-gon open tube of panels cut three times": prism(cut(polygon([1.0] * 16), 3), 3, "none"),
    "cube of 5 × 5 grids": cube(5),
    "cone": cone(16),
    "vase of conical and cylindrical bands, centred bottom": revolve(VASE, 16, "centre"),
    "open vase": revolve(VASE, 12, "none"),
    "L-bracket of cubes, faces 2 × 2 grids": voxels([(0, 0, 0), (1, 0, 0), (0, 1, 0)], 2),
    "stairs of cubes": voxels([(x, 0, z) for x in range(3) for z in range(x + 1)], 1),
    "square frame of cubes (a hole)": voxels(
        [(x, y, 0) for x in range(3) for y in range(3) if (x, y) != (1, 1)], 1
    ),
    "rounded square prism, centred caps": prism(rounded_square(3), 3, "centre"),
    "rounded square prism, fan caps": prism(rounded_square(2), 2, "fan"),
    # Rows freed by a corner in no other row: corners in single boundary faces of a jagged
    # cut, and a ribbon freed from one end to the other.
    "jagged cut of a cylinder": ds.read_mesh(str(JAGGED_CUT)),
    "wavy ribbon": ribbon(30),
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
    ours = by_magnitude(np.repeat(got.eigenvalues[listed:], 4))
    theirs = by_magnitude(reference)[: 4 * (k - listed)]
    np.testing.assert_allclose(np.abs(ours), np.abs(theirs), rtol=1e-9, err_msg=name)
    # Signs below the last magnitude: at it, a multiple ±a (one per panel of the open tube)
    # has more copies than the window holds, and which of them it takes is arbitrary.
    below = np.abs(theirs) < (1 - 1e-6) * np.abs(theirs[-1])
    np.testing.assert_allclose(ours[below], theirs[below], rtol=1e-9, err_msg=name)


def test_a_sliver_where_the_operator_is_singular_is_named_and_repaired():
    # Fan caps over sides cut in two: the fan triangles over a side's three collinear corners
    # are slivers (valid: nonzero area), where the factorisation fails.
    V, F = prism(cut(polygon([1.0] * 256), 2), 3, "fan")
    with pytest.raises(ds.SingularError, match="there is a sliver") as caught:
        ds.spectrum(V, F, k=10, eigenvectors=False)
    face, vertex = caught.value.face, caught.value.vertex
    assert vertex in F[face]
    a, b, c = V[F[face]]
    assert np.linalg.norm(np.cross(b - a, c - a)) < 1e-12 * max(
        np.linalg.norm(b - a), np.linalg.norm(c - b), np.linalg.norm(a - c)
    ) ** 2
    repaired = ds.repair(V, F)
    assert len(repaired.faces) < len(F)
    assert len(ds.spectrum(repaired.vertices, repaired.faces, k=10).eigenvalues) == 10


def test_the_smallest_pairs_of_a_finely_faceted_cylinder_match_scipy():
    # An open pipe of 448 flat sides, one triangle pair each: the smallest pairs of its
    # relative Dirac operator (±8.742e-5, each eigenvalue twice) are ill-conditioned, and the
    # Lanczos vectors short of the tolerance until refined. Converged (this host), or else the
    # error gives the tolerance that accepts them; either way they are scipy's.
    V, F = prism(polygon([1.0] * 448), 2, "none")
    try:
        got = ds.spectrum(V, F, k=10, eigenvectors=False)
    except ds.NotConvergedError as error:
        assert error.accepting_tolerance is not None, str(error)
        assert f"tolerance={error.accepting_tolerance:.0e}" in str(error)
        got = ds.spectrum(V, F, k=10, eigenvectors=False, tolerance=error.accepting_tolerance)
    dimension, reference = dense_reference(V, F, "relative-dirac")
    assert got.kernel_dimension == dimension
    ours = by_magnitude(np.repeat(got.eigenvalues, 4))
    theirs = by_magnitude(reference)[:40]
    # LAPACK's four copies of one quaternionic eigenvalue differ by up to 1e-8 relative here.
    np.testing.assert_allclose(np.abs(ours), np.abs(theirs), rtol=1e-7)
    assert np.abs(ours[0]) < 1e-4


def test_slivers_are_warned_of():
    # Fan caps over sides cut in two: the first and last fan triangle of each cap lie over a
    # side's three collinear corners (height ~1e-17), valid faces whose cotangent weights
    # dominate the operator. The spectrum is computed, with a warning naming them.
    V, F = prism(cut(polygon([1.0] * 256), 2), 2, "fan")
    a, b, c = (V[F[:, i]] for i in range(3))
    longest = np.max([np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1),
                      np.linalg.norm(a - c, axis=1)], axis=0)
    heights = np.linalg.norm(np.cross(b - a, c - a), axis=1) / longest
    thin = np.flatnonzero(heights <= 1e-9 * np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    with pytest.warns(ds.SliverWarning) as record:
        ds.spectrum(V, F, k=4, operator="laplace", eigenvectors=False)
    message = str(record[0].message)
    assert f"{len(thin)} sliver faces (face {thin[0]} first)" in message, message
    assert "dirac_spectra.repair(V, F)" in message
    assert int(re.search(r"face (\d+) first", message).group(1)) in thin
    # Centred caps have none: no warning.
    V, F = prism(cut(polygon([1.0] * 256), 2), 2, "centre")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ds.spectrum(V, F, k=4, operator="laplace", eigenvectors=False)


def test_every_backend_counts_the_pairs_near_the_kernel_once():
    """An open tube of a rounded square: the squared operator's two smallest eigenvalues,
    `6.0e-10`, lie far below the next (`7.8e-5`), and the embedded backends compute their
    copies (four real or two complex ones each) up to `1e-6` apart, beyond the fold's cluster
    width. Each backend lists them once each, as the dense reference does."""
    V, F = prism(rounded_square(8), 4, "none")
    # At the default threshold (1e-10 of the largest eigenvalue of P) the reference would take
    # the eigenvalues 6.0e-10 for kernel.
    _, reference = dense_reference(V, F, "squared", None, threshold=1e-12)
    theirs = np.sort(np.abs(reference))[::4][:4]
    for backend in ("native", "real-block", "complex-adjoint"):
        got = ds.spectrum(V, F, k=4, operator="squared", backend=backend, eigenvectors=False)
        # The reference resolves the smallest only to about 1e-4 relative.
        np.testing.assert_allclose(np.sort(np.abs(got.eigenvalues)), theirs, rtol=1e-3,
                                   err_msg=backend)


def test_a_tube_with_nearly_ruled_fillets_names_the_family_as_the_remedy():
    """An open tube of a rounded square, fillets of 32 edges, two rings: the area-weighted
    vertex normals of a fillet's top and bottom rings differ (the triangulation is not
    symmetric), so its columns of vertices are no rulings and their functions are not in the
    exact kernel, but `P` annihilates two functions constant along the columns to rounding
    (four quaternionic eigenvalues below `1e-14` of its largest where the exact kernel has two). Relative Dirac cannot resolve the pencil there:
    the error says so, offers no tolerance, and names the family, whose spectrum matches the
    dense reference."""
    V, F = prism(rounded_square(32), 2, "none")
    P, _, _ = ds.operator_matrices(V, F, "relative-dirac")
    values = np.linalg.eigvalsh(P.toarray())
    assert np.count_nonzero(values <= 1e-14 * values.max()) == 4 * 4
    with pytest.raises(ds.NotConvergedError) as raised:
        ds.spectrum(V, F, k=20, eigenvectors=False)
    assert raised.value.accepting_tolerance is None
    assert 'operator="family", tau=T' in str(raised.value)
    got = ds.spectrum(V, F, k=8, operator="family", tau=0.5, eigenvectors=False)
    dimension, reference = dense_reference(V, F, "family", 0.5)
    assert got.kernel_dimension == dimension
    listed = np.count_nonzero(got.eigenvalues == 0)
    ours = by_magnitude(np.repeat(got.eigenvalues[listed:], 4))
    np.testing.assert_allclose(ours, by_magnitude(reference)[: len(ours)], rtol=1e-9)


@pytest.mark.parametrize("offset", [0.0, 80.0])
@pytest.mark.parametrize(
    "half_sides, rtol", [((23.0, 23.0, 23.0), 1e-6), ((23.0, 2.0, 0.75), 1e-4)], ids=["cube", "thin bar"]
)
def test_a_rotated_box_stored_in_single_precision_matches_scipy_on_the_exact_box(half_sides, rtol, offset):
    # As an STL or binary PLY file stores a CAD model: away from the origin, every coordinate
    # a 32-bit float. The rounding puts noise of about 2⁻²⁴ |x| / h into the normals, which
    # before made faces that are flat count as curved and the constants of the Dirac pencils
    # count as coupled. On the thin bar (cells of 9.2 × 0.3) the noise at the vertices of the
    # thin sides is up to 15 times the flat tolerance's own term, more than the test of single
    # faces forgives: its panels are found flat as noisy planes (docs/MATH.md). The reference
    # is scipy's dense solve of the box in double precision (kernel found numerically): the
    # rounded positions' own matrices hold the noise, in couplings of the kernel of order 10⁻⁷
    # that the rounding makes and the solver treats as zero.
    V, F = cube(5)
    c, s = np.cos(0.7), np.sin(0.7)
    rotation = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    exact = (V * half_sides) @ rotation.T + offset
    rounded = exact.astype(np.float32)
    for operator in ("relative-dirac", "squared"):
        dimension, reference = dense_reference(exact, F, operator, None, 1e-11)
        got = ds.spectrum(rounded, F, k=8, operator=operator, eigenvectors=False)
        assert got.kernel_dimension == dimension == 25
        theirs = by_magnitude(reference)[::4][: len(got.eigenvalues)]
        np.testing.assert_allclose(np.abs(got.eigenvalues), np.abs(theirs), rtol=rtol)
        # Accepted as accurate as the data: exact for a change of the matrices no larger than
        # what the rounding of the positions makes.
        assert 1e3 * np.finfo(float).eps < got.backward_error_floor < 1e-4
        assert np.all(got.backward_errors <= got.backward_error_floor)


def test_a_small_mesh_the_family_cannot_resolve_is_told_to_normalise():
    """A ribbon of area 2e-8 (a fraction of a millimetre, in metres): the family at tau = 0.5
    weighs D_N there as tau = 1 - 2e-8 does at unit area, and its smallest pairs are beyond
    double precision. The message says to normalise, in Python's spelling; normalised, the
    spectrum is the ribbon's at its own scale."""
    V, F = ribbon(12)
    with pytest.raises(ds.NotConvergedError) as error:
        ds.spectrum(V * 1e-4, F, k=8, operator="family", tau=0.5, eigenvectors=False)
    message = str(error.value)
    assert 'normalize="unit-area"' in message and "smaller tau" in message, message
    assert "--" not in message and 'operator="family", tau=T (0 < T < 1)' not in message, message
    ours = ds.spectrum(V * 1e-4, F, k=8, operator="family", tau=0.5, normalize="unit-area")
    theirs = ds.spectrum(V, F, k=8, operator="family", tau=0.5, normalize="unit-area")
    np.testing.assert_allclose(ours.eigenvalues, theirs.eigenvalues, rtol=1e-8, atol=1e-12)

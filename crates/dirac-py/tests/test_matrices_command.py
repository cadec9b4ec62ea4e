"""`dirac matrices` (the command line) against the package's `operator_matrices`, read back
with scipy's own Matrix Market reader, and its Laplace pencil against `dirac spectrum`."""

import json
import subprocess

import numpy as np
import pytest
import scipy.io
import scipy.linalg
import scipy.sparse as sp

import dirac_spectra as ds
from conftest import torus


def write_matrices(dirac_binary, tmp_path, V, F, *options, form="real"):
    """Runs `dirac matrices` on the mesh `(V, F)`; returns `(P, Q, mass)` as scipy reads them."""
    mesh = tmp_path / "mesh.obj"
    ds.write_mesh(mesh, V, F)
    out = tmp_path / "pencil.mtx"
    subprocess.run(
        [str(dirac_binary), "matrices", str(mesh), *options, "--form", form, "--out", str(out)],
        capture_output=True, text=True, check=True,
    )
    read = lambda part: scipy.io.mmread(tmp_path / f"pencil.{part}.mtx")
    return sp.csc_array(read("stiffness")), sp.csc_array(read("coupling")), read("mass")


def assert_same_lower_triangle(written, assembled):
    """The file holds the lower triangle bit for bit, and the upper one is its conjugate
    transpose, which is the assembled upper triangle to rounding."""
    assert written.shape == assembled.shape
    difference = sp.tril(written) - sp.tril(assembled)
    assert difference.count_nonzero() == 0
    scale = abs(assembled).max()
    assert abs(written - assembled).max() <= 1e-14 * scale


CASES = {
    "relative-dirac": ([], {}),
    "laplace, unit area": (
        ["--operator", "laplace", "--normalize", "unit-area"],
        dict(operator="laplace", normalize="unit-area"),
    ),
    "family": (["--operator", "family:0.5"], dict(operator="family", tau=0.5)),
    "squared in a well": (
        ["--operator", "squared", "--well-radius", "0.5", "--well-center", "7"],
        dict(operator="squared", well=ds.PotentialWell(radius=0.5, center=7)),
    ),
}


@pytest.mark.parametrize("form", ["real", "complex"])
@pytest.mark.parametrize("case", CASES)
def test_the_written_matrices_are_those_of_the_package(dirac_binary, tmp_path, case, form):
    options, keywords = CASES[case]
    V, F = torus(12, 8)
    P, Q, mass = write_matrices(dirac_binary, tmp_path, V, F, *options, form=form)
    P_package, Q_package, mass_package = ds.operator_matrices(V, F, form=form, **keywords)
    assert_same_lower_triangle(P, P_package)
    assert_same_lower_triangle(Q, Q_package)
    np.testing.assert_array_equal(mass.ravel(), mass_package)


def test_relative_to_writes_the_matrices_of_the_relative_operator(dirac_binary, tmp_path):
    V, F = torus(12, 8)
    W = V * np.array([1.0, 1.0, 1.5])
    reference = tmp_path / "reference.obj"
    ds.write_mesh(reference, W, F)
    P, Q, _ = write_matrices(dirac_binary, tmp_path, V, F, "--relative-to", str(reference))
    P_package, Q_package, _ = ds.operator_matrices(V, F, form="real", relative_to=W)
    assert_same_lower_triangle(P, P_package)
    assert_same_lower_triangle(Q, Q_package)


def test_the_written_laplace_pencil_has_the_spectrum_dirac_computes(dirac_binary, tmp_path):
    """A dense solve of the files' real pencil lists each of `dirac spectrum`'s eigenvalues four
    times."""
    V, F = torus(10, 6)
    P, Q, _ = write_matrices(dirac_binary, tmp_path, V, F, "--operator", "laplace")
    values = scipy.linalg.eigh(P.toarray(), Q.toarray(), eigvals_only=True)
    mesh = tmp_path / "mesh.obj"
    run = subprocess.run(
        [str(dirac_binary), "spectrum", str(mesh), "--operator", "laplace", "-k", "8", "--json", "-q"],
        capture_output=True, text=True, check=True,
    )
    listed = np.array(json.loads(run.stdout)["eigenvalues"])
    np.testing.assert_allclose(values[: 4 * len(listed)], np.repeat(listed, 4), atol=1e-10, rtol=1e-9)


def test_an_output_that_is_not_mtx_is_a_usage_error(dirac_binary, tmp_path):
    run = subprocess.run(
        [str(dirac_binary), "matrices", "--out", str(tmp_path / "pencil.npy")],
        capture_output=True, text=True,
    )
    assert run.returncode == 2
    assert "expected a .mtx file name" in run.stderr
    assert not list(tmp_path.iterdir())

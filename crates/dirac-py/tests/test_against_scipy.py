"""`spectrum` against other solvers on the same pencil: scipy's ARPACK (`eigsh`) and LAPACK, on
the matrices of `operator_matrices`, and the Laplacian against one assembled here."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

import dirac_spectra as ds
from conftest import conjugate, quaternion_product
from reference import cotangent_laplacian, icosphere


def test_the_laplacian_is_the_cotangent_laplacian_with_barycentric_masses(sphere):
    V, F = sphere
    L, M = ds.laplacian(V, F)
    expected_L, expected_mass = cotangent_laplacian(V, F)
    assert abs(L - expected_L).max() < 1e-12 * abs(expected_L).max()
    np.testing.assert_allclose(M.diagonal(), expected_mass, rtol=1e-13)
    # Positive semidefinite with constants in the kernel (robust-laplacian's convention).
    assert np.abs(L @ np.ones(len(V))).max() < 1e-12
    assert L.diagonal().min() > 0


def test_laplace_eigenvalues_equal_eigsh_on_the_laplacian(bumpy_sphere):
    V, F = bumpy_sphere
    L, M = ds.laplacian(V, F)
    v0 = np.random.default_rng(0).normal(size=len(V))
    expected = scipy.sparse.linalg.eigsh(L, k=12, M=M, sigma=-1e-2, which="LM", v0=v0)[0]
    result = ds.spectrum(V, F, k=12, operator="laplace")
    assert result.eigenvalues[0] == 0.0  # the constants, listed exactly
    np.testing.assert_allclose(result.eigenvalues[1:], np.sort(expected)[1:], rtol=1e-9)


def test_laplace_on_a_mesh_in_many_pieces_is_the_union_of_the_pieces_spectra():
    """Twenty separate spheres, each with its own noise and size: one constant per piece in the
    kernel, constrained away piece by piece; the nonzero eigenvalues are those of the pieces
    (LAPACK on each piece's dense pencil), merged."""
    rng = np.random.default_rng(5)
    V0, F0 = icosphere(2)
    pieces = [
        (V0 * (1 + 0.1 * c) * (1 + 0.03 * rng.uniform(-1, 1, (len(V0), 1))), F0) for c in range(20)
    ]
    V = np.vstack([v + [3.0 * c, 0, 0] for c, (v, _) in enumerate(pieces)])
    F = np.vstack([f + c * len(V0) for c, (_, f) in enumerate(pieces)])
    expected = []
    for v, f in pieces:
        L, M = ds.laplacian(v, f)
        expected.extend(scipy.linalg.eigh(L.toarray(), M.toarray(), eigvals_only=True)[1:])
    expected = np.sort(expected)
    result = ds.spectrum(V, F, k=20 + 15, operator="laplace")
    assert result.kernel_dimension == 20
    np.testing.assert_array_equal(result.eigenvalues[:20], 0.0)
    np.testing.assert_allclose(result.eigenvalues[20:], expected[:15], rtol=1e-9)


def pinned_reciprocal_eigenvalues(P, Q, k: int) -> np.ndarray:
    """The k smallest |λ| of P x = λ Q x with P ⪰ 0 whose kernel is the constants, Q 𝟙 = 0
    (closed surfaces): with one vertex pinned P is definite and the λ ≠ 0 are those of the
    reduced pencil; ARPACK finds the largest |μ| of Q x = μ P x."""
    keep = np.arange(4, P.shape[0])  # vertex 0 pinned: its four real components
    P_r = P[keep][:, keep].tocsc()
    Q_r = Q[keep][:, keep].tocsc()
    factor = scipy.sparse.linalg.splu(P_r)
    P_inverse = scipy.sparse.linalg.LinearOperator(P_r.shape, matvec=factor.solve)
    v0 = np.random.default_rng(0).normal(size=P_r.shape[0])
    mu = scipy.sparse.linalg.eigsh(
        Q_r, k=4 * k, M=P_r, Minv=P_inverse, which="LM", tol=1e-13, v0=v0
    )[0]
    values = 1.0 / mu
    values = values[np.argsort(np.abs(values), kind="stable")]
    return values[::4]  # every quaternionic eigenvalue is four real ones


def test_relative_dirac_eigenvalues_equal_eigsh_on_the_real_block_pencil(bumpy_sphere):
    V, F = bumpy_sphere
    P, Q, _ = ds.operator_matrices(V, F, operator="relative-dirac", form="real")
    assert P.shape == Q.shape == (4 * len(V), 4 * len(V))
    assert abs(P - P.T).max() < 1e-12 * abs(P).max() and abs(Q - Q.T).max() < 1e-12 * abs(Q).max()
    result = ds.spectrum(V, F, k=8)
    expected = pinned_reciprocal_eigenvalues(P, Q, 8)
    np.testing.assert_allclose(np.sort(result.eigenvalues), np.sort(expected), rtol=1e-8)


def test_family_eigenvalues_equal_a_dense_solve_of_the_pencil():
    V, F = icosphere(2)  # 162 vertices: a dense 648 × 648 pencil
    tau = 0.5
    P, Q, mass = ds.operator_matrices(V, F, operator="family", tau=tau)
    P, Q = P.toarray(), Q.toarray()
    # P's kernel is the constants and Q 𝟙 = (1 − τ) M 𝟙 (G 𝟙 = 0 on a closed surface): the
    # eigenvectors with λ ≠ 0 are M-orthogonal to the constants, so adding c (M𝟙)(M𝟙)ᵀ per
    # component makes P definite without changing them, and moves the constants to μ ≈ 0.
    constants = np.kron(mass[:, None], np.eye(4))  # (4n, 4): M 𝟙 for each component
    P_definite = P + 1e3 * np.abs(P).max() * constants @ constants.T / mass.sum()
    mu = scipy.linalg.eigh(Q, P_definite, eigvals_only=True)
    lam = 1.0 / mu[np.abs(mu) > 1e-6 * np.abs(mu).max()]
    lam = lam[np.argsort(np.abs(lam), kind="stable")][::4]
    result = ds.spectrum(V, F, k=9, operator="family", tau=tau)
    assert result.eigenvalues[0] == 0.0 and result.kernel_dimension == 1
    np.testing.assert_allclose(np.sort(result.eigenvalues[1:]), np.sort(lam[:8]), rtol=1e-8)


@pytest.mark.parametrize("tau", [0.5, 0.6])
def test_literal_family_eigenvalues_equal_eigsh_on_spot(tau):
    """The literal family ``(1−τ)L + τG`` against ``M`` on a real mesh, where its matrix spans
    four orders of magnitude more than the wanted eigenvalues (at τ = 0.6 it is indefinite,
    with negative eigenvalues down to −42). ARPACK in shift-invert mode with SuperLU's LU,
    which needs no definiteness, about σ = 0.75: about zero the constants' eigenvalue 0 would
    dominate and cost the others their accuracy. Its window must reach past every eigenvalue
    of smallest |λ| compared, and its pairs must satisfy the pencil (relative residuals in the
    mass-weighted norms)."""
    V, F = ds.default_mesh()
    P, Q, mass = ds.operator_matrices(V, F, operator="family-literal", tau=tau, form="real")
    P, Q = P.tocsc(), Q.tocsc()
    weights = 1.0 / np.repeat(mass, 4)
    sigma = 0.75
    v0 = np.random.default_rng(0).normal(size=P.shape[0])
    values, vectors = scipy.sparse.linalg.eigsh(
        P, k=4 * 16, M=Q, sigma=sigma, which="LM", tol=1e-13, v0=v0
    )
    order = np.argsort(np.abs(values), kind="stable")[: 4 * 9]
    assert np.abs(values[order]).max() + sigma < np.abs(values - sigma).max()
    for i in order[4:]:  # past the constants' zero (four real copies)
        x = vectors[:, i]
        residual = P @ x - values[i] * (Q @ x)
        scale = abs(values[i]) * np.sqrt(weights @ (Q @ x) ** 2)
        assert np.sqrt(weights @ residual**2) <= 1e-9 * scale, values[i]
    expected = values[order][::4]
    result = ds.spectrum(V, F, k=9, operator="family-literal", tau=tau)
    assert result.eigenvalues[0] == 0.0  # the constants, listed exactly
    np.testing.assert_allclose(
        np.sort(result.eigenvalues), np.sort(expected), rtol=1e-9, atol=1e-12
    )


@pytest.mark.parametrize(
    "operator, tau", [("relative-dirac", None), ("laplace", None), ("family", 0.3)]
)
def test_eigenvectors_satisfy_the_pencil_and_are_mass_orthonormal(sphere, operator, tau):
    V, F = sphere
    result = ds.spectrum(V, F, k=10, operator=operator, tau=tau)
    P, Q, mass = ds.operator_matrices(V, F, operator=operator, tau=tau, form="real")
    np.testing.assert_allclose(mass, result.mass, rtol=1e-14)
    for i, lam in enumerate(result.eigenvalues):
        x = result.eigenvectors[:, i, :].ravel()
        residual = np.linalg.norm(P @ x - lam * (Q @ x))
        if lam == 0.0:  # a kernel vector: P x = 0 to rounding
            assert residual <= 1e-12 * scipy.sparse.linalg.norm(P, 1) * np.linalg.norm(x), i
        else:
            assert residual <= 1e-6 * abs(lam) * np.linalg.norm(Q @ x), (i, lam)
    # Σ_p m_p conj(φ_i(p)) φ_j(p) = δ_ij as quaternions.
    phi = result.eigenvectors
    gram = np.einsum(
        "p,pijc->ijc",
        mass,
        quaternion_product(conjugate(phi[:, :, None, :]), phi[:, None, :, :]),
    )
    expected = np.zeros_like(gram)
    expected[..., 0] = np.eye(result.k)
    np.testing.assert_allclose(gram, expected, atol=1e-9)


def test_the_complex_form_is_the_complex_adjoint_of_the_real_form(bumpy_sphere):
    V, F = bumpy_sphere
    P_real, _, _ = ds.operator_matrices(V, F, form="real")
    P_complex, _, _ = ds.operator_matrices(V, F, form="complex")
    assert P_complex.shape == (2 * len(V), 2 * len(V))
    assert abs(P_complex - P_complex.conj().T).max() < 1e-12 * abs(P_complex).max()
    # The same spectrum: the smallest eigenvalues of the two Hermitian matrices agree (each
    # real-block eigenvalue twice as often as the complex one).
    rng = np.random.default_rng(0)
    real = scipy.sparse.linalg.eigsh(P_real, k=16, sigma=-1e-3, v0=rng.normal(size=P_real.shape[0]))
    v0 = rng.normal(size=P_complex.shape[0]) + 1j * rng.normal(size=P_complex.shape[0])
    complex_ = scipy.sparse.linalg.eigsh(P_complex, k=8, sigma=-1e-3, v0=v0)
    real, complex_ = np.sort(real[0]), np.sort(complex_[0])
    np.testing.assert_allclose(real[::2], complex_, rtol=1e-8, atol=1e-10 * abs(real).max())


def test_anisotropic_laplace_eigenvalues_equal_eigsh_and_its_isotropic_end_is_the_laplacian(
    small_torus,
):
    V, F = small_torus
    # No anisotropy: the real block of the stiffness is L ⊗ I₄ with the L assembled here.
    P, Q, mass = ds.operator_matrices(V, F, operator="anisotropic-laplace", anisotropy=0.0)
    L, expected_mass = cotangent_laplacian(V, F)
    np.testing.assert_allclose(mass, expected_mass, rtol=1e-12)
    assert abs(P[::4, ::4] - L).max() < 1e-12 * abs(L).max()
    # α = 2: the k smallest of the real pencil K x = λ M x by ARPACK (shift-invert at a
    # negative shift: K is only semidefinite), each real eigenvalue four times.
    P, Q, _ = ds.operator_matrices(V, F, operator="anisotropic-laplace", anisotropy=2.0)
    K, M = P[::4, ::4].tocsc(), Q[::4, ::4].tocsc()
    assert abs(K - K.T).max() == 0.0
    v0 = np.random.default_rng(0).normal(size=K.shape[0])
    expected = np.sort(scipy.sparse.linalg.eigsh(K, k=8, M=M, sigma=-1e-3, v0=v0, tol=1e-13)[0])
    result = ds.spectrum(V, F, k=8, operator="anisotropic-laplace", anisotropy=2.0)
    assert result.anisotropy == 2.0 and result.kernel_dimension == 1
    np.testing.assert_allclose(np.sort(result.eigenvalues), expected, rtol=1e-8, atol=1e-10)


def _quaternion_block_norm(X: scipy.sparse.sparray, mass: np.ndarray) -> float:
    """``max_p Σ_q |X_pq| / √(mass[p] mass[q])`` of a real-block matrix: each ``4 × 4`` block
    is a quaternion times an orthogonal matrix, so ``|X_pq|`` is its Frobenius norm over 2."""
    coo = scipy.sparse.coo_array(X)
    n = len(mass)
    squares = scipy.sparse.coo_array(
        (coo.data**2, (coo.row // 4, coo.col // 4)), shape=(n, n)
    ).tocsr()
    squares.sum_duplicates()
    blocks = squares.tocoo()
    moduli = np.sqrt(blocks.data) / 2.0 / np.sqrt(mass[blocks.row] * mass[blocks.col])
    return float(np.bincount(blocks.row, weights=moduli, minlength=n).max())


@pytest.mark.parametrize("operator", ["relative-dirac", "laplace"])
def test_backward_errors_are_the_normwise_backward_errors_of_the_pencil(bumpy_sphere, operator):
    V, F = bumpy_sphere
    result = ds.spectrum(V, F, k=12, operator=operator)
    P, Q, mass = ds.operator_matrices(V, F, operator=operator, form="real")
    norm_p, norm_q = _quaternion_block_norm(P, mass), _quaternion_block_norm(Q, mass)
    expected = []
    for i, lam in enumerate(result.eigenvalues):
        x = result.eigenvectors[:, i, :].ravel()
        r = (P @ x - lam * (Q @ x)).reshape(-1, 4)
        dual = np.sqrt(np.sum(np.sum(r**2, axis=1) / mass))
        x_norm = np.sqrt(np.sum(mass * np.sum(result.eigenvectors[:, i, :] ** 2, axis=1)))
        expected.append(dual / ((norm_p + abs(lam) * norm_q) * x_norm))
    # The residual vector is above rounding level (a relative 1e-10 or so), so numpy's and the
    # package's agree to a few digits; below rounding level both are at the floor.
    np.testing.assert_allclose(result.backward_errors, expected, rtol=0.05, atol=1e-14)
    # The convergence rule of docs/MATH.md holds for every returned pair.
    assert result.backward_error_floor == 1e3 * np.finfo(float).eps
    passed = (result.residuals <= 100 * 1e-10) | (result.backward_errors <= result.backward_error_floor)
    assert passed.all(), (result.residuals, result.backward_errors)

"""Dense references of the package's own pencils, solved with scipy knowing nothing of the
package's kernels: what its eigensolver and its exact kernels must reproduce."""

from __future__ import annotations

import numpy as np
import scipy.linalg

import dirac_spectra as ds


# Every operator, with the weight τ of the family where it needs one.
OPERATORS = [("relative-dirac", None), ("extrinsic-dirac", None), ("squared", None),
             ("family", 0.5), ("laplace", None)]


def dense_reference(
    V: np.ndarray,
    F: np.ndarray,
    operator: str,
    tau: float | None = None,
    threshold: float = 1e-10,
    relative_to: np.ndarray | None = None,
) -> tuple[int, np.ndarray]:
    """``(dim ker P, the nonzero λ of P x = λ Q x)`` for ``operator`` in the real ``4n × 4n``
    form, each quaternionic eigenvalue 4 times (and the real operators' as ``L ⊗ I₄``); the
    dimension is quaternionic.

    The kernel ``K`` of ``P`` is where its eigenvalues are at most ``threshold`` times the
    largest. Where ``Q`` is definite (a mass matrix) the pencil is solved as it is. Otherwise
    every eigenvector with ``λ ≠ 0`` satisfies ``(Q K)ᵀ x = 0`` (from ``Kᵀ P x = 0``) and is
    ``y + K c`` with ``y`` in the complement of ``span(K, Q K)`` where ``Kᵀ Q K = 0`` (the Dirac
    pencils), or is ``y`` in the complement of ``Q K`` where ``Kᵀ Q K`` is definite (the
    family with ``τ < 1``, whose constants are eigenvectors of ``λ = 0``); ``P`` is definite
    there, so ``λ = 1/μ`` of the compressed pencil ``Zᵀ Q Z = μ Zᵀ P Z``. With ``relative_to``,
    the pencil of ``D_{f1,f2}`` relative to that surface."""
    P, Q, _ = ds.operator_matrices(V, F, operator, tau=tau, relative_to=relative_to)
    P, Q = P.toarray(), Q.toarray()
    w, U = np.linalg.eigh(P)
    K = U[:, w <= threshold * w.max()]
    if np.linalg.eigvalsh(Q).min() > 0:
        values = scipy.linalg.eigh(P, Q, eigvals_only=True)
        return K.shape[1] // 4, values[K.shape[1] :]
    QK = Q @ K
    scale = np.abs(Q).max()
    span = QK if np.abs(K.T @ QK).max() > 1e-10 * scale else np.hstack([K, QK])
    u, s, _ = np.linalg.svd(span, full_matrices=True)
    Z = u[:, (s > 1e-10 * s.max()).sum() :]
    mu = scipy.linalg.eigh(Z.T @ Q @ Z, Z.T @ P @ Z, eigvals_only=True)
    return K.shape[1] // 4, 1 / mu[np.abs(mu) > 1e-12 * np.abs(mu).max()]


def by_magnitude(values: np.ndarray) -> np.ndarray:
    """Sorted by |λ| (to 8 digits, so that ±λ stay together), then by λ."""
    return values[np.lexsort((values, np.round(np.abs(values), 8)))]

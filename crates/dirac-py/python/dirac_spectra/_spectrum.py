"""Spectra, eigenproblems and the Laplacian."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any, Callable, Literal, NamedTuple

import numpy as np
import numpy.typing as npt
import scipy.sparse

from . import _arrays, _native
from .errors import OptionsError, ScaleWarning, SliverWarning, _python_spelling, translated

#: The operator names ``spectrum`` and ``operator_matrices`` accept.
OPERATORS: tuple[str, ...] = tuple(_native.OPERATORS)

#: A face is flat when its Gauss map varies by less than this relative to its edges.
DEFAULT_FLAT_TOLERANCE: float = _native.DEFAULT_FLAT_TOLERANCE


@dataclass(frozen=True)
class PotentialWell:
    """The infinite potential well of the paper's §5.1: ``U(d) = height · σ(steepness (d − radius))``
    with ``d`` the geodesic distance (heat method) from ``center`` (default: the vertex nearest
    the area-weighted centroid) and ``σ`` the logistic function. The defaults are the paper's
    (steepness 100, height 10¹⁰), which assume a mesh of unit scale: use ``normalize="unit-area"``.
    """

    radius: float
    center: int | None = None
    steepness: float = 100.0
    height: float = 1e10


@dataclass(frozen=True)
class Spectrum:
    """The ``k`` eigenpairs of smallest ``|λ|`` of an operator on a mesh.

    Attributes:
        eigenvalues: ``(k,)`` signed, sorted by ``|λ|``, then by ``λ`` among magnitudes equal
            to within ``max(100 tol, 1e-8)`` relative (``−a`` before ``a``), each as often as its
            quaternionic multiplicity.
        eigenvectors: ``(n, k, 4)``: ``eigenvectors[p, i]`` is ``(w, x, y, z)`` of ``φ_i`` at vertex
            ``p``; mass-orthonormal (``Σ_p mass[p] conj(φ_i(p)) φ_j(p) = δ_ij``) in canonical
            phase. ``None`` when computed with ``eigenvectors=False``.
        residuals: ``(k,)`` relative residual ``‖Pφ − λQφ‖ / (|λ| ‖Qφ‖)`` of each pair in the
            operator's own eigenproblem (dual norm ``‖r‖² = Σ_p |r_p|² / mass[p]``).
        backward_errors: ``(k,)`` normwise backward error ``‖Pφ − λQφ‖ / ((‖P‖ + |λ| ‖Q‖) ‖φ‖_M)``
            of each pair, with ``‖X‖ = max_p Σ_q |X_pq| / √(mass[p] mass[q])``: the smallest
            relative change of ``P`` and ``Q`` for which the pair is exact. A pair is converged
            when its residual is at most 100 × the tolerance or its backward error at most
            ``backward_error_floor`` (as accurate as double precision, or the data, allows: an
            ill-conditioned eigenvalue can have a large relative residual and still be at that
            floor).
        backward_error_floor: ``1000 ε``, or for positions stored in single precision (every
            coordinate exactly a 32-bit float) the relative change of ``P`` and ``Q`` that their
            rounding alone makes, if larger: the matrices are known no better.
        converged: ``(k,)`` whether each pair passed the convergence test (always true: pairs that
            do not are not returned; see ``NotConvergedError``).
        kernel_dimension: quaternionic dimension of the exactly known kernel (eigenvalue 0).
        kernel_flat_vertices: vertices all of whose faces are flat (one kernel dimension each).
        kernel_constants: connected pieces whose constant function is in the kernel.
        kernel_linear_functions: pieces on which a linear function ``u f2`` of the second surface
            is in the kernel too (every triangle of ``f2`` parallel to one direction ``u``: a
            planar piece or an open prism for ``"extrinsic-dirac"``).
        kernel_ruling_functions: kernel vectors of the pieces whose rulings (vertices joined by
            coinciding corners of the triangles of the second surface, as along a crease from
            boundary to boundary) carry more than a constant and a linear function: a basis of
            the kernel on each, in their place.
        mass: ``(n,)`` barycentric vertex areas of the mesh as solved (after normalisation).
        scale: factor applied to the positions (1 without normalisation).
        statistics: eigensolver counts and times in seconds.
        operator: the operator's name; ``tau`` its weight (family only); ``anisotropy`` its
            ``α`` (anisotropic Laplacian only).
    """

    eigenvalues: np.ndarray
    eigenvectors: np.ndarray | None
    residuals: np.ndarray
    backward_errors: np.ndarray
    converged: np.ndarray
    kernel_dimension: int
    kernel_flat_vertices: int
    kernel_constants: int
    kernel_linear_functions: int
    kernel_ruling_functions: int
    mass: np.ndarray
    scale: float
    statistics: dict[str, float] = field(default_factory=dict)
    operator: str = "relative-dirac"
    tau: float | None = None
    anisotropy: float | None = None
    backward_error_floor: float = 1000 * float(np.finfo(float).eps)

    @property
    def k(self) -> int:
        """Number of eigenpairs."""
        return len(self.eigenvalues)

    @property
    def vertex_count(self) -> int:
        """Number of vertices."""
        return len(self.mass)


@dataclass(frozen=True)
class _Request:
    """What the native code reads (by attribute) for a solve."""

    operator: str
    tau: float | None
    anisotropy: float | None
    k: int
    normalize: str | None
    well: PotentialWell | None
    backend: str
    tolerance: float
    seed: int
    max_restarts: int
    include_kernel: bool | None
    flat_tolerance: float
    threads: int
    time_limit: float | None = None


def _well(well: PotentialWell | float | None) -> PotentialWell | None:
    if well is None or isinstance(well, PotentialWell):
        return well
    if isinstance(well, (int, float)):
        return PotentialWell(radius=float(well))
    raise TypeError(f"well must be a PotentialWell, a radius or None, got {type(well).__name__}")


def _threads(threads: int | None) -> int:
    if threads is None:
        return 1
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)):
        raise TypeError(f"threads must be an integer or None, got {type(threads).__name__}")
    return int(threads)


def _time_limit(seconds: Any) -> float | None:
    if seconds is None:
        return None
    if isinstance(seconds, bool) or not isinstance(seconds, (int, float, np.integer, np.floating)):
        raise TypeError(f"time_limit must be a number of seconds or None, got {type(seconds).__name__}")
    if not (np.isfinite(seconds) and seconds > 0):
        raise OptionsError(f"time_limit = {seconds} must be a finite number of seconds above 0")
    return float(seconds)


def _count(value: Any, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}")
    if value < 0:
        raise OptionsError(f"{name} = {value} must be at least 0")
    return int(value)


def _spectrum(raw: dict, request: _Request) -> Spectrum:
    return Spectrum(
        eigenvalues=raw["eigenvalues"],
        eigenvectors=raw["eigenvectors"],
        residuals=raw["residuals"],
        backward_errors=raw["backward_errors"],
        backward_error_floor=raw["backward_error_floor"],
        converged=np.ones(len(raw["eigenvalues"]), dtype=bool),
        kernel_dimension=raw["kernel_dimension"],
        kernel_flat_vertices=raw["kernel_flat_vertices"],
        kernel_constants=raw["kernel_constants"],
        kernel_linear_functions=raw["kernel_linear_functions"],
        kernel_ruling_functions=raw["kernel_ruling_functions"],
        mass=raw["mass"],
        scale=raw["scale"],
        statistics=raw["statistics"],
        operator=request.operator,
        tau=request.tau,
        anisotropy=request.anisotropy,
    )


def spectrum(
    V: npt.ArrayLike,
    F: npt.ArrayLike,
    k: int = 10,
    operator: str = "relative-dirac",
    tau: float | None = None,
    normalize: Literal["unit-area", "none"] | None = None,
    well: PotentialWell | float | None = None,
    backend: Literal["native", "real-block", "complex-adjoint"] = "native",
    tolerance: float = 1e-10,
    seed: int = 0,
    include_kernel: bool | None = None,
    eigenvectors: bool = True,
    threads: int | None = None,
    *,
    anisotropy: float | None = None,
    flat_tolerance: float = DEFAULT_FLAT_TOLERANCE,
    max_restarts: int = 1000,
    progress: Callable[[dict[str, int]], object] | None = None,
    relative_to: npt.ArrayLike | None = None,
    time_limit: float | None = None,
) -> Spectrum:
    """The ``k`` eigenpairs of smallest ``|λ|`` of ``operator`` on the mesh ``(V, F)``.

    Args:
        V: ``(n, 3)`` vertex positions, any real dtype.
        F: ``(m, 3)`` counter-clockwise triangles, any integer dtype, indices from 0.
        k: number of eigenpairs.
        operator: one of :data:`OPERATORS`: ``"relative-dirac"`` (``D_N``), ``"extrinsic-dirac"``
            (``D_f``), ``"laplace"``, ``"family"`` (``L(τ)``, needs ``tau``), ``"family-literal"``,
            ``"squared"`` (``D_N* D_N``), ``"modified-dirichlet"``, ``"anisotropic-laplace"``
            (Andreux et al. 2014, needs ``anisotropy``). ``"family-literal"`` is solved from
            the bottom of its spectrum: where it is strongly indefinite (``tau`` from about 0.7
            on curved meshes) it raises ``SolverError``; ``"relative-dirac"`` and ``"squared"``
            raise ``KernelError`` where the kernel may be larger than what the solver removes
            (rulings tied together at single vertices by rigid parts of more than 1,024
            parameters, or a reference some of whose triangles are segments of three distinct
            points).
        tau: weight of ``D_N`` in the family, in ``[0, 1]`` (0: Laplace, 1: relative Dirac).
        anisotropy: ``α ≥ 0`` of the anisotropic Laplacian: conductivity ``1/(1 + α|κ|)`` along
            each principal curvature direction (0: Laplace).
        normalize: ``"unit-area"`` scales the mesh to total area 1 first.
        well: a :class:`PotentialWell` (or its radius) restricting the operator to a region.
        backend: the eigensolver's arithmetic: native quaternions (real arithmetic for the real
            operators ``laplace``, ``anisotropic-laplace`` and ``modified-dirichlet``), or the
            ``4n × 4n`` real block or ``2n × 2n`` complex adjoint with faer's Cholesky
            (baselines).
        tolerance: relative residual the eigensolver aims for.
        seed: seed of the eigensolver's start vectors.
        include_kernel: list the exact kernel's eigenvalue 0 among the ``k``; ``None``: the
            operator's default (yes for Laplace, modified Dirichlet, the literal family and
            the family with ``tau < 1``; no for the Dirac operators and the squared one).
        eigenvectors: return the eigenvectors (they are always computed).
        threads: 1 (``None``, so that pools of worker processes do not oversubscribe the
            cores) or 2 (the most the solver uses).
        flat_tolerance: faces whose Gauss map is flat within this (relative to the edges) are
            flat: their row of ``D_N`` is exactly zero.
        max_restarts: restarts of the eigensolver before it reports non-convergence.
        progress: called after every restart of the eigensolver, and between restarts at
            least every 0.1 s, with a dict (``round``, ``restarts``, ``operator_applications``,
            ``locked``, ``wanted``: pairs converged and wanted in the current round), for a
            progress bar; an exception it raises stops the solve and propagates. Ctrl-C stops
            a solve within about 0.1 s either way (``KeyboardInterrupt``).
        relative_to: ``(n, 3)`` positions of a second surface with the same faces ``F``: the
            operators built on ``D_N`` (``"relative-dirac"``, ``"squared"``, the family) use the
            relative Dirac operator ``D_{f1,f2}`` of ``V`` and ``relative_to`` instead (paper
            Fig. 3); ``relative_to = V`` gives the spectrum of ``"extrinsic-dirac"``.
            ``OptionsError`` for the other operators.
        time_limit: seconds after which the eigensolver stops, within about 0.1 s (assembly and
            factorisation are not interrupted): ``NotConvergedError`` with the pairs that
            converged in ``partial`` and ``stopped_at_time_limit`` true. For data sets where
            a few pathological meshes should not hold up the rest.

    Raises:
        MeshError, OptionsError, KernelError, SingularError, SolverError,
        NotConvergedError (with the converged pairs in ``partial``): see
        :mod:`dirac_spectra.errors`.
    """
    request = _Request(
        operator=operator,
        tau=None if tau is None else float(tau),
        anisotropy=None if anisotropy is None else float(anisotropy),
        k=_count(k, "k"),
        normalize=normalize,
        well=_well(well),
        backend=backend,
        tolerance=float(tolerance),
        seed=_count(seed, "seed"),
        max_restarts=_count(max_restarts, "max_restarts"),
        include_kernel=None if include_kernel is None else bool(include_kernel),
        flat_tolerance=float(flat_tolerance),
        threads=_threads(threads),
        time_limit=_time_limit(time_limit),
    )
    vertices, faces = _arrays.vertices(V), _arrays.faces(F)
    reference = None if relative_to is None else _arrays.vertices(relative_to)

    @translated(make_partial=lambda raw: _spectrum(raw, request))
    def solve() -> dict:
        return _native.spectrum(
            vertices, faces, request, bool(eigenvectors), progress, reference
        )

    raw = solve()
    if raw["sliver_warning"] is not None:
        warnings.warn(_python_spelling(raw["sliver_warning"]), SliverWarning, stacklevel=2)
    if raw["scale_warning"] is not None:
        warnings.warn(_python_spelling(raw["scale_warning"]), ScaleWarning, stacklevel=2)
    return _spectrum(raw, request)


class OperatorMatrices(NamedTuple):
    """The eigenproblem ``stiffness x = λ coupling x`` of an operator (matrices as assembled).

    In ``form="real"`` the matrices are ``4n × 4n``: vertex ``p`` owns rows and columns
    ``4p … 4p+3``, a quaternion ``w + xi + yj + zk`` is the column ``(w, x, y, z)``, and each entry
    ``q`` is its left-multiplication matrix, so the matrices are real symmetric and the vector
    ``eigenvectors[:, i, :].ravel()`` of a :class:`Spectrum` satisfies the pencil. In
    ``form="complex"`` they are ``2n × 2n`` Hermitian: ``z₁ + z₂ j`` is ``(z₁, conj(z₂))``.
    ``mass`` is ``(n,)``, the diagonal of the vertex mass matrix ``M`` (repeat it 4 or 2 times
    for the expanded forms).
    """

    stiffness: scipy.sparse.csc_array
    coupling: scipy.sparse.csc_array
    mass: np.ndarray


def _csc(parts: dict) -> scipy.sparse.csc_array:
    return scipy.sparse.csc_array(
        (parts["data"], parts["indices"], parts["indptr"]), shape=tuple(parts["shape"])
    )


def operator_matrices(
    V: npt.ArrayLike,
    F: npt.ArrayLike,
    operator: str = "relative-dirac",
    tau: float | None = None,
    form: Literal["real", "complex"] = "real",
    normalize: Literal["unit-area", "none"] | None = None,
    well: PotentialWell | float | None = None,
    *,
    anisotropy: float | None = None,
    flat_tolerance: float = DEFAULT_FLAT_TOLERANCE,
    relative_to: npt.ArrayLike | None = None,
) -> OperatorMatrices:
    """The matrices ``P``, ``Q`` of the eigenproblem ``P x = λ Q x`` that :func:`spectrum` solves
    for ``operator`` (``A = D* M_F D`` and ``G = sym(Bᵀ M_F D)`` for the Dirac operators, ``L``
    and ``M`` for Laplace, …; see docs/PYTHON.md), as ``scipy.sparse`` CSC arrays, with the
    vertex masses. The residuals of :func:`spectrum` are measured against exactly these. With
    ``relative_to``, those of ``spectrum(..., relative_to=...)``: the operator built on
    ``D_{f1,f2}`` of ``V`` and the surface ``(relative_to, F)``."""
    request = _Request(
        operator=operator,
        tau=None if tau is None else float(tau),
        anisotropy=None if anisotropy is None else float(anisotropy),
        k=1,
        normalize=normalize,
        well=_well(well),
        backend="native",
        tolerance=1e-10,
        seed=0,
        max_restarts=0,
        include_kernel=None,
        flat_tolerance=float(flat_tolerance),
        threads=1,
    )
    vertices, faces = _arrays.vertices(V), _arrays.faces(F)
    reference = None if relative_to is None else _arrays.vertices(relative_to)
    raw = translated()(_native.eigenproblem)(vertices, faces, request, form, reference)
    return OperatorMatrices(_csc(raw["stiffness"]), _csc(raw["coupling"]), raw["mass"])


def laplacian(V: npt.ArrayLike, F: npt.ArrayLike) -> tuple[scipy.sparse.csc_array, scipy.sparse.dia_array]:
    """The cotangent Laplacian ``L`` (``n × n``, positive semidefinite: ``L_ij = −(cot α + cot β)/2``
    off the diagonal, rows summing to 0) and the diagonal barycentric mass matrix ``M``, as
    robust-laplacian and libigl (with the sign flipped) return them."""
    vertices, faces = _arrays.vertices(V), _arrays.faces(F)
    parts, mass = translated()(_native.laplacian)(vertices, faces)
    return _csc(parts), scipy.sparse.dia_array((mass[np.newaxis, :], [0]), shape=(len(mass),) * 2)



def geodesic_distance(V: npt.ArrayLike, F: npt.ArrayLike, sources: int | npt.ArrayLike) -> np.ndarray:
    """Geodesic distance ``(n,)`` from the vertex (or vertices) ``sources`` by the heat method
    (Crane, Weischedel, Wardetzky 2013), with Neumann boundary conditions."""
    vertices, faces = _arrays.vertices(V), _arrays.faces(F)
    indices = [int(i) for i in np.atleast_1d(np.asarray(sources, dtype=np.int64))]
    if any(i < 0 for i in indices):
        raise OptionsError(f"sources must be vertex indices ≥ 0, got {indices}")
    return translated()(_native.geodesic_distance)(vertices, faces, indices)


def potential_well(
    V: npt.ArrayLike,
    F: npt.ArrayLike,
    radius: float,
    center: int | None = None,
    steepness: float = 100.0,
    height: float = 1e10,
) -> np.ndarray:
    """The potential ``U (n,)`` of :class:`PotentialWell` on the mesh as given (the paper's §5.1:
    ``height · σ(steepness (d − radius))``, ``d`` the geodesic distance from ``center``)."""
    vertices, faces = _arrays.vertices(V), _arrays.faces(F)
    well = PotentialWell(float(radius), center, float(steepness), float(height))
    return translated()(_native.potential_well)(vertices, faces, well)

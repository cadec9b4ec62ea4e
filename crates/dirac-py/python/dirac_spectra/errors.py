"""The exceptions of ``dirac_spectra``.

Every error of the native code arrives as one of these classes; each also derives from the
builtin exception it refines, so ``except ValueError`` catches a bad mesh as it would in numpy.

=====================  ==========================  ==============================================
class                  builtin base                raised when
=====================  ==========================  ==============================================
``MeshError``          ``ValueError``              the mesh is invalid: ``face`` and/or ``vertex``
                                                   name the first bad element (empty mesh, index
                                                   out of range, repeated index, unreferenced
                                                   vertex, non-finite coordinate, zero-area face,
                                                   degenerate angle, non-manifold edge or vertex,
                                                   inconsistent orientation, vanishing normal;
                                                   the message ends with a pointer to
                                                   ``repair``), or cannot be repaired (no face
                                                   left, not orientable: ``face``)
``MeshFileError``      ``MeshError``               a mesh file is malformed (the message gives the
                                                   line) or has an unknown extension
``OptionsError``       ``ValueError``              an argument has a value that cannot be used:
                                                   unknown operator, backend or normalisation, k
                                                   out of range, tau outside [0, 1] or
                                                   anisotropy below 0, tau or anisotropy for an
                                                   operator without it, bad flat tolerance, bad
                                                   well parameters, threads not 1 or 2
``KernelError``        ``ValueError``              the operator has fewer nonzero eigenvalues
                                                   than asked for outside its exact kernel (or
                                                   none at all: a planar mesh for relative Dirac),
                                                   or has a kernel it does not remove (rulings
                                                   tied at single vertices with more than 1,024
                                                   parameters of rigid parts, or a second
                                                   surface with triangles that are segments of
                                                   three distinct points)
``SingularError``      ``ArithmeticError``         a matrix is numerically singular (``vertex``
                                                   where the factorisation failed, if known;
                                                   ``face`` a sliver there, if one is the cause)
``SolverError``        ``RuntimeError``            the eigensolver failed
``NotConvergedError``  ``SolverError``             the eigensolver stopped before all k pairs
                                                   converged: ``partial`` is a ``Spectrum`` of the
                                                   converged pairs, ``wanted`` the k asked for,
                                                   ``accepting_tolerance`` a tolerance that
                                                   accepts pairs found short of it (or None)
``DescriptorError``    ``ValueError``              a descriptor cannot be computed from the given
                                                   eigenpairs (no nonzero eigenvalue, negative
                                                   eigenvalue for HKS, bad times or energies)
=====================  ==========================  ==============================================

``spectrum`` warns with ``SliverWarning`` (a ``UserWarning``) when the mesh has sliver faces:
their height is at most 10⁻⁹ of the mesh's size, so their cotangent weights dominate every
operator; the computation goes on, and ``repair`` removes them. It warns with
``ScaleWarning`` (a ``UserWarning``) when ``operator="family"`` runs on a mesh that is not
normalised and whose area is outside [0.01, 100]: the family weighs ``D_N`` and the
Laplacian by scale, so its ``tau`` there means another ``tau`` of the mesh at unit area
(the message gives it); ``normalize="unit-area"`` makes ``tau`` mean the same on every mesh.

Files that cannot be opened or written raise the builtin ``OSError`` (``FileNotFoundError``
and so on). Bad array arguments raise ``TypeError`` (wrong dtype) or ``ValueError`` (wrong
shape) with the expected form in the message.
"""

from __future__ import annotations

import errno
import functools
from typing import Any, Callable, TypeVar

from . import _native

__all__ = [
    "DiracError",
    "MeshError",
    "MeshFileError",
    "OptionsError",
    "KernelError",
    "SingularError",
    "SolverError",
    "NotConvergedError",
    "DescriptorError",
    "ScaleWarning",
    "SliverWarning",
]


class DiracError(Exception):
    """Base class of every exception ``dirac_spectra`` raises for a failed computation."""


class MeshError(DiracError, ValueError):
    """The mesh is invalid. ``face`` and ``vertex`` name the offending element (or are None)."""

    face: int | None = None
    vertex: int | None = None


class MeshFileError(MeshError):
    """A mesh file is malformed or of an unknown format."""


class OptionsError(DiracError, ValueError):
    """An argument has a value the computation cannot use."""


class KernelError(DiracError, ValueError):
    """Fewer nonzero eigenvalues exist outside the operator's exact kernel than were asked for."""


class SingularError(DiracError, ArithmeticError):
    """A matrix is numerically singular; ``vertex`` is where it failed, if known, and ``face`` a
    sliver around it (height at most 10⁻⁹ of the mesh's size), if one is the likely cause:
    ``repair`` removes such faces."""

    vertex: int | None = None
    face: int | None = None


class SolverError(DiracError, RuntimeError):
    """The eigensolver failed."""


class NotConvergedError(SolverError):
    """The eigensolver stopped before all pairs converged.

    ``partial`` is a :class:`dirac_spectra.Spectrum` holding the pairs that did converge (sorted
    by ``|λ|``, with their residuals); ``wanted`` is the number asked for. When the solver
    found other pairs accurate to a tolerance up to 10⁻⁶ but not to the one asked for (the
    message says which ``|λ|`` and whether they lie below some of ``partial``'s),
    ``accepting_tolerance`` is the tolerance that accepts them, otherwise None.
    ``stopped_at_time_limit`` is true when ``spectrum(time_limit=...)`` stopped the solver.
    """

    partial: Any = None
    wanted: int = 0
    accepting_tolerance: float | None = None
    stopped_at_time_limit: bool = False


class DescriptorError(DiracError, ValueError):
    """A descriptor cannot be computed from the given eigenpairs."""


class SliverWarning(UserWarning):
    """The mesh has sliver faces (height at most 10⁻⁹ of its size, as CAD exporters write fans
    over collinear corners): a valid mesh, but their cotangent weights dominate every operator
    and can spoil its spectrum. ``dirac_spectra.repair(V, F)`` removes them."""


class ScaleWarning(UserWarning):
    """The family ran on a mesh that is not normalised and whose area is far from 1: it weighs
    ``D_N`` and the Laplacian by scale, so its ``tau`` means another ``tau`` of the mesh at
    unit area (the message gives it). ``normalize="unit-area"`` makes ``tau`` scale-free."""


_CLASSES: dict[str, type[Exception]] = {
    "invalid_mesh": MeshError,
    "mesh": MeshError,
    "repair": MeshError,
    "mesh_file": MeshFileError,
    "options": OptionsError,
    "kernel": KernelError,
    "singular": SingularError,
    "solver": SolverError,
    "not_converged": NotConvergedError,
    "descriptor": DescriptorError,
}

# The library's messages name the command line's options; a Python user sets keywords.
_OPTION_SPELLING = [
    ("--include-kernel", "include_kernel=True"),
    ("--flat-tolerance ", "flat_tolerance="),
    ("--tolerance ", "tolerance="),
    ("use a smaller T in --operator family:T (T = 0 is the Laplacian)",
     "use a smaller tau (tau=0 is the Laplacian)"),
    ("its T weighs D_N as T = ", "its tau weighs D_N as tau = "),
    ("(or use a smaller T)", "(or use a smaller tau)"),
    ("--operator family:T", 'operator="family", tau=T'),
    ("--operator laplace", 'operator="laplace"'),
    ("with --repair", "with dirac_spectra.repair(V, F) (or read_mesh(path, repair=True))"),
    ("--normalize unit-area", 'normalize="unit-area"'),
]


def _python_spelling(message: str) -> str:
    for cli, python in _OPTION_SPELLING:
        message = message.replace(cli, python)
    return message


# Appended to the message of an invalid mesh (not to errors of the repair itself).
REPAIR_HINT = (
    " (dirac_spectra.repair(V, F), or read_mesh(path, repair=True), merges duplicated "
    "vertices, drops degenerate faces, splits non-manifold elements and orients faces)"
)


def _translate(error: Exception, make_partial: Callable[[dict], Any] | None) -> Exception:
    """The documented exception for a ``_native.NativeError(kind, message, details)``."""
    kind, message, details = error.args
    message = _python_spelling(message)
    if kind == "io":
        # OSError(errno, text) is the subclass for the number: FileNotFoundError, ...
        return OSError(details.get("errno") or errno.EIO, message)
    if kind == "invalid_mesh":
        message += REPAIR_HINT
    translated = _CLASSES[kind](message)
    for name, value in details.items():
        if name == "partial" and make_partial is not None:
            value = make_partial(value)
        setattr(translated, name, value)
    return translated


F = TypeVar("F", bound=Callable[..., Any])


def translated(make_partial: Callable[[dict], Any] | None = None) -> Callable[[F], F]:
    """Decorator: native errors become their documented class (``make_partial`` turns the raw
    partial result of a ``NotConvergedError`` into a ``Spectrum``)."""

    def decorate(function: F) -> F:
        @functools.wraps(function)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            try:
                return function(*args, **kwargs)
            except _native.NativeError as error:
                raise _translate(error, make_partial) from None

        return wrapper  # type: ignore[return-value]

    return decorate

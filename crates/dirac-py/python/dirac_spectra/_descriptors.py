"""Per-vertex descriptors: heat, Dirac and wave kernel signatures, the segmentation descriptor.

Each takes a :class:`Spectrum` (with eigenvectors), or a mesh ``(V, F)`` whose spectrum it
computes first (keyword arguments go to :func:`spectrum`). The conventions are those of the
``dirac`` crate: ``|φ(v)|²`` is the squared quaternion norm, eigenvalues are zero when ``|λ| ≤
10⁻¹⁰ max |λ|``; see docs/PYTHON.md.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from . import _arrays, _native
from ._spectrum import Spectrum, spectrum
from .errors import DescriptorError, translated

#: Times or energies of the default samplings (Sun et al. 2009, Aubry et al. 2011).
DEFAULT_SAMPLES = 100


@dataclass(frozen=True)
class Descriptor:
    """A per-vertex descriptor: ``values`` ``(n, columns)`` and the parameter of each column
    (time, log-energy or eigenvalue); ``sigma`` is the wave kernel signature's filter width.
    ``np.asarray(descriptor)`` is ``values``."""

    values: np.ndarray
    parameters: np.ndarray
    sigma: float | None = None

    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        return self.values if dtype is None else self.values.astype(dtype)


def _modes(
    source: Spectrum | npt.ArrayLike, F: npt.ArrayLike | None, operator: str, options: dict
) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues and ``(n, k, 4)`` eigenvectors of a spectrum, or of the mesh ``(source, F)``."""
    if isinstance(source, Spectrum):
        if F is not None or options:
            raise TypeError("give either a Spectrum or a mesh (V, F) with spectrum options")
        result = source
    else:
        if F is None:
            raise TypeError("a descriptor needs a Spectrum, or both V and F")
        options.setdefault("k", 50)
        options.setdefault("operator", operator)
        result = spectrum(source, F, **options)
    if result.eigenvectors is None:
        raise DescriptorError(
            "this Spectrum has no eigenvectors (computed with eigenvectors=False); "
            "compute it with eigenvectors=True"
        )
    values = _arrays.eigenvalues(result.eigenvalues)
    return values, _arrays.eigenvectors(result.eigenvectors, len(values))


def _kernel_signature(
    kind: str,
    source: Spectrum | npt.ArrayLike,
    F: npt.ArrayLike | None,
    times: npt.ArrayLike | None,
    count: int,
    spectrum_options: dict,
) -> Descriptor:
    operator = "laplace" if kind == "heat" else "relative-dirac"
    values, vectors = _modes(source, F, operator, spectrum_options)
    table = translated()(_native.kernel_signature)(
        kind, values, vectors, _arrays.samples(times, "times"), count
    )
    return Descriptor(*table)


def hks(
    source: Spectrum | npt.ArrayLike,
    F: npt.ArrayLike | None = None,
    times: npt.ArrayLike | None = None,
    count: int = DEFAULT_SAMPLES,
    **spectrum_options: Any,
) -> Descriptor:
    """Heat kernel signature ``Σ_i e^{−t λ_i} |φ_i(v)|²`` (Sun, Ovsjanikov, Guibas 2009) at
    ``times`` (default: ``count`` times log-spaced over ``[4 ln 10/λ_max, 4 ln 10/λ_min]``).
    Needs ``λ ≥ 0``: from a mesh, the Laplace spectrum (50 pairs unless ``k`` is given)."""
    return _kernel_signature("heat", source, F, times, count, spectrum_options)


def dks(
    source: Spectrum | npt.ArrayLike,
    F: npt.ArrayLike | None = None,
    times: npt.ArrayLike | None = None,
    count: int = DEFAULT_SAMPLES,
    **spectrum_options: Any,
) -> Descriptor:
    """Dirac kernel signature ``Σ_i e^{−t |λ_i|} |φ_i(v)|²`` (paper §6.3); times as for
    :func:`hks`. From a mesh: the relative Dirac spectrum (50 pairs unless ``k`` is given)."""
    return _kernel_signature("dirac", source, F, times, count, spectrum_options)


def wks(
    source: Spectrum | npt.ArrayLike,
    F: npt.ArrayLike | None = None,
    energies: npt.ArrayLike | None = None,
    sigma: float | None = None,
    count: int = DEFAULT_SAMPLES,
    **spectrum_options: Any,
) -> Descriptor:
    """Wave kernel signature ``Σ_i g_i(e) |φ_i(v)|² / Σ_i g_i(e)``, ``g_i(e) = exp(−(e −
    ln|λ_i|)²/2σ²)`` (Aubry, Schlickewei, Cremers 2011) at log-energies ``energies`` (default:
    ``count`` energies and ``σ`` after Aubry et al.). From a mesh: the Laplace spectrum."""
    values, vectors = _modes(source, F, "laplace", spectrum_options)
    table, parameters, used_sigma = translated()(_native.wave_kernel_signature)(
        values, vectors, _arrays.samples(energies, "energies"), sigma, count
    )
    return Descriptor(table, parameters, used_sigma)


def segmentation_descriptor(
    source: Spectrum | npt.ArrayLike,
    F: npt.ArrayLike | None = None,
    **spectrum_options: Any,
) -> Descriptor:
    """The segmentation descriptor of paper §6.2, ``v ↦ (|φ_1(v)|/√|λ_1|, |φ_2(v)|/√|λ_2|, …)``
    over the nonzero modes (parameters: their eigenvalues). From a mesh: relative Dirac."""
    values, vectors = _modes(source, F, "relative-dirac", spectrum_options)
    return Descriptor(*translated()(_native.segmentation_descriptor)(values, vectors))

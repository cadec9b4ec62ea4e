"""dirac_spectra: spectra of the operators of "A Dirac Operator for Extrinsic Shape Analysis"
(Liu, Jacobson, Crane 2017), computed by a native quaternionic eigensolver.

>>> import dirac_spectra as ds
>>> V, F = ds.default_mesh()
>>> s = ds.spectrum(V, F, k=10, operator="relative-dirac")
>>> s.eigenvalues.shape, s.eigenvectors.shape
((10,), (2930, 10, 4))

numpy in, numpy out: ``V`` is ``(n, 3)`` positions, ``F`` ``(m, 3)`` triangles; eigenvectors are
``(n, k, 4)`` quaternions ``(w, x, y, z)``, mass-orthonormal. See docs/PYTHON.md.
"""

from ._descriptors import DEFAULT_SAMPLES, Descriptor, dks, hks, segmentation_descriptor, wks
from ._mesh import default_mesh, read_mesh, write_mesh
from ._repair import DEFAULT_MERGE_DISTANCE, Repaired, read_and_repair, repair
from ._spectrum import (
    DEFAULT_FLAT_TOLERANCE,
    OPERATORS,
    OperatorMatrices,
    PotentialWell,
    Spectrum,
    geodesic_distance,
    laplacian,
    operator_matrices,
    potential_well,
    spectrum,
)
from .errors import (
    DescriptorError,
    DiracError,
    KernelError,
    MeshError,
    MeshFileError,
    NotConvergedError,
    OptionsError,
    SingularError,
    ScaleWarning,
    SliverWarning,
    SolverError,
)

__version__ = "0.1.0"

__all__ = [
    "DEFAULT_FLAT_TOLERANCE",
    "DEFAULT_MERGE_DISTANCE",
    "DEFAULT_SAMPLES",
    "OPERATORS",
    "Descriptor",
    "DescriptorError",
    "DiracError",
    "KernelError",
    "MeshError",
    "MeshFileError",
    "NotConvergedError",
    "OperatorMatrices",
    "OptionsError",
    "PotentialWell",
    "Repaired",
    "SingularError",
    "ScaleWarning",
    "SliverWarning",
    "SolverError",
    "Spectrum",
    "default_mesh",
    "dks",
    "geodesic_distance",
    "hks",
    "laplacian",
    "operator_matrices",
    "potential_well",
    "read_and_repair",
    "read_mesh",
    "repair",
    "segmentation_descriptor",
    "spectrum",
    "wks",
    "write_mesh",
]

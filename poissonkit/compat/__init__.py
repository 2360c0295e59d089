"""PoissonGeometry-compatible front end.

Drop-in replacements for the classes of the PyPI packages ``poissongeometry``
(``from poisson.poisson import PoissonGeometry``) and ``numericalpoissongeometry``
(``from numpoisson.numpoisson import NumPoissonGeometry``)::

    from poissonkit.compat import PoissonGeometry, NumPoissonGeometry

Same method names, signatures and formats, computed on :mod:`poissonkit.structure`; the mesh
methods (``num_*``) are vectorised with numpy. The Hamiltonian vector field keeps
PoissonGeometry's sign ``X_h = {h, .} = -P dh`` — the opposite of poissonkit's
(:mod:`poissonkit.conventions`) — only here. Differences and the curl fix: docs/compat.md.

:func:`read_bivector` turns a PoissonGeometry-format dict (also with JSON string keys such as
``"1,2"``) into a :class:`poissonkit.structure.Bivector`, for tools that read such files.
"""

from poissonkit.compat._inputs import read_bivector
from poissonkit.compat.errors import (CasimirError, DiferentialFormError, DifferentialFormError,
                                      DimensionError, FunctionError, MultivectorError,
                                      Nonhomogeneous, Nonlinear, ParseError)
from poissonkit.compat.numeric import NumericalPoissonGeometry, NumPoissonGeometry
from poissonkit.compat.symbolic import PoissonGeometry

__all__ = [
    "CasimirError", "DiferentialFormError", "DifferentialFormError", "DimensionError",
    "FunctionError", "MultivectorError", "Nonhomogeneous", "Nonlinear", "NumPoissonGeometry",
    "NumericalPoissonGeometry", "ParseError", "PoissonGeometry", "read_bivector",
]

"""A magpylib ``Collection`` partly exact: the exact sum of the sources with a closed form plus
a tricubic table of the others (:mod:`poissonkit.numerics.fields.tabulated`).

The data is ``[n, exact data (n numbers), table data]``; ``B`` and its Jacobian are the sums
of the two parts, so the energy ``U = −c ν·B`` keeps its exact gradient.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numba import njit

from poissonkit.numerics.fields.base import CompiledField
from poissonkit.numerics.fields.magnetic import magnetic_kernel
from poissonkit.numerics.fields.tricubic import tricubic_field
from poissonkit_magnets.exact_sources import sources_add


@njit(cache=True, error_model="numpy")
def mixed_b(x, y, z, P):
    """``(B, ∂B/∂x)`` of the exact part ``P[1:1+n]`` plus the table ``P[1+n:]``."""
    n = int(P[0])
    t = tricubic_field(x, y, z, P[1 + n:])
    out = np.empty(12)
    for i in range(12):
        out[i] = t[i]
    sources_add(x, y, z, P[1:1 + n], out)
    return (out[0], out[1], out[2], out[3], out[4], out[5], out[6], out[7], out[8], out[9],
            out[10], out[11])


#: The energy kernel of a moment in a partly exact, partly tabulated field.
MIXED_MAGNET = magnetic_kernel(mixed_b)


def mixed_field(exact: np.ndarray, table: CompiledField, info: Mapping[str, Any]
                ) -> CompiledField:
    """The field of the exact sources ``exact`` plus the tabulated field ``table``; its info
    joins the table's (grid, measured error of the tabulated part) and ``info``."""
    P = np.concatenate([[float(exact.size)], exact, np.asarray(table.data, dtype=float)])
    return CompiledField("magpylib", MIXED_MAGNET, np.ascontiguousarray(P), reads="moment",
                         orientation=True, info={**dict(table.info), **dict(info)})

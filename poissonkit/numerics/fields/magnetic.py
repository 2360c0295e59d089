"""A magnet's energy ``U = −c ν·B(r)`` in a static field, from a compiled field ``B(r)``.

``c`` is the body's moment [A m²], ``ν`` its axis. The field kernel
``b(x, y, z, P) -> (B_x, B_y, B_z, J_xx, J_xy, …, J_zz)`` returns ``B`` [T] and its Jacobian
``J_ij = ∂B_i/∂x_j``; the energy kernel's partials are then ``∂U/∂r_j = −c ν_i J_ij`` and
``∂U/∂ν = −c B``, so the force is ``c ∇(ν·B)`` and the torque ``c ν × B``, exactly the
derivatives of the ``U`` the kernel returns (an interpolated ``B`` keeps its ``U`` exactly).
"""

from __future__ import annotations

import numba

from poissonkit.contracts import CompiledFunction
from poissonkit.numerics.jit import jit


def magnetic_kernel(bfield: CompiledFunction) -> CompiledFunction:
    """The energy kernel ``f(x, y, z, ν_x, ν_y, ν_z, c, P)`` of a moment ``c ν`` in the field
    ``bfield(x, y, z, P)`` (module docstring)."""

    def energy(x, y, z, n0, n1, n2, c, P):
        b0, b1, b2, j00, j01, j02, j10, j11, j12, j20, j21, j22 = bfield(x, y, z, P)
        u = -c * (n0 * b0 + n1 * b1 + n2 * b2)
        gx = -c * (n0 * j00 + n1 * j10 + n2 * j20)
        gy = -c * (n0 * j01 + n1 * j11 + n2 * j21)
        gz = -c * (n0 * j02 + n1 * j12 + n2 * j22)
        return u, gx, gy, gz, -c * b0, -c * b1, -c * b2

    return jit(energy)


@numba.njit(cache=True, error_model="numpy")
def uniform_b(x, y, z, P):
    """A uniform field ``B = (P[0], P[1], P[2])`` [T] (zero Jacobian)."""
    return (P[0], P[1], P[2], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


#: The energy kernel of a moment in a uniform field.
UNIFORM_MAGNET = magnetic_kernel(uniform_b)

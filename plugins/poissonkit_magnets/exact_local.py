"""Closed-form fields of magpylib's point-like and current sources in their own frame.

Each kernel ``k(x, y, z, P, o, out)`` adds to ``out`` (12 numbers) the field ``B`` [T] and its
Jacobian ``J_ij = ∂B_i/∂x_j`` [T/m] (row by row) at the local point ``(x, y, z)`` of the source
whose parameters start at ``P[o]``. The frame is magpylib's: the source's own position at the
origin, its orientation undone (:mod:`poissonkit_magnets.exact_sources`).

* Dipole ``m`` (``P[o:o+3]``, ``μ0 = P[o+3]``):
  ``B = μ0/(4π) (3 (m·r) r / r⁵ − m / r³)``.
* Sphere, polarisation ``J`` and radius ``R``: outside the dipole field of moment
  ``J (4/3) π R³ / μ0``, i.e. ``B = (R³/3)(3 (J·r) r / r⁵ − J / r³)``; inside (``r ≤ R``, as
  magpylib) the uniform ``B = 2 J / 3``.
* Circle (current loop about local ``z``): the elliptic-integral field of
  :func:`poissonkit_magnets.exact_loop.loop_fields`.
* Polyline: Biot–Savart of each straight segment ``A → B`` in closed form, with
  ``a = A − r``, ``b = B − r``::

      B = μ0 I/(4π) (|a| + |b|) / (|a||b| (|a||b| + a·b)) · a × b

  (``|a||b| + a·b = |a × b|² / (|a||b| − a·b)`` where ``a·b < 0``, so that the formula keeps
  its precision near the wire).
"""

from __future__ import annotations

import math

from numba import njit

from poissonkit_magnets.exact_loop import loop_fields


@njit(cache=True, error_model="numpy")
def dipole_add(x, y, z, mx, my, mz, k, out):
    """``B = k (3 (m·r) r / r⁵ − m / r³)`` and its Jacobian added to ``out``."""
    r2 = x * x + y * y + z * z
    r = math.sqrt(r2)
    inv3 = 1.0 / (r2 * r)
    inv5 = inv3 / r2
    mr = mx * x + my * y + mz * z
    rv = (x, y, z)
    mv = (mx, my, mz)
    for i in range(3):
        out[i] += k * (3.0 * mr * rv[i] * inv5 - mv[i] * inv3)
        for j in range(3):
            d = 1.0 if i == j else 0.0
            out[3 + 3 * i + j] += k * (3.0 * (mv[j] * rv[i] + mr * d + mv[i] * rv[j]) * inv5
                                       - 15.0 * mr * rv[i] * rv[j] * inv5 / r2)


@njit(cache=True, error_model="numpy")
def dipole_local(x, y, z, P, o, out):
    """magpylib ``Dipole``: ``P[o:o+4] = (m_x, m_y, m_z, μ0)``."""
    dipole_add(x, y, z, P[o], P[o + 1], P[o + 2], P[o + 3] / (4.0 * math.pi), out)


@njit(cache=True, error_model="numpy")
def sphere_local(x, y, z, P, o, out):
    """magpylib ``Sphere``: ``P[o:o+4] = (J_x, J_y, J_z, R)``."""
    rad = P[o + 3]
    if x * x + y * y + z * z <= rad * rad:
        for i in range(3):
            out[i] += 2.0 * P[o + i] / 3.0
        return
    dipole_add(x, y, z, P[o], P[o + 1], P[o + 2], rad ** 3 / 3.0, out)


@njit(cache=True, error_model="numpy")
def axisymmetric_add(x, y, br, bz, br_rho, bz_r, bz_z, br_r, out):
    """Add a field symmetric about the local ``z`` axis, given in cylindrical components
    ``(B_ρ, B_z, B_ρ/ρ, ∂B_z/∂ρ = ∂B_ρ/∂z, ∂B_z/∂z, ∂B_ρ/∂ρ)``, in Cartesian form."""
    rho = math.sqrt(x * x + y * y)
    if rho > 0.0:
        e0 = x / rho
        e1 = y / rho
    else:  # on the axis B_ρ = 0, ∂B_z/∂ρ = 0 and ∂B_ρ/∂ρ = B_ρ/ρ: any e ⟂ z serves
        e0 = 0.0
        e1 = 0.0
        br_r = br_rho
    ev = (e0, e1, 0.0)
    nv = (0.0, 0.0, 1.0)
    for i in range(3):
        out[i] += br * ev[i] + bz * nv[i]
        for j in range(3):
            d = 1.0 if i == j else 0.0
            out[3 + 3 * i + j] += (br_r * ev[i] * ev[j] + bz_r * (ev[i] * nv[j] + nv[i] * ev[j])
                                   + br_rho * (d - nv[i] * nv[j] - ev[i] * ev[j])
                                   + bz_z * nv[i] * nv[j])


@njit(cache=True, error_model="numpy")
def circle_local(x, y, z, P, o, out):
    """magpylib ``Circle`` about local ``z``: ``P[o:o+3] = (I, radius, μ0)``."""
    rho = math.sqrt(x * x + y * y)
    br, bz, br_rho, bz_r, bz_z, br_r = loop_fields(rho, z, P[o] * P[o + 2], P[o + 1])
    axisymmetric_add(x, y, br, bz, br_rho, bz_r, bz_z, br_r, out)


@njit(cache=True, error_model="numpy")
def segment_add(x, y, z, ax, ay, az, bx, by, bz, k, out):
    """Biot–Savart field of the segment ``A → B`` with ``k = μ0 I/(4π)`` (module docstring),
    and its Jacobian, added to ``out``."""
    a0 = ax - x
    a1 = ay - y
    a2 = az - z
    b0 = bx - x
    b1 = by - y
    b2 = bz - z
    al = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    be = math.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
    v0 = a1 * b2 - a2 * b1
    v1 = a2 * b0 - a0 * b2
    v2 = a0 * b1 - a1 * b0
    ga = a0 * b0 + a1 * b1 + a2 * b2
    ab = al * be
    if ga < 0.0:
        dd = (v0 * v0 + v1 * v1 + v2 * v2) / (ab - ga)
    else:
        dd = ab + ga
    if dd == 0.0 or al == 0.0 or be == 0.0:  # on the wire: leave the segment out
        return
    f = (al + be) / (ab * dd)
    # log-derivatives of f in |a|, |b|, a·b
    fa = f * (1.0 / (al + be) - 1.0 / al - be / dd)
    fb = f * (1.0 / (al + be) - 1.0 / be - al / dd)
    fg = -f / dd
    av = (a0, a1, a2)
    bv = (b0, b1, b2)
    vv = (v0, v1, v2)
    d = (a0 - b0, a1 - b1, a2 - b2)
    for i in range(3):
        out[i] += k * f * vv[i]
    for j in range(3):
        # ∂f/∂r_j with ∂|a|/∂r = −a/|a|, ∂|b|/∂r = −b/|b|, ∂(a·b)/∂r = −(a + b)
        dfj = -fa * av[j] / al - fb * bv[j] / be - fg * (av[j] + bv[j])
        # ∂(a × b)/∂r_j = e_j × (a − b)
        if j == 0:
            c0, c1, c2 = 0.0, -d[2], d[1]
        elif j == 1:
            c0, c1, c2 = d[2], 0.0, -d[0]
        else:
            c0, c1, c2 = -d[1], d[0], 0.0
        cv = (c0, c1, c2)
        for i in range(3):
            out[3 + 3 * i + j] += k * (dfj * vv[i] + f * cv[i])


@njit(cache=True, error_model="numpy")
def polyline_local(x, y, z, P, o, out):
    """magpylib ``Polyline``: ``P[o:] = (I, μ0, n, x_0, y_0, z_0, …)``, current from vertex
    ``i`` to ``i + 1``."""
    k = P[o] * P[o + 1] / (4.0 * math.pi)
    n = int(P[o + 2])
    v = o + 3
    for s in range(n - 1):
        p = v + 3 * s
        segment_add(x, y, z, P[p], P[p + 1], P[p + 2], P[p + 3], P[p + 4], P[p + 5], k, out)

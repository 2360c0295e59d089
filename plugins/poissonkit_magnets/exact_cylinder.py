"""Closed-form field of an axially polarised cylinder (magpylib ``Cylinder``) and its Jacobian.

``B`` is magpylib's expression (Derby & Olbert, Am. J. Phys. 78 (2010) 229), with Bulirsch's
general complete elliptic integral ``cel(k_c, p, c, s)`` (Numer. Math. 13 (1969) 305); lengths
in units of the radius ``a``, ``z_± = z ± h``::

    B_ρ = J/π [cel(k₊, 1, 1, −1)/√(z₊² + (1+ρ)²) − cel(k₋, 1, 1, −1)/√(z₋² + (1+ρ)²)]
    B_z = J/(π (1+ρ)) [z₊ cel(k₊, γ², 1, γ)/√(z₊² + (1+ρ)²) − z₋ cel(k₋, γ², 1, γ)/√(…)]

with ``k_± = √((z_±² + (1−ρ)²)/(z_±² + (1+ρ)²))``, ``γ = (1−ρ)/(1+ρ)``. It is ``B = μ0(H + M)``
inside the magnet too.

The Jacobian comes from the equivalent solenoid (surface current ``M = J/μ0`` per unit length):
``B = ∫_{−h}^{h} M B_loop(ρ, z − z') dz'``, so every ``z``-derivative is a difference of loop
fields at the end planes, ``∂_z B = M [B_loop(ρ, z + h) − B_loop(ρ, z − h)]``, and
``B_ρ = −M [A_φ(ρ, z + h) − A_φ(ρ, z − h)]`` with the loop's vector potential
``A_φ = (8 μ0 I a² ρ/π) S(m)/p^{3/2}``, ``S(m) = ((1 − m/2)K − E)/m²``, which gives ``B_ρ/ρ``
without cancellation near the axis. ``∂B_z/∂ρ = ∂B_ρ/∂z`` (curl-free) and
``∂B_ρ/∂ρ = −∂B_z/∂z − B_ρ/ρ`` (divergence-free) complete it.
"""

from __future__ import annotations

import math

from numba import njit

from poissonkit_magnets.exact_diametral import cylinder_diametral_add
from poissonkit_magnets.exact_local import axisymmetric_add
from poissonkit_magnets.exact_loop import cel, loop_fields, s_of_m


@njit(cache=True, error_model="numpy")
def _a_over_rho(rho: float, zeta: float, a: float) -> float:
    """``A_φ/(μ0 I ρ)`` of a loop of radius ``a`` at axial distance ``zeta``."""
    p = (a + rho) ** 2 + zeta * zeta
    m1 = ((a - rho) ** 2 + zeta * zeta) / p
    return 8.0 * a * a * s_of_m(4.0 * a * rho / p, m1) / (math.pi * p * math.sqrt(p))


@njit(cache=True, error_model="numpy")
def cylinder_axial_add(x, y, z, jz, a, h, out):
    """Field and Jacobian of a cylinder (radius ``a``, half length ``h``, polarisation ``jz``
    along its axis ``z``) added to ``out``."""
    rho_si = math.sqrt(x * x + y * y)
    r = rho_si / a
    zz = z / a
    z0 = h / a
    zph = zz + z0
    zmh = zz - z0
    dpr = 1.0 + r
    dmr = 1.0 - r
    sq0 = math.sqrt(zmh * zmh + dpr * dpr)
    sq1 = math.sqrt(zph * zph + dpr * dpr)
    k1 = math.sqrt((zph * zph + dmr * dmr) / (zph * zph + dpr * dpr))
    k0 = math.sqrt((zmh * zmh + dmr * dmr) / (zmh * zmh + dpr * dpr))
    gam = dmr / dpr
    br = jz * (cel(k1, 1.0, 1.0, -1.0) / sq1 - cel(k0, 1.0, 1.0, -1.0) / sq0) / math.pi
    bz = jz * (zph * cel(k1, gam * gam, 1.0, gam) / sq1
               - zmh * cel(k0, gam * gam, 1.0, gam) / sq0) / (dpr * math.pi)
    # Jacobian from the solenoid: loops carrying μ0 I = jz at the end planes
    lp = loop_fields(rho_si, z + h, jz, a)
    lm = loop_fields(rho_si, z - h, jz, a)
    bz_z = lp[1] - lm[1]
    bz_r = lp[0] - lm[0]
    br_rho = -jz * (_a_over_rho(rho_si, z + h, a) - _a_over_rho(rho_si, z - h, a))
    br_r = -bz_z - br_rho
    axisymmetric_add(x, y, br, bz, br_rho, bz_r, bz_z, br_r, out)


@njit(cache=True, error_model="numpy")
def cylinder_local(x, y, z, P, o, out):
    """magpylib ``Cylinder`` about local ``z``: ``P[o:o+5] = (J_x, J_y, J_z, radius,
    half length)``: the axial part of ``J`` here, the transverse one by
    :func:`poissonkit_magnets.exact_diametral.cylinder_diametral_add`."""
    if P[o + 2] != 0.0:
        cylinder_axial_add(x, y, z, P[o + 2], P[o + 3], P[o + 4], out)
    if P[o] != 0.0 or P[o + 1] != 0.0:
        cylinder_diametral_add(x, y, z, P[o], P[o + 1], P[o + 3], P[o + 4], out)

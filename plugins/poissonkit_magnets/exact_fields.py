"""Exact fields of a circular current loop and of an axially magnetised cylinder.

* Loop (radius ``a``, current ``I`` right-handed about its axis ``n``): in cylindrical
  coordinates ``(ρ, z)`` about the axis, with ``p = (a+ρ)² + z²``, ``q = (a−ρ)² + z²``,
  ``m = 4aρ/p`` and ``C = μ0 I/(2π)`` (Jackson, Classical Electrodynamics, 3rd ed., §5.5;
  Simpson et al., NASA/TM-2013-217919)::

      B_z = C p^(−1/2) [K(m) + (a² − ρ² − z²)/q E(m)]
      B_ρ = C z/(ρ p^(1/2)) [−K(m) + (a² + ρ² + z²)/q E(m)] = 16 C a² z ρ T(m) / (p^(3/2) q)

  with ``T(m) = ((1 − m/2) E − (1 − m) K)/m²`` (a power series for small ``m``, so ``B_ρ/ρ`` has
  no cancellation near the axis). The gradient comes from ``∂B_z/∂ρ``, ``∂B_z/∂z`` in closed
  form and the field equations: ``∂B_ρ/∂z = ∂B_z/∂ρ`` (curl-free),
  ``∂B_ρ/∂ρ = −∂B_z/∂z − B_ρ/ρ`` (divergence-free).
* Cylinder (radius ``a``, length ``2l``, polarisation ``J = μ0 M`` along ``n``): ``B = −μ0 ∇ψ``
  outside the magnet, ``ψ`` the potential of the two charged end disks by ring quadrature or
  its multipole series far away (:mod:`poissonkit_magnets.fields`, docs/magnets.md).

Both return ``B`` and its Jacobian ``∂B_i/∂x_j`` for the magnet energy kernel
(:func:`poissonkit.numerics.fields.magnetic.magnetic_kernel`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
from numba import njit

from poissonkit.conventions import MU0
from poissonkit.errors import InputError
from poissonkit.numerics.fields.base import CompiledField, FieldRequest
from poissonkit.numerics.fields.magnetic import magnetic_kernel
from poissonkit.numerics.fields.solids import Solid, rotvec_of_axis
from poissonkit.plugin.contributions import ExternalField, Param
from poissonkit_magnets._special import ellipk_d1, ellipke, gauss_legendre_unit
from poissonkit_magnets.fields import (N_MULTIPOLE, N_RING, cylinder_axial_moments,
                                       cylinder_psi_cartesian)

_SERIES_M = 0.1


@njit(cache=True)
def _t_and_de(m: float) -> tuple[float, float]:
    """``T(m) = ((1 − m/2)E − (1 − m)K)/m²`` and ``dE/dm``, by series below ``m = 0.1``."""
    if m < _SERIES_M:
        # K = π/2 Σ c_n mⁿ, E = −π/2 Σ c_n mⁿ/(2n − 1), c_n = ((2n−1)!!/(2n)!!)²
        c_prev = 1.0
        e_prev = 1.0
        t = 0.0
        de = 0.0
        mp = 1.0  # m^(n-2) for the T series, m^(n-1) for dE
        c = 1.0
        for n in range(1, 40):
            c *= ((n - 0.5) / n) ** 2
            e_n = -c / (2.0 * n - 1.0)
            de += n * e_n * (m ** (n - 1))
            if n >= 2:
                t += (e_n - 0.5 * e_prev - c + c_prev) * mp
                mp *= m
            c_prev = c
            e_prev = e_n
        return 0.5 * math.pi * t, 0.5 * math.pi * de
    k, e = ellipke(m)
    return ((1.0 - 0.5 * m) * e - (1.0 - m) * k) / (m * m), (e - k) / (2.0 * m)


@njit(cache=True)
def loop_local(rho: float, z: float, current: float, a: float, mu0: float
               ) -> tuple[float, float, float, float, float, float]:
    """``(B_ρ, B_z, B_ρ/ρ, ∂B_z/∂ρ, ∂B_z/∂z, ∂B_ρ/∂ρ)`` of a loop at the origin about +z."""
    cc = mu0 * current / (2.0 * math.pi)
    p = (a + rho) ** 2 + z * z
    q = (a - rho) ** 2 + z * z
    m = 4.0 * a * rho / p
    k, dk = ellipk_d1(m)
    e = ellipke(m)[1]
    t, de = _t_and_de(m)
    sp = math.sqrt(p)
    w = a * a - rho * rho - z * z
    f = w / q
    g = k + f * e
    bz = cc * g / sp
    br_rho = 16.0 * cc * a * a * z * t / (p * sp * q)
    # derivatives of m, f, p in ρ and z
    m_r = 4.0 * a * (a * a - rho * rho + z * z) / (p * p)
    m_z = -8.0 * a * rho * z / (p * p)
    f_r = (-2.0 * rho * q + w * 2.0 * (a - rho)) / (q * q)
    f_z = (-2.0 * z * q - w * 2.0 * z) / (q * q)
    p_r = 2.0 * (a + rho)
    p_z = 2.0 * z
    g_r = dk * m_r + f_r * e + f * de * m_r
    g_z = dk * m_z + f_z * e + f * de * m_z
    bz_r = cc * (g_r / sp - 0.5 * g * p_r / (p * sp))
    bz_z = cc * (g_z / sp - 0.5 * g * p_z / (p * sp))
    br_r = -bz_z - br_rho
    return rho * br_rho, bz, br_rho, bz_r, bz_z, br_r


@njit(cache=True)
def loop_b(x, y, z, P):
    """``B`` and its Jacobian (12 numbers) of the loop ``P = [centre, axis, I, a, μ0]``."""
    d0 = x - P[0]
    d1 = y - P[1]
    d2 = z - P[2]
    n0 = P[3]
    n1 = P[4]
    n2 = P[5]
    zl = d0 * n0 + d1 * n1 + d2 * n2
    r0 = d0 - zl * n0
    r1 = d1 - zl * n1
    r2 = d2 - zl * n2
    rho = math.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
    br, bz, brr, bzr, bzz, brho = loop_local(rho, zl, P[6], P[7], P[8])
    if rho > 0.0:
        e0 = r0 / rho
        e1 = r1 / rho
        e2 = r2 / rho
    else:  # on the axis B_ρ = 0 and ∂B_z/∂ρ = 0: any direction ⟂ n serves
        e0, e1, e2 = 0.0, 0.0, 0.0
        brho = brr
    ev = (e0, e1, e2)
    nv = (n0, n1, n2)
    out = np.empty(12)
    for i in range(3):
        out[i] = br * ev[i] + bz * nv[i]
        for j in range(3):
            delta = 1.0 if i == j else 0.0
            out[3 + 3 * i + j] = (brho * ev[i] * ev[j] + bzr * (ev[i] * nv[j] + nv[i] * ev[j])
                                  + brr * (delta - nv[i] * nv[j] - ev[i] * ev[j])
                                  + bzz * nv[i] * nv[j])
    return (out[0], out[1], out[2], out[3], out[4], out[5], out[6], out[7], out[8], out[9],
            out[10], out[11])


@njit(cache=True)
def cylinder_b(x, y, z, P):
    """``B = −μ0 ∇ψ`` and its Jacobian of the cylinder
    ``P = [centre, axis, M, a, l, μ0, n_ring, nodes, weights, multipoles]``."""
    d = np.array([x - P[0], y - P[1], z - P[2]])
    nu = np.array([P[3], P[4], P[5]])
    nr = int(P[10])
    sx = P[11:11 + nr]
    sw = P[11 + nr:11 + 2 * nr]
    q = P[11 + 2 * nr:]
    psi, grad, hess = cylinder_psi_cartesian(d, nu, P[6], P[7], P[8], sx, sw, q)
    k = -P[9]
    return (k * grad[0], k * grad[1], k * grad[2],
            k * hess[0, 0], k * hess[0, 1], k * hess[0, 2],
            k * hess[1, 0], k * hess[1, 1], k * hess[1, 2],
            k * hess[2, 0], k * hess[2, 1], k * hess[2, 2])


LOOP_MAGNET = magnetic_kernel(loop_b)
CYLINDER_MAGNET = magnetic_kernel(cylinder_b)


def _axis(params: Mapping[str, Any], name: str) -> np.ndarray:
    n = np.asarray(params["axis"], dtype=float)
    if n.shape != (3,) or not np.linalg.norm(n) > 0:
        raise InputError(f"{name}: axis must be a non-zero 3-vector, got {list(params['axis'])!r}")
    return n / np.linalg.norm(n)


def _centre(params: Mapping[str, Any], name: str) -> np.ndarray:
    c = np.asarray(params["position"], dtype=float)
    if c.shape != (3,):
        raise InputError(f"{name}: position must be a 3-vector, got {list(params['position'])!r}")
    return c


def _loop(params: Mapping[str, Any], request: FieldRequest, source: object = None
          ) -> CompiledField:
    P = np.concatenate([_centre(params, "current_loop"), _axis(params, "current_loop"),
                        [params["current"], params["radius"], MU0]])
    return CompiledField("current_loop", LOOP_MAGNET, P, reads="moment", orientation=True,
                         info={"current_A": params["current"], "radius_m": params["radius"],
                               "position_m": P[:3].tolist(), "axis": P[3:6].tolist()},
                         solids=(_solid("loop", "current_loop", P, radius=params["radius"]),))


def _cylinder(params: Mapping[str, Any], request: FieldRequest, source: object = None
              ) -> CompiledField:
    magnetization = params["polarization"] / MU0
    a = params["radius"]
    half = params["length"] / 2
    sx, sw = gauss_legendre_unit(N_RING)
    q = cylinder_axial_moments(magnetization, a, half, N_MULTIPOLE)
    P = np.concatenate([_centre(params, "cylinder"), _axis(params, "cylinder"),
                        [magnetization, a, half, MU0, float(N_RING)], sx, sw, q])
    return CompiledField("cylinder", CYLINDER_MAGNET, np.ascontiguousarray(P), reads="moment",
                         orientation=True,
                         info={"polarization_T": params["polarization"], "radius_m": a,
                               "length_m": params["length"], "position_m": P[:3].tolist(),
                               "axis": P[3:6].tolist()},
                         solids=(_solid("cylinder", "cylinder", P, radius=a,
                                        height=params["length"]),))


def _solid(kind: str, name: str, P: np.ndarray, **dimensions: float) -> Solid:
    """The solid of a source centred at ``P[0:3]`` with its axis ``P[3:6]`` along local z."""
    return Solid(kind, tuple(float(x) for x in P[:3]), rotvec_of_axis(P[3:6]),  # type: ignore[arg-type]
                 {k: float(v) for k, v in dimensions.items()}, field=name)


_PLACE = (
    Param("position", "vector", "centre [m]", (0.0, 0.0, 0.0), unit="m"),
    Param("axis", "vector", "axis (normalised)", (0.0, 0.0, 1.0)),
)

CURRENT_LOOP = ExternalField(
    name="current_loop",
    doc="Exact field of a circular current loop (elliptic integrals, off axis too): "
        "U = -mu nu.B on bodies with a moment.",
    params=(Param("current", "float", "current, right-handed about the axis [A]", unit="A"),
            Param("radius", "float", "loop radius [m]", unit="m", positive=True), *_PLACE),
    reads="moment", orientation=True, build=_loop)

CYLINDER = ExternalField(
    name="cylinder",
    doc="Field of an axially magnetised cylinder magnet (end-disk rings by Gauss-Legendre, "
        "multipole series far away), valid outside the magnet: U = -mu nu.B.",
    params=(Param("polarization", "float", "polarisation mu0 M along the axis [T]", unit="T"),
            Param("radius", "float", "radius [m]", unit="m", positive=True),
            Param("length", "float", "full length [m]", unit="m", positive=True), *_PLACE),
    reads="moment", orientation=True, build=_cylinder)

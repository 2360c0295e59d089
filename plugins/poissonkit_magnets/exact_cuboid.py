"""Closed-form field of a uniformly polarised cuboid (magpylib ``Cuboid``) and its Jacobian.

``B`` is magpylib's own expression (magnetic surface charges; Yang 1990, Engel-Herbert 2005,
Camacho 2013), evaluated after magpylib's reflection of the point into the octant
``x ≥ 0, y ≤ 0, z ≤ 0`` (Cichon 2019), where no term cancels near the extension of an edge.
A reflection ``S`` maps ``B(S r; J) = S B(r; S J)`` and the Jacobian to ``S J(r; S J) S``.

The Jacobian is ``−∇∇`` of ``μ0 ψ = (1/4π) Σ_faces σ ∫∫ dA'/|r − r'|``. For a face normal to
axis ``u`` the double integral is the corner sum of ``F(u, v, w)`` with ``∂²F/∂v∂w = 1/R``
(``R = |(u, v, w)|``), ``∂F/∂v = ln(w + R)``, ``∂F/∂w = ln(v + R)``; so::

    F_vw = 1/R,  F_vv = v/(R (w + R)),  F_uv = u/(R (w + R)),  (v ↔ w for F_ww, F_uw)

and the face term is harmonic off the face, so its ``uu`` entry is ``−(vv + ww)``. Where both
corners of a pair have ``w < 0`` the terms ``ln(w + R) = ln(u² + v²) − ln(R − w)`` are used
without the first part, which cancels between the two corners: no cancellation remains except
on the cuboid's edges, where the field is singular.
"""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True, error_model="numpy")
def _log_pair_g(u, v, w1, w2):
    """``g(w) = ∂_v ln(w + R) / v`` at ``w1`` minus at ``w2`` (module docstring)."""
    uv = u * u + v * v
    total = 0.0
    for t in range(2):
        w = w1 if t == 0 else w2
        sg = 1.0 if t == 0 else -1.0
        r = math.sqrt(uv + w * w)
        if w2 < 0.0:  # both corners below: drop the cancelling ln(u² + v²)
            g = -1.0 / (r * (r - w))
        elif w >= 0.0:
            g = 1.0 / (r * (w + r))
        else:
            g = (r - w) / (r * uv)
        total += sg * g
    return total


@njit(cache=True, error_model="numpy")
def _face_hessian(u, v1, v2, w1, w2):
    """Corner sums ``(uu, uv, uw, vv, ww, vw)`` of ``∇∇F`` over the rectangle with corners
    ``v ∈ {v1, v2}``, ``w ∈ {w1, w2}`` (``v1 < v2``, ``w1 < w2``; sign ``+`` at ``(v1, w1)``)."""
    huv = 0.0
    hvv = 0.0
    huw = 0.0
    hww = 0.0
    hvw = 0.0
    for t in range(2):
        v = v1 if t == 0 else v2
        w = w1 if t == 0 else w2
        sg = 1.0 if t == 0 else -1.0
        gv = sg * _log_pair_g(u, v, w1, w2)   # pairs in w at this v
        huv += u * gv
        hvv += v * gv
        gw = sg * _log_pair_g(u, w, v1, v2)   # pairs in v at this w
        huw += u * gw
        hww += w * gw
    for t in range(2):
        for s in range(2):
            v = v1 if t == 0 else v2
            w = w1 if s == 0 else w2
            sg = 1.0 if t == s else -1.0
            hvw += sg / math.sqrt(u * u + v * v + w * w)
    return -(hvv + hww), huv, huw, hvv, hww, hvw


@njit(cache=True, error_model="numpy")
def _cuboid_b_octant(x, y, z, px, py, pz, a, b, c):
    """magpylib's ``magnet_cuboid_Bfield`` for one point of the octant ``x ≥ 0, y ≤ 0,
    z ≤ 0``."""
    xma, xpa = x - a, x + a
    ymb, ypb = y - b, y + b
    zmc, zpc = z - c, z + c
    xma2, xpa2 = xma * xma, xpa * xpa
    ymb2, ypb2 = ymb * ymb, ypb * ypb
    zmc2, zpc2 = zmc * zmc, zpc * zpc
    mmm = math.sqrt(xma2 + ymb2 + zmc2)
    pmp = math.sqrt(xpa2 + ymb2 + zpc2)
    pmm = math.sqrt(xpa2 + ymb2 + zmc2)
    mmp = math.sqrt(xma2 + ymb2 + zpc2)
    mpm = math.sqrt(xma2 + ypb2 + zmc2)
    ppp = math.sqrt(xpa2 + ypb2 + zpc2)
    ppm = math.sqrt(xpa2 + ypb2 + zmc2)
    mpp = math.sqrt(xma2 + ypb2 + zpc2)
    ff2x = (math.log((xma + mmm) * (xpa + ppm) * (xpa + pmp) * (xma + mpp))
            - math.log((xpa + pmm) * (xma + mpm) * (xma + mmp) * (xpa + ppp)))
    ff2y = (math.log((-ymb + mmm) * (-ypb + ppm) * (-ymb + pmp) * (-ypb + mpp))
            - math.log((-ymb + pmm) * (-ypb + mpm) * (ymb - mmp) * (ypb - ppp)))
    ff2z = (math.log((-zmc + mmm) * (-zmc + ppm) * (-zpc + pmp) * (-zpc + mpp))
            - math.log((-zmc + pmm) * (zmc - mpm) * (-zpc + mmp) * (zpc - ppp)))
    at = math.atan2
    ff1x = (at(ymb * zmc, xma * mmm) - at(ymb * zmc, xpa * pmm) - at(ypb * zmc, xma * mpm)
            + at(ypb * zmc, xpa * ppm) - at(ymb * zpc, xma * mmp) + at(ymb * zpc, xpa * pmp)
            + at(ypb * zpc, xma * mpp) - at(ypb * zpc, xpa * ppp))
    ff1y = (at(xma * zmc, ymb * mmm) - at(xpa * zmc, ymb * pmm) - at(xma * zmc, ypb * mpm)
            + at(xpa * zmc, ypb * ppm) - at(xma * zpc, ymb * mmp) + at(xpa * zpc, ymb * pmp)
            + at(xma * zpc, ypb * mpp) - at(xpa * zpc, ypb * ppp))
    ff1z = (at(xma * ymb, zmc * mmm) - at(xpa * ymb, zmc * pmm) - at(xma * ypb, zmc * mpm)
            + at(xpa * ypb, zmc * ppm) - at(xma * ymb, zpc * mmp) + at(xpa * ymb, zpc * pmp)
            + at(xma * ypb, zpc * mpp) - at(xpa * ypb, zpc * ppp))
    k = 1.0 / (4.0 * math.pi)
    bx = k * (px * ff1x + py * ff2z + pz * ff2y)
    by = k * (px * ff2z + py * ff1y - pz * ff2x)
    bz = k * (px * ff2y - py * ff2x + pz * ff1z)
    return bx, by, bz


@njit(cache=True, error_model="numpy")
def cuboid_local(x, y, z, P, o, out):
    """magpylib ``Cuboid`` centred at the origin: ``P[o:o+6] = (J_x, J_y, J_z, a, b, c)``
    (half side lengths)."""
    s = (-1.0 if x < 0.0 else 1.0, -1.0 if y > 0.0 else 1.0, -1.0 if z > 0.0 else 1.0)
    r = (s[0] * x, s[1] * y, s[2] * z)
    pol = (s[0] * P[o], s[1] * P[o + 1], s[2] * P[o + 2])
    half = (P[o + 3], P[o + 4], P[o + 5])
    bx, by, bz = _cuboid_b_octant(r[0], r[1], r[2], pol[0], pol[1], pol[2],
                                  half[0], half[1], half[2])
    out[0] += s[0] * bx
    out[1] += s[1] * by
    out[2] += s[2] * bz
    k = -1.0 / (4.0 * math.pi)
    for i in range(3):
        if pol[i] == 0.0:
            continue
        j = (i + 1) % 3
        m = (i + 2) % 3
        v1 = r[j] - half[j]
        v2 = r[j] + half[j]
        w1 = r[m] - half[m]
        w2 = r[m] + half[m]
        for f in range(2):
            u = r[i] - half[i] if f == 0 else r[i] + half[i]
            c = k * pol[i] * (1.0 if f == 0 else -1.0)
            huu, huv, huw, hvv, hww, hvw = _face_hessian(u, v1, v2, w1, w2)
            # entries (row, column) in the reflected frame, mapped back by S J S
            out[3 + 4 * i] += c * huu
            out[3 + 4 * j] += c * hvv
            out[3 + 4 * m] += c * hww
            out[3 + 3 * i + j] += c * huv * s[i] * s[j]
            out[3 + 3 * j + i] += c * huv * s[i] * s[j]
            out[3 + 3 * i + m] += c * huw * s[i] * s[m]
            out[3 + 3 * m + i] += c * huw * s[i] * s[m]
            out[3 + 3 * j + m] += c * hvw * s[j] * s[m]
            out[3 + 3 * m + j] += c * hvw * s[j] * s[m]

"""The exact cylinder model against magpylib 6.1 and mpmath.

Truth: magpylib's analytic field of one cylinder integrated over the other's end-face charges
(an independent Gauss–Legendre x trapezoid rule, MAGNETS.md §3 "magpylib check"), and for the
energy of coaxial cylinders the Bessel-integral form of the disk–disk energy evaluated by mpmath,
``U = mu0 pi sigma1 sigma2 a1 a2 int_0^inf J1(k a1) J1(k a2) exp(-k d) / k^2 dk`` per disk pair.
"""

from __future__ import annotations

import math

import magpylib as magpy
import mpmath as mp
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from poissonkit.conventions import MU0
from poissonkit.pairs import pair_interaction

A, H, M = 1.25e-3, 20e-3, 1.58359e6  # seed 000 magnets (MAGNETS.md §1)


def _rotation_to(nu):
    nu = np.asarray(nu, float)
    v = np.cross([0.0, 0.0, 1.0], nu)
    s = np.linalg.norm(v)
    if s < 1e-15:
        return Rotation.identity() if nu[2] > 0 else Rotation.from_rotvec([math.pi, 0, 0])
    return Rotation.from_rotvec(v / s * math.atan2(s, nu[2]))


def _face_force_torque(source, centre, nu, m, a, h, n=24, na=48):
    """Force on, and torque about ``centre`` of, a cylinder's face charges in ``source``'s field."""
    x, w = np.polynomial.legendre.leggauss(n)
    x, w = 0.5 * (x + 1), 0.5 * w
    rot = _rotation_to(nu)
    u, v = rot.apply([1.0, 0, 0]), rot.apply([0, 1.0, 0])
    phi = 2 * math.pi * (np.arange(na) + 0.5) / na
    pts, wts = [], []
    for sg in (1, -1):
        for i in range(n):
            ring = (centre + sg * 0.5 * h * nu + a * x[i] * (np.cos(phi)[:, None] * u
                                                            + np.sin(phi)[:, None] * v))
            pts.append(ring)
            wts.append(np.full(na, sg * m * a * a * x[i] * w[i] * 2 * math.pi / na))
    pts, wts = np.concatenate(pts), np.concatenate(wts)
    b = MU0 * np.reshape(source.getH(pts), (-1, 3))  # B of the source at the charges
    force = (wts[:, None] * b).sum(0)
    torque = (wts[:, None] * np.cross(pts - centre, b)).sum(0)
    return force, torque


def _magpylib_truth(rvec, n1, n2, m1, m2, a1, h1, a2, h2):
    c1 = magpy.magnet.Cylinder(magnetization=(0, 0, m1), dimension=(2 * a1, h1),
                               orientation=_rotation_to(n1))
    c2 = magpy.magnet.Cylinder(magnetization=(0, 0, m2), dimension=(2 * a2, h2),
                               position=rvec, orientation=_rotation_to(n2))
    f2, t2 = _face_force_torque(c1, np.asarray(rvec, float), n2, m2, a2, h2)
    f1, t1 = _face_force_torque(c2, np.zeros(3), n1, m1, a1, h1)
    return f1, f2, t1, t2


def _unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


CONFIGS = {
    "coaxial, 2 mm face gap": ((0, 0, 0.022), (0, 0, 1), (0, 0, 1)),
    "coaxial repelling": ((0, 0, 0.023), (0, 0, 1), (0, 0, -1)),
    "side by side, 5 mm": ((0.005, 0, 0), (0, 0, 1), (0, 0, 1)),
    "side by side antiparallel": ((0.005, 0, 0), (0, 0, 1), (0, 0, -1)),
    "T at 15 mm": ((0.015, 0, 0), (1, 0, 0), (0, 0, 1)),
    "oblique 30 mm": ((0.012, -0.01, 0.025), _unit((0.2, 0.5, 1)), _unit((-0.7, 0.1, 0.3))),
}


@pytest.mark.parametrize("name", list(CONFIGS))
def test_cylinder_forces_and_torques_match_magpylib(name):
    rvec, n1, n2 = CONFIGS[name]
    out = pair_interaction("cylinder", rvec, n1, n2, magnetization=M, radius=A, length=H)
    f1, f2, t1, t2 = _magpylib_truth(rvec, np.array(n1, float), np.array(n2, float),
                                     M, M, A, H, A, H)
    mu = M * math.pi * A * A * H
    dist = np.linalg.norm(rvec)
    tscale = MU0 * mu * mu / (4 * math.pi * dist ** 3)  # dipole torque scale (T may be 0)
    assert np.linalg.norm(out.force - f2) < 1e-9 * np.linalg.norm(f2)
    assert np.linalg.norm(-out.force - f1) < 1e-9 * np.linalg.norm(f1)
    assert np.linalg.norm(out.torque2 - t2) < 1e-9 * tscale
    assert np.linalg.norm(out.torque1 - t1) < 1e-9 * tscale
    # the truth itself balances angular momentum: T1 + T2 + r x F = 0
    assert np.linalg.norm(t1 + t2 + np.cross(rvec, f2)) < 1e-9 * tscale


def test_unequal_cylinders_match_magpylib():
    rvec, n1, n2 = (0.004, 0.011, 0.018), _unit((0, 0.3, 1)), _unit((1, 0.2, 0.4))
    p = dict(magnetization1=1.2e6, magnetization2=-0.8e6, radius1=3e-3, length1=6e-3,
             radius2=1e-3, length2=12e-3)
    out = pair_interaction("cylinder", rvec, n1, n2, **p)
    f1, f2, t1, t2 = _magpylib_truth(rvec, n1, n2, 1.2e6, -0.8e6, 3e-3, 6e-3, 1e-3, 12e-3)
    assert np.linalg.norm(out.force - f2) < 1e-9 * np.linalg.norm(f2)
    assert np.linalg.norm(out.torque1 - t1) < 1e-9 * np.linalg.norm(t1)
    assert np.linalg.norm(out.torque2 - t2) < 1e-9 * np.linalg.norm(t2)


def _coaxial_energy_mpmath(dist, m1, m2, a1, h1, a2, h2):
    with mp.workdps(25):
        total = mp.mpf(0)
        for s1 in (1, -1):
            for s2 in (1, -1):
                d = mp.mpf(dist) + s2 * mp.mpf(h2) / 2 - s1 * mp.mpf(h1) / 2
                integral = mp.quad(lambda k: mp.besselj(1, k * a1) * mp.besselj(1, k * a2)
                                   * mp.exp(-k * d) / k ** 2, [0, 1 / d, 10 / d, mp.inf])
                total += s1 * s2 * integral
        return float(mp.mpf(MU0) * mp.pi * m1 * m2 * a1 * a2 * total)


@pytest.mark.parametrize("dist,a2,h2", [(0.022, A, H), (0.05, 2e-3, 5e-3)])
def test_coaxial_energy_matches_bessel_integral(dist, a2, h2):
    out = pair_interaction("cylinder", (0, 0, dist), (0, 0, 1), (0, 0, 1), magnetization1=M,
                           magnetization2=M, radius1=A, length1=H, radius2=a2, length2=h2)
    want = _coaxial_energy_mpmath(dist, M, M, A, H, a2, h2)
    assert out.energy == pytest.approx(want, rel=1e-10)


def test_partials_match_finite_differences_of_the_energy():
    from poissonkit_magnets.cylinder import cylinder_core

    args = (M, 0.9 * M, A, 1.5e-3, 0.5 * H, 4e-3, MU0, 12, 24)
    x0 = np.array([0.03, 0.3, 0.5, 0.8])  # Gram determinant 0.26 > 0: a generic configuration
    got = cylinder_core(*x0, *args)
    for k in range(4):
        step = 1e-6 * (x0[0] if k == 0 else 1.0)
        xp, xm = x0.copy(), x0.copy()
        xp[k] += step
        xm[k] -= step
        fd = (cylinder_core(*xp, *args)[0] - cylinder_core(*xm, *args)[0]) / (2 * step)
        assert got[k + 1] == pytest.approx(fd, rel=1e-6)


def test_quadrature_is_converged_near_the_faces():
    rvec, n1, n2 = (0.0005, 0, 0.0215), (0, 0, 1), (0, 0, 1)  # 1.5 mm gap, offset axes
    base = pair_interaction("cylinder", rvec, n1, n2, magnetization=M, radius=A, length=H)
    fine = pair_interaction("cylinder", rvec, n1, n2, magnetization=M, radius=A, length=H,
                            n_radial=24, n_angular=48)
    assert np.linalg.norm(base.force - fine.force) < 1e-9 * np.linalg.norm(fine.force)


def test_thin_cylinders_tend_to_dumbbells_quadratically():
    rvec, n1, n2 = (0.01, 0.004, 0.03), _unit((0.1, 0, 1)), _unit((0.3, 0.6, 0.7))
    mu = 0.15
    db = pair_interaction("dumbbell", rvec, n1, n2, moment=mu, half_length=0.5 * H)
    errs = []
    for a in (1e-3, 5e-4):
        cyl = pair_interaction("cylinder", rvec, n1, n2, moment=mu, radius=a, length=H)
        errs.append(np.linalg.norm(cyl.force - db.force) / np.linalg.norm(db.force))
    assert errs[0] / errs[1] == pytest.approx(4.0, rel=0.05)


@pytest.mark.parametrize("seed", range(3))
def test_angular_momentum_balance(seed):
    rng = np.random.default_rng(seed)
    rvec = _unit(rng.normal(size=3)) * 0.03
    n1, n2 = (_unit(v) for v in rng.normal(size=(2, 3)))
    out = pair_interaction("cylinder", rvec, n1, n2, magnetization=M, radius=A, length=H)
    scale = np.linalg.norm(out.torque1) + np.linalg.norm(out.torque2)
    assert np.linalg.norm(out.torque1 + out.torque2 + np.cross(rvec, out.force)) < 1e-12 * scale

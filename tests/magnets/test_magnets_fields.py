"""Bodies given by their scalar potential (seed eqs. (17), (18)), current loops and
superconducting rings, against magpylib 6.1 fields and mpmath (MAGNETS.md §6, §7)."""

from __future__ import annotations

import math

import magpylib as magpy
import mpmath as mp
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from poissonkit.conventions import MU0
from poissonkit.pairs import pair_interaction

A, H, M = 1.25e-3, 20e-3, 1.58359e6


def _unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def _rotation_to(nu):
    v = np.cross([0.0, 0.0, 1.0], nu)
    s = np.linalg.norm(v)
    if s < 1e-15:
        return Rotation.identity() if nu[2] > 0 else Rotation.from_rotvec([math.pi, 0, 0])
    return Rotation.from_rotvec(v / s * math.atan2(s, nu[2]))


def _b(source, pts):
    return MU0 * np.reshape(source.getH(np.atleast_2d(pts)), (-1, 3))


def _grad_mb(source, x, m, rel=1e-6):
    """grad(m . B) at x, 4th-order central differences of magpylib's field."""
    h = rel * np.linalg.norm(x)
    out = np.zeros(3)
    for k in range(3):
        st = np.zeros(3)
        st[k] = h
        mb = _b(source, [x + 2 * st, x + st, x - st, x - 2 * st]) @ m
        out[k] = (-mb[0] + 8 * mb[1] - 8 * mb[2] + mb[3]) / (12 * h)
    return out


def _torque_on_cylinder(field_source, nu, a, h, m, n=24, na=48):
    x, w = np.polynomial.legendre.leggauss(n)
    x, w = 0.5 * (x + 1), 0.5 * w
    rot = _rotation_to(nu)
    u, v = rot.apply([1.0, 0, 0]), rot.apply([0, 1.0, 0])
    phi = 2 * math.pi * (np.arange(na) + 0.5) / na
    torque = np.zeros(3)
    for sg in (1, -1):
        for i in range(n):
            pts = sg * 0.5 * h * nu + a * x[i] * (np.cos(phi)[:, None] * u
                                                  + np.sin(phi)[:, None] * v)
            wts = sg * m * a * a * x[i] * w[i] * 2 * math.pi / na
            torque += wts * np.cross(pts, _b(field_source, pts)).sum(0)
    return torque


DIPOLE_CASES = {
    "far, multipole series": ((0.02, 0.01, 0.045), _unit((0.1, 0.2, 1)), _unit((1, -0.3, 0.2))),
    "near, beside the magnet": ((0.004, 0.001, 0.003), (0, 0, 1), _unit((0.4, 0.3, 0.8))),
    "3 mm above the face": ((0.0003, 0, 0.013), (0, 0, 1), _unit((0.1, 0, 1))),
}


@pytest.mark.parametrize("name", list(DIPOLE_CASES))
def test_dipole_in_cylinder_field_matches_magpylib(name):
    rvec, n1, n2 = (np.asarray(v, float) for v in DIPOLE_CASES[name])
    mu = 0.02
    out = pair_interaction("dipole_cylinder_field", rvec, n1, n2, magnetization1=M,
                           radius1=A, length1=H, moment2=mu)
    cyl = magpy.magnet.Cylinder(magnetization=(0, 0, M), dimension=(2 * A, H),
                                orientation=_rotation_to(n1))
    b = _b(cyl, rvec)[0]
    m = mu * n2
    assert out.energy == pytest.approx(-m @ b, rel=1e-10)
    f = _grad_mb(cyl, rvec, m)
    assert np.linalg.norm(out.force - f) < 1e-7 * np.linalg.norm(f)
    assert np.linalg.norm(out.torque2 - np.cross(m, b)) < 1e-10 * np.linalg.norm(m) * np.linalg.norm(b)
    dip = magpy.misc.Dipole(moment=m, position=rvec)
    t1 = _torque_on_cylinder(dip, n1, A, H, M)
    assert np.linalg.norm(out.torque1 - t1) < 1e-8 * np.linalg.norm(t1)


@pytest.mark.parametrize("name", list(DIPOLE_CASES))
def test_dumbbell_in_cylinder_field_matches_magpylib(name):
    rvec, n1, n2 = (np.asarray(v, float) for v in DIPOLE_CASES[name])
    mu, l2 = 0.02, 1e-3
    out = pair_interaction("dumbbell_cylinder_field", rvec, n1, n2, magnetization1=M,
                           radius1=A, length1=H, moment2=mu, half_length2=l2)
    cyl = magpy.magnet.Cylinder(magnetization=(0, 0, M), dimension=(2 * A, H),
                                orientation=_rotation_to(n1))
    kap = mu / (2 * l2)
    poles = [rvec + l2 * n2, rvec - l2 * n2]
    bp = _b(cyl, poles)
    force = kap * (bp[0] - bp[1])
    torque2 = np.cross(l2 * n2, kap * bp[0]) + np.cross(-l2 * n2, -kap * bp[1])
    # U = mu0 kappa (psi(+) - psi(-)) = -kappa int_{-}^{+} B . dl along the dumbbell
    t, w = np.polynomial.legendre.leggauss(40)
    seg = rvec + np.outer(t * l2, n2)
    energy = -kap * l2 * (w @ (_b(cyl, seg) @ n2))
    assert out.energy == pytest.approx(energy, rel=1e-9)
    assert np.linalg.norm(out.force - force) < 1e-10 * np.linalg.norm(force)
    assert np.linalg.norm(out.torque2 - torque2) < 1e-10 * np.linalg.norm(torque2)


def test_dumbbell_in_cylinder_field_on_axis_uses_closed_form_psi():
    # MAGNETS.md §7: psi(0, z) = M/2 [sqrt((z-l)^2+a^2) - |z-l| - sqrt((z+l)^2+a^2) + |z+l|]
    l = H / 2

    def psi(z):
        return M / 2 * (math.hypot(z - l, A) - abs(z - l) - math.hypot(z + l, A) + abs(z + l))

    mu, l2, dist = 0.03, 4e-3, 0.016
    out = pair_interaction("dumbbell_cylinder_field", (0, 0, dist), (0, 0, 1), (0, 0, 1),
                           magnetization1=M, radius1=A, length1=H, moment2=mu, half_length2=l2)
    want = MU0 * mu / (2 * l2) * (psi(dist + l2) - psi(dist - l2))
    assert out.energy == pytest.approx(want, rel=1e-12)


def test_dipole_in_loop_field_matches_magpylib():
    cur, a = 3.0, 0.01
    rvec, n1, n2 = np.array([0.004, -0.003, 0.006]), _unit((0.2, 0, 1)), _unit((1, 1, 0.3))
    mu = 0.05
    out = pair_interaction("dipole_loop", rvec, n1, n2, current1=cur, radius1=a, moment2=mu)
    loop = magpy.current.Circle(current=cur, diameter=2 * a, orientation=_rotation_to(n1))
    b = _b(loop, rvec)[0]
    m = mu * n2
    assert out.energy == pytest.approx(-m @ b, rel=1e-12)
    f = _grad_mb(loop, rvec, m)
    assert np.linalg.norm(out.force - f) < 1e-8 * np.linalg.norm(f)
    assert np.linalg.norm(out.torque2 - np.cross(m, b)) < 1e-12 * mu * np.linalg.norm(b)
    # torque on the loop: I oint y x (dl x B_dipole(y)), trapezoid rule
    rot = _rotation_to(n1)
    phi = 2 * math.pi * np.arange(400) / 400
    y = a * (np.cos(phi)[:, None] * rot.apply([1.0, 0, 0]) + np.sin(phi)[:, None] * rot.apply([0, 1.0, 0]))
    dl = a * (2 * math.pi / 400) * (-np.sin(phi)[:, None] * rot.apply([1.0, 0, 0])
                                    + np.cos(phi)[:, None] * rot.apply([0, 1.0, 0]))
    bd = _b(magpy.misc.Dipole(moment=m, position=rvec), y)
    t1 = cur * np.cross(y, np.cross(dl, bd)).sum(0)
    assert np.linalg.norm(out.torque1 - t1) < 1e-9 * np.linalg.norm(t1)


def test_loop_field_closed_form_matches_magpylib():
    from poissonkit_magnets.fields import loop_psi_local

    loop = magpy.current.Circle(current=2.0, diameter=0.02)
    rng = np.random.default_rng(3)
    for rho, z in rng.uniform([0.0, -0.02], [0.03, 0.02], size=(20, 2)):
        pr, pz = loop_psi_local(rho, z, 2.0, 0.01)
        hh = loop.getH([rho, 0, z])
        assert np.allclose([-pr, -pz], [hh[0], hh[2]], rtol=0, atol=1e-12 * np.linalg.norm(hh))


def _maxwell_mp(a, b, d):
    """Maxwell's M at the current mpmath precision (callers use 30 digits)."""
    k2 = mp.mpf(4) * a * b / ((a + b) ** 2 + mp.mpf(d) ** 2)
    k = mp.sqrt(k2)
    return mp.mpf(MU0) * mp.sqrt(mp.mpf(a) * b) * ((2 / k - k) * mp.ellipk(k2)
                                                    - 2 / k * mp.ellipe(k2))


@pytest.mark.parametrize("d", [0.002, 0.02, 0.2, 2.0])
def test_coaxial_mutual_inductance_is_stable_at_small_modulus(d):
    from poissonkit_magnets.loops import mutual_inductance_coaxial

    a, b = 0.01, 0.006
    with mp.workdps(30):
        want = float(_maxwell_mp(a, b, d))
    assert mutual_inductance_coaxial(a, b, d, MU0) == pytest.approx(want, rel=1e-13)


@pytest.mark.parametrize("d", [0.004, 0.03])
def test_coaxial_loops_energy_and_force_match_maxwell(d):
    a, b, i1, i2 = 0.01, 0.006, 2.0, -3.0
    out = pair_interaction("loops", (0, 0, d), (0, 0, 1), (0, 0, 1), current1=i1, current2=i2,
                           radius1=a, radius2=b)
    with mp.workdps(30):
        mut = float(_maxwell_mp(a, b, d))
        fz = i1 * i2 * float(mp.diff(lambda x: _maxwell_mp(a, b, x), d))
    assert out.energy == pytest.approx(-i1 * i2 * mut, rel=1e-12)
    assert out.force[2] == pytest.approx(fz, rel=1e-10)
    assert np.linalg.norm(out.force[:2]) < 1e-12 * abs(fz)


def test_tilted_loops_match_magpylib_flux_and_force():
    a, b, i1, i2 = 0.01, 0.007, 1.5, 2.5
    rvec, n1, n2 = np.array([0.006, 0.002, 0.012]), _unit((0.1, 0.2, 1)), _unit((0.5, -0.2, 1))
    out = pair_interaction("loops", rvec, n1, n2, current1=i1, current2=i2, radius1=a,
                           radius2=b)
    loop1 = magpy.current.Circle(current=i1, diameter=2 * a, orientation=_rotation_to(n1))
    rot = _rotation_to(n2)
    u, v = rot.apply([1.0, 0, 0]), rot.apply([0, 1.0, 0])
    # flux of loop 1's field through loop 2's disk (Gauss-Legendre x trapezoid)
    x, w = np.polynomial.legendre.leggauss(40)
    x, w = 0.5 * (x + 1), 0.5 * w
    phi = 2 * math.pi * (np.arange(80) + 0.5) / 80
    flux = 0.0
    for xi, wi in zip(x, w):
        pts = rvec + b * xi * (np.cos(phi)[:, None] * u + np.sin(phi)[:, None] * v)
        flux += wi * b * b * xi * (2 * math.pi / 80) * (_b(loop1, pts) @ n2).sum()
    assert out.energy == pytest.approx(-i2 * flux, rel=1e-10)
    # force on loop 2: I2 oint dl x B1
    phi = 2 * math.pi * np.arange(300) / 300
    y = rvec + b * (np.cos(phi)[:, None] * u + np.sin(phi)[:, None] * v)
    dl = b * (2 * math.pi / 300) * (-np.sin(phi)[:, None] * u + np.cos(phi)[:, None] * v)
    f = i2 * np.cross(dl, _b(loop1, y)).sum(0)
    t2 = i2 * np.cross(y - rvec, np.cross(dl, _b(loop1, y))).sum(0)
    assert np.linalg.norm(out.force - f) < 1e-10 * np.linalg.norm(f)
    assert np.linalg.norm(out.torque2 - t2) < 1e-10 * np.linalg.norm(t2)


def test_superconducting_rings_keep_their_flux_and_feel_the_induced_currents():
    from poissonkit_magnets.loops import mutual_inductance_coaxial, ring_currents, self_inductance

    a, b, wire = 0.01, 0.008, 2e-4
    phi1, phi2 = 3e-7, -1e-7
    l1, l2 = self_inductance(a, wire), self_inductance(b, wire)
    p = dict(flux1=phi1, flux2=phi2, radius1=a, radius2=b, wire_radius=wire)
    for d in (0.003, 0.01):
        out = pair_interaction("superconducting_rings", (0, 0, d), (0, 0, 1), (0, 0, 1), **p)
        mut = mutual_inductance_coaxial(a, b, d, MU0)
        i1, i2 = ring_currents(d, 1.0, 1.0, 1.0, phi1, phi2, a, b, l1, l2, MU0, 96)
        assert l1 * i1 + mut * i2 == pytest.approx(phi1, rel=1e-12)  # flux kept
        assert mut * i1 + l2 * i2 == pytest.approx(phi2, rel=1e-12)
        # F = -dU/dd at constant flux = I1 I2 dM/dd (mpmath derivative of Maxwell's M)
        with mp.workdps(30):
            fz = i1 * i2 * float(mp.diff(lambda x: _maxwell_mp(a, b, x), d))
        assert out.force[2] == pytest.approx(fz, rel=1e-9)
        h = 1e-7
        up = pair_interaction("superconducting_rings", (0, 0, d + h), (0, 0, 1), (0, 0, 1), **p)
        dn = pair_interaction("superconducting_rings", (0, 0, d - h), (0, 0, 1), (0, 0, 1), **p)
        assert out.force[2] == pytest.approx(-(up.energy - dn.energy) / (2 * h), rel=1e-6)


FIELD_MODELS = {
    "dipole_cylinder_field": dict(magnetization1=M, radius1=A, length1=H, moment2=0.02),
    "dumbbell_cylinder_field": dict(magnetization1=M, radius1=A, length1=H, moment2=0.02,
                                    half_length2=3e-3),
    "dipole_loop": dict(current1=2.0, radius1=0.01, moment2=0.02),
    "loops": dict(current1=2.0, current2=-1.0, radius1=0.01, radius2=0.006),
    "superconducting_rings": dict(flux1=2e-7, flux2=1e-7, radius1=0.01, radius2=0.006,
                                  wire_radius1=1e-4, wire_radius2=1e-4),
}


@pytest.mark.parametrize("name", list(FIELD_MODELS))
def test_field_model_partials_match_finite_differences_of_the_energy(name):
    from poissonkit.plugin import potential
    from poissonkit_magnets.models import evaluate

    params = potential(name).resolve_params(FIELD_MODELS[name])
    x0 = np.array([0.025, 0.3, 0.5, 0.8])  # generic: Gram determinant 0.26 > 0
    got = evaluate(name, params, *x0)
    for k in range(4):
        step = 1e-6 * (x0[0] if k == 0 else 1.0)
        xp, xm = x0.copy(), x0.copy()
        xp[k] += step
        xm[k] -= step
        fd = (evaluate(name, params, *xp)[0] - evaluate(name, params, *xm)[0]) / (2 * step)
        scale = abs(got[0]) / (x0[0] if k == 0 else 1.0)
        assert abs(got[k + 1] - fd) < 1e-6 * max(abs(fd), scale)


def test_seed_18_reduces_to_16_for_a_thin_source():
    # FORMULAS.md §1: (18) with the factor eps reproduces (16) when psi is a dumbbell's; a thin
    # cylinder's psi tends to that of the dumbbell with l = h/2, with an O(a^2) error.
    rvec, n1, n2 = np.array([0.006, 0.004, 0.02]), _unit((0.1, 0.3, 1)), _unit((0.5, -0.2, 0.8))
    mu1, mu2, l2 = 0.05, 0.02, 3e-3
    want = pair_interaction("dumbbell", rvec, n1, n2, moment1=mu1, moment2=mu2,
                            half_length1=H / 2, half_length2=l2)
    errs = []
    for a in (4e-4, 2e-4):
        got = pair_interaction("dumbbell_cylinder_field", rvec, n1, n2,
                               magnetization1=mu1 / (math.pi * a * a * H), radius1=a, length1=H,
                               moment2=mu2, half_length2=l2)
        errs.append(max(abs(got.energy - want.energy) / abs(want.energy),
                        np.linalg.norm(got.force - want.force) / np.linalg.norm(want.force)))
    assert errs[0] < 1e-2
    assert errs[0] / errs[1] == pytest.approx(4.0, rel=0.05)

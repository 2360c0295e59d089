"""Dipole and dumbbell models against independent truth.

Oracles: FORMULAS.md §1 (dumbbell U at a rational point, the (17) value as the l''->0 limit of
(16)), sympy differentiation of the closed forms, magpylib 6.1 dipole fields.
"""

from __future__ import annotations

import math

import magpylib as magpy
import numpy as np
import pytest
import sympy as sp

from poissonkit.conventions import MU0
from poissonkit.pairs import pair_interaction
from poissonkit_magnets.analytic import (
    C1, C2, C3, R, dipole_core, dipole_expr, dumbbell_core, dumbbell_expr,
    effective_half_length,
)

# FORMULAS.md §1, "U of (16) as a function": r = 7/3, c' = 1/5, c'' = -2/7, c''' = 3/11
POINT = (7 / 3, 1 / 5, -2 / 7, 3 / 11)


def test_dumbbell_energy_matches_formulas_oracle():
    # l' = 1/2, l'' = 1/3, kappa' = 2, kappa'' = 3, mu0 = 1  (moments mu = 2 kappa l)
    u = dumbbell_core(*POINT, 2 * 2 * 0.5, 2 * 3 / 3, 0.5, 1 / 3, 1.0)[0]
    assert u == pytest.approx(0.010084745574149882902, rel=1e-14)


def test_dumbbell_tends_to_seed_17_oracle_as_probe_shrinks():
    # FORMULAS.md §1: (17) with body 1 the dumbbell (l' = 1/2, kappa' = 2) and a dipole mu = 3
    # is the l'' -> 0 limit of (16); the error of (16) is O(l''^2).
    oracle = 0.015520467726623271130
    errs = [abs(dumbbell_core(*POINT, 2.0, 3.0, 0.5, l2, 1.0)[0] - oracle) for l2 in (2e-3, 1e-3)]
    assert errs[1] < 1e-6
    assert errs[0] / errs[1] == pytest.approx(4.0, rel=0.01)


def test_dumbbell_tends_to_dipole_with_quadratic_error():
    args = (0.05, 0.3, -0.6, 0.2)
    ud = dipole_core(*args, 0.7, 1.3, MU0)
    errs = []
    for l in (4e-4, 2e-4):
        ub = dumbbell_core(*args, 0.7, 1.3, l, 1.5 * l, MU0)
        errs.append(max(abs(ub[i] - ud[i]) / abs(ud[i]) for i in range(5)))
    assert errs[1] < 1e-3
    assert errs[0] / errs[1] == pytest.approx(4.0, rel=0.02)


@pytest.mark.parametrize("which", ["dipole", "dumbbell"])
def test_compiled_partials_equal_sympy_derivatives(which):
    if which == "dipole":
        expr = dipole_expr(0.7, -1.1, MU0)
        got = dipole_core(*POINT, 0.7, -1.1, MU0)
    else:
        expr = dumbbell_expr(0.7, -1.1, 0.3, 0.45, MU0)
        got = dumbbell_core(*POINT, 0.7, -1.1, 0.3, 0.45, MU0)
    at = dict(zip((R, C1, C2, C3), (sp.Rational(7, 3), sp.Rational(1, 5), sp.Rational(-2, 7),
                                    sp.Rational(3, 11))))
    want = [expr] + [sp.diff(expr, s) for s in (R, C1, C2, C3)]
    for g, w in zip(got, want):
        assert g == pytest.approx(float(w.subs(at).evalf(30)), rel=1e-12, abs=1e-300)


def _dipole_truth(rvec, m1, m2):
    """Force on 2 and both torques from magpylib's Dipole field (H, times mu0)."""
    def b_of(moment, at):
        return MU0 * np.reshape(magpy.misc.Dipole(moment=moment).getH(np.atleast_2d(at)), (-1, 3))

    h = 1e-6 * np.linalg.norm(rvec)
    force = np.zeros(3)
    for k in range(3):
        step = np.zeros(3)
        step[k] = h
        pts = np.array([rvec + 2 * step, rvec + step, rvec - step, rvec - 2 * step])
        mb = b_of(m1, pts) @ m2
        force[k] = (-mb[0] + 8 * mb[1] - 8 * mb[2] + mb[3]) / (12 * h)
    t2 = np.cross(m2, b_of(m1, rvec)[0])
    t1 = np.cross(m1, b_of(m2, -rvec)[0])
    return force, t1, t2


@pytest.mark.parametrize("seed", range(4))
def test_dipole_force_and_torques_match_magpylib(seed):
    rng = np.random.default_rng(seed)
    rvec = rng.normal(size=3) * 0.05
    n1, n2 = (v / np.linalg.norm(v) for v in rng.normal(size=(2, 3)))
    mu1, mu2 = 0.155, 0.08
    out = pair_interaction("dipole", rvec, n1, n2, moment1=mu1, moment2=mu2)
    f, t1, t2 = _dipole_truth(rvec, mu1 * n1, mu2 * n2)
    scale_f = np.linalg.norm(f)
    assert np.linalg.norm(out.force - f) < 1e-8 * scale_f
    assert np.linalg.norm(out.torque1 - t1) < 1e-10 * np.linalg.norm(t1)
    assert np.linalg.norm(out.torque2 - t2) < 1e-10 * np.linalg.norm(t2)
    assert out.energy == pytest.approx(-(mu2 * n2) @ (MU0 * magpy.misc.Dipole(
        moment=mu1 * n1).getH(rvec)), rel=1e-10)


def test_dumbbell_forces_equal_explicit_pole_sums():
    # Four Coulomb pole pairs, mu0 q_a q_b / (4 pi d^2) along d, like poles repel.
    rng = np.random.default_rng(7)
    rvec = np.array([0.01, -0.02, 0.025])
    n1, n2 = (v / np.linalg.norm(v) for v in rng.normal(size=(2, 3)))
    mu1, mu2, l1, l2 = 0.15, 0.05, 0.01, 0.004
    out = pair_interaction("dumbbell", rvec, n1, n2, moment1=mu1, moment2=mu2,
                           half_length1=l1, half_length2=l2)
    force = np.zeros(3)
    t1 = np.zeros(3)
    t2 = np.zeros(3)
    energy = 0.0
    for s1 in (1, -1):
        for s2 in (1, -1):
            qa, qb = s1 * mu1 / (2 * l1), s2 * mu2 / (2 * l2)
            pa, pb = s1 * l1 * n1, rvec + s2 * l2 * n2
            d = pb - pa
            fb = MU0 * qa * qb * d / (4 * math.pi * np.linalg.norm(d) ** 3)
            energy += MU0 * qa * qb / (4 * math.pi * np.linalg.norm(d))
            force += fb
            t2 += np.cross(pb - rvec, fb)
            t1 += np.cross(pa, -fb)
    assert out.energy == pytest.approx(energy, rel=1e-13)
    assert np.allclose(out.force, force, rtol=0, atol=1e-12 * np.linalg.norm(force))
    assert np.allclose(out.torque1, t1, rtol=0, atol=1e-12 * np.linalg.norm(t1))
    assert np.allclose(out.torque2, t2, rtol=0, atol=1e-12 * np.linalg.norm(t2))


def test_octupole_dumbbell_matches_the_cylinder_octupole_moment():
    # MAGNETS.md §2: q3 of a cylinder is mu (l^2 - 3 a^2/4); a dumbbell has mu l^2.
    a, h = 1.25e-3, 0.02
    le = effective_half_length(a, h)
    # independent: a z-dipole at x' adds d/dz'(r'^3 P3) = 3 r'^2 P2 to q3, so
    # q3 = 3 M int (z^2 - s^2/2) dV, integrated here by Gauss-Legendre
    zs, wz = np.polynomial.legendre.leggauss(20)
    ss, ws = np.polynomial.legendre.leggauss(20)
    z = 0.5 * h * zs
    s = 0.5 * a * (ss + 1)
    zz, sss = np.meshgrid(z, s, indexing="ij")
    integrand = 3 * (zz ** 2 - 0.5 * sss ** 2) * 2 * math.pi * sss  # 3 r^2 P2(cos)
    vol_int = (wz[:, None] * ws[None, :] * integrand).sum() * 0.5 * h * 0.5 * a
    q3_per_m = vol_int / (math.pi * a * a * h)
    assert le ** 2 == pytest.approx(q3_per_m, rel=1e-12)


def test_octupole_dumbbell_rejects_flat_magnets():
    from poissonkit.errors import InputError

    with pytest.raises(InputError, match="sqrt\\(3\\)"):
        pair_interaction("dumbbell_octupole", (0, 0, 1), (0, 0, 1), (0, 0, 1), moment=1.0,
                         radius=0.02, length=0.01)

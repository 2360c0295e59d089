"""Routh sphere, survey (86)–(90): vertical and horizontal rank-2 bivectors, Proposition 5 and the
choice of alpha, beta in (89)–(90), checked in exact arithmetic at rational points of the sphere,
with negative controls that must fail."""

from __future__ import annotations

from types import SimpleNamespace

import pytest
import sympy as sp
from poissonkit_nonholonomic import routh_horizontal as rh
from poissonkit_nonholonomic.claims import CLAIMS
from poissonkit_nonholonomic.routh import routh_parts

PARAMS = dict(R=2, a=sp.Rational(1, 2), m=3, I1=5, I3=7, u=10)
POINT = [sp.Rational(-40, 297), sp.Rational(128, 297), sp.Rational(-265, 297)]


def _system(casimir, **over):
    return SimpleNamespace(params={**PARAMS, **over, "casimir": casimir})


def test_point_is_on_sphere():
    assert sum(x**2 for x in POINT) == 1


def test_claims_registered():
    assert set(rh.HORIZONTAL_CLAIMS) <= set(CLAIMS["nh.routh_sphere_rank4"])


@pytest.mark.parametrize("casimir", ["jellett", "routh"])
@pytest.mark.parametrize("claim", rh.HORIZONTAL_CLAIMS, ids=lambda c: c.__name__)
def test_claims_hold(casimir, claim):
    ok, detail, _ = claim(_system(casimir))
    assert ok, detail


def test_claims_hold_other_parameters():
    s = _system("jellett", R=1, a=sp.Rational(-1, 3), m=2, I1=3, I3=2, u=0)
    for claim in rh.HORIZONTAL_CLAIMS:
        ok, detail, _ = claim(s)
        assert ok, (claim.__name__, detail)


@pytest.mark.parametrize("k", [1, 2])
def test_no_constant_coefficient(k):
    """The certificate: lambda is unique at each point and differs between gamma3 = 4/5, 3/5;
    in particular lambda = 1 (the coefficient J_k read in (90)) fails."""
    p = routh_parts(**PARAMS)
    lams = [rh.point_data(p, g, k)["lam"] for g in ([sp.Rational(3, 5), 0, sp.Rational(4, 5)],
                                                  [sp.Rational(4, 5), 0, sp.Rational(3, 5)])]
    assert sp.simplify(lams[0] - lams[1]) != 0
    assert all(sp.simplify(lam - 1) != 0 for lam in lams)


@pytest.mark.parametrize("k", [1, 2])
def test_wrong_coefficient_fails(k):
    """Negative control: X = nu (P_v + beta Pbar) dH + lambda' J_k X_S fails for lambda' != lambda."""
    p = routh_parts(**PARAMS)
    d = rh.point_data(p, POINT, k)
    lam, nu = d["lam"] * sp.Rational(11, 10), d["nu"]
    rem = d["X"] - nu * (d["Y"].dot(d["dH"]) * d["XS"] + d["b"] / nu * d["PbdH"]) \
        - lam * d["Jk"] * d["XS"]
    assert any(sp.simplify(sp.radsimp(sp.expand(r))) != 0 for r in rem)


def test_gamma3_not_a_casimir_of_horizontal():
    """Negative control: gamma3 (a Casimir of the vertical part) is not one of Pbar."""
    d = rh.point_data(routh_parts(**PARAMS), POINT, 1)
    assert d["V1"][2] != 0


def test_vertical_generates_symmetry_and_field_is_not_vertical():
    """P_v dH is a multiple of X_S, but X is not (the horizontal part is needed)."""
    d = rh.point_data(routh_parts(**PARAMS), POINT, 2)
    assert sp.simplify(d["b"]) != 0

"""Survey Remark 9, (48): the Chaplygin ball on T*S^2 in sphero-conical coordinates.

Independent truth: the coefficients of (48) are derived from the ball's own integrals
(M, omega) and (M, M) (the registered nh.chaplygin_ball); the canonical bracket must make them
commute (the survey: integrable, in involution for the canonical bracket), and the separated
variables must be s_k = (1 + d u_k)/u_k. With d != 1 the other reading of the garbled OCR,
d (1 + u_k)/u_k, must fail.
"""

from __future__ import annotations

import pytest
import sympy as sp
from poissonkit_nonholonomic.ball import chaplygin_ball
from poissonkit_nonholonomic.separation import (
    chaplygin_separation_48,
    chaplygin_spheroconical,
    separated_variables_48,
)

from poissonkit.errors import InputError
from poissonkit.structure.checks import in_involution


@pytest.fixture(scope="module")
def sph():
    return chaplygin_spheroconical(2, 3, 5, 2)


def test_integrals_commute_for_the_canonical_bracket(sph):
    H1, H2 = sph.hamiltonian * 2, sph.integrals["H2=(M,M)"]
    assert in_involution(sph.structure, [H1, H2]).holds
    # control: a perturbation that depends on u_1 only breaks it
    assert not in_involution(sph.structure, [H1, H2 + sph.coords[0]]).holds


def test_separated_variables(sph):
    ok, detail, _ = separated_variables_48(sph)
    assert ok, detail


def test_other_reading_of_the_roots_fails(sph):
    u, p = sph.coords[:2], sph.coords[2:]
    d = sph.params["d"]
    H1, H2 = sph.hamiltonian * 2, sph.integrals["H2=(M,M)"]
    f1 = [sp.diff(H1, p[0], 2) / 2, sp.diff(H1, p[0], p[1]) / 2, sp.diff(H1, p[1], 2) / 2]
    f2 = [sp.diff(H2, p[0], 2) / 2, sp.diff(H2, p[0], p[1]) / 2, sp.diff(H2, p[1], 2) / 2]
    s = sp.Symbol("s")
    pencil = (f2[1] - f1[1] * s) ** 2 - (f2[0] - f1[0] * s) * (f2[2] - f1[2] * s)
    assert sp.cancel(pencil.subs(s, d * (1 + u[0]) / u[0])) != 0
    assert sp.cancel(pencil.subs(s, (1 + d * u[0]) / u[0])) == 0


@pytest.mark.parametrize("I, d", [((1, 2, 3), 1), ((2, 3, 5), 2), ((5, 3, 4), sp.Rational(1, 3))])
def test_claim_on_the_registered_ball(I, d):
    ok, detail, method = chaplygin_separation_48(chaplygin_ball(*I, d))
    assert ok, detail
    assert method.startswith("exact")


def test_equal_moments_are_refused():
    with pytest.raises(InputError):
        chaplygin_spheroconical(1, 1, 3, 1)

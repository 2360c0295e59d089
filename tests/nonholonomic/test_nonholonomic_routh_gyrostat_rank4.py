"""Survey (96): the shifted rank-4 bivector of the Routh sphere with an axial rotor.

Independent truth: the rotor's equations of motion (49)/(95) (``M x omega`` replaced by
``(M + S) x omega``), the shifted integrals derived and tested in
``test_nonholonomic_routh_gyrostat.py``, and the rotor-free decomposition (Proposition 5).
The opposite shift is a negative control that must fail.
"""

from __future__ import annotations

import pytest
import sympy as sp
from poissonkit_nonholonomic.routh import _rank4, routh_gyrostat_parts
from poissonkit_nonholonomic.routh_gyrostat import (
    routh_gyrostat_rank4,
    shifted_bivector,
    shifted_bivector_96,
    shifted_integrals_96,
)

from poissonkit.errors import InputError
from poissonkit.structure.bivector import Bivector
from poissonkit.structure.casimirs import is_casimir
from poissonkit.structure.checks import check_vanishing
from poissonkit.structure.jacobi import check_jacobi


@pytest.fixture(scope="module")
def jellett():
    return routh_gyrostat_rank4()


def test_claims_hold(jellett):
    for claim in (shifted_bivector_96, shifted_integrals_96):
        ok, detail, _method = claim(jellett)
        assert ok, detail


def test_shifted_bivector_is_poisson_with_the_shifted_casimir(jellett):
    P = jellett.structure
    res = check_jacobi(P, method="random", seed=3)
    assert res.is_poisson and res.false_positive_bound < 1e-6
    (J1s,) = [v for k, v in jellett.casimirs.items() if k.startswith("J1_s")]
    gam = P.coords[:3]
    assert is_casimir(P, J1s, constraints=(sum(g**2 for g in gam) - 1,)).holds
    # the unshifted Jellett integral is not a Casimir of P_s (s != 0)
    assert not is_casimir(P, J1s - jellett.params["s"] * jellett.params["R"] * gam[2]).holds


def test_opposite_shift_fails():
    """The reading of (96)'s block is fixed by the checks: the other sign breaks them."""
    gp = routh_gyrostat_parts()
    q = gp["params"]
    P, _, _ = _rank4(q["R"], q["a"], q["m"], q["I1"], q["I3"], "jellett")
    coords = list(gp["gamma"]) + list(gp["M"])
    wrong = shifted_bivector(P, q["s"], sign=-1)
    dJ = sp.Matrix([sp.diff(gp["J1"], x) for x in coords])
    res = check_vanishing({f"{{{x}, J1_s}}": e for x, e in zip(coords, wrong * dJ)},
                          (sum(g**2 for g in gp["gamma"]) - 1,), coords=coords,
                          method="random", seed=2)
    assert not res.holds


def test_zero_rotor_is_the_rotor_free_bivector(jellett):
    sys0 = routh_gyrostat_rank4(s=0)
    from poissonkit_nonholonomic.routh import routh_sphere_rank4

    assert sys0.structure.matrix == routh_sphere_rank4().structure.matrix
    assert Bivector.from_matrix(jellett.structure.matrix - sys0.structure.matrix,
                                sys0.coords).matrix[3, 4] == jellett.params["s"]


def test_bad_arguments():
    with pytest.raises(InputError):
        routh_gyrostat_rank4(casimir="other")
    with pytest.raises(InputError):
        shifted_bivector(sp.zeros(6), 1, sign=2)


def test_routh_casimir_choice():
    sys_ = routh_gyrostat_rank4(casimir="routh")
    for claim in (shifted_bivector_96, shifted_integrals_96):
        ok, detail, _method = claim(sys_)
        assert ok, detail

"""The non-holonomic systems are registered through the plugin hooks like any other plugin."""

from __future__ import annotations

import pytest

from poissonkit.errors import InputError
from poissonkit.plugin import entries, plugin_reports, system
from poissonkit.structure.system import HamiltonianSystem

EXPECTED = {"nh.chaplygin_ball", "nh.chaplygin_gyrostat", "nh.chaplygin_ball_sphere_bmf",
            "nh.veselova", "nh.veselova_gyrostat", "nh.routh_sphere", "nh.suslov",
            "nh.suslov_rank2", "nh.suslov_potential", "nh.generalized_chaplygin", "nh.p_gf",
            "nh.suslov_rank4", "nh.ball_on_paraboloid", "nh.routh_sphere_rank4",
            "nh.ball_on_paraboloid_rank4", "nh.routh_gyrostat_rank4", "nh.chaplygin_spheroconical"}


def test_plugin_loads_and_contributes_every_system():
    report = next(r for r in plugin_reports() if r.name == "nonholonomic")
    assert report.status == "ok", report.error
    assert set(report.contributions["system"]) == EXPECTED
    tagged = {n for n, e in entries("system").items() if "nonholonomic" in e.tags}
    assert tagged == EXPECTED


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_each_entry_builds_a_named_hamiltonian_system_from_default_parameters(name):
    entry = system(name)
    built = entry.build(**entry.resolve_params({}))
    assert isinstance(built, HamiltonianSystem)
    assert built.name == name and built.doc


def test_user_parameters_are_validated():
    entry = system("nh.chaplygin_ball")
    with pytest.raises(InputError):
        entry.resolve_params({"I1": -1.0})
    s = entry.build(**entry.resolve_params({"I1": 0.5, "d": 2}))
    assert float(s.params["I1"]) == 0.5 and float(s.params["d"]) == 2
    with pytest.raises(InputError):
        system("nh.suslov_potential").build(U="__import__('os')")


# ------------------------------------------------------------ system-specific claims in `verify`
def _small_system():
    from poissonkit.structure import e3

    P = e3("gamma_M")
    M = P.coords[3:]
    return HamiltonianSystem(P, sum(m**2 for m in M) / 2)


def test_entry_claims_are_registered_for_the_reconstructed_structures():
    for name in ("nh.routh_sphere_rank4", "nh.suslov_rank4", "nh.ball_on_paraboloid_rank4",
                 "nh.chaplygin_ball", "nh.veselova"):
        claims = system(name).claims
        assert claims and all(callable(c) and c.__doc__ for c in claims), name


def test_verify_runs_claims_and_a_failing_or_broken_claim_spoils_the_report():
    from poissonkit.commands.verify import verify

    def holds(sys_):
        """a claim that holds"""
        return True, "", "test"

    def fails(sys_):
        """a claim that fails"""
        return False, "counterexample at x = 1", "test"

    def broken(sys_):
        """a claim with a malformed result"""
        return "yes"

    good = verify(_small_system(), "e3", claims=(holds,))
    assert good["ok"] and good["system"]["checks"][-1]["what"] == "a claim that holds"
    bad = verify(_small_system(), "e3", claims=(holds, fails))
    assert not bad["ok"] and bad["status"] == "failed"
    assert "counterexample" in bad["system"]["checks"][-1]["failures"][0]
    err = verify(_small_system(), "e3", claims=(broken,))
    assert not err["ok"] and err["status"] == "error"

"""``poissonkit verify`` under a time budget: undecided checks, exit codes, almost-Poisson
entries, decimals used as written.

Truth: so(3) is Poisson with Casimir |m|^2 (FORMULAS.md §2); the Routh sphere's rank-2 bracket
is not Poisson (survey §5.2 keeps it for integration; its rank-4 bivector P^(k) is the Poisson
one); Suslov's measure is 1/(I13 omega_x + I23 omega_y) with the inertia as given (survey (125)).
"""

from __future__ import annotations

import json
import subprocess
import sys
import time

import pytest
import sympy as sp

from poissonkit.cli import main
from poissonkit.commands import verify as verify_cmd
from poissonkit.commands.verify import EXIT_CODES, exact_number, verify
from poissonkit.errors import InputError
from poissonkit.structure import HamiltonianSystem, so3


def _rigid_body():
    P = so3()
    H = sum(c ** 2 for c in P.coords) / 2
    return HamiltonianSystem(P, H, integrals={"H": H}, name="rb")


def test_a_check_that_never_ends_is_undecided_and_terminated():
    def forever(sys_):
        """a claim that never finishes"""
        while True:
            pass

    t0 = time.monotonic()
    rep = verify(_rigid_body(), casimir_degree=0, timeout=3, claims=(forever,))
    assert time.monotonic() - t0 < 60  # the worker was terminated, not waited for
    assert rep["status"] == "undecided" and rep["exit_code"] == EXIT_CODES["undecided"] == 3
    last = rep["system"]["checks"][-1]
    assert last["status"] == "undecided" and last["holds"] is None
    # the other claims were decided within the budget
    assert rep["jacobi"]["is_poisson"] is True
    assert all(c["status"] == "holds" for c in rep["system"]["checks"][:-1])


def test_a_failed_claim_beats_an_undecided_one():
    def forever(sys_):
        """never finishes"""
        while True:
            pass

    def fails(sys_):
        """fails"""
        return False, "counterexample", "test"

    rep = verify(_rigid_body(), casimir_degree=0, timeout=3, claims=(fails, forever))
    assert rep["status"] == "failed" and rep["exit_code"] == 1


def test_exit_codes_are_distinct():
    assert sorted(EXIT_CODES.values()) == [0, 1, 2, 3]


def test_no_budget_runs_in_process():
    rep = verify(_rigid_body(), casimir_degree=2, timeout=0)
    assert rep["ok"] and rep["rank"] == 2
    assert [sp.sympify(c) for c in rep["casimirs"]] == [sp.sympify("m_x**2 + m_y**2 + m_z**2")]


@pytest.mark.parametrize("text, value", [("0.3333", sp.Rational(3333, 10000)),
                                         ("1/3", sp.Rational(1, 3)), ("-2.5e-3", sp.Rational(-1, 400)),
                                         ("7", sp.Integer(7))])
def test_decimals_are_read_as_written(text, value):
    assert exact_number(text) == value


@pytest.mark.parametrize("text", ["nan", "inf", "1/0", "x", "", "1e999999999999"])
def test_bad_numbers_are_typed_errors(text):
    with pytest.raises(InputError):
        exact_number(text)


def test_suslov_reports_its_parameters_as_written(capsys):
    assert main(["verify", "nh.suslov", "--casimir-degree", "0", "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    measure = next(c["what"] for c in rep["system"]["checks"] if "measure" in c["what"])
    assert "omega_y/3" in measure and "3333333333333333" not in measure  # default I23 = 1/3
    assert main(["verify", "nh.suslov", "--param", "I23=0.3333", "--casimir-degree", "0",
                 "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    measure = next(c["what"] for c in rep["system"]["checks"] if "measure" in c["what"])
    assert "3333*omega_y/10000" in measure


def test_almost_poisson_entries_say_so_and_exit_by_their_claim(capsys):
    assert main(["verify", "--list"]) == 0
    listed = {line.split()[0]: line for line in capsys.readouterr().out.splitlines()}
    for name in ("nh.routh_sphere", "nh.ball_on_paraboloid"):
        assert "almost-Poisson" in listed[name]
    assert "almost-Poisson" not in listed["nh.routh_sphere_rank4"]
    code = main(["verify", "nh.routh_sphere", "--casimir-degree", "0"])
    out = capsys.readouterr().out
    assert "deliberately not Poisson" in out
    assert "Jacobi identity: fails, as the entry states" in out
    assert code == 0
    # verdicts first; equations of motion only on request
    assert out.index("Jacobi identity") < out.index("Brackets")
    assert "Equations of motion" not in out


def test_an_almost_poisson_claim_fails_when_the_bracket_is_poisson(monkeypatch):
    rep = verify(_rigid_body(), casimir_degree=0, almost_poisson=True)
    assert rep["jacobi"]["is_poisson"] and rep["jacobi"]["as_claimed"] is False
    assert rep["status"] == "failed" and rep["exit_code"] == 1


def test_equations_of_motion_only_with_the_flag(capsys):
    assert main(["verify", "two_tops_hamiltonian", "--casimir-degree", "0"]) == 0
    assert "Equations of motion" not in capsys.readouterr().out
    assert main(["verify", "two_tops_hamiltonian", "--casimir-degree", "0", "--equations"]) == 0
    assert "Equations of motion" in capsys.readouterr().out


def test_negative_or_nan_timeout_is_refused(capsys):
    assert main(["verify", "so3", "--timeout", "-1"]) == 2
    assert main(["verify", "so3", "--timeout", "nan"]) == 2


def _listed() -> list[str]:
    from poissonkit.plugin import names

    return sorted(names("system"))


@pytest.mark.slow
@pytest.mark.timeout(3600)
def test_every_listed_entry_finishes_within_a_minute():
    """Each ``poissonkit verify NAME`` (a fresh process, default options) ends within 60 s with
    a decided verdict that matches the entry's claim (exit 0)."""
    timings = {}
    for name in _listed():
        t0 = time.monotonic()
        proc = subprocess.run([sys.executable, "-m", "poissonkit", "verify", name],
                              capture_output=True, text=True, timeout=120)
        timings[name] = time.monotonic() - t0
        print(f"{name}: exit {proc.returncode}, {timings[name]:.1f} s")
        assert proc.returncode == 0, (name, proc.stdout[-2000:], proc.stderr[-2000:])
    slowest = max(timings, key=timings.get)
    assert timings[slowest] <= 60, (slowest, timings[slowest])

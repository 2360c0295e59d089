"""``poissonkit verify`` never reports ok when a check crashes, and does not hide import failures.

Truth: so(3) with H = |m|^2/2 (|m|^2 is a Casimir, so H is a first integral; FORMULAS.md §2's
e(3) Casimir (gamma, gamma) restricted to m). The crashes are injected with monkeypatch.
"""

from __future__ import annotations

import sys

import pytest

from poissonkit import structure
from poissonkit.cli import main
from poissonkit.commands import verify as verify_cmd
from poissonkit.commands.verify import verify
from poissonkit.structure import HamiltonianSystem, checks, so3
from poissonkit.structure.verification import TimeLimit


def _system():
    P = so3()
    H = sum(c ** 2 for c in P.coords) / 2
    return HamiltonianSystem(P, H, integrals={"H": H}, casimirs={"|m|^2": 2 * H}, name="rb")


def test_all_checks_passing_gives_status_ok():
    rep = verify(_system(), casimir_degree=0)
    assert rep["ok"] is True and rep["status"] == "ok" and rep["errors"] == []
    assert {c["status"] for c in rep["system"]["checks"]} == {"holds"}


def test_crashing_check_makes_the_report_an_error(monkeypatch):
    def boom(*args, **kwargs):
        raise RuntimeError("internal bug")

    monkeypatch.setattr(checks, "is_first_integral", boom)
    rep = verify(_system(), casimir_degree=0)
    assert rep["ok"] is False and rep["status"] == "error"
    entry = next(c for c in rep["system"]["checks"] if c["what"].startswith("first integral"))
    assert entry["status"] == "error" and "RuntimeError: internal bug" in entry["error"]
    # the other claims are still checked and reported
    assert any(c["status"] == "holds" for c in rep["system"]["checks"])


def test_crashing_check_gives_nonzero_exit(monkeypatch, capsys):
    from poissonkit.structure import casimirs

    def boom(*args, **kwargs):
        raise ZeroDivisionError("oops")

    monkeypatch.setattr(casimirs, "is_casimir", boom)
    # a check that raised is an error (exit 2), distinct from a claim that fails (exit 1)
    assert main(["verify", "two_tops_hamiltonian", "--casimir-degree", "0"]) == \
        verify_cmd.EXIT_ERROR
    assert "ERROR" in capsys.readouterr().out


def test_crash_in_rank_is_an_error_but_a_typed_refusal_is_a_note(monkeypatch):
    from poissonkit.errors import InputError
    from poissonkit.structure import casimirs

    monkeypatch.setattr(casimirs, "rank", lambda *a, **k: 1 / 0)
    rep = verify(so3(), casimir_degree=0)
    assert rep["status"] == "error" and not rep["ok"] and "rank" in rep["errors"][0]

    def refuse(*a, **k):
        raise InputError("not applicable")

    monkeypatch.setattr(casimirs, "rank", refuse)
    rep = verify(so3(), casimir_degree=0)
    assert rep["ok"] and rep["status"] == "ok" and any("not applicable" in n for n in rep["notes"])


def test_timeout_of_the_casimir_search_is_a_note_not_an_error(monkeypatch):
    from poissonkit.structure import casimirs

    def slow(*a, **k):
        raise TimeLimit

    monkeypatch.setattr(casimirs, "find_casimirs", slow)
    rep = verify(so3(), casimir_degree=2, timeout=5)
    assert rep["ok"] and any("not finished within" in n for n in rep["notes"])


def test_broken_first_party_module_is_not_silently_skipped(monkeypatch):
    # An import regression in checks must surface, not turn into "not checked" notes.
    monkeypatch.delattr(structure, "checks")
    monkeypatch.setitem(sys.modules, "poissonkit.structure.checks", None)
    with pytest.raises(ImportError):
        verify(_system(), casimir_degree=0)

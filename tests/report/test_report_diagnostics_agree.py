"""The same run gives the same diagnostics on every path: ``Solution.summary()``, the
``summary.json`` of ``poissonkit run`` and the sweep outcomes; and the run summary's keys.

Truth for the shared numbers: the three paths must agree bit for bit (one definition); the
values themselves are pinned against hand arithmetic in tests/numerics/test_numerics_diagnostics.py.
Here the run's |Δj| and |ΔH| are also recomputed with plain numpy from the saved trajectory.
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np
import pytest

from poissonkit import cli
from poissonkit.commands.run import add_arguments, build_spec
from poissonkit.numerics.diagnostics import QUANTITIES
from poissonkit.numerics.solution import Solution
from poissonkit.report import conserved_quantities, diagnostics, invariant_report
from poissonkit.sweeps.outcomes import OUTCOMES
from poissonkit.sweeps.targets import RunRecord

ARGS = ["--periods", "0.5", "--tilt", "0.01", "--no-contact"]


@pytest.fixture(scope="module")
def seed_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("seed") / "out"
    code = cli.main(["run", *ARGS, "--out", str(out), "--no-progress", "--no-plots"])
    assert code == 0
    parser = argparse.ArgumentParser()
    add_arguments(parser)
    spec = build_spec(parser.parse_args(ARGS))
    summary = json.loads((out / "summary.json").read_text())
    with np.load(out / "trajectory.npz") as z:
        t, y = z["t"], z["y"]
    return spec.system, summary, t, y


def test_solution_run_summary_and_sweep_outcomes_agree(seed_run):
    system, summary, t, y = seed_run
    sol = Solution(t=t, y=y, method=summary["method"], steps=summary["steps"], wall_time=0.0,
                   system=system)
    s = sol.summary()
    for q in QUANTITIES:
        for key in (f"max_abs_{q}", f"max_rel_{q}", f"{q}_scale"):
            assert s[key] == summary[key], key
    record = RunRecord(sol, "bounded", math.nan, np.array([1.0]), 1.0, 1.0, 1.0)
    for name in ("max_rel_energy_error", "max_rel_casimir_drift",
                 "max_rel_angular_momentum_drift"):
        assert OUTCOMES[name].compute(record) == summary[name], name
    # independent recomputation of two figures from the saved states
    H = np.array([float(system.energy(row)) for row in y])
    assert summary["max_abs_energy_error"] == float(np.max(np.abs(H - H[0])))
    u = system.unpack(y)
    j = np.cross(u["r"], u["p"]) + u["m1"] + u["m2"]
    assert summary["max_abs_angular_momentum_drift"] == pytest.approx(
        float(np.max(np.linalg.norm(j - j[0], axis=1))), rel=1e-12, abs=1e-30)
    u0 = system.unpack(y[0])
    scale = (np.linalg.norm(np.cross(u0["r"], u0["p"])) + np.linalg.norm(u0["m1"])
             + np.linalg.norm(u0["m2"]))
    assert summary["angular_momentum_drift_scale"] == pytest.approx(scale, rel=1e-15)
    assert summary["max_rel_angular_momentum_drift"] < 1e-13  # a tilted orbit: j(0) ≠ 0


def test_run_summary_keys_are_the_unified_ones(seed_run):
    _system, summary, _t, _y = seed_run
    for q in QUANTITIES:
        assert {f"max_abs_{q}", f"max_rel_{q}", f"{q}_scale"} <= set(summary)
    for old in ("max_casimir_drift", "max_linear_momentum_drift", "angular_momentum_reference"):
        assert old not in summary
    assert summary["energy_error_scale"] == abs(summary["energy_reference"])


def test_a_system_without_bodies_reports_energy_and_casimirs_only():
    class Spinner:
        """A free top: H = |m|² / 2, Casimir |m|² (state = m)."""

        def energy(self, y):
            return 0.5 * np.sum(np.asarray(y) ** 2, axis=-1)

        def casimirs(self, y):
            return np.sum(np.asarray(y) ** 2, axis=-1)[..., None]

    y = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    rep = invariant_report(Spinner(), diagnostics(Spinner(), np.arange(2.0), y))
    assert set(conserved_quantities(Spinner())) == {"linear_momentum", "angular_momentum"}
    assert rep["max_rel_energy_error"] == 0.0 and rep["casimir_drift_scale"] == [1.0]
    assert not any("momentum_drift" in k for k in rep)

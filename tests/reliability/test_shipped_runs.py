"""Every shipped scene and example runs clean: no contact between bodies, energy error within
the scene's stated tolerance (``run.energy_tol``), exit code 0. And the checks themselves: a
scene whose magnets snap together stops at the located contact with its own exit code, an
energy error above tolerance gives a warning and its own exit code, and the summary reports
only the invariants a scene really has."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from scene_texts import CYLINDER_MAGNETS, magnet_scene  # type: ignore[import-not-found]

from poissonkit import cli
from poissonkit.commands.run import EXIT_CONTACT, EXIT_ENERGY

ROOT = Path(__file__).resolve().parents[2]
SCENES = sorted((ROOT / "poissonkit" / "scene" / "shipped").glob("*.toml"))
#: scenes cheap enough for the default run (one dumbbell kernel to compile)
QUICK_SCENES = {"two_magnets"}
#: examples/nonholonomic_verify.py exits 1 by design for now: its survey lists known
#: non-Poisson (almost-Poisson) entries as failures; the verify exit semantics are being
#: reworked separately (issue 10 part 5), after which it joins this list.
EXCLUDED_EXAMPLES = {"nonholonomic_verify.py"}
EXAMPLES = sorted(p for p in (ROOT / "examples").glob("*.py") if p.name not in EXCLUDED_EXAMPLES)


def _summary(out: Path) -> dict:
    return json.loads((out / "summary.json").read_text())


@pytest.mark.parametrize("scene", [
    pytest.param(p, id=p.stem, marks=() if p.stem in QUICK_SCENES else pytest.mark.slow)
    for p in SCENES] + [pytest.param(None, id="builtin-seed000", marks=pytest.mark.slow)])
def test_shipped_scene_runs_clean(tmp_path, scene, capsys):
    out = tmp_path / "out"
    args = ["run"] + ([str(scene)] if scene else ["--periods", "2"])
    code = cli.main(args + ["--out", str(out), "--no-progress", "--no-plots"])
    err = capsys.readouterr().err
    s = _summary(out)
    assert code == 0, (s.get("warnings"), err)
    assert s["status"] == "done" and not s["warnings"] and "warning" not in err
    assert s["max_rel_energy_error"] <= s["energy_tol"]
    assert s["t_reached"] == pytest.approx(s["t_end"], rel=1e-12)


@pytest.mark.slow
@pytest.mark.parametrize("script", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_script_runs_clean(tmp_path, script):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), str(ROOT / "plugins"),
                                         env.get("PYTHONPATH", "")])
    env["MPLBACKEND"] = "Agg"
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=1800)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "Traceback" not in done.stderr and "warning:" not in done.stderr.lower()


SNAP = magnet_scene(
    "snap",
    ("a", "[0.0, 0.0, 0.0]", "[0.0, 0.0, 1.0]", "{fixed}"),
    ("b", "[0.0, 0.0, 0.04]", "[0.0, 0.0, 1.0]"),
    defaults=CYLINDER_MAGNETS.replace("magnetization = 1.58359e6", "moment = 0.15546875")
) + """[interactions]
potential = "dumbbell"
[run]
method = "splitting4"
step = 1e-4
duration = 0.05
"""


def test_magnets_snapping_together_stop_at_the_located_contact(tmp_path, capsys):
    """Coaxial cylinders of length 20 mm touch when their centres are 20 mm apart (end faces
    meet): the geometric answer the located contact must reproduce."""
    scene = tmp_path / "snap.toml"
    scene.write_text(SNAP.format(fixed="fixed = true"))
    out = tmp_path / "out"
    code = cli.main(["run", str(scene), "--out", str(out), "--no-progress", "--no-plots"])
    err = capsys.readouterr().err
    assert code == EXIT_CONTACT
    s = _summary(out)
    assert s["status"] == "contact" and "touched" in err
    (ev,) = s["events"]
    scale = s["parameters"]["scales"]["length"]
    assert ev["kind"] == "contact"
    assert ev["value"] * scale == pytest.approx(0.02, abs=1e-9)  # end faces meet
    assert ev["time_error_s"] < 1e-9 * 1e-4 * 1.01  # bracket: 1e-9 of the step
    assert s["t_reached_s"] == pytest.approx(ev["time_s"]) and s["t_reached_s"] < 0.05
    assert s["min_distance_m"] >= 0.02 - 1e-9  # nothing saved after the contact
    # a fixed magnet pulls: momentum is not an invariant here and is not reported as a drift
    assert "max_rel_angular_momentum_drift" not in s and "max_rel_linear_momentum_drift" not in s
    assert "fixed bodies (a)" in s["not_reported"]["angular_momentum"]


def test_energy_error_above_tolerance_warns_and_exits_nonzero(tmp_path, capsys):
    out = tmp_path / "out"
    code = cli.main(["run", str(ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"),
                     "--duration", "0.01", "--energy-tol", "1e-16", "--out", str(out),
                     "--no-progress", "--no-plots"])
    err = capsys.readouterr().err
    assert code == EXIT_ENERGY
    assert "warning: energy error" in err and "exceeds" in err
    s = _summary(out)
    assert s["warnings"] and s["max_rel_energy_error"] > 1e-16
    # released from rest without spin: the scale Σ|r×p| + Σ|m| is 0, replaced by 1, so the
    # relative figure is the absolute one
    assert s["angular_momentum_drift_scale"] == 1.0
    assert s["max_rel_angular_momentum_drift"] == s["max_abs_angular_momentum_drift"]
    assert s["max_abs_angular_momentum_drift"] < 1e-12
    assert s["max_abs_energy_error"] == pytest.approx(
        s["max_rel_energy_error"] * abs(s["energy_reference"]))


def test_long_trajectory_stays_on_disk_in_parts(tmp_path, monkeypatch, capsys):
    """Above MAX_NPZ_ROWS saved rows the trajectory is not gathered into memory: it stays in
    parts, and the summary's maxima still cover every row (computed part by part)."""
    from poissonkit.commands import run
    from poissonkit.numerics.checkpoint import read_trajectory
    from poissonkit.report import diagnostics
    from poissonkit.scene import build_run, load_scene

    monkeypatch.setattr(run, "MAX_NPZ_ROWS", 100)
    monkeypatch.setattr(run, "PLOT_ROWS", 40)
    out = tmp_path / "out"
    scene = ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"
    assert cli.main(["run", str(scene), "--duration", "0.02", "--out", str(out),
                     "--no-progress", "--no-plots"]) == 0
    s = _summary(out)
    assert "trajectory.parts" in s["trajectory"] and not (out / "trajectory.npz").exists()
    t, y = read_trajectory(out / "trajectory.parts")
    assert len(t) == 201 and t[-1] == pytest.approx(s["t_end"])
    full = diagnostics(build_run(load_scene(scene)).system, t, y).maxima()
    assert s["max_rel_energy_error"] == full["max_rel_energy_error"]

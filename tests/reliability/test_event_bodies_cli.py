"""``poissonkit run`` of a scene whose run stops on a :class:`Collision`: the summary's event
and the warning line name the two bodies that met (by construction ``a`` and ``b``, which
are not the first pair of the scene) and the distance in metres."""

from __future__ import annotations

import json
import textwrap

import pytest

from poissonkit import cli
from poissonkit.plugin import manager

_PLUGIN = '''
import numpy as np
from poissonkit.numerics import AllPairs, Body, NBodySystem
from poissonkit.numerics.events import Collision
from poissonkit.numerics.runspec import RunSpec
from poissonkit.plugin import SceneEntry, hookimpl


def _load():
    # a and b, 1 m apart, close at 2 m/s and meet 0.1 m apart at t = 0.45 s; far stays far
    system = NBodySystem([Body("far", 1.0), Body("a", 1.0), Body("b", 1.0)],
                         [AllPairs("gravity", {"G": 1e-9})])
    y0 = system.pack([[50.0, 0, 0], [0, 0, 0], [0, 1.0, 0]], [[0, 0, 0], [0, 1, 0], [0, -1, 0]])
    return RunSpec("pk_test_head_on", system, y0, 5.0, method="splitting4", step=0.01,
                   events=(Collision(0.1),))


@hookimpl
def poissonkit_scenes():
    return [SceneEntry("pk_test_head_on", "Two bodies meeting head on.", load=_load)]
'''
EXIT_CONTACT = 4  # poissonkit.commands.run: stopped by a contact or collision


def test_summary_and_warning_name_the_bodies_that_met(tmp_path, monkeypatch, capsys):
    (tmp_path / "pk_test_head_on.py").write_text(textwrap.dedent(_PLUGIN))
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(manager, "BUILTIN_PLUGINS",
                        manager.BUILTIN_PLUGINS + (("test-head-on", "pk_test_head_on"),))
    manager.reset()
    out = tmp_path / "out"
    code = cli.main(["run", "pk_test_head_on", "--out", str(out), "--no-progress", "--no-plots"])
    err = capsys.readouterr().err
    assert code == EXIT_CONTACT, err
    (event,) = json.loads((out / "summary.json").read_text())["events"]
    assert event["kind"] == "collision" and event["time_s"] == pytest.approx(0.45, abs=1e-6)
    assert event["detail"]["bodies"] == ["a", "b"]
    assert event["detail"]["distance_m"] == pytest.approx(0.1, abs=1e-8)
    assert "bodies 'a' and 'b' touched (collision) at a centre distance of 0.1 m" in err

"""A field from a plugin that is not built in works end to end, and the registry lists the
built-in fields."""

from __future__ import annotations

import numpy as np
import pytest

import poissonkit as pk
from poissonkit.errors import UnknownEntryError
from poissonkit.numerics.nbody import Body, NBodySystem
from poissonkit.plugin import names, plugin_reports


def test_builtin_fields_are_registered():
    assert {"gravity", "uniform", "magpylib", "current_loop", "cylinder"} <= set(names("field"))
    core = next(r for r in plugin_reports() if r.name == "core-fields")
    assert core.contributions == {"field": ["gravity", "uniform"]}


def test_a_third_party_field_moves_charged_bodies(efield_plugin):
    q, M, E = 2e-6, 1e-3, (300.0, 0.0, -50.0)
    s = NBodySystem([Body("q", M, attributes={"charge": q}), Body("n", M)],
                    fields=[pk.field("test_efield", E=E)])
    y0 = s.pack([[0, 0, 0], [1, 0, 0]], np.zeros((2, 3)))
    t = 0.5
    sol = pk.solve(s, y0, t, method="splitting4", step=0.05)
    a = q * np.array(E) / M
    assert sol.y[-1][:3] == pytest.approx(0.5 * a * t * t, rel=1e-12)
    assert sol.y[-1][6:9] == pytest.approx([1, 0, 0])  # no charge: no force
    assert sol.summary()["max_rel_energy_error"] < 1e-12


def test_without_the_plugin_the_field_is_an_unknown_name():
    with pytest.raises(UnknownEntryError, match="test_efield"):
        pk.field("test_efield", E=(1, 0, 0)).compile()

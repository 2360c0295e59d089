"""The integrator registry: documented, typed entries; bad options are typed errors."""

from __future__ import annotations

import pytest

from poissonkit.errors import InputError, UnknownNameError
from poissonkit.numerics.solver import make_integrator
from poissonkit.plugin import entries, integrator


def test_every_integrator_is_documented_with_order_and_family():
    found = entries("integrator")
    for name in ("splitting2", "splitting4", "splitting6", "splitting8", "midpoint", "rk45",
                 "dop853", "radau", "lsoda", "logh2", "logh4", "logh6", "logh8"):
        e = found[name]
        assert e.doc and e.family in ("splitting", "implicit", "scipy", "time_transformed")
        obj = e.factory(**e.resolve_params({}))
        assert hasattr(obj, "integrate") and obj.order == e.order


def test_bad_options_and_names_are_typed_errors():
    with pytest.raises(UnknownNameError):
        make_integrator("splitting6", {"adaptiv": True})
    with pytest.raises(InputError):
        make_integrator("splitting6", {"iterations": "many"})
    with pytest.raises(UnknownNameError) as info:
        integrator("verlet")
    assert "midpoint" in str(info.value)

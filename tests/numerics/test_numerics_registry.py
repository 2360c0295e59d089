"""The integrator registry: documented, typed entries; bad options are typed errors."""

from __future__ import annotations

import pytest

from poissonkit.contracts import Integrator
from poissonkit.errors import InputError, UnknownNameError
from poissonkit.numerics.solver import make_integrator
from poissonkit.plugin import entries, integrator


def test_every_integrator_is_documented_with_order_family_and_capabilities():
    found = entries("integrator")
    for name in ("splitting2", "splitting4", "splitting6", "splitting8", "midpoint", "rk45",
                 "dop853", "radau", "lsoda", "logh2", "logh4", "logh6", "logh8",
                 "wisdom_holman", "wisdom_holman_corrected"):
        e = found[name]
        assert e.doc and e.family in ("splitting", "implicit", "scipy", "time_transformed",
                                      "hierarchical")
        obj = e.factory(**e.resolve_params({}))
        assert isinstance(obj, Integrator) and obj.order == e.order
        assert obj.capabilities == e.capabilities
        # every compiled loop runs on the shared driver; scipy's controller cannot resume
        compiled = e.family != "scipy"
        assert e.capabilities.checkpoint == e.capabilities.stream == compiled
        assert e.capabilities.located_events == compiled and e.capabilities.events
    assert found["wisdom_holman"].capabilities.point_masses_only
    assert not found["midpoint"].capabilities.needs_splitting


def test_bad_options_and_names_are_typed_errors():
    with pytest.raises(UnknownNameError):
        make_integrator("splitting6", {"adaptiv": True})
    with pytest.raises(InputError):
        make_integrator("splitting6", {"iterations": "many"})
    with pytest.raises(UnknownNameError) as info:
        integrator("verlet")
    assert "midpoint" in str(info.value)

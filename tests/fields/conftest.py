"""Fixtures of the external-field tests."""

from __future__ import annotations

import pytest

from field_cases import CYLINDER, REGION, TOL


@pytest.fixture
def efield_plugin(monkeypatch):
    """The plugin of ``field_plugin_efield`` registered next to the built-ins."""
    from poissonkit.plugin import manager, reset

    monkeypatch.setattr(manager, "BUILTIN_PLUGINS",
                        (*manager.BUILTIN_PLUGINS, ("test-efield", "field_plugin_efield")))
    reset()
    yield
    reset()


@pytest.fixture(scope="session")
def tabulated_cylinder():
    """The magpylib cylinder's field tabulated over :data:`REGION` to :data:`TOL`."""
    import poissonkit as pk

    return pk.field("magpylib", **{"class": "Cylinder", "params": CYLINDER}, tol=TOL,
                    region=REGION, mode="table").compile()

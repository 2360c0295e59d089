"""Fixtures of the external-field tests."""

from __future__ import annotations

import pytest

#: A cylinder magnet (magpylib keywords, SI) and the box above it the tests tabulate.
CYLINDER = {"polarization": [0.0, 0.0, 1.0], "dimension": [0.05, 0.01]}
REGION = (-0.01, -0.01, 0.025, 0.01, 0.01, 0.045)
TOL = 1e-4


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
                    region=REGION).compile()

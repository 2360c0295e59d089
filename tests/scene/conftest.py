"""Fixtures of the scene tests: a third-party potential plugin registered like an installed one."""

from __future__ import annotations

import pytest


@pytest.fixture
def yukawa_plugin(monkeypatch):
    """The plugin of ``scene_yukawa_plugin`` registered next to the built-ins."""
    from poissonkit.plugin import manager, reset

    monkeypatch.setattr(manager, "BUILTIN_PLUGINS",
                        (*manager.BUILTIN_PLUGINS, ("test-yukawa", "scene_yukawa_plugin")))
    reset()
    yield
    reset()

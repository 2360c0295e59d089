"""Shared test fixtures."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: The seeds and the verified reference live beside the project root.
SHARED = ROOT.parent / "shared"


@pytest.fixture(autouse=True)
def _fresh_plugin_manager(monkeypatch):
    """Each test sees a plugin manager built from the current environment."""
    from poissonkit.plugin import reset

    reset()
    yield
    reset()


os.environ.setdefault("MPLBACKEND", "Agg")

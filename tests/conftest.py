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


@pytest.fixture
def reference_dir() -> Path:
    """``shared/reference`` (skip if the checkout has no shared folder beside it)."""
    path = SHARED / "reference"
    if not path.is_dir():
        pytest.skip("shared/reference is not beside the project")
    return path


os.environ.setdefault("MPLBACKEND", "Agg")

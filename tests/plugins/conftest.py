"""Fixtures of the plugin tests: the example third-party plugin, discoverable for real."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
import tomllib

ROOT = Path(__file__).resolve().parents[2]  # the project root
EXAMPLE = ROOT / "examples" / "external_plugin"


def _project() -> dict:
    return tomllib.loads((EXAMPLE / "pyproject.toml").read_text())["project"]


@pytest.fixture
def example_discoverable(tmp_path, monkeypatch):
    """Put the example's package and a dist-info with its real entry points on sys.path."""
    project = _project()
    eps = project["entry-points"]["poissonkit"]
    info = tmp_path / f"{project['name'].replace('-', '_')}-{project['version']}.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(
        f"Metadata-Version: 2.1\nName: {project['name']}\nVersion: {project['version']}\n")
    (info / "entry_points.txt").write_text(
        "[poissonkit]\n" + "".join(f"{k} = {v}\n" for k, v in eps.items()))
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.syspath_prepend(str(EXAMPLE / "src"))
    # an installed (possibly older) copy imported by an earlier test must not shadow the source
    for name in [m for m in sys.modules if m == "poissonkit_lj" or m.startswith("poissonkit_lj.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.delenv("POISSONKIT_DISABLE_PLUGIN_AUTOLOAD", raising=False)
    monkeypatch.delenv("POISSONKIT_BLOCK_PLUGINS", raising=False)
    return project


@pytest.fixture
def site(tmp_path, monkeypatch):
    """A folder on ``sys.path`` for fake distributions (``*.dist-info`` plus modules, what
    ``pip install`` leaves behind); entry-point plugins load."""
    path = tmp_path / "site"
    path.mkdir()
    monkeypatch.syspath_prepend(str(path))
    monkeypatch.delenv("POISSONKIT_DISABLE_PLUGIN_AUTOLOAD", raising=False)
    monkeypatch.delenv("POISSONKIT_BLOCK_PLUGINS", raising=False)
    return path

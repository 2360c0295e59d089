"""Fixtures of the compat tests: the PyPI peer packages the compat layer is checked against.

The peers are pinned in the ``[test]`` extra. Locally a missing peer skips only the tests that
compare against it; under CI (environment variable ``CI`` set) it fails them, so a broken
install cannot turn into silently skipped comparisons.
"""

from __future__ import annotations

import importlib
import os
from types import ModuleType

import pytest


def import_peer(module: str, package: str) -> ModuleType:
    """Import a peer module; skip the test when it is absent, fail instead under CI."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        message = f"{package} (pinned in the [test] extra) is not importable: {exc}"
        if os.environ.get("CI"):
            pytest.fail(message, pytrace=False)
        pytest.skip(message)


@pytest.fixture(scope="session")
def peer() -> type:
    """``poissongeometry``'s ``PoissonGeometry`` class (module ``poisson.poisson``)."""
    return import_peer("poisson.poisson", "poissongeometry").PoissonGeometry


@pytest.fixture(scope="session")
def numeric_peer() -> type:
    """``numericalpoissongeometry``'s ``NumPoissonGeometry`` class (``numpoisson.numpoisson``)."""
    return import_peer("numpoisson.numpoisson", "numericalpoissongeometry").NumPoissonGeometry

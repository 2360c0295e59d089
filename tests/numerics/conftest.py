"""Fixtures of the numerics tests (helpers live in numerics_helpers.py)."""

from __future__ import annotations

import pytest
from numerics_helpers import BOUND, DIPOLE  # type: ignore[import-not-found]


@pytest.fixture(scope="session")
def dipole_pair():
    """Two-body centre-of-mass system, FORMULAS §1 parameters (mu = 2, alpha = 3, 5), with
    the bounded potential of ``numerics_helpers.BOUND``."""
    from poissonkit.numerics import TwoBodySystem

    return TwoBodySystem(None, None, 3.0, 5.0, BOUND, reduced_mass=2.0)


@pytest.fixture(scope="session")
def oracle_pair():
    """FORMULAS §1 oracle system: pure dipoles, mu = 2, alpha' = 3, alpha'' = 5."""
    from poissonkit.numerics import TwoBodySystem

    return TwoBodySystem(None, None, 3.0, 5.0, DIPOLE, reduced_mass=2.0)



"""``validation.vector3``: three finite reals, else an InputError naming the field.

Its finiteness test is three scalar checks (scenes validate 10⁶ vectors); these cases pin
what it accepts and refuses, whichever component is bad.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from poissonkit.errors import InputError
from poissonkit.validation import vector3


@pytest.mark.parametrize("value", [(1, 2, 3), [0.5, -1e300, 0.0], np.array([[1.0], [2.0], [3.0]]),
                                   (np.float32(1.0), 2, np.int64(3))])
def test_three_finite_reals_pass(value):
    v = vector3(value, "axis")
    assert v.shape == (3,) and v.dtype == float
    np.testing.assert_array_equal(v, np.asarray(value, dtype=float).reshape(-1))


@pytest.mark.parametrize("k", range(3))
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_a_non_finite_component_anywhere_is_refused(k, bad):
    value = [1.0, 2.0, 3.0]
    value[k] = bad
    with pytest.raises(InputError, match="bodies\\[2\\].axis must be a finite 3-vector"):
        vector3(value, "bodies[2].axis")


@pytest.mark.parametrize("value", [(1.0, 2.0), (1.0, 2.0, 3.0, 4.0), "abc", None, ("a", 1, 2)])
def test_not_three_numbers_is_refused(value):
    with pytest.raises(InputError, match="pos must be a"):
        vector3(value, "pos")

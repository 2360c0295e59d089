"""Stability maps: the PNG helper and the boundary read off a map (synthetic datasets)."""

from __future__ import annotations

import numpy as np
import pytest

from poissonkit.errors import InputError
from poissonkit.sweeps.params import design_from
from poissonkit.sweeps.plot import boundary, stability_map
from poissonkit.sweeps.store import empty_dataset


def _map():
    design = design_from({"spin_ratio": [0.0, 5.0, 10.0, 15.0], "tilt": [0.0, 0.1, 0.2]})
    ds = empty_dataset(design, ["fate", "megno"], {"scene": "test"},
                       {"spin_ratio": "1", "tilt": "rad"})
    # bounded from spin 5 at tilt 0, from 10 at tilt 0.1, never at 0.2; an isolated bounded
    # point below the edge (spin 0, tilt 0.2) must not count as the boundary
    fate = np.array([[1, 1, 0], [0, 1, 1], [0, 0, 1], [0, 0, 1]], dtype="i1")
    ds["fate"].values = fate
    ds["megno"].values = np.where(fate == 0, 2.0, np.nan)
    ds["completed"].values[:] = True
    return ds


def test_boundary_is_the_smallest_value_from_which_all_are_bounded():
    edge = boundary(_map(), along="spin_ratio")
    assert edge.dims == ("tilt",)
    np.testing.assert_array_equal(edge.values[:2], [5.0, 10.0])
    assert np.isnan(edge.values[2])


def test_stability_map_writes_a_png(tmp_path):
    out = stability_map(_map(), tmp_path / "map.png", mark={"spin_ratio": 10.0, "tilt": 0.1})
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000


def test_stability_map_needs_two_dimensions(tmp_path):
    design = design_from({"tilt": [0.0, 0.1]})
    ds = empty_dataset(design, ["fate"], {}, {"tilt": "rad"})
    with pytest.raises(InputError, match="two parameters"):
        stability_map(ds, tmp_path / "x.png")

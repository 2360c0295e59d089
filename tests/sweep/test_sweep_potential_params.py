"""Sweeping a potential parameter compiles nothing per point (parameters are run-time data).

Truth for the numbers: every point is also run in this process through a scene whose potential
parameters are compiled in as constants (the magnets' constant-parameter kernels); the sweep
must give exactly those outcomes (bit-identical kernels, so equal numbers).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from poissonkit.sweeps import sweep
from poissonkit.sweeps.compiles import compilations, count_compilations
from poissonkit.sweeps.outcomes import DEFAULT_OUTCOMES, reduce_run
from poissonkit.sweeps.targets import TomlScene

SCENE = Path(__file__).resolve().parents[2] / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"
MOMENTS = (0.12, 0.14, 0.17, 0.2)


def _worker_compilations(client) -> int:
    return sum(client.run(compilations).values())


def test_potential_parameter_sweep_compiles_nothing_per_point(dask_client):
    dask_client.run(count_compilations)
    # every worker builds the scene once (an initial-condition sweep, one point per worker)
    sweep(str(SCENE), {"bodies.right.r.0": [0.04, 0.041]}, client=dask_client,
          progress=False, batch_size=1)
    before = _worker_compilations(dask_client)
    ds = sweep(str(SCENE), {"bodies.right.moment": list(MOMENTS)}, client=dask_client,
               progress=False, batch_size=1)
    assert _worker_compilations(dask_client) == before  # no compilation for any moment
    assert bool(ds["completed"].all()) and not bool(ds["failed"].any())


@pytest.mark.slow
def test_potential_parameter_sweep_equals_constant_kernels(monkeypatch):
    from poissonkit.plugin import entries, registry

    scene = TomlScene.from_file(SCENE)
    prep = scene.prepare()
    runtime = [reduce_run(scene.run(prep, {"bodies.right.moment": m}), DEFAULT_OUTCOMES)
               for m in MOMENTS[:2]]
    dumbbell = entries("potential")["dumbbell"]
    constant = dataclasses.replace(dumbbell, param_kernel=None, param_values=None)
    real = registry.entries

    def patched(kind):
        out = dict(real(kind))
        if kind == "potential":
            out["dumbbell"] = constant
        return out

    monkeypatch.setattr(registry, "entries", patched)  # the scene now builds constant kernels
    for m, got in zip(MOMENTS[:2], runtime):
        ref = reduce_run(scene.run(prep, {"bodies.right.moment": m}), DEFAULT_OUTCOMES)
        for name in DEFAULT_OUTCOMES:
            np.testing.assert_array_equal(np.asarray(got[name], dtype=float),
                                          np.asarray(ref[name], dtype=float), err_msg=name)

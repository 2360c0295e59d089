"""The body limit of scene files is set by memory (docs/scenes.md, "How many bodies")."""

from __future__ import annotations

import time

import numpy as np
import pytest

from poissonkit.errors import SceneError
from poissonkit.scene import loads_scene
from poissonkit.scene.limits import (
    BYTES_PER_BODY,
    BYTES_PER_PAIR,
    SceneTooLargeError,
    check_memory,
    estimate_bytes,
)


def _points(n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.uniform(-1.0, 1.0, (n, 3)) * n ** (1 / 3)


def _text(pos: np.ndarray, pairs: str = "all") -> str:
    lines = ['name = "many"', "[interactions]", 'potential = "gravity"', f'pairs = "{pairs}"',
             "[run]", "duration = 1.0", "step = 0.1"]
    for r in pos:
        lines += ["[[bodies]]", "mass = 1.0", f"r = [{float(r[0])!r}, {float(r[1])!r}, {float(r[2])!r}]"]
    return "\n".join(lines)


def test_two_thousand_bodies_load():
    start = time.perf_counter()
    scene = loads_scene(_text(_points(2000)))
    assert len(scene.bodies) == 2000
    assert time.perf_counter() - start < 30  # the overlap test is no longer O(N^2) in Python


def test_coincident_bodies_are_still_found_among_many():
    pos = _points(2000)
    pos[1900] = pos[1500]
    with pytest.raises(SceneError, match=r"bodies\[1900\]\.r: body 'b1900' overlaps body "
                                         r"'b1500' \(bodies\[1500\]\)"):
        loads_scene(_text(pos))


def test_overlaps_match_the_pairwise_test():
    """The tree search names the same first pair as testing every pair in order."""
    from poissonkit.scene.geometry import overlapping, shape_of
    from poissonkit.scene.schema import check_overlaps

    rng = np.random.default_rng(3)
    for _trial in range(20):
        bodies = [{"name": f"c{k}", "r": tuple(rng.uniform(-0.05, 0.05, 3)),
                   "nu": tuple(rng.normal(size=3)), "radius": 0.004, "length": 0.01}
                  for k in range(25)]
        shapes = [shape_of(b["r"], b["nu"], b["radius"], b["length"] / 2) for b in bodies]
        first = next(((i, j) for i in range(25) for j in range(i + 1, 25)
                      if overlapping(shapes[i], shapes[j])), None)
        if first is None:
            check_overlaps(bodies)
            continue
        i, j = first
        with pytest.raises(SceneError, match=rf"^bodies\[{j}\]\.r: .*\(bodies\[{i}\]\)"):
            check_overlaps(bodies)


def test_limit_names_the_estimate_and_the_memory():
    need = estimate_bytes(1000, 499500)
    assert need == 1000 * BYTES_PER_BODY + 499500 * BYTES_PER_PAIR
    assert check_memory(1000, 499500, available=4 * need) == need
    with pytest.raises(SceneTooLargeError, match=r"bodies: a scene of 1000 bodies and 499500 "
                                                 r"interacting pairs needs about 983 MiB.*"
                                                 r"0\.5 of the 1,500 MiB available"):
        check_memory(1000, 499500, available=1500 * 2**20)


def test_a_huge_assembly_is_refused_before_it_is_built(monkeypatch):
    # its pairs are all alike (none held): the bodies alone decide, against a fixed 4 GiB
    monkeypatch.setattr("poissonkit.scene.limits.available_memory", lambda: 4 * 2**30)
    text = """
[assembly]
name = "random_cluster"
params = { n = 1000000, cluster_radius = 1.0, mass = 1.0, potential = "gravity" }
[run]
duration = 1.0
step = 0.1
"""
    with pytest.raises(SceneTooLargeError, match=r"^assembly\.params: a scene of 1000000 bodies"):
        loads_scene(text)


def test_two_thousand_bodies_build_as_one_all_pairs_interaction():
    from poissonkit.numerics.nbody import AllPairs
    from poissonkit.scene import build_run

    start = time.perf_counter()
    run = build_run(loads_scene(_text(_points(2000))))
    assert time.perf_counter() - start < 60
    (inter,) = run.system.interactions
    assert isinstance(inter, AllPairs) and len(inter.members) == 2000
    assert run.y0.shape == (6 * 2000,)

"""Huge scene values give one typed error and no numpy warnings before it.

Found by mutating the shipped scenes' numbers to 1e300 / 1e308 / 1e100 / 10**400: four typed
errors printed numpy ``RuntimeWarning`` lines first (overflow in a norm, a product, a sum),
three more died with ``OverflowError`` / ``ZeroDivisionError`` tracebacks, and a few built
with warnings and failed later in the run.
"""

from __future__ import annotations

import tomllib
import warnings

import pytest

from poissonkit import cli
from poissonkit.errors import InputError, SceneError
from poissonkit.scene import build_run
from poissonkit.scene.loader import shipped_scene
from poissonkit.scene.schema import scene_from_mapping


def _mutated(scene: str, path: tuple, value) -> dict:
    data = tomllib.loads(shipped_scene(scene).read_text())
    node = data
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return data


CASES = [  # (scene, path, value, words of the message)
    ("planned_cluster", ("bodies", 0, "r", 0), 1e300, "finite"),           # norm overflow
    ("magnet_chain", ("assembly", "params", "spacing"), 1e308, "finite"),   # product overflow
    ("magnet_chain", ("assembly", "params", "mass"), 1e308, "mass"),        # sum overflow
    ("planned_cluster", ("bodies", 0, "nu", 0), 1e300, "axis"),             # axis norm overflow
    ("magnet_chain", ("assembly", "params", "n"), 10**400, "assembly.params"),  # OverflowError
    ("magnet_chain", ("assembly", "params", "n"), 1e300, "assembly.params"),    # OverflowError
    ("magnet_chain", ("assembly", "params", "spacing"), 1e100, "range"),  # ZeroDivisionError
    ("two_magnets", ("defaults", "moment"), 1e300, "range"),              # OverflowError
]


@pytest.mark.parametrize("scene, path, value, words", CASES)
def test_huge_values_are_one_typed_error_without_warnings(scene, path, value, words):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a numpy RuntimeWarning fails the test
        with pytest.raises(SceneError, match=words):
            build_run(scene_from_mapping(_mutated(scene, path, value)))


@pytest.mark.parametrize("field", ["r", "p", "m"])
def test_overflowing_state_is_refused_by_the_run_without_warnings(field):
    body = 0 if field == "r" else 1
    data = _mutated("two_magnets", ("bodies", body, field, 0), 1e308)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        spec = build_run(scene_from_mapping(data))
    from poissonkit.numerics.solver import solve

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(InputError, match="NaN or inf"):
            solve(spec.system, spec.y0, spec.t_end, method=spec.method, step=spec.step)


def test_command_line_prints_one_line(tmp_path, capfd):
    text = shipped_scene("two_magnets").read_text().replace(
        "r = [0.04, 0.0, 0.0]", "r = [1e308, 0.0, 0.0]")
    scene = tmp_path / "huge.toml"
    scene.write_text(text)
    code = cli.main(["run", str(scene), "--out", str(tmp_path / "o"), "--no-progress",
                     "--no-plots"])
    err = capfd.readouterr().err
    assert code == 1
    assert "RuntimeWarning" not in err and "Traceback" not in err
    assert err.strip().count("\n") == 0 and "NaN or inf" in err

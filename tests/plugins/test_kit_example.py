"""The example third-party plugin's own tests (``examples/external_plugin/tests``: the kit and
its own truth) pass with the plugin discoverable through its real entry points. The kit's fast
cases run here directly; the whole of its test folder, slow cases included, in a subprocess."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys

import pytest
from conftest import EXAMPLE, ROOT


def _example_module(name: str):
    spec = importlib.util.spec_from_file_location(f"example_{name}", EXAMPLE / "tests" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_example_passes_the_fast_checks_of_the_kit(example_discoverable):
    from poissonkit.plugin import reset
    from poissonkit.testing import plugin_checks

    reset()
    try:
        examples = _example_module("test_kit").EXAMPLES
        cases = [c for c in plugin_checks("lennard_jones", examples=examples) if not c.slow]
        assert {c.kind for c in cases} >= {"potential"} and len(cases) >= 3 * 7
        for case in cases:
            case()
    finally:
        reset()


def test_the_example_api_version_is_listed(example_discoverable):
    from poissonkit.plugin import plugin_reports, reset

    reset()
    try:
        (report,) = [r for r in plugin_reports() if r.name == "lennard_jones"]
        assert report.api == "1.0" and not report.warnings
    finally:
        reset()


@pytest.mark.slow
def test_the_example_test_folder_passes(example_discoverable, tmp_path):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    run = subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-q",
                          "-m", "slow or not slow", "-W", "ignore::UserWarning",
                          str(EXAMPLE / "tests")], capture_output=True, text=True, env=env,
                         cwd=tmp_path, check=False)
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-2000:]
    assert ROOT.exists()

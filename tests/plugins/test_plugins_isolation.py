"""The project's registry tests pass with a third-party plugin installed.

A user who installs any plugin must still be able to run this suite: tests that need the
built-ins alone switch autoloading off (``POISSONKIT_DISABLE_PLUGIN_AUTOLOAD=1``), the others
check that the built-in entries are included rather than that the list is exact. The check is
real: ``third_party_echo`` (one renamed copy of an entry of every kind) is installed as a
distribution in a directory on ``PYTHONPATH`` and the registry tests run in a child process.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from poissonkit.plugin.manager import KINDS

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).parent

#: Test files that look at the whole registry (listings, unknown-name messages, families,
#: blocked built-ins, outcomes).
REGISTRY_TESTS = (
    "tests/plugins/test_plugins_host.py",
    "tests/plugins/test_plugins_builtins_blocked.py",
    "tests/plugins/test_plugins_listing_details.py",
    "tests/scene/test_model_families.py",
    "tests/scene/test_scene_loader.py",
    "tests/scene/test_scene_registry.py",
    "tests/scene/test_scene_discovery.py",
    "tests/sweep/test_sweep_outcomes.py",
    "tests/sweep/test_sweep_plugins.py",
    "tests/numerics/test_numerics_registry.py",
)


def _install_echo(site: Path) -> dict[str, str]:
    """Install ``third_party_echo`` into ``site``; the environment of a process that sees it."""
    info = site / "poissonkit_echo-1.0.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: poissonkit-echo\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text("[poissonkit]\necho = third_party_echo\n")
    shutil.copy(HERE / "third_party_echo.py", site / "third_party_echo.py")
    env = {k: v for k, v in os.environ.items()
           if k not in ("POISSONKIT_DISABLE_PLUGIN_AUTOLOAD", "POISSONKIT_BLOCK_PLUGINS")}
    env["PYTHONPATH"] = os.pathsep.join([str(site), str(ROOT), str(ROOT / "plugins"),
                                         env.get("PYTHONPATH", "")])
    return env


def test_the_echo_plugin_adds_an_entry_of_every_kind(tmp_path):
    env = _install_echo(tmp_path / "site")
    code = ("from poissonkit.plugin.manager import KINDS, entries\n"
            "print(sorted(k for k, _ in KINDS.values()\n"
            "             if any(n.startswith('echo_') for n in entries(k))))\n")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         timeout=120, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == str(sorted(k for k, _ in KINDS.values()))


@pytest.mark.timeout(600)
@pytest.mark.slow  # a child pytest over the registry tests (about 30 s on an idle machine)
def test_registry_tests_pass_with_a_third_party_plugin_installed(tmp_path):
    env = _install_echo(tmp_path / "site")
    done = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                           "-x", *REGISTRY_TESTS], env=env, capture_output=True, text=True,
                          timeout=600, cwd=ROOT)
    assert done.returncode == 0, done.stdout[-4000:] + done.stderr[-2000:]
    assert " passed" in done.stdout.splitlines()[-1]

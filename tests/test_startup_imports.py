"""What the fast paths of the command line load: a guard that does not depend on the machine.

``import poissonkit``, ``poissonkit --help`` and ``poissonkit scenes`` must not import the heavy
libraries (numba, sympy, scipy, networkx, matplotlib): each costs tenths of a second to seconds
of start-up, which the timing benchmark (``benchmarks/bench_cli_startup.py``) measures only on a
quiet machine. Here a child interpreter runs the command and reports ``sys.modules``. Third-party
plugins are switched off (``POISSONKIT_DISABLE_PLUGIN_AUTOLOAD=1``): one that imports heavy
modules when it loads keeps its own cost.

The listing is fast because the plugin host loads plugins by kind
(:data:`poissonkit.plugin.manager.BUILTIN_KINDS`); the tests below also check that table
against the hook modules and that loading by kind gives the same registries as loading all.
"""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from poissonkit.plugin import manager
from poissonkit.plugin.contributions import Entry

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("numba", "sympy", "scipy", "networkx", "matplotlib")

#: Runs the CLI in-process (as ``python -m poissonkit``) and prints the heavy modules loaded.
PROBE = """
import json, runpy, sys
argv, watched = json.loads(sys.argv[1]), json.loads(sys.argv[2])
sys.argv = ["poissonkit", *argv]
try:
    runpy.run_module("poissonkit", run_name="__main__", alter_sys=True)
except SystemExit as exc:
    code = exc.code
else:
    code = 0
heavy = sorted({m.split(".")[0] for m in sys.modules} & set(watched))
print(json.dumps({"code": code, "heavy": heavy}), file=sys.stderr)
"""


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "POISSONKIT_BLOCK_PLUGINS"}
    env["POISSONKIT_DISABLE_PLUGIN_AUTOLOAD"] = "1"
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), str(ROOT / "plugins"),
                                         env.get("PYTHONPATH", "")])
    return env


def _heavy_after(code: str, *args: str) -> dict[str, object]:
    done = subprocess.run([sys.executable, "-c", code, *args], env=_env(), cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stderr.strip().splitlines()[-1])


def test_import_poissonkit_loads_no_heavy_library():
    code = ("import json, sys, poissonkit\n"
            f"heavy = sorted(m for m in {HEAVY!r} if m in sys.modules)\n"
            "print(json.dumps({'code': 0, 'heavy': heavy}), file=sys.stderr)\n")
    assert _heavy_after(code) == {"code": 0, "heavy": []}


@pytest.mark.parametrize("argv", [["--help"], ["scenes"], ["scenes", "--json"]],
                         ids=["help", "scenes", "scenes-json"])
def test_fast_commands_load_no_heavy_library(argv):
    # a control first: the probe does see a heavy import (run --help loads the numerics)
    if argv == ["--help"]:
        seen = _heavy_after(PROBE, json.dumps(["plugins"]), json.dumps(HEAVY))
        assert seen["code"] == 0 and "numba" in seen["heavy"], seen
    assert _heavy_after(PROBE, json.dumps(argv), json.dumps(HEAVY)) == {"code": 0, "heavy": []}


@pytest.mark.parametrize("name, module", manager.BUILTIN_PLUGINS)
def test_declared_kinds_of_each_builtin_match_its_hooks(name, module):
    hooks = importlib.import_module(module)
    offered = {kind for hook, (kind, _) in manager.KINDS.items() if hasattr(hooks, hook)}
    assert manager.BUILTIN_KINDS.get(module) == offered, (
        f"built-in plugin {name!r}: BUILTIN_KINDS[{module!r}] must list the kinds of its hooks")


def _listed(found: dict[str, Entry]) -> list[tuple[str, str, str]]:
    """Name, entry type and doc of each entry, in registry order (some hooks build their
    entries anew at each call, so the entries themselves are not compared)."""
    return [(n, type(e).__name__, e.doc) for n, e in found.items()]


def test_loading_by_kind_gives_the_registries_of_loading_everything(monkeypatch):
    monkeypatch.setenv("POISSONKIT_DISABLE_PLUGIN_AUTOLOAD", "1")
    kinds = [kind for kind, _ in manager.KINDS.values()]
    manager.reset()
    try:
        by_kind = {}
        for kind in kinds:  # each from a fresh host, so only that kind's plugins are loaded
            manager.reset()
            by_kind[kind] = _listed(manager.entries(kind))
            providers = manager.providers(kind)
            assert sorted(providers) == sorted(n for n, _, _ in by_kind[kind])
        manager.reset()
        reports = manager.plugin_reports()
        for kind in kinds:
            assert _listed(manager.entries(kind)) == by_kind[kind], kind
            owners = {n: r.name for r in reports for n in r.contributions.get(kind, [])}
            assert manager.providers(kind) == owners, kind
    finally:
        manager.reset()


def test_a_scene_listing_loads_only_the_plugins_with_scenes(monkeypatch):
    monkeypatch.setenv("POISSONKIT_DISABLE_PLUGIN_AUTOLOAD", "1")
    manager.reset()
    try:
        assert "seed000" in manager.entries("scene")
        state = manager._get()
        loaded = {s.report.name for s in state.slots if s.loaded}
        scene_plugins = {n for n, m in manager.BUILTIN_PLUGINS
                         if "scene" in manager.BUILTIN_KINDS[m]}
        assert loaded == scene_plugins
    finally:
        manager.reset()


def test_loaded_reports_name_every_plugin_without_calling_other_hooks(monkeypatch):
    monkeypatch.setenv("POISSONKIT_DISABLE_PLUGIN_AUTOLOAD", "1")
    manager.reset()
    try:
        manager.entries("potential")
        light = [(r.name, r.source, r.version, r.status, r.error)
                 for r in manager.loaded_reports()]
        state = manager._get()
        assert all(s.loaded for s in state.slots)
        assert not any("outcome" in s.called or "system" in s.called for s in state.slots)
        full = [(r.name, r.source, r.version, r.status, r.error)
                for r in manager.plugin_reports()]
        assert light == full
        assert [n for n, _ in manager.BUILTIN_PLUGINS] == [r[0] for r in full]
    finally:
        manager.reset()


HALF_BROKEN = '''
from poissonkit.plugin import Param, SceneEntry, hookimpl

@hookimpl
def poissonkit_scenes():
    return [SceneEntry("pk_half_broken_scene", "A scene of a plugin with a broken hook.",
                       params=(Param("n", "int", "count", 1),), load=lambda **p: None)]

@hookimpl
def poissonkit_potentials():
    raise RuntimeError("this hook is broken on purpose")
'''


def test_a_third_party_plugin_is_loaded_whole_even_for_one_kind(tmp_path, monkeypatch):
    # loading by kind must not let a third-party plugin's scenes through while another of its
    # hooks fails: the whole plugin is skipped, as when everything is loaded
    from tests.plugins.test_plugins_host import install_fake

    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delenv("POISSONKIT_DISABLE_PLUGIN_AUTOLOAD", raising=False)
    monkeypatch.delenv("POISSONKIT_BLOCK_PLUGINS", raising=False)
    install_fake(tmp_path, "pk-half", "1.0", {"pk_half": "pk_half_broken_mod"},
                 {"pk_half_broken_mod": HALF_BROKEN})
    importlib.invalidate_caches()
    manager.reset()
    try:
        assert "pk_half_broken_scene" not in manager.entries("scene")
        assert "seed000" in manager.entries("scene")
        (half,) = [r for r in manager.plugin_reports() if r.name == "pk_half"]
        assert half.status == "failed" and "broken on purpose" in half.error
        assert "pk_half_broken_scene" not in manager.entries("scene")
    finally:
        manager.reset()

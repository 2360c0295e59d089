"""The plugin host: listing, failure isolation, environment switches, registry errors, docs.

Third-party plugins are discovered for real: each test writes a distribution
(``*.dist-info`` with ``METADATA`` and ``entry_points.txt``) and its module into a temporary
directory put on ``sys.path``, which is exactly what ``pip install`` leaves behind.
"""

from __future__ import annotations

import inspect
import json
import re
import textwrap
from pathlib import Path

import pytest

from poissonkit.cli import main as cli_main
from poissonkit.errors import UnknownNameError
from poissonkit.plugin import contributions as contrib
from poissonkit.plugin import hookspecs, plugin_reports, potential
from poissonkit.plugin.manager import BUILTIN_PLUGINS, KINDS, entries

ROOT = Path(__file__).resolve().parents[2]  # the project root

GOOD = '''
from poissonkit.plugin import PairPotential, Param, hookimpl
import sympy as sp

@hookimpl
def poissonkit_potentials():
    r = sp.Symbol("r", real=True)
    return [PairPotential("pk_test_spring", "Harmonic spring U = k (r - r0)^2 / 2.",
                          params=(Param("k", "float", "stiffness [N/m]", positive=True),
                                  Param("r0", "float", "rest length [m]", default=1.0)),
                          expr=lambda p: p["k"] * (r - p["r0"]) ** 2 / 2, orientation="none")]
'''
BROKEN_IMPORT = "import a_module_that_does_not_exist_anywhere\n"
RAISING_HOOK = '''
from poissonkit.plugin import hookimpl

@hookimpl
def poissonkit_potentials():
    raise RuntimeError("this hook is broken on purpose")
'''
WRONG_TYPE = '''
from poissonkit.plugin import SystemEntry, hookimpl

@hookimpl
def poissonkit_potentials():
    return [SystemEntry("pk_test_not_a_potential", "a system where a potential belongs")]
'''
DUPLICATE = '''
from poissonkit.plugin import PairPotential, hookimpl

@hookimpl
def poissonkit_potentials():
    return [PairPotential("gravity", "a second potential called gravity", expr=lambda p: 0)]
'''
NO_DOC = '''
from poissonkit.plugin import PairPotential, hookimpl

@hookimpl
def poissonkit_potentials():
    return [PairPotential("pk_test_undocumented", "", expr=lambda p: 0)]
'''


def install_fake(site: Path, dist: str, version: str, eps: dict[str, str],
                 modules: dict[str, str]) -> None:
    """Write a distribution with entry points in group ``poissonkit`` into ``site``."""
    info = site / f"{dist.replace('-', '_')}-{version}.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {dist}\nVersion: {version}\n")
    lines = "".join(f"{name} = {target}\n" for name, target in eps.items())
    (info / "entry_points.txt").write_text(f"[poissonkit]\n{lines}")
    for mod, src in modules.items():
        (site / f"{mod}.py").write_text(textwrap.dedent(src))


def report(name: str):
    found = [r for r in plugin_reports() if r.name == name]
    assert found, f"plugin {name!r} not reported; reports: {[r.name for r in plugin_reports()]}"
    return found[0]


# ------------------------------------------------------------------------------ listing


def test_cli_lists_every_builtin_plugin_with_version_and_contributions(capsys):
    assert cli_main(["plugins"]) == 0
    out = capsys.readouterr().out
    from poissonkit import __version__

    for name, _module in BUILTIN_PLUGINS:
        assert re.search(rf"^{re.escape(name)} {re.escape(__version__)} \(builtin\)", out, re.MULTILINE), out
    # the nbody plugin's contributions are spelled out under its name
    block = re.split(r"\n\S", out.split("\nnbody ", 1)[1], maxsplit=1)[0]
    assert "assembly: chain, ring, lattice, random_cluster" in block
    assert "potential: gravity" in block


def test_cli_json_matches_the_reports_and_the_registries(capsys, site):
    install_fake(site, "pk-good", "2.3.4", {"pk_good": "pk_good_mod"}, {"pk_good_mod": GOOD})
    assert cli_main(["plugins", "--json"]) == 0
    listed = {r["name"]: r for r in json.loads(capsys.readouterr().out)}
    assert listed["pk_good"]["version"] == "2.3.4"
    assert listed["pk_good"]["source"] == "pk-good"
    assert listed["pk_good"]["status"] == "ok"
    assert listed["pk_good"]["contributions"] == {"potential": ["pk_test_spring"]}
    # every registered entry is attributed to exactly one listed plugin
    for kind, _etype in KINDS.values():
        owners = [n for r in listed.values() for n in r["contributions"].get(kind, [])]
        assert sorted(owners) == sorted(entries(kind)), kind


def test_external_plugin_entries_are_usable_with_validated_params(site):
    install_fake(site, "pk-good", "1.0", {"pk_good": "pk_good_mod"}, {"pk_good_mod": GOOD})
    spring = potential("pk_test_spring")
    params = spring.resolve_params({"k": 2.0})
    assert params == {"k": 2.0, "r0": 1.0}
    import sympy as sp

    expr = spring.expr(params)
    assert float(expr.subs(sp.Symbol("r", real=True), 3.0)) == pytest.approx(4.0)
    with pytest.raises(Exception, match="'k' must be > 0"):
        spring.resolve_params({"k": -1.0})


# ------------------------------------------------------------------------------ failures


@pytest.mark.parametrize("source, expected", [
    (BROKEN_IMPORT, "ModuleNotFoundError"),
    (RAISING_HOOK, "this hook is broken on purpose"),
    (WRONG_TYPE, "returned SystemEntry, expected PairPotential"),
    (DUPLICATE, "'gravity' is already provided"),
    (NO_DOC, "lacks a name or a doc string"),
], ids=["import-error", "raising-hook", "wrong-entry-type", "duplicate-name", "missing-doc"])
def test_misbehaving_plugin_is_reported_and_skipped_never_fatal(site, capsys, source, expected,
                                                                 request):
    module = "pk_bad_" + re.sub(r"\W", "_", request.node.callspec.id)  # fresh module per case
    install_fake(site, "pk-bad", "0.0.1", {"pk_bad": module}, {module: source})
    install_fake(site, "pk-good", "1.0", {"pk_good": "pk_good_mod"}, {"pk_good_mod": GOOD})
    bad = report("pk_bad")
    assert bad.status == "failed"
    assert expected in bad.error
    assert bad.contributions == {}
    # the host and the other plugins are unaffected
    assert report("pk_good").status == "ok"
    assert potential("pk_test_spring").name == "pk_test_spring"
    gravity = potential("gravity")
    assert "Newtonian" in gravity.doc  # the built-in one, not the duplicate
    assert not any(n.startswith("pk_test_not") or n == "pk_test_undocumented"
                   for kind, _ in KINDS.values() for n in entries(kind))
    # and the CLI shows the failure with its reason, exit code 0
    assert cli_main(["plugins"]) == 0
    out = capsys.readouterr().out
    line = next(ln for ln in out.splitlines() if ln.startswith("pk_bad "))
    assert "[FAILED]" in line and expected in line


def test_plugin_whose_name_clashes_with_a_builtin_contributes_nothing(site):
    install_fake(site, "pk-clash", "1.0", {"nbody": "pk_good_mod"}, {"pk_good_mod": GOOD})
    clash = [r for r in plugin_reports() if r.name == "nbody" and r.source == "pk-clash"]
    assert clash and clash[0].status == "failed"
    assert "pk_test_spring" not in entries("potential")


# ------------------------------------------------------------------------------ switches


def test_disable_autoload_keeps_builtins_and_skips_entry_points(site, monkeypatch):
    install_fake(site, "pk-good", "1.0", {"pk_good": "pk_good_mod"}, {"pk_good_mod": GOOD})
    monkeypatch.setenv("POISSONKIT_DISABLE_PLUGIN_AUTOLOAD", "1")
    names = [r.name for r in plugin_reports()]
    assert "pk_good" not in names
    assert [n for n, _ in BUILTIN_PLUGINS] == names[: len(BUILTIN_PLUGINS)]
    with pytest.raises(UnknownNameError):
        potential("pk_test_spring")
    assert potential("gravity").name == "gravity"


def test_block_plugins_by_name_builtin_and_external(site, monkeypatch):
    install_fake(site, "pk-good", "1.0", {"pk_good": "pk_good_mod"}, {"pk_good_mod": GOOD})
    monkeypatch.setenv("POISSONKIT_BLOCK_PLUGINS", " nbody , pk_good")
    assert report("nbody").status == "blocked"
    assert report("pk_good").status == "blocked"
    assert report("magnets").status == "ok"
    for name in ("pk_test_spring", "gravity"):
        with pytest.raises(UnknownNameError):
            potential(name)
    assert "chain" not in entries("assembly")


# ------------------------------------------------------------------------------ look-ups


def test_unknown_names_fail_listing_the_available_ones():
    with pytest.raises(UnknownNameError) as info:
        potential("no_such_potential")
    msg = str(info.value)
    assert "unknown potential 'no_such_potential'" in msg
    assert "gravity" in msg and set(info.value.available) == set(entries("potential"))
    from poissonkit.plugin import assembly

    with pytest.raises(UnknownNameError, match="unknown assembly 'helix'; available: ") as info:
        assembly("helix")
    # inclusion, not equality: an installed third-party plugin may add assemblies
    assert {"chain", "lattice", "random_cluster", "ring"} <= set(info.value.available)
    assert set(info.value.available) == set(entries("assembly"))
    with pytest.raises(UnknownNameError, match="available: .*potential"):
        entries("potentials")


# ------------------------------------------------------------------------------ docs


DOC = ROOT / "docs" / "plugins.md"


def _hooks() -> list[str]:
    return [name for name, fn in inspect.getmembers(hookspecs, inspect.isfunction)
            if hasattr(fn, f"{hookspecs.PROJECT}_spec")]


def _section(text: str, heading: str) -> str:
    """Body of the markdown section whose heading contains ``heading`` (in backticks)."""
    m = re.search(rf"^#+ .*`{re.escape(heading)}`.*$", text, re.MULTILINE)
    if not m:
        return ""
    rest = text[m.end():]
    nxt = re.search(r"^#+ ", rest, re.MULTILINE)
    return rest[: nxt.start()] if nxt else rest


def test_every_hook_is_documented_in_docs_plugins_md():
    text = DOC.read_text(encoding="utf-8")
    hooks = _hooks()
    assert set(hooks) == set(KINDS), "hookspecs and the manager's KINDS disagree"
    for hook in hooks:
        body = _section(text, hook)
        assert len(body.split()) >= 15, f"docs/plugins.md lacks a section documenting {hook}"
        etype = KINDS[hook][1].__name__
        assert etype in body, f"the section of {hook} does not name its entry type {etype}"


def test_every_entry_type_and_field_is_documented():
    text = DOC.read_text(encoding="utf-8")
    types = [contrib.Param] + [etype for _kind, etype in KINDS.values()]
    for etype in types:
        body = _section(text, etype.__name__)
        assert body, f"docs/plugins.md has no section for {etype.__name__}"
        for field in etype.__dataclass_fields__:
            assert re.search(rf"`{field}`", body), f"{etype.__name__}.{field} is not documented"


def test_environment_switches_are_documented():
    text = DOC.read_text(encoding="utf-8")
    from poissonkit.plugin.manager import ENV_BLOCK, ENV_DISABLE

    assert ENV_BLOCK in text and ENV_DISABLE in text
    assert "[project.entry-points.poissonkit]" in text

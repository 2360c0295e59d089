"""Plugin failures surface where they matter: failed plugins are named by every look-up of an
entry they might have provided, and misspelt hook names are reported as warnings.

Fake third-party plugins are installed for real (a ``*.dist-info`` with entry points on
``sys.path``), as in ``test_plugins_host.py``.
"""

from __future__ import annotations

import json

import pytest

from poissonkit.cli import main as cli_main
from poissonkit.errors import SceneError, UnknownEntryError, UnknownNameError
from poissonkit.plugin import assembly, lookup, plugin_reports, potential
from poissonkit.plugin.manager import plugin_manager
from poissonkit.scene import loads_scene
from tests.plugins.test_plugins_host import BROKEN_IMPORT, GOOD, install_fake

MISSPELT = '''
from poissonkit.plugin import Assembly, PairPotential, hookimpl

@hookimpl
def poissonkit_assembly():  # misspelt: the hook is poissonkit_assemblies
    return []

def poissonkit_potential():  # misspelt and undecorated: pluggy never sees it
    return []

@hookimpl
def poissonkit_potentials():
    return [PairPotential("pk_test_zero", "A zero potential.", expr=lambda p: 0,
                          orientation="none")]
'''

SCENE = '''
name = "uses_a_missing_assembly"
[assembly]
name = "pk_lj_cluster"
params = {}
[interactions]
potential = "gravity"
[run]
method = "splitting4"
duration = 1.0
step = 0.01
'''


def _report(name: str):
    return next(r for r in plugin_reports() if r.name == name)


def test_unknown_entry_names_the_failed_plugin(site):
    install_fake(site, "pk-broken", "0.1", {"pk_broken": "pk_broken_mod"},
                 {"pk_broken_mod": BROKEN_IMPORT})
    assert _report("pk_broken").status == "failed"
    for get, kind in ((assembly, "assembly"), (potential, "potential")):
        with pytest.raises(UnknownEntryError) as exc:
            get("pk_lj_cluster")
        msg = str(exc.value)
        assert msg.startswith(f"unknown {kind} 'pk_lj_cluster'; available: ")
        assert "(plugin 'pk_broken' failed to load: ModuleNotFoundError" in msg
        assert msg.endswith("; see `poissonkit plugins`)")
        assert isinstance(exc.value, UnknownNameError) and isinstance(exc.value, KeyError)
        assert exc.value.failed[0][0] == "pk_broken"
    # a scene using the missing assembly says so in its field's message
    with pytest.raises(SceneError, match=r"assembly\.name: unknown assembly .*'pk_broken' "
                       r"failed to load"):
        loads_scene(SCENE, source="test")


def test_run_of_an_unknown_name_names_the_failed_plugin(site, capsys):
    install_fake(site, "pk-broken", "0.1", {"pk_broken": "pk_broken_mod"},
                 {"pk_broken_mod": BROKEN_IMPORT})
    assert cli_main(["run", "pk_lj_scene", "--no-progress"]) == 1
    err = capsys.readouterr().err
    assert "shipped scene files:" in err and "plugin 'pk_broken' failed to load" in err


def test_without_failed_plugins_the_message_is_unchanged(site):
    install_fake(site, "pk-good", "1.0", {"pk_good": "pk_good_mod"}, {"pk_good_mod": GOOD})
    with pytest.raises(UnknownEntryError) as exc:
        lookup("potential", "pk_nothing")
    assert "failed to load" not in str(exc.value) and exc.value.failed == []


def test_misspelt_hooks_are_warnings_never_fatal(site, capsys):
    install_fake(site, "pk-typo", "1.0", {"pk_typo": "pk_typo_mod"}, {"pk_typo_mod": MISSPELT})
    typo = _report("pk_typo")
    assert typo.status == "ok"
    assert typo.contributions == {"potential": ["pk_test_zero"]}
    assert potential("pk_test_zero").name == "pk_test_zero"  # the rest of the plugin works
    assert len(typo.warnings) == 2
    assert "unknown hook 'poissonkit_assembly'" in typo.warnings[0]
    assert "did you mean 'poissonkit_assemblies'?" in typo.warnings[0]
    assert "unknown hook 'poissonkit_potential'" in typo.warnings[1]
    # pluggy agrees that the decorated one has no hook specification
    from pluggy import PluginValidationError

    with pytest.raises(PluginValidationError, match="poissonkit_assembly"):
        plugin_manager().check_pending()
    # the built-in plugins have no such warnings (no false positives)
    assert not [r.name for r in plugin_reports() if r.source == "builtin" and r.warnings]
    assert cli_main(["plugins"]) == 0
    out = capsys.readouterr().out
    block = out.split("pk_typo 1.0 (pk-typo)", 1)[1]
    assert block.startswith(" [plugin API unversioned]  [2 WARNINGS]")
    assert "    warning: unknown hook 'poissonkit_assembly' is ignored" in block
    assert cli_main(["plugins", "--json"]) == 0
    listed = {r["name"]: r for r in json.loads(capsys.readouterr().out)}
    assert listed["pk_typo"]["warnings"] == typo.warnings

"""The plugin API is versioned: a plugin states the version it was written for
(``POISSONKIT_API`` of its hooks module), ``poissonkit plugins`` shows it and warns on a
mismatch; built-ins carry the host's own version."""

from __future__ import annotations

import json

import pytest
from test_plugins_host import install_fake

from poissonkit.cli import main as cli_main
from poissonkit.plugin import plugin_reports, reset
from poissonkit.plugin.hookspecs import PLUGIN_API_VERSION
from poissonkit.plugin.manager import api_mismatch

SOURCE = '''
from poissonkit.plugin import PairPotential, Param, hookimpl
{declaration}

def _u(p):
    import sympy as sp
    return p["k"] / sp.Symbol("r", real=True)

@hookimpl
def poissonkit_potentials():
    return [PairPotential("{potential}", "a test potential",
                          params=(Param("k", "float", "strength [J m]", 1.0, unit="J m"),),
                          expr=_u, orientation="none")]
'''


@pytest.fixture
def versioned(site):
    plugins = {"pk_api_same": 'POISSONKIT_API = "1.0"', "pk_api_major": 'POISSONKIT_API = "2.0"',
               "pk_api_newer": 'POISSONKIT_API = "1.9"', "pk_api_none": "",
               "pk_api_bad": 'POISSONKIT_API = "one"'}
    for name, declaration in plugins.items():
        install_fake(site, name.replace("_", "-"), "0.1", {name: name},
                     {name: SOURCE.format(declaration=declaration, potential=f"{name}_u")})
    reset()
    yield {r.name: r for r in plugin_reports()}
    reset()


def test_the_host_version_is_major_minor():
    major, minor = (int(x) for x in PLUGIN_API_VERSION.split("."))
    assert major >= 1 and minor >= 0


@pytest.mark.parametrize("declared, host, ok", [
    ("1.0", "1.0", True), ("1.0", "1.3", True), ("unversioned", "1.0", True),
    ("1.4", "1.3", False), ("2.0", "1.3", False), ("0.9", "1.0", False), ("one", "1.0", False),
])
def test_a_mismatch_is_another_major_or_a_newer_minor(declared, host, ok):
    assert (api_mismatch(declared, host) is None) == ok


def test_each_plugin_reports_the_version_it_was_written_for(versioned):
    assert versioned["pk_api_same"].api == "1.0" and versioned["pk_api_same"].warnings == []
    assert versioned["pk_api_none"].api == "unversioned" and versioned["pk_api_none"].warnings == []
    assert versioned["magnets"].api == PLUGIN_API_VERSION  # built-ins: the host's own
    (major,) = versioned["pk_api_major"].warnings
    assert "written for plugin API 2.0" in major and "another major version" in major
    assert "upgrade poissonkit" in versioned["pk_api_newer"].warnings[0]
    assert "not a version" in versioned["pk_api_bad"].warnings[0]
    # a mismatch warns, it does not block: the potential is registered
    assert versioned["pk_api_major"].status == "ok"
    assert versioned["pk_api_major"].contributions["potential"] == ["pk_api_major_u"]


def test_poissonkit_plugins_prints_the_versions_and_warns(versioned, capsys):
    assert cli_main(["plugins"]) == 0
    out = capsys.readouterr().out
    lines = out.splitlines()
    assert lines[0] == f"plugin API {PLUGIN_API_VERSION}"
    head = next(i for i, line in enumerate(lines) if line.startswith("pk_api_major "))
    assert lines[head].endswith("[plugin API 2.0]  [1 WARNING]")
    assert lines[head + 1].startswith("    warning: written for plugin API 2.0")
    assert any(line.startswith("pk_api_none 0.1 (pk-api-none) [plugin API unversioned]")
               for line in lines)
    assert cli_main(["plugins", "--json"]) == 0
    listed = {r["name"]: r for r in json.loads(capsys.readouterr().out)}
    assert listed["pk_api_same"]["api"] == "1.0" and listed["magnets"]["api"] == PLUGIN_API_VERSION

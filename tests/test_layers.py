"""The layering rule: the core never imports a plugin, and plugins use only public core API.

``docs/architecture.md`` states the rule; these tests keep it. They read the source (AST), so
an import hidden inside a function fails as surely as one at the top of a module.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CORE = ROOT / "poissonkit"
PLUGINS = ROOT / "plugins"
#: The one core module allowed to *name* the built-in plugins (as strings, not imports).
MANAGER = CORE / "plugin" / "manager.py"


def _imports(path: Path) -> list[tuple[int, str, list[str]]]:
    """``(line, module, imported names)`` of every import statement in ``path``."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    out: list[tuple[int, str, list[str]]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.extend((node.lineno, a.name, []) for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.append((node.lineno, node.module, [a.name for a in node.names]))
    return out


def _sources(folder: Path) -> list[Path]:
    return sorted(p for p in folder.rglob("*.py") if "__pycache__" not in p.parts)


def test_the_core_never_imports_a_plugin():
    offenders = [f"{path.relative_to(ROOT)}:{line} imports {module}"
                 for path in _sources(CORE)
                 for line, module, _ in _imports(path)
                 if module.split(".")[0].startswith("poissonkit_")]
    assert not offenders, "the core imports plugins:\n" + "\n".join(offenders)


def test_the_layering_test_sees_imports_inside_functions(tmp_path):
    # a negative control: the walk must find an import nested in a function body
    src = tmp_path / "mod.py"
    src.write_text("def f():\n    from poissonkit_magnets import fidelity\n    return fidelity\n")
    assert [(line, module) for line, module, _ in _imports(src)] == [(2, "poissonkit_magnets")]


def test_the_manager_names_builtin_plugins_only_as_strings():
    from poissonkit.plugin.manager import BUILTIN_PLUGINS

    assert not [m for _, m, _ in _imports(MANAGER) if m.startswith("poissonkit_")]
    assert {name for name, _ in BUILTIN_PLUGINS} >= {"magnets", "nbody", "nonholonomic"}


@pytest.mark.parametrize("plugin", sorted(p.name for p in PLUGINS.iterdir()
                                          if (p / "__init__.py").exists()))
def test_plugins_borrow_only_public_core_api(plugin):
    bad = []
    for path in _sources(PLUGINS / plugin):
        for line, module, names in _imports(path):
            if module.split(".")[0] != "poissonkit":
                continue
            parts = module.split(".")
            where = f"{path.relative_to(ROOT)}:{line}"
            if parts[:2] in (["poissonkit", "commands"], ["poissonkit", "cli"]):
                bad.append(f"{where} imports the CLI module {module}")
            if any(p.startswith("_") for p in parts[1:]):
                bad.append(f"{where} imports the private module {module}")
            bad.extend(f"{where} imports the private name {module}.{n}" for n in names
                       if n.startswith("_"))
    assert not bad, "\n".join(bad)

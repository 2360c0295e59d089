"""The non-holonomic plugin borrows only public core API: no CLI modules, no private names.

Truth: the plugin's own source, read as an AST; and the Jacobi verdict of its report, which
must be the verify engine's (the same verdict ``poissonkit.verify`` gives).
"""

from __future__ import annotations

import ast
from pathlib import Path

import poissonkit_nonholonomic
from poissonkit.structure.verification import jacobi_verdict

PLUGIN = Path(poissonkit_nonholonomic.__file__).parent


def _core_imports(tree: ast.AST) -> list[tuple[str, str]]:
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and \
                node.module.split(".")[0] == "poissonkit":
            out += [(node.module, a.name) for a in node.names]
        elif isinstance(node, ast.Import):
            out += [(a.name, "") for a in node.names if a.name.split(".")[0] == "poissonkit"]
    return out


def test_plugin_imports_no_cli_module_and_no_private_core_name():
    bad = []
    for path in sorted(PLUGIN.glob("*.py")):
        for module, name in _core_imports(ast.parse(path.read_text())):
            parts = module.split(".")
            if parts[:2] in (["poissonkit", "commands"], ["poissonkit", "cli"]) \
                    or any(p.startswith("_") for p in parts[1:]) or name.startswith("_"):
                bad.append(f"{path.name}: from {module} import {name}")
    assert bad == []


def test_the_guard_sees_a_private_import():
    tree = ast.parse("from poissonkit.commands.verify import _jacobi_task\n")
    assert _core_imports(tree) == [("poissonkit.commands.verify", "_jacobi_task")]


def test_plugin_jacobi_claim_is_the_engine_verdict():
    from poissonkit_nonholonomic.suslov import suslov_rank4
    from poissonkit_nonholonomic.verify import verify_system

    system = suslov_rank4()
    report = verify_system(system, extra=False, seed=3)
    engine = jacobi_verdict(system.structure, "auto", constraints=system.constraints,
                            trials=3, seed=3)
    assert report["checks"][0]["ok"] is engine.is_poisson is True

"""The layering rules: the package order inside the core, and the core never importing a plugin.

``docs/architecture.md`` states the rules; these tests keep them. They read the source (AST),
so an import hidden inside a function fails as surely as one at the top of a module.

The core's packages form a stack (:data:`LAYERS`, lowest first). A module may import modules of
its own layer or of a lower one, never of a higher one, whether at the top of the module or
lazily inside a function. The one exception is an import under ``if TYPE_CHECKING:``: it never
runs, so it cannot make a cycle, and annotations may name a type of a higher layer (e.g. a
numerics module annotating a :class:`~poissonkit.numerics.runspec.RunSpec` argument). The
contracts (:mod:`poissonkit.contracts`) are held to more: see
:func:`test_the_contracts_import_no_implementation_module`.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CORE = ROOT / "poissonkit"
PLUGINS = ROOT / "plugins"
ARCHITECTURE = ROOT / "docs" / "architecture.md"
#: The one core module allowed to *name* the built-in plugins (as strings, not imports).
MANAGER = CORE / "plugin" / "manager.py"

#: The package order, lowest first: ``(layer, members)``, a member being the first name after
#: ``poissonkit.`` (a subpackage or a top-level module; ``""`` is the package root,
#: ``poissonkit/__init__.py``, the public facade that re-exports from every layer).
LAYERS: tuple[tuple[str, tuple[str, ...]], ...] = (
    # leaves: no poissonkit import but other leaves (errors are imported by all of them)
    ("leaves", ("errors", "_version", "conventions", "validation", "input_limits", "_display",
                "_lazy", "files", "killpoints", "geometry", "contracts", "traits")),
    # the pluggy host: hook specifications, entry types, registries
    ("plugin", ("plugin",)),
    # the symbolic layer (sympy)
    ("structure", ("structure",)),
    # the PoissonGeometry-compatible front end of the symbolic layer
    ("compat", ("compat",)),
    # codegen, N-body, fields, integrators, events, diagnostics, equilibria
    ("numerics", ("numerics",)),
    # scenes (schema, loader, graph → system, planner) and the pair-interaction calculator,
    # which evaluates registered potentials between two placed bodies
    ("scene", ("scene", "pairs")),
    # other engines that run a built scene (LAMMPS), returning poissonkit's state layout
    ("engines", ("engines",)),
    # summaries, trajectories, figures and the 3D view of runs
    ("report", ("report",)),
    # sweeps on Dask over scenes
    ("sweeps", ("sweeps",)),
    # the kit for plugin authors: checks of every kind of contribution (they build systems,
    # scenes and sweep records), hypothesis strategies, the plugin template
    ("testing", ("testing",)),
    # one module per CLI subcommand and the parser that lists them
    ("commands", ("commands",)),
    # the entry points and the package facade
    ("entry", ("cli", "__main__", "")),
)
_RANK = {member: rank for rank, (_, members) in enumerate(LAYERS) for member in members}

#: What :mod:`poissonkit.contracts` may still name under ``TYPE_CHECKING``, and why: types that
#: belong to the implementation they describe (each holds or returns numerics objects), so they
#: cannot move next to the contracts without dragging that implementation along.
CONTRACTS_MAY_NAME = {
    # holds EventRecord rows of the numerics' events
    "poissonkit.numerics.integrators.base": {"RawResult"},
    # holds a Checkpoint and a TrajectoryStream of numerics/checkpoint.py
    "poissonkit.numerics.integrators.driver": {"Control"},
    # the symbolic bivector itself (a sympy matrix with its whole algebra)
    "poissonkit.structure": {"Bivector"},
    # holds a Solution and the system of the sweep's run
    "poissonkit.sweeps.targets": {"RunRecord"},
}


def _imports(path: Path) -> list[tuple[int, str, list[str]]]:
    """``(line, module, imported names)`` of every absolute import statement in ``path``."""
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


def _module_name(path: Path, root: Path) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    """``id`` of every node under an ``if TYPE_CHECKING:`` (or ``typing.TYPE_CHECKING``)."""
    inside: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for stmt in node.body:  # the ``else`` branch runs
                inside.update(id(n) for n in ast.walk(stmt))
    return inside


def _core_imports(path: Path, root: Path) -> list[tuple[int, str, bool]]:
    """``(line, target module, under TYPE_CHECKING)`` of every poissonkit import of ``path``.

    Relative imports are resolved against the module's package; ``from poissonkit.x import y``
    targets ``poissonkit.x.y`` when that is a module of the tree, else ``poissonkit.x``.
    """
    module = _module_name(path, root)
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    guarded = _type_checking_nodes(tree)
    out: list[tuple[int, str, bool]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                base = ".".join(anchor + ([base] if base else []))
            targets = []
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                is_module = any((root / Path(*sub.split("."))).with_suffix(s).exists()
                                for s in (".py",)) or (root / Path(*sub.split("."))).is_dir()
                targets.append(sub if is_module else base)
        else:
            continue
        out.extend((node.lineno, t, id(node) in guarded) for t in targets
                   if t == "poissonkit" or t.startswith("poissonkit."))
    return out


def _layer_of(module: str) -> int | None:
    parts = module.split(".")
    return _RANK.get(parts[1] if len(parts) > 1 else "")


def _upward_imports(root: Path) -> list[str]:
    """Every import of a module of a higher layer, outside ``TYPE_CHECKING``, under ``root``
    (the folder holding the ``poissonkit`` package)."""
    bad = []
    for path in _sources(root / "poissonkit"):
        module = _module_name(path, root)
        here = _layer_of(module)
        for line, target, type_only in _core_imports(path, root):
            there = _layer_of(target)
            if type_only or here is None or there is None or there <= here:
                continue
            bad.append(f"{path.relative_to(root)}:{line} ({LAYERS[here][0]}) imports {target} "
                       f"({LAYERS[there][0]})")
    return bad


def test_every_core_module_has_a_layer():
    members = {_module_name(p, ROOT).split(".")[1] if "." in _module_name(p, ROOT) else ""
               for p in _sources(CORE)}
    assert not members - set(_RANK), f"place these in LAYERS: {sorted(members - set(_RANK))}"


def test_no_module_imports_a_higher_layer():
    bad = _upward_imports(ROOT)
    assert not bad, "upward imports (lower layers must not import higher ones):\n" + "\n".join(bad)


def _fake_tree(tmp_path: Path, source: str) -> Path:
    for package in ("poissonkit", "poissonkit/numerics", "poissonkit/report"):
        (tmp_path / package).mkdir(exist_ok=True)
        (tmp_path / package / "__init__.py").write_text("")
    (tmp_path / "poissonkit" / "report" / "atomic.py").write_text("")
    (tmp_path / "poissonkit" / "numerics" / "checkpoint.py").write_text(source)
    return tmp_path


@pytest.mark.parametrize("source", [
    "from poissonkit.report import atomic\n",
    "import poissonkit.report.atomic\n",
    "def save():\n    from ..report.atomic import write_text\n    return write_text\n",
    "from poissonkit import report\n",
])
def test_the_layer_test_catches_an_upward_import(tmp_path, source):
    # negative control: a numerics module importing the report layer, at the top, inside a
    # function, relatively or as ``from package import module``, is caught
    bad = _upward_imports(_fake_tree(tmp_path, source))
    assert len(bad) == 1 and "(numerics) imports poissonkit.report" in bad[0], bad


def test_the_layer_test_lets_type_checking_imports_and_lower_layers_pass(tmp_path):
    source = ("from typing import TYPE_CHECKING\nfrom poissonkit.numerics import checkpoint\n"
              "if TYPE_CHECKING:\n    from poissonkit.report.atomic import write_text\n")
    assert _upward_imports(_fake_tree(tmp_path, source)) == []


def test_the_contracts_import_no_implementation_module():
    # at run time contracts import nothing of poissonkit; for annotations only the listed types
    # of CONTRACTS_MAY_NAME (entangled with their implementation; see there)
    path = CORE / "contracts.py"
    tree = ast.parse(path.read_text(encoding="utf-8"))
    guarded = _type_checking_nodes(tree)
    bad = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            bad += [a.name for a in node.names if a.name.split(".")[0] == "poissonkit"]
        elif isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").split(".")[0]
                                                   == "poissonkit"):
            allowed = CONTRACTS_MAY_NAME.get(node.module or "", set()) if id(node) in guarded \
                else set()
            bad += [f"{node.module}.{a.name}" for a in node.names if a.name not in allowed]
    assert not bad, f"contracts.py imports implementation: {bad}"


def test_the_architecture_page_lists_every_layer_in_order():
    text = ARCHITECTURE.read_text(encoding="utf-8")
    positions = []
    for layer, members in LAYERS:
        names = [f"`poissonkit.{m}`" if m else "`poissonkit`" for m in members]
        missing = [n for n in names if n not in text]
        assert not missing, f"docs/architecture.md does not name {missing} (layer {layer})"
        positions.append(text.index(f"| {layer} |"))
    assert positions == sorted(positions), "the layers table is not in the order of LAYERS"


def _defined(path: Path, kind: type[ast.AST]) -> list[ast.AST]:
    return [n for n in ast.parse(path.read_text(encoding="utf-8")).body if isinstance(n, kind)]


def test_the_architecture_page_states_every_hook_and_protocol():
    text = ARCHITECTURE.read_text(encoding="utf-8")
    hooks = [n.name for n in _defined(CORE / "plugin" / "hookspecs.py", ast.FunctionDef)]
    protocols = [n.name for n in _defined(CORE / "contracts.py", ast.ClassDef)
                 if any(ast.unparse(b) == "Protocol" for b in n.bases)]
    assert len(hooks) >= 8 and len(protocols) >= 30  # the walk finds them (negative control)
    missing = [f"hook {h}" for h in hooks if f"| `{h}` |" not in text]
    missing += [f"protocol {p}" for p in protocols if f"`{p}`" not in text]
    assert not missing, f"docs/architecture.md does not state: {missing}"
    # the numerics never import the reports; the page must not allow it again
    numerics_row = next(line for line in text.splitlines() if line.startswith("| numerics |"))
    assert "report" not in numerics_row


#: What the type check must hold strictly: the contracts and the plugin-facing registry.
STRICT_MODULES = {"poissonkit.contracts", "poissonkit.plugin.contributions",
                  "poissonkit.plugin.registry", "poissonkit.plugin.hookspecs"}
STRICT_FLAGS = {"disallow_untyped_defs", "disallow_incomplete_defs", "disallow_untyped_calls",
                "disallow_any_generics", "check_untyped_defs", "no_implicit_reexport",
                "warn_return_any", "strict_equality"}


def test_mypy_checks_the_contracts_strictly_and_ci_runs_it():
    import tomllib

    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["mypy"]
    assert {"poissonkit", "plugins/poissonkit_magnets"} <= set(config["files"])
    overrides = config.get("overrides", [])
    strict = [o for o in overrides if STRICT_FLAGS <= {k for k, v in o.items() if v is True}]
    covered = {m for o in strict for m in ([o["module"]] if isinstance(o["module"], str)
                                           else o["module"])}
    assert STRICT_MODULES <= covered, f"not strict: {STRICT_MODULES - covered}"
    relaxed = {m for o in overrides if o.get("ignore_errors")
               for m in ([o["module"]] if isinstance(o["module"], str) else o["module"])}
    assert not STRICT_MODULES & relaxed
    assert "python -m mypy" in (ROOT / ".ci" / "run").read_text(encoding="utf-8")


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

"""Fast from the first second: what ``import poissonkit`` and the light commands load, and the
notice printed when kernels compile (timings: benchmarks/bench_cli_startup.py)."""

from __future__ import annotations

import io
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("sympy", "numpy", "numba", "scipy", "matplotlib", "xarray", "dask", "plotly",
         "networkx", "importlib.metadata")


def _loaded(code: str) -> set[str]:
    """The heavy modules in ``sys.modules`` after running ``code`` in a fresh interpreter."""
    probe = (code + "\nimport sys\nprint(' '.join(m for m in " + repr(HEAVY)
             + " if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         timeout=120, cwd=ROOT)
    assert out.returncode == 0, out.stderr
    return set(out.stdout.split())


def test_import_poissonkit_loads_no_heavy_dependency():
    assert _loaded("import poissonkit") == set()


def test_help_loads_no_heavy_dependency_and_no_command_module():
    code = ("import sys, contextlib, io\nfrom poissonkit.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    try:\n        main(['--help'])\n    except SystemExit:\n        pass\n"
            "assert not any(m.startswith('poissonkit.commands.') and m != "
            "'poissonkit.commands.parser' for m in sys.modules), sorted(sys.modules)")
    assert _loaded(code) == set()


def test_first_use_of_a_lazy_name_imports_it():
    code = ("import sys, poissonkit as pk\nassert 'sympy' not in sys.modules\n"
            "assert pk.Bivector.__name__ == 'Bivector' and 'sympy' in sys.modules\n"
            "assert pk.__version__")
    assert "sympy" in _loaded(code)


def test_compile_notice_only_when_it_takes_a_while():
    from types import SimpleNamespace

    from poissonkit.numerics.solve_compile import COMPILE_SECONDS, compile_notice

    spec = SimpleNamespace(method="wisdom_holman", system=object(), metadata={})
    out = io.StringIO()
    with compile_notice(spec, stream=out, after=0.05):  # type: ignore[arg-type]
        time.sleep(0.5)
    text = out.getvalue()
    assert text.startswith("compiling kernels (first run of this scene type with "
                           "wisdom_holman; about ")
    assert f"about {COMPILE_SECONDS['wisdom_holman']} s" in text
    quick = io.StringIO()
    with compile_notice(spec, stream=quick, after=0.5):  # type: ignore[arg-type]
        pass
    time.sleep(0.7)
    assert quick.getvalue() == ""  # a warm start says nothing
    with compile_notice(spec, enabled=False, stream=quick, after=0.0):  # type: ignore[arg-type]
        time.sleep(0.1)
    assert quick.getvalue() == ""


@pytest.mark.parametrize("kind", ["two-body", "n-body"])
def test_scene_kind_of_a_real_spec(kind):
    """The kind is read from the run: the seed scene is a two-body system, a scene file with
    bodies an N-body one."""
    from poissonkit.numerics.runspec import RunSpec
    from poissonkit.numerics.solve_compile import scene_kind
    from poissonkit.plugin import scene
    from poissonkit.scene import build_run, load_scene

    if kind == "two-body":
        loaded = scene("seed000").load()
        spec = loaded if isinstance(loaded, RunSpec) else build_run(loaded)
    else:
        spec = build_run(load_scene(ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"))
    assert scene_kind(spec) == kind

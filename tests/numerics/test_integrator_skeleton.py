"""The integrators' shared skeleton: status codes by name, module sizes of the package."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import poissonkit.numerics.integrators as integrators_pkg

INTEGRATORS = Path(integrators_pkg.__file__).parent


def literal_statuses(source: str) -> list[int]:
    """Line numbers of ``return <int literal>, ...`` (a status written as a number)."""
    lines = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Return) and isinstance(node.value, ast.Tuple) and node.value.elts:
            first = node.value.elts[0]
            if isinstance(first, ast.Constant) and type(first.value) is int:
                lines.append(node.lineno)
    return lines


def test_literal_status_is_found() -> None:
    """Negative control: the scan sees a status returned as a number."""
    src = "def run(y, t):\n    if y:\n        return 1, t, 0\n    return RUNNING, t, 0\n"
    assert literal_statuses(src) == [3]


@pytest.mark.parametrize("path", sorted(INTEGRATORS.rglob("*.py")), ids=lambda p: p.name)
def test_no_literal_status(path: Path) -> None:
    """Every compiled loop returns its status by name (RUNNING, NONFINITE, DONE, ...)."""
    assert literal_statuses(path.read_text(encoding="utf-8")) == []


@pytest.mark.parametrize("path", sorted(INTEGRATORS.rglob("*.py")), ids=lambda p: p.name)
def test_module_size(path: Path) -> None:
    """Modules of one job: none over 600 lines."""
    assert len(path.read_text(encoding="utf-8").splitlines()) <= 600


def test_options_are_listed_as_data() -> None:
    """Each option of an entry: name, type, default, doc and allowed values."""
    from poissonkit.plugin import integrator

    opts = {o.name: o for o in integrator("discrete_gradient").options()}
    assert set(opts) == {"gradient", "tol", "max_iterations", "newton"}
    g = opts["gradient"]
    assert (g.type, g.default, g.choices) == ("str", "auto", ("auto", "avf", "gonzalez"))
    assert g.doc
    wh = {o.name: o for o in integrator("wisdom_holman").options()}
    assert wh["correctors"].choices == (0, 3, 5, 7, 11, 17)
    assert "10_6_4" in wh["table"].choices and "" in wh["table"].choices
    assert opts["tol"].choices == ()  # any positive float


def test_solve_checks_options_against_the_entry() -> None:
    """Unknown options and values outside the declared choices are typed errors, raised before
    anything runs; the messages list what is valid."""
    import numpy as np

    from poissonkit.errors import InputError, UnknownNameError
    from poissonkit.numerics import solve

    with pytest.raises(UnknownNameError, match="max_iterations") as err:
        solve(object(), np.zeros(3), 1.0, "midpoint", step=0.1, options={"maxiter": 3})
    assert "tol" in str(err.value)
    with pytest.raises(InputError, match="'avf', 'gonzalez'"):
        solve(object(), np.zeros(3), 1.0, "discrete_gradient", step=0.1,
              options={"gradient": "exact"})
    with pytest.raises(InputError, match="correctors"):
        solve(object(), np.zeros(3), 1.0, "wisdom_holman", step=0.1, options={"correctors": 9})


def test_choices_name_declared_options() -> None:
    """Negative control: allowed values for an option the entry does not have are refused."""
    from poissonkit.errors import InputError
    from poissonkit.plugin import IntegratorEntry, Param

    with pytest.raises(InputError, match="not one of its options"):
        IntegratorEntry("x", "doc", params=(Param("a", "int", "", 1),), choices={"b": (1,)})


def test_entry_and_object_agree() -> None:
    """Family, capabilities and a fixed order are declared once: the registry entry and the
    object its factory builds report the same."""
    from poissonkit.plugin import entries

    for name, entry in entries("integrator").items():
        if entry.family in ("", "explicit") or not entry.family:
            continue
        obj = entry.factory(**entry.resolve_params({}))
        assert obj.capabilities == entry.capabilities, name
        assert getattr(obj, "family", entry.family) == entry.family, name
        if entry.family in ("implicit", "splitting", "time_transformed"):
            assert obj.order == entry.order, name

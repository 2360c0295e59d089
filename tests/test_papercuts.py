"""Papercuts a SymPy or REBOUND user hits in the first hour (issue 32), each pinned."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import sympy as sp

import poissonkit as pk
from poissonkit.errors import InputError, ParseError, UnknownNameError


def test_bivector_with_swapped_arguments_names_the_order():
    x, y, z = sp.symbols("x y z", real=True)
    M = sp.Matrix([[0, z, -y], [-z, 0, x], [y, -x, 0]])
    with pytest.raises(InputError, match=r"\(coords, matrix\).*swap"):
        pk.Bivector(M, (x, y, z))
    with pytest.raises(InputError, match=r"\(coords, matrix\)"):
        pk.Bivector([[0, z, -y], [-z, 0, x], [y, -x, 0]], [x, y, z])
    P = pk.Bivector((x, y, z), M)  # the documented order still works
    assert P.bracket(x, y) == z  # so(3): {x, y} = z


FIELD = ["x2*x3", "-x1*x3", "0"]
COORDS = ["x1", "x2", "x3"]


def test_hamiltonize_takes_a_positional_field_and_a_text_prefactor():
    by_keyword = pk.hamiltonize(field=FIELD, coords=COORDS, hamiltonian="(x1**2 + x2**2)/2",
                                degree=1)
    positional = pk.hamiltonize(FIELD, coords=COORDS, hamiltonian="(x1**2 + x2**2)/2", degree=1)
    assert positional.found and positional.status == by_keyword.status
    assert [P.matrix for P in positional.solutions] == [P.matrix for P in by_keyword.solutions]
    x3 = sp.Symbol("x3", real=True)
    res = pk.hamiltonize(FIELD, coords=COORDS, hamiltonian="(x1**2 + x2**2)/2", degree=0,
                         prefactor="x3")
    assert res.ansatz.prefactor == x3
    # independent check: X = P dH for every bracket found, P = x3 * (constant Q)
    x1, x2 = sp.symbols("x1 x2", real=True)
    H = (x1 ** 2 + x2 ** 2) / 2
    for P in res.solutions:
        grad = sp.Matrix([sp.diff(H, c) for c in (x1, x2, x3)])
        assert sp.simplify(P.matrix * grad - sp.Matrix([x2 * x3, -x1 * x3, 0])) == sp.zeros(3, 1)
    with pytest.raises(ParseError, match="not allowed"):
        pk.hamiltonize(FIELD, coords=COORDS, hamiltonian="x1", prefactor="__import__")


def test_hamiltonize_result_repr_is_readable_and_explains_free_parameters():
    res = pk.hamiltonize(FIELD, coords=COORDS, integrals=["x1**2 + x2**2", "x3**2"], degree=1)
    text = repr(res)
    assert len(text.splitlines()) > 5
    assert "free parameters t1" in text and "arbitrary constants" in text
    assert "solution [0]: P = [[" in text
    assert str(res) == text


@pytest.fixture(scope="module")
def free_top():
    """A free rigid body on so(3)*, H = sum m_i^2 / (2 I_i), I = (1, 2, 3) (compiled)."""
    m = pk.so3().coords
    I1, I2, I3 = sp.symbols("I1 I2 I3", positive=True)
    H = m[0] ** 2 / (2 * I1) + m[1] ** 2 / (2 * I2) + m[2] ** 2 / (2 * I3)
    top = pk.HamiltonianSystem(pk.so3(), H, casimirs={"|m|^2": m[0] ** 2 + m[1] ** 2 + m[2] ** 2},
                               params={"I1": 1.0, "I2": 2.0, "I3": 3.0}, name="free_top")
    return pk.compile_system(top)


def test_solution_plots_the_state_and_keeps_the_drifts_default(free_top):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sol = pk.solve(free_top, [1.0, 0.1, 0.5], 1.0, "midpoint", step=0.02)
    ax = sol.plot(kind="state")
    lines = ax.get_lines()
    assert [ln.get_label() for ln in lines] == list(sol.layout())
    np.testing.assert_array_equal(lines[1].get_ydata(), sol.y[:, 1])
    assert [ln.get_label() for ln in sol.plot(kind="state", components=["m_z"]).get_lines()] \
        == ["m_z"]
    assert sol.plot().get_yscale() == "log"  # the default is still the drifts
    with pytest.raises(InputError, match="kind"):
        sol.plot(kind="phase")
    with pytest.raises(InputError, match="available"):
        sol.plot(kind="state", components=["q"])
    plt.close("all")


def test_energy_error_relative_and_absolute(free_top):
    sol = pk.solve(free_top, [1.0, 0.1, 0.5], 2.0, "rk45", tol=1e-4)
    H0 = 1.0 / 2 + 0.01 / 4 + 0.25 / 6  # by hand, m = (1, 0.1, 0.5), I = (1, 2, 3)
    absolute = sol.energy_error(relative=False)
    np.testing.assert_allclose(absolute, np.abs(sol.energy() - H0), rtol=0, atol=1e-15)
    np.testing.assert_allclose(sol.energy_error(), absolute / H0, rtol=1e-12)
    assert np.max(absolute) > 0  # rk45 at 1e-4 drifts: the test can tell the two apart


def test_to_xarray_names_the_time_dimension_time(free_top):
    pytest.importorskip("xarray")
    sol = pk.solve(free_top, [1.0, 0.1, 0.5], 0.1, "midpoint", step=0.02)
    ds = sol.to_xarray()
    assert ds["y"].dims == ("time", "component")
    np.testing.assert_array_equal(ds["time"].values, sol.t)
    np.testing.assert_array_equal(ds["t"].values, sol.t)  # the older name still reads
    assert "t" not in ds.dims


def test_dir_of_the_package_is_the_public_api():
    names = dir(pk)
    assert set(names) == set(pk.__all__) | {"__version__"}
    for helper in ("importlib", "annotations", "killpoints", "version", "errors", "structure"):
        assert helper not in names
    code = "import poissonkit as pk; print(sorted(set(dir(pk)) - set(pk.__all__)))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.stdout.strip() == "['__version__']", out.stderr


def test_an_unknown_algebra_name_is_an_input_error():
    for call in (pk.lie_algebra, pk.lie_poisson):
        with pytest.raises(InputError, match="unknown Lie algebra 'so5'.*so\\(n\\)") as err:
            call("so5")
        assert isinstance(err.value, UnknownNameError)  # as before

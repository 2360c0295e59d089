"""Notebook-friendly objects: text, HTML and LaTeX forms, ``Solution.to_xarray`` and ``plot``.

Truths used: brackets and Jacobiator components computed by hand for small structures (the
display must show the mathematics, not merely be non-empty); the free rigid body's energy and
``|m|^2`` are conserved by the implicit midpoint rule to round-off (a quadratic invariant,
Cooper's theorem), so the drifts the plot draws and the Dataset holds must be at round-off
level while the state moved by O(1).
"""

from __future__ import annotations

import html
import re
from xml.etree import ElementTree

import numpy as np
import pytest
import sympy as sp

import poissonkit as pk
from poissonkit.errors import InputError
from poissonkit.structure import Bivector


def _well_formed(fragment: str) -> None:
    ElementTree.fromstring(fragment)  # raises on unbalanced or unescaped markup


def _balanced_latex(s: str) -> None:
    assert s.startswith("$") and s.endswith("$")
    depth = 0
    for a, b in zip(" " + s, s):
        if b == "{" and a != "\\":
            depth += 1
        elif b == "}" and a != "\\":
            depth -= 1
        assert depth >= 0, s
    assert depth == 0, s
    assert s.count("\\begin{") == s.count("\\end{")


@pytest.fixture(scope="module")
def free_top_solution():
    P = pk.so3()
    m = P.coords
    I1, I2, I3 = sp.symbols("I1 I2 I3", positive=True)
    H = m[0] ** 2 / (2 * I1) + m[1] ** 2 / (2 * I2) + m[2] ** 2 / (2 * I3)
    top = pk.HamiltonianSystem(P, H, casimirs={"|m|^2": m[0] ** 2 + m[1] ** 2 + m[2] ** 2},
                               params={"I1": 1.0, "I2": 2.0, "I3": 3.0}, name="free_top")
    return top, pk.solve(pk.compile_system(top), [1.0, 0.1, 0.5], t_end=4.0,
                         method="midpoint", step=0.02)


def test_bivector_shows_its_brackets_as_text_html_and_latex():
    P = pk.so3()
    text = str(P)
    # so(3): {m_x, m_y} = m_z, {m_x, m_z} = -m_y, {m_y, m_z} = m_x, and nothing else
    assert "{m_x, m_y} = m_z" in text and "{m_x, m_z} = -m_y" in text
    assert "{m_y, m_z} = m_x" in text and text.count(" = ") == 3
    h = P._repr_html_()
    _well_formed(h)
    assert "{m_x, m_y}" in html.unescape(h) and "R^3" in h
    tex = P._repr_latex_()
    _balanced_latex(tex)
    assert "\\{m_{x}, m_{y}\\} &= m_{z}" in tex


def test_long_listings_are_cut_with_a_count():
    # seed 000's 18-dimensional structure has 3 + 2 * 9 = 21 non-zero brackets above the
    # diagonal; 4 copies of e(3) plus the orbit have 3 + 4 * 9 = 39; 6 copies: 57 > 40 shown
    parts = [("orbit", pk.canonical(3, "r", "p"))] + [(f"top{k}", pk.e3()) for k in range(6)]
    P = pk.direct_sum(*parts)
    assert "... (17 more)" in str(P)
    assert "17 more" in P._repr_html_() and "17 more" in P._repr_latex_()


def test_system_shows_hamiltonian_multiplier_and_invariants(free_top_solution):
    top, _ = free_top_solution
    text = str(top)
    assert "free_top" in text and "Casimir |m|^2: m_x**2 + m_y**2 + m_z**2" in text
    assert "N:" not in text  # multiplier 1 is not shown
    conformal = pk.HamiltonianSystem(pk.so3(), top.hamiltonian, multiplier=sp.Rational(1, 2))
    assert "N: 1/2" in str(conformal)
    _well_formed(top._repr_html_())
    tex = top._repr_latex_()
    _balanced_latex(tex)
    assert tex.startswith("$\\begin{aligned}H &= ") and "\\frac{m_{x}^{2}}{2 I_{1}}" in tex


def test_jacobi_result_shows_the_hand_computed_jacobiator():
    # {x1, x2} = x3, {x2, x3} = x2, {x1, x3} = 0 on R^3:
    # Jac(x1, x2, x3) = {x1, {x2, x3}} + {x2, {x3, x1}} + {x3, {x1, x2}}
    #                 = {x1, x2} + 0 + {x3, x3} = x3  (not Poisson)
    B = Bivector.from_components({(1, 2): "x3", (2, 3): "x2"}, ["x1", "x2", "x3"])
    bad = pk.check_jacobi(B, method="exact")
    assert not bad
    assert re.search(r"Jac\(x1, x2, x3\) = -?x3", str(bad)) and "FAILS" in str(bad)
    _well_formed(bad._repr_html_())
    assert "#cf222e" in bad._repr_html_()  # failure shown in red
    tex = bad._repr_latex_()
    _balanced_latex(tex)
    assert "\\operatorname{Jac}(x_{1}, x_{2}, x_{3})" in tex
    good = pk.check_jacobi(pk.e3())
    assert str(good).startswith("Jacobi identity: holds (exact")
    _balanced_latex(good._repr_latex_())


def test_check_result_and_verify_report_display():
    P = pk.so3()
    m = P.coords
    sys_ = pk.HamiltonianSystem(P, m[0] ** 2 / 2 + m[1] ** 2)
    # m_z is not conserved: dm_z/dt = {m_z, H} = m_x m_y (1 - 2) != 0
    res = pk.is_first_integral(sys_, m[2])
    assert not res and "FAILS" in str(res)
    _well_formed(res._repr_html_())
    _balanced_latex(res._repr_latex_())
    report = pk.verify(P, name="so3")
    assert isinstance(report, dict) and report["ok"]
    text = str(report)
    assert "Jacobi identity: OK" in text and "Rank (generic): 2" in text
    assert "m_x**2 + m_y**2 + m_z**2" in text
    _well_formed(report._repr_html_())
    _balanced_latex(report._repr_latex_())
    assert "so3: ok" in report._repr_html_()


def test_solution_text_and_html_summarise_the_run(free_top_solution):
    _, sol = free_top_solution
    assert repr(sol) == "Solution(method='midpoint', steps=200, t=[0, 4], saved=201, dim=3)"
    text = str(sol)
    assert "free_top" in text and "steps: 200" in text and "max |ΔH|/|H|" in text
    assert "|ΔP|" not in text  # the rigid body defines no linear momentum
    _well_formed(sol._repr_html_())
    _balanced_latex(sol._repr_latex_())


def test_to_xarray_holds_states_drifts_and_run_attributes(free_top_solution):
    _, sol = free_top_solution
    ds = sol.to_xarray()
    assert list(ds["component"].values) == ["m_x", "m_y", "m_z"]
    assert ds["y"].shape == (201, 3)
    np.testing.assert_array_equal(ds["t"].values, sol.t)
    np.testing.assert_array_equal(ds["y"].sel(component="m_y").values, sol.y[:, 1])
    # the state moved by O(1) while midpoint keeps both quadratic invariants to round-off
    assert np.ptp(sol.y[:, 1]) > 0.1
    assert float(ds["energy_error"].max()) < 1e-12
    assert float(ds["casimir_drift"].max()) < 1e-12
    assert ds.attrs["method"] == "midpoint" and ds.attrs["steps"] == 200
    assert "tol" not in ds.attrs  # None is left out so the dataset serialises


def test_plot_draws_the_nonzero_drifts_and_returns_the_axes(free_top_solution):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    _, sol = free_top_solution
    fig, ax0 = plt.subplots()
    ax = sol.plot(ax=ax0)
    assert ax is ax0
    labels = [line.get_label() for line in ax.get_lines()]
    # energy and |m|^2 drift at round-off; angular momentum is not defined (all zero): skipped
    assert labels == ["|ΔH|/|H|", "Casimir drift"]
    assert ax.get_yscale() == "log"
    np.testing.assert_allclose(ax.get_lines()[0].get_xdata(), sol.t)
    assert isinstance(sol.plot(), matplotlib.axes.Axes)
    assert [ln.get_label() for ln in sol.plot(invariants="energy").get_lines()] == ["|ΔH|/|H|"]
    with pytest.raises(InputError, match="available"):
        sol.plot(invariants=("entropy",))
    plt.close("all")

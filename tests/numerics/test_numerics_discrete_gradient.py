"""The discrete-gradient integrator: energy to round-off on non-quadratic Hamiltonians with
non-constant brackets (where implicit midpoint keeps it only to O(h^2)), order 2 against DOP853
at rtol 1e-13, the Casimir behaviour its docstring states, and the driver's services."""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest
import sympy as sp
from scipy.integrate import quad

from poissonkit.errors import CapabilityError, InputError, IntegrationError
from poissonkit.numerics import compile_system, solve
from poissonkit.numerics.checkpoint import Checkpoint, read_trajectory
from poissonkit.numerics.codegen import polynomial_degree
from poissonkit.numerics.events import Collision
from poissonkit.numerics.integrators.discrete_gradient import DiscreteGradient, avf_nodes
from poissonkit.plugin import integrator, system
from poissonkit.structure import Bivector, HamiltonianSystem, canonical
from poissonkit.structure.blocks import so3

DG = "discrete_gradient"


def _relative_energy_drift(cs, y: np.ndarray) -> float:
    e = cs.energy(y)
    return float(np.max(np.abs(e - e[0])) / abs(e[0]))


@pytest.fixture(scope="module")
def quartic_so3():
    """so(3) (linear bracket, Casimir |m|^2) with a quartic Hamiltonian."""
    P = so3()
    m1, m2, m3 = P.coords
    H = (m1**2 + m2**2 / 2 + m3**2 / 3) / 2 + (m1**4 + 2 * m3**4) / 4 + m1 * m2 * m3**2
    hs = HamiltonianSystem(P, H, casimirs={"|m|^2": m1**2 + m2**2 + m3**2},
                           name="so(3), quartic H")
    return compile_system(hs), np.array([0.6, -0.8, 0.5])


@pytest.fixture(scope="module")
def chaplygin_ball():
    """The Chaplygin ball in conformal form X = -g^{-1} P_g dH (rational H, bracket with a
    square root), from the nonholonomic plugin's registry entry."""
    ball = system("nh.chaplygin_ball").build(I1=1, I2=2, I3=3, d=1)
    return compile_system(ball), np.array([0.0, 0.6, 0.8, 1.0, -0.5, 0.2])


@pytest.fixture(scope="module")
def plank_lv():
    """Plank's quadratic bracket {x_i, x_j} = a_ij x_i x_j (J. Math. Phys. 36 (1995) 3520) with
    H = sum x_i - nu_i ln x_i: the Lotka-Volterra system x_i' = x_i sum_j a_ij (x_j - nu_j).
    a has kernel (1, 1, 1), so x1 x2 x3 is a (cubic) Casimir."""
    x = sp.symbols("x1 x2 x3", positive=True)
    a = sp.Matrix([[0, 1, -1], [-1, 0, 1], [1, -1, 0]])
    P = Bivector.from_matrix(sp.Matrix(3, 3, lambda i, j: a[i, j] * x[i] * x[j]), x)
    H = sum(x[i] - (i + 1) * sp.log(x[i]) for i in range(3))
    hs = HamiltonianSystem(P, H, casimirs={"x1 x2 x3": x[0] * x[1] * x[2]},
                           name="Plank Lotka-Volterra")
    return compile_system(hs), np.array([1.5, 1.0, 2.0])


SYSTEMS = ["quartic_so3", "chaplygin_ball", "plank_lv"]


@pytest.mark.parametrize("name", SYSTEMS)
def test_energy_is_kept_to_round_off_where_midpoint_keeps_it_to_its_order(request, name):
    cs, y0 = request.getfixturevalue(name)
    sol = solve(cs, y0, 100.0, DG, step=0.02, save_every=50)  # 5000 steps
    assert _relative_energy_drift(cs, sol.y) < 1e-14
    mid = solve(cs, y0, 100.0, "midpoint", step=0.02, save_every=50)
    assert _relative_energy_drift(cs, mid.y) > 1e-8  # O(h^2): these H are not quadratic
    # both follow the same trajectory to O(h^2)
    assert np.max(np.abs(sol.y[-1] - mid.y[-1])) < 0.05


@pytest.mark.parametrize("name", SYSTEMS)
def test_energy_is_kept_to_round_off_over_1e5_steps(request, name):
    cs, y0 = request.getfixturevalue(name)  # about a second per system once compiled
    sol = solve(cs, y0, 2000.0, DG, step=0.02, save_every=500)
    assert sol.steps == 100_000
    assert _relative_energy_drift(cs, sol.y) < 1e-13


def test_the_discrete_gradient_is_chosen_from_the_hamiltonian(quartic_so3, chaplygin_ball,
                                                               plank_lv):
    assert solve(*quartic_so3, 0.1, DG, step=0.01).extra["gradient"] == "avf"
    assert solve(*quartic_so3, 0.1, DG, step=0.01).extra["nodes"] == 2  # degree 4: 2 nodes
    for cs, y0 in (chaplygin_ball, plank_lv):
        assert solve(cs, y0, 0.1, DG, step=0.01).extra["gradient"] == "gonzalez"
    # Gonzalez's discrete gradient is exact for polynomial H too
    cs, y0 = quartic_so3
    sol = solve(cs, y0, 50.0, DG, step=0.02, options={"gradient": "gonzalez"})
    assert sol.extra["gradient"] == "gonzalez" and _relative_energy_drift(cs, sol.y) < 1e-14
    with pytest.raises(InputError, match="polynomial"):
        solve(*plank_lv, 0.1, DG, step=0.01, options={"gradient": "avf"})
    with pytest.raises(InputError, match="gradient"):
        DiscreteGradient(gradient="itoh")


def test_avf_quadrature_is_exact_for_the_degree_read_from_h():
    x, y = sp.symbols("x y")
    assert polynomial_degree(x**3 * y + y**2, (x, y)) == 4
    assert polynomial_degree(sp.Integer(3), (x, y)) == 0
    assert polynomial_degree(sp.log(x) + y, (x, y)) is None
    assert polynomial_degree(1 / (1 + x**2), (x, y)) is None
    for degree in range(1, 9):
        s, w = avf_nodes(degree)
        assert len(s) == max(1, math.ceil(degree / 2))
        # the integrand of a degree-p Hamiltonian is a polynomial of degree p - 1 in s
        poly = np.polynomial.Polynomial(np.arange(1.0, degree + 1.0))
        exact = poly.integ()(1.0) - poly.integ()(0.0)
        assert abs(np.dot(w, poly(s)) - exact) <= 1e-14 * abs(exact)


@pytest.mark.parametrize("name", SYSTEMS)
def test_discrete_gradient_is_second_order(request, name):
    cs, y0 = request.getfixturevalue(name)
    ref = solve(cs, y0, 2.0, "dop853", tol=1e-13, options={"atol": 1e-14}).y[-1]
    errs = [np.max(np.abs(solve(cs, y0, 2.0, DG, step=h).y[-1] - ref)) for h in (0.02, 0.01)]
    assert 1.8 <= np.log2(errs[0] / errs[1]) <= 2.3
    assert errs[1] < 1e-3


@pytest.mark.parametrize("name", ["quartic_so3", "chaplygin_ball"])
def test_quadratic_casimirs_are_kept_to_round_off(request, name):
    # C(x') - C(x) = grad C(midpoint) . (x' - x) = h grad C(mid)^T S(mid) gradbar H = 0 for
    # quadratic C: |m|^2 on so(3); (gamma, gamma) and (gamma, M) of the ball
    cs, y0 = request.getfixturevalue(name)
    sol = solve(cs, y0, 100.0, DG, step=0.05, save_every=20)
    c = cs.casimirs(sol.y)
    assert np.max(np.abs(c - c[0])) < 1e-13


def test_a_cubic_casimir_drifts_at_order_two(plank_lv):
    # x1 x2 x3 is a Casimir of Plank's bracket but not quadratic: not kept exactly, O(h^2)
    cs, y0 = plank_lv
    drift = []
    for h in (0.04, 0.02):
        sol = solve(cs, y0, 20.0, DG, step=h)
        c = cs.casimirs(sol.y)[:, 0]
        drift.append(np.max(np.abs(c - c[0])) / abs(c[0]))
    assert drift[1] > 1e-8  # really not conserved
    assert 3.0 <= drift[0] / drift[1] <= 5.0  # at the method's order


@pytest.mark.parametrize("newton", [True, False])
def test_conformal_heavy_top_with_a_quartic_term(newton):
    # e(3) with a multiplier N != 1 and a polynomial H (average vector field, S = N P at the
    # midpoint): H to round-off, the quadratic Casimirs (gamma, gamma), (gamma, L) too, with
    # Newton or fixed-point iteration
    from poissonkit.structure import e3

    P = e3("gamma_M")
    g1, g2, g3, L1, L2, L3 = P.coords
    H = (L1**2 / 2 + L2**2 / 3 + L3**2 / 4) / 2 + g3 + (L1 * g2) ** 2 / 2
    hs = HamiltonianSystem(P, H, multiplier=1 / (1 + g3**2 / 4),
                           casimirs={"gamma2": g1**2 + g2**2 + g3**2,
                                     "area": g1 * L1 + g2 * L2 + g3 * L3})
    cs = compile_system(hs)
    x0 = np.array([0.6, 0.0, 0.8, 1.0, -0.5, 0.3])
    sol = solve(cs, x0, 50.0, DG, step=0.05, options={"newton": newton})
    assert sol.extra["gradient"] == "avf" and sol.extra["newton"] is newton
    assert _relative_energy_drift(cs, sol.y) < 1e-14
    c = cs.casimirs(sol.y)
    assert np.max(np.abs(c - c[0])) < 1e-13


def test_non_convergence_is_a_typed_error(quartic_so3):
    cs, y0 = quartic_so3
    with pytest.raises(IntegrationError, match="did not converge"):
        solve(cs, y0, 1.0, DG, step=0.1, options={"max_iterations": 1})


def test_systems_without_a_symbolic_form_are_refused(dipole_pair):
    from numerics_helpers import orbit_state  # type: ignore[import-not-found]

    with pytest.raises(CapabilityError, match="symbolic form"):
        solve(dipole_pair, orbit_state(), 1.0, DG, step=0.01)


def test_registry_entry_declares_the_driver_services():
    entry = integrator(DG)
    assert entry.order == 2 and entry.family == "implicit"
    caps = entry.capabilities
    assert caps.checkpoint and caps.stream and caps.stop and caps.events and caps.located_events
    assert caps.needs_kernels and not caps.needs_splitting and not caps.adaptive
    assert "Cohen & Hairer" in entry.doc


def test_resume_is_bit_identical_and_streams_every_row(tmp_path, plank_lv):
    cs, y0 = plank_lv
    calls = {"n": 0}

    def stop() -> bool:
        calls["n"] += 1
        return calls["n"] == 3

    ck = Checkpoint(tmp_path / "ck", 200)
    part = solve(cs, y0, 20.0, DG, step=0.01, checkpoint=ck, stop=stop, save_every=3,
                 stream=tmp_path / "parts")
    assert part.extra["interrupted"]
    full = solve(cs, y0, 20.0, DG, step=0.01, checkpoint=ck, resume=True, save_every=3,
                 stream=tmp_path / "parts")
    ref = solve(cs, y0, 20.0, DG, step=0.01, save_every=3)
    assert "resumed_from" in full.extra
    assert full.y[-1].tobytes() == ref.y[-1].tobytes()  # compensation restored with the state
    t, y = read_trajectory(tmp_path / "parts")
    assert np.array_equal(t, ref.t) and np.array_equal(y, ref.y)


@numba.njit(cache=True)
def _radius(y, data, work):
    return math.sqrt(y[0] * y[0] + y[1] * y[1])


class _WithRadius:
    """A compiled symbolic system whose "smallest distance" is the radius |q| (so that the
    driver's collision search watches it)."""

    def __init__(self, cs) -> None:
        self._cs = cs
        self.kernels = cs.kernels._replace(min_distance=_radius)
        self.data = cs.data
        self.dim = cs.dim
        self.layout = cs.layout

    def work(self):
        return self._cs.work()

    def rhs(self, t, y):
        return self._cs.rhs(t, y)

    def energy(self, y):
        return self._cs.energy(y)

    def symbolic_form(self):
        return self._cs.symbolic_form()


def test_a_located_event_matches_the_quadrature_time():
    # radial fall in the quartic well H = |p|^2/2 + |q|^4/4 from rest at |q| = 1: |q| = 1/2 at
    # t* = int_{1/2}^1 dq / sqrt(2 (1/4 - q^4/4))
    P = canonical(2)
    q1, q2, p1, p2 = P.coords
    cs = compile_system(HamiltonianSystem(P, (p1**2 + p2**2) / 2 + (q1**2 + q2**2) ** 2 / 4))
    t_star = quad(lambda q: 1.0 / math.sqrt(0.5 * (1.0 - q**4)), 0.5, 1.0, epsabs=1e-14)[0]
    sol = solve(_WithRadius(cs), [1.0, 0.0, 0.0, 0.0], 5.0, DG, step=1e-3,
                events=(Collision(0.5),))
    assert sol.message == "event" and len(sol.events) == 1
    assert abs(sol.events[0].time - t_star) < 1e-6  # O(h^2) trajectory error dominates
    assert abs(math.hypot(*sol.y[-1, :2]) - 0.5) < 1e-6
    assert _relative_energy_drift(cs, sol.y) < 1e-14


@pytest.mark.slow  # two fresh processes, the first compiling everything (~1 min)
def test_a_second_process_compiles_nothing(tmp_path):
    # generated kernels (N P, grad H, H) and the time loop come from the disk cache
    import json
    import os
    import subprocess
    import sys
    from pathlib import Path

    from poissonkit.numerics import jit as jitmod

    def probe() -> dict:
        env = {**os.environ, jitmod.CACHE_ENV: str(tmp_path)}
        out = subprocess.run([sys.executable, str(Path(__file__).with_name(
            "warm_start_probe.py")), "discrete_gradient"], env=env, capture_output=True,
            text=True, timeout=600, check=False)
        assert out.returncode == 0, out.stderr[-3000:]
        return json.loads(out.stdout.strip().splitlines()[-1])

    first = probe()
    assert any("run" in name for name in first["compiled"])
    second = probe()
    assert second["compiles"] == 0, second["compiled"]
    assert second["values"] == first["values"]


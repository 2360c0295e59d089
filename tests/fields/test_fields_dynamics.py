"""External fields in the N-body dynamics: the right-hand side is P∇H with the field in H,
energy and Casimirs are kept by the splittings with a tabulated field, an exact field and
its table give the same motion, gravity gives the parabola."""

from __future__ import annotations

import magpylib as magpy
import numba
import numpy as np
import pytest

import poissonkit as pk
from poissonkit.errors import InputError
from poissonkit.numerics.fields import CompiledField
from poissonkit.numerics.fields.tabulated import TABULATED_MAGNET
from poissonkit.numerics.nbody import AllPairs, Body, NBodySystem

G = (0.0, 0.0, -9.81)
ALPHA = 1 / 2e-6


@numba.njit(cache=True)
def skewed(x, y, z, n0, n1, n2, c, P):
    """The tabulated magnet's energy with forces 0.1 % larger than its gradient (module level,
    so the kernels built on it are cached like any plugin's)."""
    u, gx, gy, gz, h0, h1, h2 = TABULATED_MAGNET(x, y, z, n0, n1, n2, c, P)
    return u, 1.001 * gx, 1.001 * gy, 1.001 * gz, h0, h1, h2


def top_system(fields, moment=0.1):
    return NBodySystem([Body("top", 0.02, alpha=ALPHA, attributes={"moment": moment})],
                       fields=fields)


def top_state(system, r=(0.001, 0.0005, 0.035), p=(0.0004, 0.0, 0.0)):
    return system.pack([r], [p], [[0.05, 0.0, -1.0]], [[0.0, 0.0, -2e-4]],
                       normalize=True)


def test_gravity_gives_the_parabola():
    s = NBodySystem([Body("a", 2.0)], fields=[pk.field("gravity", g=G)])
    y0 = s.pack([[0.0, 0.0, 0.0]], [[2.0, 0.0, 10.0]])
    sol = pk.solve(s, y0, 1.0, method="splitting2", step=0.1)
    r = sol.y[-1][:3]
    assert r == pytest.approx([1.0, 0.0, 5.0 - 0.5 * 9.81], abs=1e-12)
    assert s.energy(y0) == pytest.approx((4 + 100) / 4)  # p²/2M, U(0) = 0


def test_rhs_is_the_poisson_bracket_with_the_field_energy():
    """ṗ = −∂H/∂r and ṁ = ∂H/∂m × m + ∂H/∂ν × ν, ∂H from differences of the energy."""
    loop = pk.field("current_loop", current=800.0, radius=0.03, axis=(0.2, 0.1, 1.0))
    s = top_system([loop, pk.field("gravity", g=G)])
    y = top_state(s, r=(0.004, -0.003, 0.02))
    f = s.rhs(0.0, y)
    d = 1e-7

    def grad(slots):
        out = []
        for k in slots:
            e = np.zeros_like(y)
            e[k] = d
            out.append((s.energy(y + e) - s.energy(y - e)) / (2 * d))
        return np.array(out)

    dH_dr, dH_dnu = grad(range(0, 3)), grad(range(6, 9))
    nu, m = y[6:9], y[9:12]
    assert f[3:6] == pytest.approx(-dH_dr, rel=1e-6, abs=1e-9 * np.abs(dH_dr).max())
    torque = np.cross(ALPHA * m, m) + np.cross(dH_dnu, nu)
    assert f[9:12] == pytest.approx(torque, rel=1e-6, abs=1e-9 * np.abs(torque).max())
    assert np.dot(f[9:12], nu) == pytest.approx(0.0, abs=1e-12 * np.abs(torque).max())


def test_energy_and_casimirs_stay_at_round_off_with_the_tabulated_field(tabulated_cylinder):
    s = top_system([tabulated_cylinder, pk.field("gravity", g=G)])
    y0 = top_state(s, p=(0.0015, 0.0005, 0.0))
    sol = pk.solve(s, y0, 0.06, method="splitting6", step=2e-4)
    summary = sol.summary()
    assert summary["max_rel_energy_error"] < 1e-12
    assert summary["max_abs_casimir_drift"] < 1e-13
    # the top crossed cells of the table (where the interpolant is only C¹), so the energy
    # test means something
    lo = np.array(tabulated_cylinder.info["region_m"][0])
    h = np.array(tabulated_cylinder.info["spacing_m"])
    cells = {tuple(c) for c in np.floor((sol.y[:, :3] - lo) / h).astype(int)}
    assert len(cells) >= 3
    # a closed system's momenta are not claimed for a body in external fields
    from poissonkit.report.summary import conserved_quantities

    assert set(conserved_quantities(s)) == {"linear_momentum", "angular_momentum"}


def test_forces_that_are_not_the_gradient_of_the_energy_would_show(tabulated_cylinder):
    """Control: the same table with forces 0.1 % off its gradient drifts far above round-off."""
    wrong = CompiledField("skewed", skewed, tabulated_cylinder.data, reads="moment",
                          orientation=True)
    s = top_system([wrong, pk.field("gravity", g=G)])
    sol = pk.solve(s, top_state(s), 0.06, method="splitting6", step=2e-4)
    assert sol.summary()["max_rel_energy_error"] > 1e-7


@pytest.mark.parametrize("kind", ["exact", "tabulated"])
def test_exact_loop_and_its_magpylib_table_give_the_same_motion(kind):
    tol = 1e-5
    loop = dict(current=1500.0, radius=0.03)
    exact = top_system([pk.field("current_loop", **loop), pk.field("gravity", g=G)], 0.05)
    y0 = top_state(exact, r=(0.001, 0.0005, 0.015))
    ref = pk.solve(exact, y0, 0.04, method="splitting6", step=1e-4)
    if kind == "exact":  # the field itself against magpylib's Circle
        src = magpy.current.Circle(current=1500.0, diameter=0.06)
        pts = ref.y[::40, :3]
        nu = np.array([0.0, 0.0, 1.0])
        got = np.array([exact.fields[0].energy(p, nu, -1.0)[2] for p in pts])
        assert got == pytest.approx(src.getB(pts), rel=1e-9, abs=1e-12)
        return
    src = magpy.current.Circle(current=1500.0, diameter=0.06)
    table = pk.field(src, tol=tol, region=(-0.006, -0.006, 0.008, 0.006, 0.006, 0.022))
    tab = exact.with_fields([]).__class__(exact.bodies, fields=[table.compile(),
                                                                 pk.field("gravity", g=G)])
    sol = pk.solve(tab, y0, 0.04, method="splitting6", step=1e-4)
    # a relative force error tol moves the body by about tol times what the forces moved it
    moved = np.max(np.linalg.norm(ref.y[:, :3] - ref.y[0, :3]
                                  - np.outer(ref.t, y0[3:6] / 0.02), axis=1))
    assert np.max(np.linalg.norm(sol.y[:, :3] - ref.y[:, :3], axis=1)) <= 10 * tol * moved
    assert np.max(np.abs(sol.y[:, 6:9] - ref.y[:, 6:9])) <= 10 * tol
    assert moved > 1e-4  # the fields did move it


def test_a_field_on_the_axis_of_a_point_mass_is_refused():
    with pytest.raises(InputError, match="point mass"):
        NBodySystem([Body("p", 1.0, attributes={"moment": 0.1})],
                    fields=[pk.field("uniform", B=(0, 0, 1.0))])


def test_fixed_bodies_and_bodies_without_the_attribute_feel_nothing():
    s = NBodySystem([Body("a", 1.0, alpha=1.0), Body("b", 1.0, alpha=1.0,
                                                     attributes={"moment": 2.0})],
                    fields=[pk.field("uniform", B=(0.0, 0.0, 0.5))])
    y = s.pack([[0, 0, 0], [1, 0, 0]], np.zeros((2, 3)), [[1, 0, 0], [1, 0, 0]],
               np.zeros((2, 3)))
    f = s.rhs(0.0, y)
    # state: r, p of a and b (12), then ν, m of a (12:18) and of b (18:24)
    assert np.all(f[15:18] == 0.0)  # body a: no torque
    assert f[21:24] == pytest.approx(np.cross([2.0, 0, 0], [0, 0, 0.5]))  # μ ν × B
    assert s.energy(y) == pytest.approx(0.0)  # ν ⟂ B


@pytest.mark.parametrize("method", [
    "splitting2", pytest.param("splitting4", marks=pytest.mark.slow)])
def test_a_field_is_never_dropped_by_a_faster_path(method):
    """Point masses with gravity among themselves take the direct-sum loop of the splittings
    — unless a field is present: in a uniform field the centre of mass falls on the parabola
    whatever the pair forces do."""
    g = np.array([0.0, 0.0, -1.0])
    s = NBodySystem([Body("a", 1.0), Body("b", 1e-3)], [AllPairs("gravity", {"G": 1.0})],
                    fields=[pk.field("gravity", g=tuple(g))])
    y0 = s.pack([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], [[0.0, 0.0, 0.5], [0.0, 1e-3, 0.5e-3]])
    t = 2.0
    sol = pk.solve(s, y0, t, method=method, step=0.01)
    m = np.array([1.0, 1e-3])
    r = sol.y[-1].reshape(2, 2, 3)[:, 0]
    cm = (m[:, None] * r).sum(0) / m.sum()
    cm0 = np.array([1e-3 / m.sum(), 0.0, 0.0])
    v0 = np.array([0.0, 1e-3, 0.5 + 0.5e-3]) / m.sum()
    assert cm == pytest.approx(cm0 + v0 * t + 0.5 * g * t**2, abs=1e-11)
    assert abs(s.energy(sol.y[-1]) - s.energy(y0)) < 1e-6 * abs(s.energy(y0))


def test_wisdom_holman_refuses_an_external_field():
    s = NBodySystem([Body("a", 1.0), Body("b", 1e-3)], [AllPairs("gravity", {"G": 1.0})],
                    fields=[pk.field("gravity", g=(0.0, 0.0, -1.0))])
    y0 = s.pack([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], [[0.0, 0.0, 0.0], [0.0, 1e-3, 0.0]])
    with pytest.raises(InputError, match="external fields"):
        pk.solve(s, y0, 1.0, method="wisdom_holman", step=0.01)


def test_a_field_works_with_verlet_lists():
    """A Verlet skin adds the list to the scratch data the field kernels receive; the field's
    uniform pull still moves the centre of mass on the parabola."""
    g = np.array([0.0, 0.0, -1.0])
    bodies = [Body(f"b{k}", 1.0) for k in range(3)]
    s = NBodySystem(bodies, [AllPairs("gravity", {"G": 1.0})], cutoff=3.0, skin=0.5,
                    fields=[pk.field("gravity", g=tuple(g))])
    y0 = s.pack([[0.0, 0.0, 0.0], [1.5, 0.0, 0.0], [0.0, 1.5, 0.0]], np.zeros((3, 3)))
    sol = pk.solve(s, y0, 1.0, method="splitting2", step=0.01)
    r = sol.y[-1].reshape(3, 2, 3)[:, 0]
    assert r.mean(0) == pytest.approx(np.array([0.5, 0.5, 0.0]) + 0.5 * g, abs=1e-12)

"""Bad input to the numerics gives typed errors (subclasses of PoissonkitError), never a raw
numpy/Python exception or a silent NaN; coincident bodies raise OverlapError."""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest
import sympy as sp
from numerics_helpers import DIPOLE  # type: ignore[import-not-found]

from poissonkit.errors import (
    InputError,
    IntegrationError,
    NonFiniteStateError,
    PoissonkitError,
)
from poissonkit.numerics import (
    Body,
    Interaction,
    NBodySystem,
    NonUnitAxisError,
    TwoBodySystem,
    compile_system,
    solve,
)
from poissonkit.numerics.nbody import OverlapError
from poissonkit.structure import HamiltonianSystem, e3

E_Z = [0.0, 0.0, 1.0]
ZERO = [0.0, 0.0, 0.0]


def _heavy_top():
    P = e3("gamma_M")
    _, _, g3, L1, L2, L3 = P.coords
    a = sp.Symbol("a", positive=True)
    H = (L1**2 + L2**2 + L3**2) / 2 + a * g3
    return HamiltonianSystem(P, H, params={"a": 1.0}, name="heavy top")


def _tops():
    # same bodies and potential as test_numerics_nbody (shares the compiled kernels)
    return NBodySystem([Body("a", 1.5, 2.0), Body("b", 0.7, 3.0)], [Interaction("a", "b", DIPOLE)])


# ----------------------------------------------------------------------------- compile_system
@pytest.mark.parametrize("value", [math.nan, math.inf, "abc", None])
def test_non_numeric_parameter_is_rejected_by_name(value):
    # a NaN used to be substituted into H = ... + a g3, whose derivative sympy makes 0: the
    # field silently lost the gravity term
    with pytest.raises(InputError, match="parameter 'a'"):
        compile_system(_heavy_top(), params={"a": value})


def test_finite_parameter_gives_the_hand_derived_field():
    # e3 bracket, H = |L|^2/2 + a g3: gamma' = gamma x L, L' = L x L + gamma x (a e3)
    cs = compile_system(_heavy_top(), params={"a": 2.0})
    y = np.array([0.0, 0.6, 0.8, 1.0, 0.0, 0.0])
    g, L = y[:3], y[3:]
    want = np.concatenate([np.cross(g, L), np.cross(g, [0.0, 0.0, 2.0])])
    got = np.empty(6)
    cs.kernels.rhs(y, cs.data, (np.zeros(6),), got)
    assert np.allclose(np.abs(got), np.abs(want), atol=1e-14)
    assert np.abs(got[3]) == pytest.approx(1.2)  # the gravity torque is present


# ----------------------------------------------------------------------------- solve inputs
@pytest.mark.parametrize("kwargs, name", [
    ({"y0": "abc"}, "y0"),
    ({"y0": [[1.0], [1.0, 2.0]]}, "y0"),
    ({"t_end": "x"}, "t_end"),
    ({"t_end": None}, "t_end"),
    ({"t_end": math.nan}, "t_end"),
    ({"step": "a"}, "step"),
    ({"step": -0.1}, "step"),
    ({"tol": "a"}, "tol"),
    ({"t0": "a"}, "t0"),
])
def test_solve_rejects_malformed_arguments_with_input_error(oracle_pair, kwargs, name):
    args = {"y0": oracle_pair.pack([1.0, 0, 0], ZERO, E_Z, ZERO, E_Z, ZERO), "t_end": 1.0,
            "step": 0.1}
    args.update(kwargs)
    y0, t_end = args.pop("y0"), args.pop("t_end")
    with pytest.raises(InputError, match=name):
        solve(oracle_pair, y0, t_end, **args)


def test_fixed_step_method_rejects_non_numeric_step():
    from poissonkit.numerics.integrators.base import check_step

    with pytest.raises(InputError, match="step"):
        check_step("a", 1.0, "splitting6")


# ----------------------------------------------------------------------------- Body
@pytest.mark.parametrize("field, value", [
    ("position", (0.0, 0.0, math.nan)),
    ("position", (0.0, 0.0)),
    ("position", "abc"),
    ("axis", (0.0, math.inf, 1.0)),
    ("axis", (1.0, 0.0)),
    ("axis", (0.0, 0.0, 0.0)),
])
def test_body_rejects_malformed_position_and_axis(field, value):
    kwargs = {"position": (1.0, 2.0, 3.0), "axis": (0.0, 0.0, 1.0)}
    kwargs[field] = value
    with pytest.raises(InputError, match=field):
        Body("fixed", 1.0, 2.0, fixed=True, **kwargs)


def test_body_stores_position_and_axis_as_float_triples():
    b = Body("fixed", 1.0, 2.0, fixed=True, position=[1, 2, 3], axis=np.array([0, 0, 2]))
    assert b.position == (1.0, 2.0, 3.0) and b.axis == (0.0, 0.0, 2.0)


# ----------------------------------------------------------------------------- TwoBodySystem
@pytest.mark.parametrize("kwargs, name", [
    ({"mass1": None, "mass2": None, "reduced_mass": "abc"}, "reduced_mass"),
    ({"mass1": None, "mass2": None, "reduced_mass": -1.0}, "reduced_mass"),
    ({"mass1": "abc", "mass2": 1.0}, "mass1"),
    ({"mass1": 1.0, "mass2": 0.0}, "mass2"),
    ({"mass1": 1.0, "mass2": 1.0, "alpha1": "x"}, "alpha1"),
])
def test_two_body_constructor_names_the_bad_argument(kwargs, name):
    args = {"alpha1": 3.0, "alpha2": 5.0}
    args.update(kwargs)
    with pytest.raises(InputError, match=name) as info:
        TwoBodySystem(args.pop("mass1"), args.pop("mass2"), args.pop("alpha1"),
                      args.pop("alpha2"), DIPOLE, **args)
    other = {"reduced_mass": "mass1", "mass1": "reduced_mass"}.get(name)
    assert other is None or other not in str(info.value)


def test_two_body_pack_rejects_non_numeric_vector(oracle_pair):
    with pytest.raises(InputError, match="'r'|r must"):
        oracle_pair.pack("abc", ZERO, E_Z, ZERO, E_Z, ZERO)


def test_non_unit_axis_message_shows_plain_numbers(oracle_pair):
    with pytest.raises(NonUnitAxisError) as info:
        oracle_pair.pack([1.0, 0, 0], ZERO, [0, 0, 0.5], ZERO, E_Z, ZERO)
    assert "np.float64" not in str(info.value) and "0.5" in str(info.value)
    system = _tops()
    with pytest.raises(NonUnitAxisError) as info:
        system.pack([[0, 0, 0], [1, 0, 0]], np.zeros((2, 3)), [E_Z, [0, 0, 2.0]], np.zeros((2, 3)))
    assert "np.float64" not in str(info.value) and "2" in str(info.value)
    y = np.concatenate([[0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0], [0, 0, 0.5], ZERO, E_Z, ZERO])
    with pytest.raises(NonUnitAxisError) as info:
        system.check_state(y)
    assert "np.float64" not in str(info.value) and "0.25" in str(info.value)


# ----------------------------------------------------------------------------- overlap
def test_nbody_coincident_bodies_raise_overlap_everywhere():
    system = _tops()
    with pytest.raises(OverlapError, match="'a' and 'b'"):
        system.pack([[1.0, 2, 3], [1.0, 2, 3]], np.zeros((2, 3)), [E_Z, E_Z], np.zeros((2, 3)))
    good = system.pack([[0.0, 0, 0], [1.0, 0, 0]], np.zeros((2, 3)), [E_Z, E_Z], np.zeros((2, 3)))
    bad = good.copy()
    bad[6:9] = 0.0  # body b moved onto body a
    for call in (lambda: system.energy(bad), lambda: system.energy(np.stack([good, bad])),
                 lambda: system.rhs(0.0, bad), lambda: system.check_state(bad)):
        with pytest.raises(OverlapError):
            call()
    for method in ("splitting6", "midpoint", "rk45"):
        with pytest.raises(OverlapError):
            solve(system, bad, 1.0, method=method, step=0.1)
    # FORMULAS.md §1 dipole U = (c3 - 3 c1 c2)/r^3 at r = 1, e = e_x, both axes e_z: U = 1
    assert system.energy(good) == pytest.approx(1.0, rel=1e-14)


def test_moving_body_on_a_fixed_body_overlaps_but_two_fixed_bodies_may_coincide():
    bodies = [Body("wall", 1.0, fixed=True, position=(0.0, 0.0, 0.0)),
              Body("pin", 1.0, fixed=True, position=(0.0, 0.0, 0.0)),
              Body("ball", 1.0)]
    system = NBodySystem(bodies, [Interaction("wall", "ball", -1 / sp.Symbol("r", real=True))])
    y = system.pack([[0.0, 0.0, 2.0]], [ZERO])  # fixed-fixed coincidence is harmless
    assert system.energy(y) == pytest.approx(-0.5, rel=1e-14)
    with pytest.raises(OverlapError, match="'wall' and 'ball'|'pin' and 'ball'"):
        system.pack([ZERO], [ZERO])


def test_two_body_zero_separation_raises_overlap(dipole_pair):
    with pytest.raises(OverlapError):
        dipole_pair.pack(ZERO, ZERO, E_Z, ZERO, E_Z, ZERO)
    y = dipole_pair.pack([1.0, 0, 0], ZERO, E_Z, ZERO, E_Z, ZERO)
    y[:3] = 0.0
    for call in (lambda: dipole_pair.energy(y), lambda: dipole_pair.rhs(0.0, y),
                 lambda: dipole_pair.check_state(y),
                 lambda: solve(dipole_pair, y, 1.0, method="midpoint", step=0.1)):
        with pytest.raises(OverlapError):
            call()


def test_plugin_kernel_division_by_zero_becomes_overlap_error():
    # the magnets plugin's dipole kernel divides by r**3 with Python semantics
    system = TwoBodySystem(1.0, 1.0, 1.0, 1.0, "dipole", {"moment1": 1.0, "moment2": 1.0})
    y = np.zeros(18)
    y[8] = y[14] = 1.0
    for call in (lambda: system.energy(y), lambda: system.rhs(0.0, y)):
        with pytest.raises(OverlapError):
            call()


@numba.njit
def _wall(r, c1, c2, c3):
    # stands for a kernel with Python division semantics (like the magnets plugin's) that is
    # singular at r = 0.47; raising explicitly keeps it independent of numba's error model
    if r <= 0.47:
        raise ZeroDivisionError("division by zero")
    return 0.0, 0.0, 0.0, 0.0, 0.0


@pytest.mark.parametrize("method", ["splitting2", "midpoint"])
def test_division_by_zero_during_integration_names_the_step(method):
    # free motion r(t) = 1 - t (mu = 1, p = -1) reaches the singular r = 0.47 at t = 0.53, in
    # step 6 of h = 0.1; both methods first evaluate the force inside that step at the
    # half-step r(0.55) = 0.45 (Strang kick / midpoint), so step 6 must be named
    system = TwoBodySystem(None, None, 1.0, 1.0, _wall, reduced_mass=1.0)
    y = system.pack([1.0, 0, 0], [-1.0, 0, 0], E_Z, ZERO, E_Z, ZERO)
    with pytest.raises(NonFiniteStateError, match="division by zero") as info:
        solve(system, y, 1.0, method=method, step=0.1)
    assert info.value.step == 6
    assert info.value.time == pytest.approx(0.5)
    sol = solve(system, y, 0.5, method=method, step=0.1)  # the steps before are fine
    assert sol.y[-1, 0] == pytest.approx(0.5, abs=1e-12)


def test_division_by_zero_in_scipy_method_is_typed():
    system = TwoBodySystem(None, None, 1.0, 1.0, _wall, reduced_mass=1.0)
    y = system.pack([1.0, 0, 0], [-1.0, 0, 0], E_Z, ZERO, E_Z, ZERO)
    with pytest.raises(IntegrationError, match="division by zero"):
        solve(system, y, 1.0, method="rk45")


# ----------------------------------------------------------------------------- code hygiene
def test_save_buffer_public_methods_are_documented_and_dead_code_is_gone():
    from poissonkit.numerics import kernels
    from poissonkit.numerics.integrators.base import SaveBuffer

    for name in ("new", "commit", "add", "arrays"):
        assert getattr(SaveBuffer, name).__doc__
    assert not hasattr(SaveBuffer, "last_time")
    assert not hasattr(kernels, "rotate_about")


def test_energy_is_shared_by_both_systems():
    from poissonkit.numerics import nbody, twobody

    assert twobody.evaluate_energy is nbody.evaluate_energy
    assert issubclass(OverlapError, InputError) and issubclass(OverlapError, PoissonkitError)

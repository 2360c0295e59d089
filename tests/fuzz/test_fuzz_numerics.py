"""Fuzzing the numeric entry points: ``pair_interaction`` and ``solve`` arguments.

Property (see ``fuzzkit``): a finite result (energy, force, torques; a trajectory), or a typed
:class:`~poissonkit.errors.PoissonkitError`; never another exception, a hang or a NaN. ``solve``
runs on a free rigid body (so(3), compiled once) whose motion is bounded, so every finite
request that is accepted must come back finite; requests far beyond a run's reach (steps of
1e-300) must be refused, not attempted.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from fuzzkit import FAST, SLOW, assert_finite, outcome, slow, special_floats
from strategies import huge, values
from poissonkit import pair_interaction, solve
from poissonkit.plugin import names

# ------------------------------------------------------------------ pair_interaction
_floats = st.one_of(st.floats(-0.2, 0.2), st.sampled_from(special_floats()),
                    st.floats(allow_nan=True, allow_infinity=True))
_vectors = st.one_of(
    st.tuples(_floats, _floats, _floats).map(list),
    st.sampled_from([[0, 0, 1], [0, 0, 0.05], [0.03, 0, 0], [0, 0, 0], [1, 0], [1, 0, 0, 0],
                     "001", None, [[1, 0, 0]], ["1", 0, 0], [True, 0, 0]]),
    values,
)
_units = st.one_of(st.sampled_from([[0, 0, 1], [1, 0, 0], [0, 1, 0], [0.6, 0.8, 0]]), _vectors)
# parameters near the seed magnets (m ~ 0.16 A m^2, a ~ 1.25 mm, h ~ 20 mm), and hostile ones
_PARAMS = ["moment", "magnetization", "radius", "length", "half_length", "current", "flux",
           "wire_radius", "tol", "mass", "G", "alpha", "m1", "m2", "bogus"]
_param_values = st.one_of(st.sampled_from([0.155, 1.58e6, 1.25e-3, 0.02, 0.01, 1.0, 1e-2]),
                          st.sampled_from(special_floats()), huge, values)


@st.composite
def _pair_case(draw):
    """A valid call (seed-like magnets 5 cm apart), then 0-3 fields replaced by hostile ones."""
    case = {"model": draw(st.sampled_from(sorted(names("potential")) + ["auto"])),
            "r": draw(st.sampled_from([[0.05, 0, 0], [0, 0, 0.04], [0.03, 0.02, 0.01]])),
            "nu1": draw(st.sampled_from([[0, 0, 1], [1, 0, 0], [0.6, 0.8, 0]])),
            "nu2": draw(st.sampled_from([[0, 0, 1], [0, 1, 0], [0, 0, -1]])),
            "params": {"moment": 0.155, "radius": 1.25e-3, "length": 0.02}}
    if case["model"] == "auto":
        case["params"]["tol"] = 1e-2
    hostile = {"model": st.one_of(st.sampled_from(["", "no_such_model", "__import__", "dipole "]),
                                  values),
               "r": _vectors, "nu1": _vectors, "nu2": _vectors,
               "params": st.dictionaries(st.sampled_from(_PARAMS), _param_values, max_size=5)}
    for key in draw(st.lists(st.sampled_from(sorted(hostile)), max_size=3, unique=True)):
        new = draw(hostile[key])
        if key == "params" and draw(st.booleans()):
            new = {**case["params"], **new}  # change a few, keep the rest
        case[key] = new
    return case["model"], case["r"], case["nu1"], case["nu2"], case["params"]


def _pair(case):
    model, r, nu1, nu2, params = case
    res = outcome("pair_interaction",
                  lambda: pair_interaction(model, r, nu1, nu2, **params))
    if res is not None:
        assert_finite(res.energy, "energy")
        assert_finite(res.force, "force")
        assert_finite(res.torque1, "torque1")
        assert_finite(res.torque2, "torque2")


@pytest.mark.timeout(600)
@pytest.mark.filterwarnings("error::RuntimeWarning")  # no numpy warning leaks to the user
@FAST
@given(_pair_case())
def test_pair_interaction_arguments(case):
    _pair(case)


# ------------------------------------------------------------------ solve
@pytest.fixture(scope="module")
def rigid_body():
    from poissonkit.numerics.system import compile_system
    from poissonkit.structure import HamiltonianSystem, so3

    P = so3()
    m = P.coords
    return compile_system(HamiltonianSystem(P, (m[0] ** 2 + m[1] ** 2 / 2 + m[2] ** 2 / 3) / 2))


_METHODS = st.one_of(st.sampled_from(sorted(names("integrator"))),
                     st.sampled_from(["", "no_such_method", "RK45", None, 3]))


@st.composite
def _solve_case(draw):
    """A valid call, then 0-3 arguments replaced by hostile ones."""
    method = draw(st.sampled_from(sorted(names("integrator"))))
    case = {"y0": draw(st.tuples(st.floats(-2, 2), st.floats(-2, 2), st.floats(-2, 2)).map(list)),
            "t_end": draw(st.floats(0.01, 1.0)), "method": method,
            "step": draw(st.floats(1e-2, 0.1)), "tol": None, "save_every": 1, "options": None,
            "t0": 0.0}
    hostile = {
        "y0": _vectors,
        "t_end": st.one_of(st.sampled_from(special_floats()), huge, st.sampled_from(["1", None])),
        "method": st.sampled_from(["", "no_such_method", "RK45", None, 3]),
        "step": st.one_of(st.none(), st.sampled_from(special_floats()),
                          st.sampled_from([1e-12, 1e-300, "0.1", -0.1])),
        "tol": st.one_of(st.floats(1e-10, 1e-3), st.sampled_from(special_floats()), values),
        "save_every": st.one_of(st.integers(-2, 5), huge, st.sampled_from([1.5, "2", True])),
        "options": st.dictionaries(st.sampled_from(["newton", "atol", "adaptive", "bogus",
                                                    "max_step"]), values, max_size=2),
        "t0": st.one_of(st.floats(-1, 1), st.sampled_from(special_floats())),
    }
    for key in draw(st.lists(st.sampled_from(sorted(hostile)), max_size=3, unique=True)):
        case[key] = draw(hostile[key])
    return (case["y0"], case["t_end"], case["method"], case["step"], case["tol"],
            case["save_every"], case["options"], case["t0"])


def _work_is_bounded(case) -> bool:
    """Requests small enough to run within the deadline (larger valid ones are skipped; the
    absurd ones, 1e-300 steps or 1e300 s, must be refused)."""
    y0, t_end, method, step, tol, save_every, options, t0 = case
    try:
        span = float(t_end) - float(t0)
    except (TypeError, ValueError, OverflowError):
        return True
    if not math.isfinite(span) or span <= 0:
        return True
    if step is None:
        return span <= 10
    try:
        n = span / float(step)
    except (TypeError, ValueError, ZeroDivisionError, OverflowError):
        return True
    return not (2e4 < n <= 1e10)


def _solve(system, case):
    if not _work_is_bounded(case):
        return
    y0, t_end, method, step, tol, save_every, options, t0 = case
    sol = outcome("solve", lambda: solve(system, y0, t_end, method, step=step, tol=tol,
                                         save_every=save_every, options=options, t0=t0))
    if sol is not None:
        assert_finite(sol.y, "trajectory")
        assert_finite(sol.t, "times")


@pytest.mark.timeout(600)
@FAST
@given(case=_solve_case())
def test_solve_arguments(rigid_body, case):
    _solve(rigid_body, case)


@slow
@pytest.mark.timeout(7200)
@SLOW
@given(_pair_case())
def test_pair_interaction_slow(case):
    _pair(case)


@slow
@pytest.mark.timeout(7200)
@SLOW
@given(case=_solve_case())
def test_solve_slow(rigid_body, case):
    _solve(rigid_body, case)


@pytest.mark.parametrize("method", ["rk45", "dop853", "radau", "lsoda"])
@pytest.mark.parametrize("max_step", [5e-324, 1e-12])
def test_a_max_step_beyond_reach_is_refused_not_run(rigid_body, method, max_step):
    """Found by the slow fuzz run: a tiny scipy ``max_step`` hung (1e-12: 1e12 steps) or failed
    deep inside scipy (Radau, subnormal: a bare ValueError)."""
    from poissonkit.errors import InputError

    with pytest.raises(InputError, match="max_step"):
        solve(rigid_body, [1.0, 0.5, 0.2], 1.0, method, tol=1e-6,
              options={"max_step": max_step})


def test_a_save_every_beyond_int64_is_refused(rigid_body):
    """Found by the slow fuzz run: ``save_every = 2**63`` overflowed inside the compiled loop."""
    from poissonkit.errors import InputError

    with pytest.raises(InputError, match="save_every"):
        solve(rigid_body, [0.0, 0.0, 0.0], 1.0, "midpoint", step=0.0625, save_every=2 ** 63)

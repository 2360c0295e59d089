"""Capabilities declared on registry entries and integrator objects: ``solve`` refuses, before
any work, what an integrator cannot do, with a typed error naming the method and capability."""

from __future__ import annotations

import numpy as np
import pytest

from poissonkit.contracts import Integrator, NumericsSystem
from poissonkit.errors import CapabilityError, InputError
from poissonkit.numerics import AllPairs, Body, NBodySystem, solve
from poissonkit.numerics.checkpoint import Checkpoint
from poissonkit.numerics.events import ClosestApproach, Collision
from poissonkit.numerics.integrators.base import RawResult
from poissonkit.plugin import Capabilities, entries


class Oscillator:
    """ẋ = v, v̇ = −x in Python, counting right-hand-side calls (no compiled kernels)."""

    dim = 2
    layout = ("x", "v")

    def __init__(self) -> None:
        self.calls = 0

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        self.calls += 1
        return np.array([y[1], -y[0]])

    def energy(self, y: np.ndarray) -> np.ndarray:
        y = np.asarray(y)
        return 0.5 * (y[..., 0] ** 2 + y[..., 1] ** 2)


class Euler:
    """A third-party integrator: forward Euler, declaring what it can do."""

    name = "euler"
    order = 1

    def __init__(self, capabilities: Capabilities) -> None:
        self.capabilities = capabilities
        self.control_seen: list[object] = []

    def integrate(self, system, y0, t_end, *, step, tol, events=(), progress=False,
                  save_every=1, t0=0.0, control=None):
        self.control_seen.append(control)
        n = int(round((t_end - t0) / step))
        y = np.array(y0, dtype=float)
        for _ in range(n):
            y = y + step * system.rhs(0.0, y)
        return RawResult(np.array([t0, t_end]), np.array([y0, y]), n)


def test_the_contracts_describe_the_objects():
    assert isinstance(Oscillator(), NumericsSystem)
    assert isinstance(Euler(Capabilities()), Integrator)
    for name, entry in entries("integrator").items():
        obj = entry.factory(**entry.resolve_params({}))
        assert isinstance(obj, Integrator), name
        # one declaration: the entry solve reads and the object it runs agree
        assert obj.capabilities == entry.capabilities, name
        assert not hasattr(obj, "supports_control"), name


@pytest.mark.parametrize("method", ["dop853", "rk45", "radau", "lsoda"])
def test_scipy_cannot_checkpoint(tmp_path, method):
    osc = Oscillator()
    with pytest.raises(CapabilityError, match="checkpoint") as info:
        solve(osc, [1.0, 0.0], 1.0, method, tol=1e-8, checkpoint=Checkpoint(tmp_path, 10))
    assert info.value.method == method and info.value.capability == "checkpoint"
    assert method in str(info.value) and isinstance(info.value, InputError)
    assert osc.calls == 0  # refused before any work


def test_scipy_cannot_locate_closest_approaches():
    osc = Oscillator()
    with pytest.raises(CapabilityError, match="located_events"):
        solve(osc, [1.0, 0.0], 1.0, "dop853", tol=1e-8, events=(ClosestApproach(0.5),))
    assert osc.calls == 0


def test_a_stop_request_is_not_refused_but_scipy_runs_to_the_end():
    osc = Oscillator()
    sol = solve(osc, [1.0, 0.0], 1.0, "dop853", tol=1e-10, stop=lambda: True)
    assert sol.t[-1] == 1.0
    np.testing.assert_allclose(sol.y[-1], [np.cos(1.0), -np.sin(1.0)], atol=1e-8)


def test_systems_an_integrator_cannot_take_are_refused_before_compiling():
    osc = Oscillator()
    with pytest.raises(CapabilityError, match="needs_kernels"):
        solve(osc, [1.0, 0.0], 1.0, "midpoint", step=0.1)
    with pytest.raises(CapabilityError, match="needs_kernels"):
        solve(osc, [1.0, 0.0], 1.0, "splitting4", step=0.1)
    tops = NBodySystem([Body("a", 1.0), Body("b", 1.0, alpha=1.0)],
                       [AllPairs("gravity", {"G": 1.0})])
    y = tops.pack([[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [0, 1, 0]], axes=[[0, 0, 1]],
                  angular_momenta=[[0, 0, 0]])
    with pytest.raises(CapabilityError, match="point_masses_only"):
        solve(tops, y, 1.0, "wisdom_holman", step=0.1)
    assert tops._kernels is None  # refused from the declaration, nothing compiled


def test_third_party_integrators_declare_capabilities_the_same_way(tmp_path):
    none = Euler(Capabilities())
    with pytest.raises(CapabilityError, match="euler cannot do 'events'"):
        solve(Oscillator(), [1.0, 0.0], 1.0, none, step=0.01, events=(Collision(0.1),))
    with pytest.raises(CapabilityError, match="euler cannot do 'checkpoint'"):
        solve(Oscillator(), [1.0, 0.0], 1.0, none, step=0.01,
              checkpoint=Checkpoint(tmp_path, 10))
    assert none.control_seen == []
    sol = solve(Oscillator(), [1.0, 0.0], 1.0, none, step=1e-3)
    assert none.control_seen == [None] and sol.method == "euler"
    assert abs(sol.y[-1, 0] - np.cos(1.0)) < 1e-3  # forward Euler, first order
    # without the stream capability, solve writes the rows after the run
    from poissonkit.numerics.checkpoint import read_trajectory

    solve(Oscillator(), [1.0, 0.0], 1.0, none, step=1e-2, stream=tmp_path / "rows")
    assert none.control_seen[-1] is None and len(read_trajectory(tmp_path / "rows")[0]) == 2
    # with it, the run controls are handed over
    able = Euler(Capabilities(stream=True))
    solve(Oscillator(), [1.0, 0.0], 1.0, able, step=1e-2, stream=tmp_path / "s2",
          stop=lambda: False)
    (control,) = able.control_seen
    assert control.stream is not None and control.stop is None  # no stop capability


def test_an_object_without_the_contract_is_a_typed_error():
    class Bare:
        name, order = "bare", 1

        def integrate(self, *args, **kwargs):  # pragma: no cover - never reached
            raise AssertionError

    with pytest.raises(InputError, match="capabilities"):
        solve(Oscillator(), [1.0, 0.0], 1.0, Bare(), step=0.1)

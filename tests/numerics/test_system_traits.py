"""Declared system traits (:mod:`poissonkit.traits`): each built-in system class declares exactly
the contracts ``isinstance`` finds on an instance; asking never evaluates a property; a system
that declares nothing is still answered by ``isinstance``."""

from __future__ import annotations

import inspect

import numpy as np
import pytest
import sympy as sp

from poissonkit import contracts
from poissonkit.errors import InputError
from poissonkit.numerics.integrators.base import HasLoopKernels
from poissonkit.traits import SystemTraits, offers

#: every runtime-checkable contract a numerics system may fulfil (those code asks about)
SYSTEM_CONTRACTS = [p for name, p in vars(contracts).items()
                    if inspect.isclass(p) and getattr(p, "_is_runtime_protocol", False)
                    and (name.startswith(("Has", "Declares")) or name in (
                        "NumericsSystem", "CompiledFrom"))
                    and name != "HasRunCost"] + [HasLoopKernels]


def _systems():
    from poissonkit import field
    from poissonkit.numerics import AllPairs, Body, NBodySystem, compile_system
    from poissonkit.numerics.conformal import LambdifiedSystem
    from poissonkit.numerics.twobody import TwoBodySystem
    from poissonkit.structure import HamiltonianSystem, so3

    r, c1, c2, c3 = sp.symbols("r c1 c2 c3", real=True)
    m = so3().coords
    hsys = HamiltonianSystem(so3(), (m[0] ** 2 + m[1] ** 2 / 2 + m[2] ** 2 / 3) / 2)
    gravity = NBodySystem([Body("a", 1.0), Body("b", 2.0)], [AllPairs("gravity", {"G": 1.0})])
    tops = NBodySystem([Body("a", 1.0, 1.0), Body("b", 1.0, 1.0)],
                       [AllPairs((c3 - 3 * c1 * c2) / r**3)], cutoff=3.0)
    return {
        "nbody gravity": gravity,
        "nbody tops with a cutoff": tops,
        "nbody in a field": gravity.with_fields([field("gravity", g=[0.0, 0.0, -9.81])]),
        "two-body": TwoBodySystem(None, None, 3.0, 5.0, (c3 - 3 * c1 * c2) / r**3,
                                  reduced_mass=2.0),
        "compiled symbolic": compile_system(hsys),
        "lambdified symbolic": LambdifiedSystem(hsys),
    }


LABELS = ["nbody gravity", "nbody tops with a cutoff", "nbody in a field", "two-body",
          "compiled symbolic", "lambdified symbolic"]


def test_the_contract_list_is_the_one_code_asks_about():
    names = {p.__name__ for p in SYSTEM_CONTRACTS}
    assert {"NumericsSystem", "HasCompiledKernels", "HasCasimirs", "HasBodies",
            "HasGravity", "DeclaresNotConserved", "CompiledFrom"} <= names


@pytest.mark.parametrize("label", LABELS)
def test_declared_traits_say_what_isinstance_says(label):
    systems = _systems()
    assert set(systems) == set(LABELS)
    system = systems[label]
    declared = type(system).traits
    assert isinstance(declared, SystemTraits)
    found = {p for p in SYSTEM_CONTRACTS if isinstance(system, p)}
    missing = sorted(p.__name__ for p in found - declared.contracts)
    extra = sorted(p.__name__ for p in declared.contracts - found)
    assert not missing and not extra, f"{label}: undeclared {missing}, declared but absent {extra}"
    for p in SYSTEM_CONTRACTS:
        assert offers(system, p) == (p in found), p.__name__


class _Probe:
    """A declared system whose kernels property would compile (here: raise) if evaluated."""

    traits = SystemTraits(contracts.HasCompiledKernels)

    @property
    def kernels(self):
        raise AssertionError("offers() evaluated a property")

    data = ()

    def work(self):
        return ()


def test_asking_never_evaluates_a_property():
    assert offers(_Probe(), contracts.HasCompiledKernels)
    assert not offers(_Probe(), contracts.HasCasimirs)
    # the negative control: isinstance does evaluate it on this Python when it probes
    # properties, which is why declarations exist (3.12+ tests members without evaluating)


class _DuckSystem:
    """A third party's system written against the protocols alone, declaring nothing."""

    dim = 1

    def rhs(self, t, y):
        return -np.asarray(y)

    def energy(self, y):
        return 0.5 * float(np.dot(y, y))

    def casimirs(self, y):
        return np.zeros((np.atleast_2d(y).shape[0], 0))


def test_an_undeclared_system_is_answered_by_isinstance():
    s = _DuckSystem()
    assert offers(s, contracts.NumericsSystem) and offers(s, contracts.HasCasimirs)
    assert not offers(s, contracts.HasBodies)


def test_traits_take_protocols_only():
    with pytest.raises(InputError, match="Protocol"):
        SystemTraits(int)
    with pytest.raises(InputError, match="Protocol"):
        SystemTraits(contracts.Body)  # a Protocol, but not runtime-checkable

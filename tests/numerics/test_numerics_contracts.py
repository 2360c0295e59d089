"""Dispatch on the contracts of :mod:`poissonkit.contracts` instead of attribute probes.

Truth: small hand-made systems that offer exactly one capability each (or none), so the
expected branch of each consumer is known by construction; and the built-in systems, which
must satisfy the contracts they are documented to.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from poissonkit import contracts as c
from poissonkit.errors import InputError
from poissonkit.numerics import diagnostics
from poissonkit.numerics.events import TWO_BODY_NAMES, body_frames, body_names
from poissonkit.numerics.nbody import AllPairs, Body, NBodySystem
from poissonkit.numerics.solution import Solution
from poissonkit.report.summary import conserved_quantities


def test_diagnostics_protocols_are_the_contracts():
    # one definition each: the diagnostics module re-exports the contracts' classes
    assert diagnostics.HasEnergy is c.HasEnergy
    assert diagnostics.HasCasimirs is c.HasCasimirs
    assert diagnostics.HasCasimirScales is c.HasCasimirScales
    assert diagnostics.HasBodyMomenta is c.HasBodyMomenta


def test_builtin_systems_satisfy_their_contracts(oracle_pair):
    r = sp.Symbol("r", real=True)
    nbody = NBodySystem([Body("a", 1.0), Body("b", 2.0)], [AllPairs(-1 / r)])
    for system in (oracle_pair, nbody):
        assert isinstance(system, c.NumericsSystem)
        assert isinstance(system, c.HasBodyMomenta)
        assert isinstance(system, c.HasCasimirs) and isinstance(system, c.HasLayout)
    assert isinstance(nbody, c.HasBodies) and not isinstance(oracle_pair, c.HasBodies)
    assert body_names(nbody) == ("a", "b")
    assert body_names(oracle_pair) == TWO_BODY_NAMES


def test_body_frames_of_a_system_without_bodies_or_unpack_is_a_typed_error():
    class KernelsOnly:
        kernels = None
        data = ()

        def work(self):
            return ()

    with pytest.raises(InputError, match="neither bodies nor"):
        body_frames(KernelsOnly(), np.zeros(6))


class Energy:
    def energy(self, y):
        return np.asarray(y, dtype=float)[..., 0]


class Declared(Energy):
    not_conserved = {"angular_momentum": "a rotor drives it"}


class Undeclared(Energy):
    not_conserved = None  # None leaves it to the summary's own rule


class Fielded(Energy):
    external_fields = ("uniform B",)


def test_conserved_quantities_reads_the_declarations():
    assert conserved_quantities(Declared()) == {"angular_momentum": "a rotor drives it"}
    undefined = "the system does not define it"
    assert conserved_quantities(Undeclared()) == {"linear_momentum": undefined,
                                                  "angular_momentum": undefined}
    fields = conserved_quantities(Fielded())
    assert fields["linear_momentum"] == "external fields act on the bodies"


def test_conserved_quantities_names_the_fixed_bodies():
    r = sp.Symbol("r", real=True)
    system = NBodySystem([Body("sun", 1.0, fixed=True, position=(0, 0, 0)), Body("b", 1.0)],
                         [AllPairs(-1 / r)])
    out = conserved_quantities(system)
    assert out["angular_momentum"] == out["linear_momentum"]
    assert "fixed bodies (sun)" in out["linear_momentum"]


def test_solution_names_a_compiled_system_by_its_source_and_uses_its_layout():
    class Source:
        name = "toy source"

    class Compiled(Energy):
        hamiltonian_system = Source()
        layout = ("h", "x")

    class Anonymous(Energy):
        pass

    y = np.array([[1.0, 0.0], [1.0, 0.5]])
    sol = Solution(t=np.arange(2.0), y=y, method="toy", steps=1, wall_time=0.0,
                   system=Compiled())
    assert sol._system_name() == "toy source" and sol.layout() == ("h", "x")
    sol = Solution(t=np.arange(2.0), y=y, method="toy", steps=1, wall_time=0.0,
                   system=Anonymous())
    assert sol._system_name() == "Anonymous" and sol.layout() == ("y0", "y1")


def test_compile_system_refuses_what_is_not_a_hamiltonian_system():
    from poissonkit.numerics.system import compile_system

    class LooksLikeOne:  # has the attributes, is not the type
        structure = hsys = hamiltonian = multiplier = None
        coords = casimirs = integrals = params = original = {}

    for bad in (object(), LooksLikeOne()):
        with pytest.raises(InputError, match="needs a HamiltonianSystem, got"):
            compile_system(bad)

"""What each built-in integrator family is and can do, declared once.

A :class:`Traits` names the family, its :class:`~poissonkit.plugin.contributions.Capabilities`
and, when the family has one, its classical order. The registry entries
(:mod:`poissonkit.numerics.hooks`) and the integrator classes both read them from here, so the
entry :func:`~poissonkit.numerics.solve` checks and the object it runs agree. Pure data: the
registry reads it without loading a compiled loop.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from poissonkit.plugin.contributions import Capabilities


@dataclass(frozen=True)
class Traits:
    """One integrator family's declaration.

    Attributes
    ----------
    family
        Family name listed by ``poissonkit plugins`` (``"splitting"``, ``"implicit"``, …).
    capabilities
        What its integrators can do.
    order
        Classical order shared by every member, or ``0`` when each member (a table, a
        composition) states its own.
    """

    family: str
    capabilities: Capabilities
    order: int = 0


#: Every compiled loop on the shared driver: checkpoint/resume, streaming, stop, located events.
COMPILED = Capabilities(checkpoint=True, stream=True, stop=True, events=True,
                        located_events=True, needs_kernels=True)

#: Splittings of the exact kinetic and potential flows (``adaptive`` is an option).
SPLITTING = Traits("splitting", replace(COMPILED, adaptive=True, needs_splitting=True))

#: Time-transformed (logarithmic-Hamiltonian) splittings: the physical step adapts.
TIME_TRANSFORMED = Traits("time_transformed",
                          replace(COMPILED, adaptive=True, needs_splitting=True))

#: Implicit midpoint: any compiled system.
MIDPOINT = Traits("implicit", COMPILED, order=2)

#: Discrete gradient: a compiled symbolic system (``compile_system``), on the shared driver.
DISCRETE_GRADIENT = Traits("implicit", COMPILED, order=2)

#: Wisdom–Holman: point masses around a dominant body (the order depends on the options).
WISDOM_HOLMAN = Traits("hierarchical", replace(COMPILED, point_masses_only=True))

#: scipy's ``solve_ivp``: adaptive, terminal events located on its dense output (sign changes
#: only); its step-size controller cannot be checkpointed, it streams once finished and does not
#: look at stop requests.
SCIPY = Traits("scipy", Capabilities(events=True, adaptive=True))

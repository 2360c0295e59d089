"""What each built-in integrator family can do, declared once.

The registry entries (:mod:`poissonkit.numerics.builtin`) and the integrator classes both point
here, so the entry :func:`~poissonkit.numerics.solve` reads and the object it runs agree.
"""

from __future__ import annotations

from dataclasses import replace

from poissonkit.plugin.contributions import Capabilities

#: Every compiled loop on the shared driver: checkpoint/resume, streaming, stop, located events.
COMPILED = Capabilities(checkpoint=True, stream=True, stop=True, events=True,
                        located_events=True, needs_kernels=True)

#: Splittings of the exact kinetic and potential flows (``adaptive`` is an option).
SPLITTING = replace(COMPILED, adaptive=True, needs_splitting=True)

#: Time-transformed (logarithmic-Hamiltonian) splittings: the physical step adapts.
TIME_TRANSFORMED = replace(COMPILED, adaptive=True, needs_splitting=True)

#: Implicit midpoint: any compiled system.
MIDPOINT = COMPILED

#: Discrete gradient: a compiled symbolic system (``compile_system``), on the shared driver.
DISCRETE_GRADIENT = COMPILED

#: Wisdom–Holman: point masses around a dominant body.
WISDOM_HOLMAN = replace(COMPILED, point_masses_only=True)

#: scipy's ``solve_ivp``: adaptive, terminal events located on its dense output (sign changes
#: only); its step-size controller cannot be checkpointed, it streams once finished and does not
#: look at stop requests.
SCIPY = Capabilities(events=True, adaptive=True)

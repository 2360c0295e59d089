"""The seed 000 scene: two cylinder magnets ("dumbbells") on a circular orbit.

Parts: :mod:`.table` (parameters), :mod:`.orbit` (circular orbit, units, initial states),
:mod:`.two_body` (the two-body form and its N-body twin), :mod:`.fate` (how perturbed orbits
end), :mod:`.runs` (the built-in scene of ``poissonkit run``).

Zub, *Mathematical model of magnetically interacting rigid bodies*, Maple table "Parameters of
cylindrical magnets (dumb-bells)" and the circular-orbit momentum ``P_orb``. Everything here is
derived from the geometry at full precision with :mod:`mpmath` (``dps`` digits), then rounded to
floats only where the numerics need them.

Derivation (see ``docs/seed000.md``)
------------------------------------
* ``V = pi (d/2)^2 h``, ``m_cyl = rho V``, reduced mass ``m = m_cyl/2`` (two equal magnets).
* Inertia of a solid cylinder about its centre: transverse ``I_perp = m_cyl (3 a^2 + h^2)/12``,
  axial ``I_axial = m_cyl a^2/2`` (``a = d/2``); ``alpha = 1/I_perp``. This convention
  reproduces the seed's printed ``mI`` to all 20 printed digits.
* ``J_Fe = mu/V`` (the seed derives the magnetisation from the moment, not the other way round).
* Dumbbell model: charges ``±kappa = ±mu/(2l)`` at ``±l nu`` with ``l = h/2``
  (Zub's seed eq. (16)).
* Circular orbit: the seed's ``GetP_orb(mu1, mu2, l1, l2, R_orb, m)`` balances centrifugal and
  magnetic force, ``P^2/(m R) = |F(R)|``. The seed does not print ``R_orb``; the radius
  ``R_orb = 10 mm`` (= ``l``) with both axes perpendicular to the orbital plane and *antiparallel*
  (side by side, attracting) reproduces the printed ``P_orb = 6.4910356642626862477e-4 N s`` to all
  20 printed digits. The parallel side-by-side pair has the same ``|F|`` but repels, so it has
  no circular orbit.
"""

from poissonkit_magnets.seed000.table import (CONFIGURATIONS, DENSITY, DIAMETER, HEIGHT, MOMENT,
                                              ORBIT_RADIUS, SEED_PRINTED, SeedTable,
                                              dumbbell_energy, parameter_table, radial_force)
from poissonkit_magnets.seed000.orbit import (CircularOrbit, circular_orbit, find_orbit_radius,
                                              initial_state, metadata, nondimensional_parameters,
                                              scales)
from poissonkit_magnets.seed000.two_body import (dumbbell_potential, nbody_state, nbody_system,
                                                 relative_orbit, two_body_system)
from poissonkit_magnets.seed000.fate import OrbitFate, axis_distance, orbit_fate
from poissonkit_magnets.seed000.runs import default_run, main, scene_run

#: The two-body form was called ``seed_system``; the name stays for existing code.
seed_system = two_body_system

__all__ = [
    "CONFIGURATIONS",
    "CircularOrbit",
    "DENSITY",
    "DIAMETER",
    "HEIGHT",
    "MOMENT",
    "ORBIT_RADIUS",
    "OrbitFate",
    "SEED_PRINTED",
    "SeedTable",
    "axis_distance",
    "circular_orbit",
    "default_run",
    "dumbbell_energy",
    "dumbbell_potential",
    "find_orbit_radius",
    "initial_state",
    "main",
    "metadata",
    "nbody_state",
    "nbody_system",
    "nondimensional_parameters",
    "orbit_fate",
    "parameter_table",
    "radial_force",
    "relative_orbit",
    "scales",
    "scene_run",
    "seed_system",
]

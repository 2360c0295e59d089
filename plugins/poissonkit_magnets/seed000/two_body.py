"""The two-body form of seed 000: the 18-variable relative system and its N-body twin.

The seed integrates the relative motion ``(r, p, nu', m', nu'', m'')`` of two equal magnets
(:func:`two_body_system`, a :class:`~poissonkit.numerics.twobody.TwoBodySystem`);
:func:`nbody_system` is the same scene with two bodies, and :func:`nbody_state` /
:func:`relative_orbit` convert between the two state forms.
"""

from __future__ import annotations

import mpmath
import numpy as np

from poissonkit_magnets.seed000.orbit import CircularOrbit, circular_orbit, scales
from poissonkit_magnets.seed000.table import SeedTable, parameter_table


def nbody_state(y18: np.ndarray) -> np.ndarray:
    """Two-body state ``(r, p, nu', m', nu'', m'')`` -> N-body state of :func:`nbody_system`.

    Equal masses, centre of mass at the origin and at rest: ``r_1 = -r/2``, ``r_2 = r/2``,
    ``p_1 = -p``, ``p_2 = p`` (``p = mu rdot = M rdot_2`` with ``mu = M/2``).
    """
    y = np.asarray(y18, dtype=float)
    if y.shape[-1] != 18:
        from poissonkit.errors import DimensionError

        raise DimensionError(f"two-body state must have 18 entries, got {y.shape}")
    r, p = y[..., 0:3], y[..., 3:6]
    return np.concatenate([-r / 2, -p, r / 2, p, y[..., 6:18]], axis=-1)


def relative_orbit(y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(r, p)`` of the seed's 18-variable form from N-body states (rows) of
    :func:`nbody_system`."""
    y = np.asarray(y, dtype=float)
    return y[..., 6:9] - y[..., 0:3], (y[..., 9:12] - y[..., 3:6]) / 2


def dumbbell_potential():
    """The pair potential used: the magnets plugin's ``"dumbbell"`` when registered, else the
    same energy (Zub's seed eq. (16)) as a sympy expression in ``r, c1, c2, c3``."""
    from poissonkit.errors import UnknownNameError
    from poissonkit.plugin import potential

    t = parameter_table()
    params = {"moment1": float(t.mu), "moment2": float(t.mu), "half_length1": float(t.l),
              "half_length2": float(t.l), "mu0": float(t.mu0)}
    try:
        return potential("dumbbell"), params
    except UnknownNameError:
        return dumbbell_expression(t), {}


def dumbbell_expression(table: SeedTable | None = None):
    """The seed's dumbbell energy (Zub's seed eq. (16)) as a sympy expression in
    ``r, c1, c2, c3``: charges ``±μ/(2l)`` at ``±l ν`` of each magnet, summed over the four
    pole pairs (SI). Written from the paper, independent of the compiled kernels."""
    import sympy as sp

    t = table or parameter_table()
    r, c1, c2, c3 = sp.symbols("r c1 c2 c3", real=True)
    l = sp.Float(float(t.l))
    K = sp.Float(float(t.mu0 * (t.mu / (2 * t.l)) ** 2 / (4 * mpmath.pi)))
    return K * sum(e1 * e2 / sp.sqrt(r**2 + 2 * l**2 + 2 * r * l * (e2 * c2 - e1 * c1)
                                     - 2 * e1 * e2 * l**2 * c3)
                   for e1 in (1, -1) for e2 in (1, -1))


def two_body_system(table: SeedTable | None = None, orbit: CircularOrbit | None = None):
    """The seed scene as a :class:`~poissonkit.numerics.twobody.TwoBodySystem` (SI reduced mass
    at full precision, ``alpha`` of both magnets, dumbbell potential), integrated in the internal
    units of :func:`scales`."""
    from poissonkit.numerics.twobody import TwoBodySystem

    t = table or parameter_table()
    o = orbit or circular_orbit(table=t)
    pot, params = dumbbell_potential()
    return TwoBodySystem(None, None, float(t.alpha), float(t.alpha), pot, params,
                         scales=scales(o, t), reduced_mass=float(t.m))


def nbody_system(table: SeedTable | None = None, orbit: CircularOrbit | None = None):
    """The same scene as an :class:`~poissonkit.numerics.nbody.NBodySystem`: two tops
    ``"magnet1"``, ``"magnet2"`` (state order ``r_1, p_1, r_2, p_2, ν_1, m_1, ν_2, m_2``)."""
    from poissonkit.numerics.nbody import Body, Interaction, NBodySystem

    t = table or parameter_table()
    o = orbit or circular_orbit(table=t)
    pot, params = dumbbell_potential()
    bodies = [Body("magnet1", mass=float(t.m_cyl), alpha=float(t.alpha)),
              Body("magnet2", mass=float(t.m_cyl), alpha=float(t.alpha))]
    return NBodySystem(bodies, [Interaction(0, 1, pot, params)], scales=scales(o, t))

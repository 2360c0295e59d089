"""Wisdom–Holman splitting in Jacobi coordinates for systems with one dominant mass.

For ``N`` point masses with Newtonian gravity (plus any other orientation-free pair potential)
the Hamiltonian is split as ``H = H_K + H_I``:

* ``H_K = Σ_{i≥1} [p'_i²/(2 m'_i) − G m'_i η_i / |x'_i|] + P²/(2 M)`` — independent Kepler
  problems of the Jacobi coordinates ``x'_i = r_i − R_{i−1}`` (``R_{i−1}`` the centre of mass of
  bodies ``0 … i−1``, ``η_i = m_0 + … + m_i``, ``m'_i = m_i η_{i−1}/η_i``) and the free motion of
  the centre of mass. Its flow is exact: a universal-variable Kepler solver (Stumpff functions
  with argument halving, Halley's iteration safeguarded by bisection) per body.
* ``H_I = V(r) + Σ_{i≥1} G m'_i η_i / |x'_i|`` — the full pair potential minus the Keplerian
  parts. It depends on positions only, so its flow is an exact kick; for a hierarchical system
  it is of the size ``ε`` of the planet-to-star mass ratio.

(J. Wisdom & M. Holman, AJ 102 (1991) 1528; the Jacobi form as in H. Rein & D. Tamayo,
MNRAS 452 (2015) 376, WHFast.) The steps are the ``SABA_n`` compositions of J. Laskar &
P. Robutel, Celest. Mech. Dyn. Astron. 80 (2001) 39: Kepler drifts between the Gauss–Legendre
nodes of ``[0, h]`` and kicks with the Gauss weights, error ``O(ε h^{2n} + ε² h²)``; ``n = 1`` is
the classical Wisdom–Holman map. With ``corrector=True`` the ``ε² h²`` term is removed by the
kick of ``−g_n h³ ε² {{A,B},B}/2`` on both sides of each step (``SABAC_n``, same paper;
consecutive steps share one), whose force is a Hessian-vector product of ``H_I``: for gravity
alone the analytic derivative of the kick (the "jerk"), otherwise a central difference of the
kick acceleration (three force evaluations; its relative error ~1e-10 multiplies a term that
is already ``O(ε² h²)``, and the angular momentum it changes is ``O(δ²)``, below round-off).

Further tables (:mod:`.tables`): the ``ABA``/``ABAH``
methods of Blanes, Casas, Farrés, Laskar, Makazaga & Murua (2013), and the symplectic
correctors of Wisdom, Holman & Touma (1996) as in WHFast: the state is carried in processed
coordinates and corrected where it is written out; with the corrector kick the one-stage step
becomes WHT96's modified-kick kernel (the kick in the middle of the step, half SABAC₁'s
coefficient, which removes the ``ε² h²`` term left by the conjugation).

When Newtonian gravity is the system's only interaction, the kick is a dedicated pair loop
that leaves out the star–first-planet pair (it cancels the first Kepler term exactly, as in
WHFast), and the steps between two write-outs run in one tight compiled loop.

Every sub-flow is the exact flow of a rotation- and translation-invariant Hamiltonian, so
total linear and angular momentum are kept to round-off and the map is symplectic; the energy
error stays bounded without drift.

Modules: :mod:`.tables` (coefficients), :mod:`.kepler` (the Kepler flow), :mod:`.jacobi`
(coordinates), :mod:`.kicks` (kicks and correctors), :mod:`.loop` (the compiled time loop),
:mod:`.integrator` (:class:`WisdomHolman`).
"""

from poissonkit.numerics.integrators.wisdom_holman.integrator import WisdomHolman
from poissonkit.numerics.integrators.wisdom_holman.jacobi import (from_jacobi, jacobi_of_inertial,
                                                                  to_jacobi)
from poissonkit.numerics.integrators.wisdom_holman.kepler import (drift_all, drift_planets,
                                                                  kepler_drift, stumpff)
from poissonkit.numerics.integrators.wisdom_holman.kicks import (gravity_correct,
                                                                 gravity_corrector_kick,
                                                                 gravity_kick, gravity_kick_accel,
                                                                 gravity_kick_jerk,
                                                                 gravity_modified_kick,
                                                                 gravity_steps)
from poissonkit.numerics.integrators.wisdom_holman.tables import CORRECTOR_G, saba_coefficients

__all__ = [
    "CORRECTOR_G",
    "WisdomHolman",
    "drift_all",
    "drift_planets",
    "from_jacobi",
    "gravity_correct",
    "gravity_corrector_kick",
    "gravity_kick",
    "gravity_kick_accel",
    "gravity_kick_jerk",
    "gravity_modified_kick",
    "gravity_steps",
    "jacobi_of_inertial",
    "kepler_drift",
    "saba_coefficients",
    "stumpff",
    "to_jacobi",
]

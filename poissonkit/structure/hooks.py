"""Built-in plugin registering the core structures (e(3), so(3), seed 000 two-body, deformed
brackets of the survey, ...), listed by ``poissonkit verify --list``.

Bracket names end in ``_bracket`` where the non-holonomic plugin registers the full system
under the plain name (``chaplygin_ball`` is the system, ``chaplygin_ball_bracket`` the bivector
with symbolic parameters).
"""

from __future__ import annotations

import sympy as sp

from poissonkit.plugin.contributions import Param, SystemEntry
from poissonkit.plugin.hookspecs import hookimpl
from poissonkit.structure.bivector import direct_sum
from poissonkit.structure.blocks import canonical, e3, se3, so3


# The two-top structure and system stay in the core although seed 000 introduced them: they are
# the generic bracket of two interacting rigid bodies with an undefined potential U (no magnet,
# parameter, orbit or fate in them), like the survey's brackets tagged "seed001"; the tag
# records provenance. The seed 000 *scene* lives in the magnets plugin.
def two_tops() -> object:
    """Seed 000 eq. (15): ``canonical(r, p) + e(3) + e(3)`` on R^18."""
    return direct_sum(("orbit", canonical(3, "r", "p")), ("top1", e3()), ("top2", e3()))


def two_tops_hamiltonian():
    """Seed 000 two-body system (19)/(20) with an undefined potential ``U(r, c', c'', c''')``.

    ``H = p^2/(2 mu) + alpha1 |m'|^2/2 + alpha2 |m''|^2/2 + U``; claimed Casimirs
    ``|nu'|^2, |nu''|^2, (nu', m'), (nu'', m'')`` and integrals: the energy and the three
    components of the total angular momentum ``j = r x p + m' + m''`` (seed 000 eq. (22)).
    """
    from poissonkit.structure.system import HamiltonianSystem

    P = two_tops()
    c = P.coords
    r, p, nu1, m1, nu2, m2 = (sp.Matrix(c[3 * k:3 * k + 3]) for k in range(6))
    mu, a1, a2 = sp.symbols("mu alpha1 alpha2", positive=True)
    dist = sp.sqrt(r.dot(r))
    U = sp.Function("U")(dist, r.dot(nu1) / dist, r.dot(nu2) / dist, nu1.dot(nu2))
    H = p.dot(p) / (2 * mu) + a1 * m1.dot(m1) / 2 + a2 * m2.dot(m2) / 2 + U
    j = r.cross(p) + m1 + m2
    return HamiltonianSystem(
        structure=P, hamiltonian=H,
        casimirs={"|nu'|^2": nu1.dot(nu1), "|nu''|^2": nu2.dot(nu2),
                  "(nu',m')": nu1.dot(m1), "(nu'',m'')": nu2.dot(m2)},
        integrals={"H": H, "j_x": j[0], "j_y": j[1], "j_z": j[2]},
        name="two_tops_hamiltonian", doc="Seed 000 (19)/(20), generic U(r, c', c'', c''')")


def _deformed(name: str, **preset: object):
    """The builder of :mod:`poissonkit.structure.deformed`'s ``name`` (imported when built),
    with the keywords ``preset``."""
    def build(**kw):
        from poissonkit.structure import deformed

        return getattr(deformed, name)(**preset, **kw)
    return build


#: The survey's deformed brackets with symbolic parameters: registered name, description, the
#: function of :mod:`poissonkit.structure.deformed` and the keywords it is built with.
_SURVEY: tuple[tuple[str, str, str, dict[str, None]], ...] = (
    ("p_gf_bracket", "Survey (22)/(23): P_{g,f} with undefined g(gamma), f(gamma).", "p_gf",
     {"g": None, "f": None}),
    ("p_gf_phi_bracket", "P_{g,f} plus Remark 5's phi(gamma) term, all three functions undefined.",
     "p_gf", {"g": None, "f": None, "phi": None}),
    ("chaplygin_ball_bracket",
     "Survey (38)/(39): P_g with g = sqrt(1 - d(gamma, A gamma)), symbolic I, d.", "chaplygin_ball",
     {}),
    ("chaplygin_gyrostat_bracket", "Survey (49): P_sg, the Chaplygin ball with gyrostat S (symbolic).",
     "chaplygin_gyrostat", {}),
    ("veselova_bracket", "Survey (65): Veselova bracket P_v in (gamma, K), b = (gamma, K).",
     "veselova", {}),
    ("veselova_gyrostat_bracket", "Survey (70): Veselova gyrostat bracket P_k in (gamma, K), rotor k.",
     "veselova_gyrostat", {}),
    ("canonical_deformation",
     "Survey (42): {q_i, p_j} = g(q) delta_ij, {p_i, p_j} = p_i d_j g - p_j d_i g.",
     "canonical_deformation", {}),
)


@hookimpl
def poissonkit_systems() -> list[SystemEntry]:
    """Core Lie–Poisson, canonical and deformed structures."""
    return [
        SystemEntry("so3", "so(3) Lie–Poisson bracket {m_i, m_j} = eps_ijk m_k.",
                    build=lambda: so3(), tags=("lie-poisson",)),
        SystemEntry("e3", "e(3) Lie–Poisson bracket in seed 000's order (nu, m).",
                    build=lambda: e3("nu_m"), tags=("lie-poisson",)),
        SystemEntry("e3_gamma_M", "e(3) Lie–Poisson bracket in the survey's order (gamma, M), eq. (9).",
                    build=lambda: e3("gamma_M"), tags=("lie-poisson", "seed001")),
        SystemEntry("se3", "se(3)* Lie–Poisson bracket (L, P) from 4x4 matrix commutators.",
                    build=lambda: se3(), tags=("lie-poisson",)),
        SystemEntry("canonical3", "Canonical bracket on R^6, {q_i, p_j} = delta_ij.",
                    build=lambda: canonical(3), tags=("canonical",)),
        SystemEntry("two_tops", "Seed 000 eq. (15): canonical(r, p) + e(3) + e(3), 18 dimensions.",
                    build=two_tops, tags=("seed000",)),
        SystemEntry("two_tops_hamiltonian",
                    "Seed 000 (19)/(20): two tops, generic U(r,c',c'',c'''), Casimirs and j claimed.",
                    build=two_tops_hamiltonian, tags=("seed000", "system")),
        *(SystemEntry(name, doc, build=_deformed(function, **preset), tags=("seed001", "deformed"))
          for name, doc, function, preset in _SURVEY),
        SystemEntry("chaplygin_ball_numeric_bracket",
                    "P_g of the Chaplygin ball with numeric I = (I1, I2, I3) and d.",
                    params=(Param("I", "vector", "principal moments (kg m^2)", (1.0, 2.0, 3.0)),
                            Param("d", "float", "m b^2 (kg m^2)", 1.0, positive=True)),
                    build=lambda I=(1, 2, 3), d=1: _deformed("chaplygin_ball")(
                        I=tuple(sp.nsimplify(v) for v in I), d=sp.nsimplify(d)),
                    tags=("seed001", "deformed")),
    ]

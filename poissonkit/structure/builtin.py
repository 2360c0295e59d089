"""Built-in plugin registering the core structures (e(3), so(3), seed 000 two-body, ...)."""

from __future__ import annotations

from poissonkit.plugin.contributions import SystemEntry
from poissonkit.plugin.hookspecs import hookimpl
from poissonkit.structure.bivector import direct_sum
from poissonkit.structure.blocks import canonical, e3, so3


@hookimpl
def poissonkit_systems() -> list[SystemEntry]:
    """Core Lie–Poisson and canonical structures."""
    return [
        SystemEntry("so3", "so(3) Lie–Poisson bracket {m_i, m_j} = eps_ijk m_k.",
                    build=lambda: so3(), tags=("lie-poisson",)),
        SystemEntry("e3", "e(3) Lie–Poisson bracket in seed 000's order (nu, m).",
                    build=lambda: e3("nu_m"), tags=("lie-poisson",)),
        SystemEntry("canonical3", "Canonical bracket on R^6, {q_i, p_j} = delta_ij.",
                    build=lambda: canonical(3), tags=("canonical",)),
        SystemEntry("two_tops", "Seed 000 eq. (15): canonical(r, p) + e(3) + e(3), 18 dimensions.",
                    build=lambda: direct_sum(("orbit", canonical(3, "r", "p")), ("top1", e3()),
                                             ("top2", e3())), tags=("seed000",)),
    ]

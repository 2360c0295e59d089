"""pluggy hook implementations of the nbody plugin: graph assemblies and point-mass gravity."""

from __future__ import annotations

from typing import Any

from poissonkit.plugin.contributions import Assembly, PairPotential, Param
from poissonkit.plugin.hookspecs import hookimpl

# networkx and sympy are imported by the hooks and builders that need them, not with this module:
# the host loads it for any registry of a kind it contributes.

#: Flat, typed body parameters shared by every registered assembly (0 = absent).
_BODY_PARAMS = (
    Param("mass", "float", "mass of each body [kg]", unit="kg", positive=True),
    Param("alpha", "float", "1/I_perp of each body [1/(kg m^2)]; 0 = point mass", default=0.0,
          unit="1/(kg m^2)"),
    Param("moment", "float", "magnetic moment [A m^2]; 0 = none", default=0.0, unit="A m^2"),
    Param("body_radius", "float", "magnet radius [m]; 0 = none", default=0.0, unit="m"),
    Param("body_length", "float", "magnet full height [m]; 0 = none", default=0.0, unit="m"),
    Param("potential", "str", "pair potential name (registry)", default="dipole"),
    Param("interactions", "str", "'complete' or 'neighbours'", default="complete"),
)


def _body(params: dict[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """Split flat registry parameters into (body template, builder keywords)."""
    params = dict(params)
    body: dict[str, Any] = {"mass": params.pop("mass")}
    for flat, key in (("alpha", "alpha"), ("moment", "moment"), ("body_radius", "radius"),
                      ("body_length", "length")):
        value = params.pop(flat, 0.0)
        if value:
            body[key] = value
    return body, params


def _chain(**params: Any):
    from poissonkit_nbody import graphs

    body, kw = _body(params)
    return graphs.chain(kw.pop("n"), kw.pop("spacing"), body, **kw)


def _ring(**params: Any):
    from poissonkit_nbody import graphs

    body, kw = _body(params)
    return graphs.ring(kw.pop("n"), kw.pop("ring_radius"), body, **kw)


def _lattice(**params: Any):
    from poissonkit_nbody import graphs

    body, kw = _body(params)
    shape = (kw.pop("nx"), kw.pop("ny")) + ((kw.pop("nz"),) if kw.get("nz", 0) else ())
    kw.pop("nz", None)
    return graphs.lattice(shape, kw.pop("spacing"), body, **kw)


def _cluster(**params: Any):
    from poissonkit_nbody import graphs

    body, kw = _body(params)
    if not kw.get("min_distance"):
        kw.pop("min_distance", None)
    return graphs.random_cluster(kw.pop("n"), kw.pop("cluster_radius"), body, **kw)


@hookimpl
def poissonkit_assemblies() -> list[Assembly]:
    """Chains, rings, 2D/3D lattices and seeded random clusters built as networkx graphs."""
    from poissonkit_nbody import graphs

    n = Param("n", "int", "number of bodies", positive=True)
    spacing = Param("spacing", "float", "centre-to-centre distance [m]", unit="m", positive=True)
    return [
        Assembly("chain", graphs.chain.__doc__.split("\n")[0], build=_chain, params=(
            n, spacing, Param("axes", "str", "'aligned', 'alternating' or 'transverse'",
                              default="aligned"), *_BODY_PARAMS)),
        Assembly("ring", graphs.ring.__doc__.split("\n")[0], build=_ring, params=(
            n, Param("ring_radius", "float", "radius of the ring [m]", unit="m", positive=True),
            Param("axes", "str", "'tangent', 'radial' or 'normal'", default="tangent"),
            *_BODY_PARAMS)),
        Assembly("lattice", graphs.lattice.__doc__.split("\n")[0], build=_lattice, params=(
            Param("nx", "int", "sites along x", positive=True),
            Param("ny", "int", "sites along y", positive=True),
            Param("nz", "int", "sites along z; 0 = a 2D lattice", default=0),
            spacing, Param("axes", "str", "'aligned' or 'checkerboard'", default="aligned"),
            *_BODY_PARAMS)),
        Assembly("random_cluster", graphs.random_cluster.__doc__.split("\n")[0], build=_cluster,
                 params=(
            n, Param("cluster_radius", "float", "radius of the ball holding the centres [m]",
                     unit="m", positive=True),
            Param("seed", "int", "random seed", default=0),
            Param("min_distance", "float", "minimum centre distance [m]; 0 = from body size",
                  default=0.0, unit="m"),
            Param("axes", "str", "'random' or 'aligned'", default="random"),
            *_BODY_PARAMS)),
    ]


@hookimpl
def poissonkit_potentials() -> list[PairPotential]:
    """Point-mass gravity."""
    from poissonkit_nbody.potentials import GRAVITY

    return [GRAVITY]

"""pluggy hook implementations of the magnets plugin.

Contributes the pair potentials of :mod:`poissonkit_magnets.models` (names and parameters as in
docs/architecture.md, "Magnet potential names and parameters"; the extra models are documented in
docs/magnets.md), the magnet model family of the planner (:mod:`poissonkit_magnets.family`)
and the built-in scene ``seed000`` (:mod:`poissonkit_magnets.seed000`), the
default scene of ``poissonkit run``.
"""

from __future__ import annotations

from functools import cache, partial

from poissonkit.plugin.contributions import (ExternalField, ModelFamily, OutcomeEntry,
                                             PairPotential, Param, SceneEntry)
from poissonkit.plugin.hookspecs import hookimpl

# Each hook imports what it hands out when it is called: the host calls only the hooks of the
# kinds a command needs (``poissonkit scenes`` calls poissonkit_scenes alone), so listing the
# scenes loads neither the models (sympy, numba) nor the fields.


def _dipole_energy_scale(bodies, length: float) -> float | None:
    """Energy unit of a magnet scene: the dipole energy ``mu0 mu^2 / (4 pi L^3)`` of the
    strongest magnets at the length unit (``None`` without a magnet)."""
    import math

    from poissonkit.conventions import MU0

    strongest = max(b.attr("moment") or 0.0 for b in bodies)
    if not strongest > 0:
        return None
    return MU0 * strongest ** 2 / (4 * math.pi * length ** 3)


@cache
def _potential_entries() -> tuple[PairPotential, ...]:
    """Built once per process: compiled kernels are cached per entry, so handing out the same
    entries after every plugin-manager rebuild avoids recompiling them."""
    from poissonkit_magnets.models import MODELS, evaluator, kernel, param_kernel, param_values
    from poissonkit_magnets.pair_params import MAGNET_QUANTITIES, complete_params

    return tuple(
        PairPotential(name=m.name, doc=m.doc, params=m.params, expr=m.expr,
                      kernel=partial(kernel, m.name), orientation="both",
                      param_kernel=partial(param_kernel, m.name),
                      param_values=partial(param_values, m.name),
                      evaluate=partial(evaluator, m.name),
                      complete_params=partial(complete_params, tuple(p.name for p in m.params)),
                      body_quantities=MAGNET_QUANTITIES,
                      energy_scale=_dipole_energy_scale)
        for m in MODELS
    )


@hookimpl
def poissonkit_potentials() -> list[PairPotential]:
    """The magnet pair potentials (SI units)."""
    return list(_potential_entries())


@hookimpl
def poissonkit_model_families() -> list[ModelFamily]:
    """The magnet family: dipole, dumbbells, exact cylinders, with their error estimate."""
    from poissonkit_magnets.family import MAGNET_FAMILY

    return [MAGNET_FAMILY]


def _seed_sweep(**options):
    from poissonkit_magnets.seed000_sweep import SeedScene

    return SeedScene(**options)


def _seed_scene(**params):
    from poissonkit_magnets import seed000  # mpmath tables: only when the scene is used

    return seed000.scene_run(**params)


#: The seed 000 orbit; its parameters are the run options ``poissonkit run`` passes through.
SEED_SCENE = SceneEntry(
    name="seed000",
    doc="Two cylinder magnets (dumbbell model) on the seed's circular orbit, R_orb = 10 mm; "
        "order-6 splitting, T_orb/200 steps.",
    params=(
        Param("periods", "float", "duration in orbital periods", 20.0, positive=True),
        Param("duration", "float", "duration [s] (overrides periods)", unit="s", positive=True,
              optional=True),
        Param("method", "str", "integrator registry name", "splitting6"),
        Param("step", "float", "fixed step [s] (default T_orb/200)", unit="s", positive=True,
              optional=True),
        Param("tol", "float", "tolerance of adaptive methods", positive=True, optional=True),
        Param("tilt", "float", "tilt of both axes [rad] (0: the exact circular orbit)", 0.0,
              unit="rad"),
        Param("spin_ratio", "float", "alpha|m|/omega_orb of each top", 20.0),
    ),
    load=_seed_scene,
    default=True,
    sweep=_seed_sweep,
)


@hookimpl
def poissonkit_scenes() -> list[SceneEntry]:
    """The built-in seed 000 scene (the default of ``poissonkit run``) and the Levitron."""
    from poissonkit_magnets.levitron_scene import LEVITRON_SCENE

    return [SEED_SCENE, LEVITRON_SCENE]


@hookimpl
def poissonkit_fields() -> list[ExternalField]:
    """External magnetic fields: magpylib sources (tabulated), the exact current loop and
    cylinder."""
    from poissonkit_magnets.exact_fields import CURRENT_LOOP, CYLINDER
    from poissonkit_magnets.magpylib_field import MAGPYLIB

    return [MAGPYLIB, CURRENT_LOOP, CYLINDER]


@hookimpl
def poissonkit_outcomes() -> list[OutcomeEntry]:
    """The Levitron's fine fate (flip told from fall by the axis) as a sweep outcome."""
    from poissonkit_magnets.levitron_sweep import levitron_fate_outcome

    return [levitron_fate_outcome()]

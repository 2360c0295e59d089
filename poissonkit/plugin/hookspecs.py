"""Hook specifications: everything a plugin can contribute.

Each hook returns a list of entries (see :mod:`poissonkit.plugin.contributions`). The built-in
plugins under ``plugins/`` and poissonkit's own integrators implement these same hooks; a
third-party package does so by declaring an entry point in the group ``poissonkit``::

    [project.entry-points.poissonkit]
    myplugin = "my_package.hooks"

Every hook here must be documented in ``docs/plugins.md`` (a test checks it).

Versions
--------
The hooks and the entry types they return form the plugin API, versioned as
:data:`PLUGIN_API_VERSION` (``"major.minor"``). A plugin states the version it was written for
with a module attribute of its hooks module, ``POISSONKIT_API = "1.0"`` (without one it is
``"unversioned"``); ``poissonkit plugins`` shows it and warns when it does not match
(:func:`poissonkit.plugin.manager.api_mismatch`). The deprecation policy is in ``docs/plugins.md`` ("Plugin API
versions"): a minor version only adds; a hook or field to be removed first warns for at least
two minor releases and goes only with the next major version.
"""

from __future__ import annotations

import pluggy

from poissonkit.plugin.contributions import (Assembly, ExternalField, IntegratorEntry, ModelFamily,
                                             OutcomeEntry, PairPotential, SceneEntry, SystemEntry)

PROJECT = "poissonkit"

#: The version of the plugin API (hooks and entry types): ``"major.minor"``.
PLUGIN_API_VERSION = "1.0"
#: The module attribute of a plugin's hooks module naming the API version it was written for.
API_ATTRIBUTE = "POISSONKIT_API"
#: What a plugin that declares no version is shown as.
UNVERSIONED = "unversioned"

hookspec = pluggy.HookspecMarker(PROJECT)
hookimpl = pluggy.HookimplMarker(PROJECT)


@hookspec
def poissonkit_potentials() -> list[PairPotential]:
    """Return pair potentials U(r, c1, c2, c3) this plugin provides.

    Returns
    -------
    list of PairPotential
        Each with a unique name, a doc string, typed parameters and a symbolic ``expr`` and/or
        a compiled ``kernel``.
    """
    raise NotImplementedError  # a specification: pluggy calls the implementations


@hookspec
def poissonkit_assemblies() -> list[Assembly]:
    """Return N-body assemblies (graph builders) this plugin provides.

    Returns
    -------
    list of Assembly
        Each ``build(**params)`` returns a networkx graph of bodies and interactions.
    """
    raise NotImplementedError  # a specification: pluggy calls the implementations


@hookspec
def poissonkit_systems() -> list[SystemEntry]:
    """Return named Poisson structures and Hamiltonian systems (for ``poissonkit verify``).

    Returns
    -------
    list of SystemEntry
        Each ``build(**params)`` returns a Bivector or a HamiltonianSystem.
    """
    raise NotImplementedError  # a specification: pluggy calls the implementations


@hookspec
def poissonkit_integrators() -> list[IntegratorEntry]:
    """Return time integrators this plugin provides.

    Returns
    -------
    list of IntegratorEntry
        Each ``factory(**params)`` returns an integrator object.
    """
    raise NotImplementedError  # a specification: pluggy calls the implementations


@hookspec
def poissonkit_scenes() -> list[SceneEntry]:
    """Return built-in scenes (runnable with ``poissonkit run NAME``).

    Returns
    -------
    list of SceneEntry
    """
    raise NotImplementedError  # a specification: pluggy calls the implementations


@hookspec
def poissonkit_model_families() -> list[ModelFamily]:
    """Return model families: pair potentials of one physical pair at several fidelities.

    Returns
    -------
    list of ModelFamily
        Each names its models (registered potentials) cheapest first, with an error estimator
        and the test of which pairs it models; the planner and ``pair_interaction("auto")``
        choose per pair the cheapest model within a tolerance.
    """
    raise NotImplementedError  # a specification: pluggy calls the implementations


@hookspec
def poissonkit_outcomes() -> list[OutcomeEntry]:
    """Return sweep outcomes: quantities one run of a sweep is reduced to.

    Returns
    -------
    list of OutcomeEntry
        Each with a name, a doc string, a numpy dtype, an SI unit, a fill value for points not
        computed, and ``compute(record)`` of the run's
        :class:`~poissonkit.sweeps.targets.RunRecord`; choose them with
        ``sweep(..., outcomes=[...])`` or ``poissonkit sweep --outcomes``.
    """
    raise NotImplementedError  # a specification: pluggy calls the implementations


@hookspec
def poissonkit_fields() -> list[ExternalField]:
    """Return external fields: one-body energies ``U(r, ν)`` (gravity, magnetic fields).

    Returns
    -------
    list of ExternalField
        Each with a name, a doc string, typed parameters, the body attribute it couples to
        (``reads``: ``"mass"``, ``"moment"``, ...) and ``build(params, request, source)``
        returning the compiled one-body kernel and its data; the numerics derive forces and
        torques from its partials (``docs/fields.md``).
    """
    raise NotImplementedError  # a specification: pluggy calls the implementations

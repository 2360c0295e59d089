"""A well-behaved third-party plugin for the isolation test: one entry of every kind.

Each entry is a renamed copy (prefix ``echo_``) of a built-in entry, so anything a test does with
every registered entry (build it, verify it, run it) works, and only a test that expects the
exact list of entries can notice it. ``tests/plugins/test_plugins_isolation.py`` installs it as
a distribution (dist-info with entry points) and runs the registry tests with it present.
"""

from __future__ import annotations

from dataclasses import replace

from poissonkit.plugin.contributions import SceneEntry
from poissonkit.plugin.hookspecs import hookimpl


def _first(entries, prefix="echo_"):
    """A renamed copy of the first entry (not the default scene: one default is enough)."""
    entry = entries[0]
    changes = {"name": prefix + entry.name}
    if isinstance(entry, SceneEntry):
        changes["default"] = False
    return [replace(entry, **changes)]


@hookimpl
def poissonkit_potentials():
    from poissonkit_nbody import hooks

    return _first(hooks.poissonkit_potentials())


@hookimpl
def poissonkit_assemblies():
    from poissonkit_nbody import hooks

    return _first(hooks.poissonkit_assemblies())


@hookimpl
def poissonkit_systems():
    from poissonkit.structure import hooks

    return _first(hooks.poissonkit_systems())


@hookimpl
def poissonkit_integrators():
    from poissonkit.numerics import hooks

    return _first(hooks.poissonkit_integrators())


@hookimpl
def poissonkit_scenes():
    from poissonkit_magnets import hooks

    return _first(hooks.poissonkit_scenes())


@hookimpl
def poissonkit_model_families():
    from poissonkit.plugin.contributions import ModelFamily

    # a family of its own pairs only (it claims none of the built-in bodies)
    return [ModelFamily("echo_family", "A family that applies to no pair.",
                        models=("echo_gravity",), applies=lambda body1, body2: False)]


@hookimpl
def poissonkit_outcomes():
    from poissonkit.sweeps import hooks

    return _first(hooks.poissonkit_outcomes())


@hookimpl
def poissonkit_fields():
    from poissonkit.numerics.fields import hooks

    return _first(hooks.poissonkit_fields())

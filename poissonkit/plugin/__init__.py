"""pluggy host: hook specifications, the lazily built manager and named registries."""

from poissonkit.plugin.contributions import (Assembly, Capabilities, Entry, ExternalField,
                                             IntegratorEntry, ModelFamily, OutcomeEntry,
                                             PairPotential, Param, SceneEntry, SystemEntry)
from poissonkit.plugin.hookspecs import hookimpl
from poissonkit.plugin.manager import entries, plugin_manager, plugin_reports, reset
from poissonkit.plugin.registry import (assembly, default_scene, external_field, external_fields,
                                        integrator, integrators, lookup, model_families,
                                        model_family, names, potential, scene, system)

__all__ = [
    "Assembly", "Capabilities", "Entry", "ExternalField", "IntegratorEntry", "ModelFamily", "OutcomeEntry",
    "PairPotential", "Param", "SceneEntry", "SystemEntry",
    "assembly", "default_scene", "entries", "external_field", "external_fields", "hookimpl", "integrator", "integrators", "lookup",
    "model_families", "model_family", "names", "plugin_manager",
    "plugin_reports", "potential", "reset", "scene", "system",
]

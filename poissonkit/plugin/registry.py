"""Look-ups by name in the plugin registries, with helpful errors."""

from __future__ import annotations

from poissonkit.errors import UnknownEntryError
from poissonkit.plugin.contributions import (Assembly, Entry, ExternalField, IntegratorEntry,
                                             ModelFamily, PairPotential, SceneEntry, SystemEntry)
from poissonkit.plugin.manager import entries, plugin_reports


def failed_plugins() -> list[tuple[str, str]]:
    """``(name, error)`` of every plugin that failed to load (its entries are missing)."""
    return [(r.name, r.error) for r in plugin_reports() if r.status == "failed"]


def lookup(kind: str, name: str) -> Entry:
    """Return the entry ``name`` of registry ``kind``.

    Raises
    ------
    UnknownEntryError
        If no loaded plugin provides it; the message lists the available names and any plugin
        that failed to load (the entry may be one of its).
    """
    found = entries(kind)
    if name not in found:
        raise UnknownEntryError(kind, name, found, failed_plugins())
    return found[name]


def potential(name: str) -> PairPotential:
    """The pair potential registered as ``name``."""
    return lookup("potential", name)  # type: ignore[return-value]


def assembly(name: str) -> Assembly:
    """The N-body assembly registered as ``name``."""
    return lookup("assembly", name)  # type: ignore[return-value]


def system(name: str) -> SystemEntry:
    """The Poisson structure / system registered as ``name``."""
    return lookup("system", name)  # type: ignore[return-value]


def integrator(name: str) -> IntegratorEntry:
    """The integrator registered as ``name``."""
    return lookup("integrator", name)  # type: ignore[return-value]


def integrators() -> dict[str, IntegratorEntry]:
    """Every registered integrator by name (built-in and from plugins).

    Returns
    -------
    dict of str to IntegratorEntry
        Each entry carries its ``doc``, ``order``, ``family`` and typed ``params``; pass the
        name as ``method=`` to :func:`poissonkit.solve`.

    Examples
    --------
    >>> import poissonkit as pk
    >>> "splitting6" in pk.integrators()
    True
    """
    return entries("integrator")  # type: ignore[return-value]


def scene(name: str) -> SceneEntry:
    """The built-in scene registered as ``name``."""
    return lookup("scene", name)  # type: ignore[return-value]


def default_scene() -> SceneEntry:
    """The scene ``poissonkit run`` uses without an argument.

    The first scene entry flagged ``default`` in registration order; built-in plugins register
    before third-party ones, so an installed plugin cannot silently replace it.

    Raises
    ------
    SceneError
        If no registered scene is flagged as the default (e.g. its plugin was blocked).
    """
    for entry in entries("scene").values():
        if isinstance(entry, SceneEntry) and entry.default:
            return entry
    from poissonkit.errors import SceneError

    raise SceneError("no default scene is registered (is the magnets plugin blocked or "
                     "broken? see `poissonkit plugins`); name a scene file or scene")


def names(kind: str) -> list[str]:
    """Sorted names in registry ``kind``."""
    return sorted(entries(kind))


def model_family(name: str) -> ModelFamily:
    """The model family registered as ``name``."""
    return lookup("model_family", name)  # type: ignore[return-value]


def model_families() -> list[ModelFamily]:
    """Every registered model family, in registration order (built-in plugins first)."""
    return list(entries("model_family").values())  # type: ignore[arg-type]


def external_field(name: str) -> ExternalField:
    """The external field registered as ``name`` (``"gravity"``, ``"uniform"``, ...)."""
    return lookup("field", name)  # type: ignore[return-value]


def external_fields() -> dict[str, ExternalField]:
    """Every registered external field by name (built-in and from plugins)."""
    return entries("field")  # type: ignore[return-value]

"""The plugin manager: built once, lazily, on first use.

Built-in plugins (poissonkit's own integrators and systems, and the packages under ``plugins/``)
are registered explicitly through the same hooks third-party plugins use; third-party plugins are
discovered through the entry-point group ``poissonkit``.

Environment switches
--------------------
``POISSONKIT_DISABLE_PLUGIN_AUTOLOAD=1``
    Do not load entry-point plugins (built-ins are still registered).
``POISSONKIT_BLOCK_PLUGINS=name1,name2``
    Never register the plugins with these names (built-in or external).

A plugin that fails to import, or whose hook raises or returns malformed entries, is recorded in
:func:`plugin_reports` and skipped; it never breaks the host. Hook implementations whose name no
hook specification has (a misspelt ``poissonkit_assembly``) are reported as warnings on their
plugin (:func:`unknown_hooks`); the rest of the plugin is used.
"""

from __future__ import annotations

import importlib
import importlib.metadata as md
import os
import threading
from dataclasses import dataclass, field
from typing import Any

import pluggy

from poissonkit.plugin import hookspecs
from poissonkit.plugin.contributions import (Assembly, Entry, ExternalField, IntegratorEntry,
                                             ModelFamily, OutcomeEntry, PairPotential, SceneEntry,
                                             SystemEntry)

#: Built-in plugin modules: (plugin name, module path). Registered like any other plugin.
BUILTIN_PLUGINS: tuple[tuple[str, str], ...] = (
    ("core-systems", "poissonkit.structure.hooks"),
    ("core-integrators", "poissonkit.numerics.hooks"),
    ("core-fields", "poissonkit.numerics.fields.hooks"),
    ("magnets", "poissonkit_magnets.hooks"),
    ("nbody", "poissonkit_nbody.hooks"),
    ("nonholonomic", "poissonkit_nonholonomic.hooks"),
    ("core-outcomes", "poissonkit.sweeps.hooks"),
)

#: hook name -> (registry kind, entry type)
KINDS: dict[str, tuple[str, type[Entry]]] = {
    "poissonkit_potentials": ("potential", PairPotential),
    "poissonkit_assemblies": ("assembly", Assembly),
    "poissonkit_systems": ("system", SystemEntry),
    "poissonkit_integrators": ("integrator", IntegratorEntry),
    "poissonkit_scenes": ("scene", SceneEntry),
    "poissonkit_model_families": ("model_family", ModelFamily),
    "poissonkit_outcomes": ("outcome", OutcomeEntry),
    "poissonkit_fields": ("field", ExternalField),
}

ENV_DISABLE = "POISSONKIT_DISABLE_PLUGIN_AUTOLOAD"
ENV_BLOCK = "POISSONKIT_BLOCK_PLUGINS"


@dataclass
class PluginReport:
    """What one plugin is and what it contributed (or why it was skipped)."""

    name: str
    source: str  # "builtin" or the distribution name
    version: str = ""
    status: str = "ok"  # "ok", "failed", "blocked"
    error: str = ""
    contributions: dict[str, list[str]] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    #: The plugin API version it was written for (``POISSONKIT_API`` of its hooks module;
    #: built-ins: the host's own), or ``"unversioned"``.
    api: str = hookspecs.UNVERSIONED


@dataclass
class _State:
    pm: pluggy.PluginManager
    reports: list[PluginReport]
    entries: dict[str, dict[str, Entry]]


_lock = threading.Lock()
_state: _State | None = None


def _blocked() -> set[str]:
    return {n.strip() for n in os.environ.get(ENV_BLOCK, "").split(",") if n.strip()}


def _dist_version(module_name: str) -> str:
    top = module_name.split(".")[0]
    for dist_name in md.packages_distributions().get(top, []):
        try:
            return md.version(dist_name)
        except md.PackageNotFoundError:
            continue
    return ""


def _collect(plugin: Any, entries: dict[str, dict[str, Entry]]) -> dict[str, list[Entry]]:
    """Call every hook of one plugin and validate its entries (registries are not touched)."""
    found: dict[str, list[Entry]] = {}
    for hook_name, (kind, etype) in KINDS.items():
        impl = getattr(plugin, hook_name, None)
        if impl is None:
            continue
        result = impl()
        if result is None:
            continue
        items = list(result)
        for item in items:
            if not isinstance(item, etype):
                raise TypeError(f"{hook_name} returned {type(item).__name__}, expected {etype.__name__}")
            if not item.name or not item.doc:
                raise TypeError(f"{hook_name}: entry {item.name!r} lacks a name or a doc string")
            if item.name in entries[kind] or any(i.name == item.name for i in found.get(kind, [])):
                raise TypeError(f"{kind} {item.name!r} is already provided by another plugin")
        found[kind] = items
    return found


def unknown_hooks(pm: pluggy.PluginManager, plugin: object) -> list[str]:
    """Warnings for the hook implementations of ``plugin`` that match no hook specification.

    Decorated implementations are checked the way :meth:`pluggy.PluginManager.check_pending`
    does (a registered hook without a spec, not marked ``optionalhook``); undecorated functions
    named like a hook (``poissonkit_*``) are reported too, since pluggy never sees them.
    """
    import difflib
    import inspect

    known = sorted(KINDS)
    seen: set[str] = set()
    for caller in pm.get_hookcallers(plugin) or []:
        if not caller.has_spec() and any(i.plugin is plugin and not i.optionalhook
                                         for i in caller.get_hookimpls()):
            seen.add(caller.name)
    prefix = f"{hookspecs.PROJECT}_"
    for attr in dir(plugin):
        if attr.startswith(prefix) and attr not in known:
            if inspect.isfunction(getattr(plugin, attr)):
                seen.add(attr)
    out = []
    for name in sorted(seen):
        close = difflib.get_close_matches(name, known, n=1)
        hint = f"; did you mean {close[0]!r}?" if close else f"; hooks: {', '.join(known)}"
        out.append(f"unknown hook {name!r} is ignored{hint}")
    return out


def api_mismatch(declared: str, host: str = hookspecs.PLUGIN_API_VERSION) -> str | None:
    """Why a plugin written for API ``declared`` may not work with this host's ``host``
    version, or ``None`` when it will (same major version, minor not newer; or unversioned).

    Examples
    --------
    >>> api_mismatch("1.0", "1.2") is None
    True
    >>> print(api_mismatch("2.0", "1.2"))  # doctest: +NORMALIZE_WHITESPACE
    written for plugin API 2.0, this poissonkit has 1.2 (another major version: hooks or
    entry fields it uses may differ)
    """
    if declared == hookspecs.UNVERSIONED:
        return None
    try:
        major, minor = (int(x) for x in declared.split("."))
        h_major, h_minor = (int(x) for x in host.split("."))
    except ValueError:
        return (f"{hookspecs.API_ATTRIBUTE} = {declared!r} is not a version 'major.minor' "
                f"(this poissonkit has {host})")
    if major != h_major:
        return (f"written for plugin API {declared}, this poissonkit has {host} (another major "
                "version: hooks or entry fields it uses may differ)")
    if minor > h_minor:
        return (f"written for plugin API {declared}, newer than this poissonkit's {host}: "
                "upgrade poissonkit")
    return None


def _api_version(plugin: object, source: str) -> str:
    """The API version a plugin declares; built-ins ship with the host and have its own."""
    if source == "builtin":
        return hookspecs.PLUGIN_API_VERSION
    declared = getattr(plugin, hookspecs.API_ATTRIBUTE, None)
    return hookspecs.UNVERSIONED if declared is None else str(declared)


def _register(pm: pluggy.PluginManager, name: str, loader, source: str, version: str,
              reports: list[PluginReport], entries: dict[str, dict[str, Entry]]) -> None:
    report = PluginReport(name=name, source=source, version=version)
    reports.append(report)
    if name in _blocked():
        report.status = "blocked"
        return
    try:
        plugin = loader()
        found = _collect(plugin, entries)
        pm.register(plugin, name=name)
    except Exception as exc:  # a broken plugin must never break the host
        report.status = "failed"
        report.error = f"{type(exc).__name__}: {exc}"
        return
    report.warnings = unknown_hooks(pm, plugin)
    report.api = _api_version(plugin, source)
    mismatch = api_mismatch(report.api)
    if mismatch is not None:
        report.warnings.append(mismatch)
    # only a plugin that registered cleanly contributes entries
    for kind, items in found.items():
        for item in items:
            entries[kind][item.name] = item
        report.contributions[kind] = [i.name for i in items]


def _build() -> _State:
    pm = pluggy.PluginManager(hookspecs.PROJECT)
    pm.add_hookspecs(hookspecs)
    reports: list[PluginReport] = []
    entries: dict[str, dict[str, Entry]] = {kind: {} for kind, _ in KINDS.values()}
    from poissonkit._version import __version__

    for name, module in BUILTIN_PLUGINS:
        _register(pm, name, lambda m=module: importlib.import_module(m), "builtin",
                  __version__, reports, entries)
    if os.environ.get(ENV_DISABLE, "").strip() not in ("1", "true", "yes"):
        for ep in md.entry_points(group=hookspecs.PROJECT):
            dist = ep.dist.name if ep.dist is not None else ""
            version = ep.dist.version if ep.dist is not None else ""
            _register(pm, ep.name, ep.load, dist or "entry point", version, reports, entries)
    return _State(pm=pm, reports=reports, entries=entries)


def _get() -> _State:
    global _state
    with _lock:
        if _state is None:
            _state = _build()
        return _state


def plugin_manager() -> pluggy.PluginManager:
    """The lazily built :class:`pluggy.PluginManager` with every plugin that loaded."""
    return _get().pm


def plugin_reports() -> list[PluginReport]:
    """One report per plugin seen: built-in and external, loaded, failed or blocked."""
    return list(_get().reports)


def entries(kind: str) -> dict[str, Entry]:
    """All entries of one kind (``"potential"``, ``"assembly"``, ``"system"``, ``"integrator"``,
    ``"scene"``, ``"model_family"``, ``"outcome"``, ``"field"``), by name."""
    state = _get()
    if kind not in state.entries:
        from poissonkit.errors import UnknownNameError

        raise UnknownNameError("registry", kind, state.entries)
    return dict(state.entries[kind])


def reset() -> None:
    """Forget the manager so the next use rebuilds it (tests; after installing a plugin)."""
    global _state
    with _lock:
        _state = None

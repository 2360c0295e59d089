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

Plugins are loaded, and their hooks called, as their entries are first needed: :func:`entries`
of one kind imports only the built-ins that declare that kind (:data:`BUILTIN_KINDS`) and calls
only their hook of that kind, so ``poissonkit scenes`` imports neither sympy nor numba. A
third-party plugin (its kinds unknown before it is imported) is loaded and all its hooks are
called on first use of any registry. :func:`plugin_reports` and :func:`plugin_manager` load
everything. A built-in hook that raises therefore skips the whole built-in only from the moment
that hook is called (built-ins do not raise in a sound installation).
"""

from __future__ import annotations

import importlib
import importlib.metadata as md
import os
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
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

#: What each built-in plugin module contributes (registry kinds): a command that needs one kind
#: (``poissonkit scenes``: scenes only) imports only the built-ins that declare it, and calls
#: only their hooks of that kind, instead of every module (sympy, numba, networkx...).
#: ``tests/test_startup_imports.py`` checks the table against the modules' hooks.
BUILTIN_KINDS: dict[str, frozenset[str]] = {
    "poissonkit.structure.hooks": frozenset({"system"}),
    "poissonkit.numerics.hooks": frozenset({"integrator"}),
    "poissonkit.numerics.fields.hooks": frozenset({"field"}),
    "poissonkit_magnets.hooks": frozenset({"potential", "model_family", "scene", "field",
                                           "outcome"}),
    "poissonkit_nbody.hooks": frozenset({"assembly", "potential"}),
    "poissonkit_nonholonomic.hooks": frozenset({"system"}),
    "poissonkit.sweeps.hooks": frozenset({"outcome"}),
}

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


@dataclass(eq=False)
class _Slot:
    """One plugin in registration order: how it loads, what it declares, what it returned."""

    report: PluginReport
    loader: Callable[[], object]
    #: The registry kinds its hooks contribute (built-ins, :data:`BUILTIN_KINDS`), or ``None``
    #: when unknown (third-party plugins): then every hook is called on first use.
    kinds: frozenset[str] | None
    plugin: object = None
    loaded: bool = False
    #: What each called hook returned (entry types and docs checked), by kind.
    found: dict[str, list[Entry]] = field(default_factory=dict)
    #: Kinds whose hook was called; kinds whose names were checked against earlier plugins.
    called: set[str] = field(default_factory=set)
    checked: set[str] = field(default_factory=set)

    @property
    def ok(self) -> bool:
        return self.report.status == "ok"


@dataclass
class _State:
    pm: pluggy.PluginManager
    slots: list[_Slot]
    #: Every plugin loaded and every hook called (what plugin_reports and plugin_manager need).
    complete: bool = False


_ALL_KINDS: tuple[str, ...] = tuple(kind for kind, _ in KINDS.values())
_lock = threading.RLock()
_state: _State | None = None


def _blocked() -> set[str]:
    return {n.strip() for n in os.environ.get(ENV_BLOCK, "").split(",") if n.strip()}


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


def _slots() -> list[_Slot]:
    """Every plugin, built-ins first, in registration order; nothing is imported yet."""
    from poissonkit._version import __version__

    slots = [_Slot(PluginReport(name=name, source="builtin", version=__version__),
                   partial(importlib.import_module, module), BUILTIN_KINDS.get(module))
             for name, module in BUILTIN_PLUGINS]
    if os.environ.get(ENV_DISABLE, "").strip() not in ("1", "true", "yes"):
        for ep in md.entry_points(group=hookspecs.PROJECT):
            dist = ep.dist.name if ep.dist is not None else ""
            version = ep.dist.version if ep.dist is not None else ""
            slots.append(_Slot(PluginReport(name=ep.name, source=dist or "entry point",
                                            version=version), ep.load, None))
    blocked = _blocked()
    for slot in slots:
        if slot.report.name in blocked:
            slot.report.status = "blocked"
    return slots


def _fail(state: _State, slot: _Slot, exc: Exception) -> None:
    """Record why a plugin is skipped; it contributes nothing (a broken plugin never breaks
    the host)."""
    report = slot.report
    report.status = "failed"
    report.error = f"{type(exc).__name__}: {exc}"
    report.warnings, report.api, report.contributions = [], hookspecs.UNVERSIONED, {}
    slot.found.clear()
    if slot.plugin is not None and state.pm.is_registered(slot.plugin):
        state.pm.unregister(slot.plugin)


def _load(state: _State, slot: _Slot) -> None:
    """Import one plugin and register it with pluggy (once)."""
    if slot.loaded:
        return
    slot.loaded = True
    if not slot.ok:
        return
    for earlier in state.slots[:state.slots.index(slot)]:
        if earlier.report.name == slot.report.name:  # pluggy refuses a name already taken
            _load(state, earlier)
    try:
        plugin = slot.loader()
        state.pm.register(plugin, name=slot.report.name)
    except Exception as exc:  # a broken plugin must never break the host
        _fail(state, slot, exc)
        return
    slot.plugin = plugin
    report = slot.report
    report.warnings = unknown_hooks(state.pm, plugin)
    report.api = _api_version(plugin, report.source)
    mismatch = api_mismatch(report.api)
    if mismatch is not None:
        report.warnings.append(mismatch)


def _call(state: _State, slot: _Slot, kinds: tuple[str, ...]) -> None:
    """Call the hooks of ``kinds`` not called yet; check the types and docs of their entries."""
    for hook_name, (kind, etype) in KINDS.items():
        if kind not in kinds or kind in slot.called or not slot.ok:
            continue
        slot.called.add(kind)
        impl = getattr(slot.plugin, hook_name, None)
        if impl is None:
            continue
        try:
            result = impl()
            if result is None:
                continue
            items = list(result)
            for item in items:
                if not isinstance(item, etype):
                    raise TypeError(f"{hook_name} returned {type(item).__name__}, "
                                    f"expected {etype.__name__}")
                if not item.name or not item.doc:
                    raise TypeError(f"{hook_name}: entry {item.name!r} lacks a name or a doc "
                                    "string")
        except Exception as exc:  # a broken plugin must never break the host
            _fail(state, slot, exc)
            return
        slot.found[kind] = items


def _gathered(state: _State, kind: str, upto: _Slot | None = None) -> dict[str, Entry]:
    """The checked entries of ``kind`` of the plugins before ``upto`` (all: ``None``)."""
    out: dict[str, Entry] = {}
    for slot in state.slots:
        if slot is upto:
            break
        if slot.ok and kind in slot.checked:
            for item in slot.found.get(kind, []):
                out[item.name] = item
    return out


def _check(state: _State, slot: _Slot, kind: str) -> None:
    """Refuse a plugin whose entry of ``kind`` has the name of an earlier plugin's entry."""
    if kind in slot.checked or not slot.ok:
        return
    slot.checked.add(kind)
    taken = _gathered(state, kind, upto=slot)
    for item in slot.found.get(kind, []):
        if item.name in taken:
            _fail(state, slot, TypeError(f"{kind} {item.name!r} is already provided by another "
                                         "plugin"))
            return


def _ensure(state: _State, kind: str) -> None:
    """Collect the entries of one kind, in registration order.

    A built-in whose declared kinds (:data:`BUILTIN_KINDS`) do not include ``kind`` is not
    even imported; a plugin of unknown kinds (third-party) is loaded and all its hooks are
    called, so that any of its hooks failing skips the whole plugin as before.
    """
    for slot in state.slots:
        if slot.kinds is not None and kind not in slot.kinds:
            continue
        _load(state, slot)
        _call(state, slot, _ALL_KINDS if slot.kinds is None else (kind,))
        _check(state, slot, kind)


def _complete(state: _State) -> None:
    """Load every plugin and call every hook (listings, reports, the pluggy manager)."""
    if state.complete:
        return
    for slot in state.slots:
        _load(state, slot)
        _call(state, slot, _ALL_KINDS)
        for kind in _ALL_KINDS:
            _check(state, slot, kind)
    for slot in state.slots:
        if slot.ok:  # only a plugin that registered cleanly contributes entries
            slot.report.contributions = {kind: [i.name for i in slot.found[kind]]
                                         for kind in _ALL_KINDS if kind in slot.found}
    state.complete = True


def _get() -> _State:
    global _state
    if _state is None:
        pm = pluggy.PluginManager(hookspecs.PROJECT)
        pm.add_hookspecs(hookspecs)
        _state = _State(pm=pm, slots=_slots())
    return _state


def plugins_token() -> object:
    """An object that stays the same until :func:`reset`: keys a cache by the plugins in use
    without loading any of them (:func:`plugin_manager` loads every one)."""
    with _lock:
        return _get().pm  # hashable by identity; not yet loaded with the plugins


def plugin_manager() -> pluggy.PluginManager:
    """The lazily built :class:`pluggy.PluginManager` with every plugin that loaded."""
    with _lock:
        state = _get()
        _complete(state)
        return state.pm


def plugin_reports() -> list[PluginReport]:
    """One report per plugin seen: built-in and external, loaded, failed or blocked."""
    with _lock:
        state = _get()
        _complete(state)
        return [slot.report for slot in state.slots]


def loaded_reports() -> list[PluginReport]:
    """One report per plugin, every plugin imported but no further hook called.

    What a run's provenance needs (name, source, version, status) without calling the hooks of
    kinds the run did not use (sweep outcomes, symbolic systems, fields...), which
    :func:`plugin_reports` calls to list every contribution. A plugin that fails to import is
    reported ``"failed"`` as there; one whose uncalled hook would raise is still ``"ok"``.
    The ``contributions`` of a report are filled only once :func:`plugin_reports` has run.
    """
    with _lock:
        state = _get()
        for slot in state.slots:
            _load(state, slot)
        return [slot.report for slot in state.slots]


def entries(kind: str) -> dict[str, Entry]:
    """All entries of one kind (``"potential"``, ``"assembly"``, ``"system"``, ``"integrator"``,
    ``"scene"``, ``"model_family"``, ``"outcome"``, ``"field"``), by name, in registration
    order. Only the plugins that may contribute this kind are loaded."""
    if kind not in _ALL_KINDS:
        from poissonkit.errors import UnknownNameError

        raise UnknownNameError("registry", kind, _ALL_KINDS)
    with _lock:
        state = _get()
        _ensure(state, kind)
        return _gathered(state, kind)


def providers(kind: str) -> dict[str, str]:
    """Which plugin contributed each entry of ``kind``: entry name → plugin name.

    Like :func:`entries`, it loads only the plugins that may contribute this kind (the scene
    listing names each scene's plugin without importing the others).
    """
    entries(kind)
    with _lock:
        state = _get()
        return {item.name: slot.report.name for slot in state.slots
                if slot.ok and kind in slot.checked for item in slot.found.get(kind, [])}


def reset() -> None:
    """Forget the manager so the next use rebuilds it (tests; after installing a plugin)."""
    global _state
    with _lock:
        _state = None

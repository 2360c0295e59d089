"""``parametrize_with_checks``: the kit's checks of a plugin as parametrised pytest tests.

A plugin's whole kit test::

    from poissonkit.testing import parametrize_with_checks

    @parametrize_with_checks("my_plugin")
    def test_kit(case):
        case()

Each contribution the plugin registers becomes one or more cases (one per check of a
potential); cases that integrate or compile whole systems carry the ``slow`` mark (register it
in your pytest configuration, or run them with ``-m slow``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from poissonkit.errors import InputError
from poissonkit.plugin.contributions import PairPotential

#: Kinds of contribution the kit checks, and the check of each (potentials: per check).
KINDS = ("potential", "model_family", "field", "integrator", "assembly", "scene", "outcome")
#: Kinds whose check integrates or compiles a whole system: marked slow.
SLOW_KINDS = frozenset({"model_family", "field", "integrator", "scene", "outcome"})


@dataclass(frozen=True)
class KitCase:
    """One check of one contribution; calling it runs the check (raises ``CheckFailed``).

    Attributes
    ----------
    kind, name
        The registry kind and the contribution's name.
    check
        For a potential, the name of one of its checks; else ``""`` (every check).
    slow
        Whether the case compiles or integrates a whole system.
    options
        Keyword arguments of the check function (example parameters, bodies, ...).
    """

    kind: str
    name: str
    check: str = ""
    slow: bool = False
    options: Mapping[str, Any] = field(default_factory=dict)

    @property
    def id(self) -> str:
        """The pytest id: ``kind-name[-check]``."""
        return "-".join(x for x in (self.kind, self.name, self.check) if x)

    def __call__(self) -> None:
        from poissonkit import testing

        run: Callable[..., None] = getattr(testing, f"check_{self.kind}")
        kw = dict(self.options)
        if self.check:
            kw["checks"] = (self.check,)
        run(self.name, **kw)

    def __repr__(self) -> str:
        return self.id


def _contributions(plugin: str) -> dict[str, list[str]]:
    from poissonkit.plugin import plugin_reports

    for report in plugin_reports():
        if report.name == plugin:
            if report.status != "ok":
                raise InputError(f"plugin {plugin!r} is {report.status}: {report.error}")
            return report.contributions
    names = ", ".join(r.name for r in plugin_reports())
    raise InputError(f"no plugin named {plugin!r}; plugins: {names}")


def plugin_checks(plugin: str, *, examples: Mapping[str, Mapping[str, Any]] | None = None,
                  skip: Iterable[str] = ()) -> list[KitCase]:
    """Every kit case of the contributions a registered plugin makes.

    Parameters
    ----------
    plugin
        The plugin's name (its entry-point name; ``poissonkit plugins`` lists them).
    examples
        Keyword arguments per contribution name for its check (``params``, ``bodies``,
        ``source``, ``distances``, ...), e.g. ``{"my_potential": {"params": {...}}}``; a key
        ``"kind:name"`` (``"field:cylinder"``) wins over the bare name when two kinds share it.
    skip
        Case ids (``"potential-x-kick"``) or contribution names to leave out (say why).

    Returns
    -------
    list of KitCase
    """
    from poissonkit.plugin import entries
    from poissonkit.testing.checks_potential import COMPILING, EXPENSIVE, POTENTIAL_CHECKS

    examples = examples or {}
    skipped = set(skip)
    cases = []
    for kind, names in sorted(_contributions(plugin).items()):
        if kind not in KINDS:
            continue  # systems: ``poissonkit verify`` checks them
        for name in names:
            opts = dict(examples.get(f"{kind}:{name}", examples.get(name, {})))
            if kind == "potential":
                # a potential without an expr has its own compiled kernel (quadratures, loops
                # of nodes): compiling it takes tens of seconds on a cold cache
                entry = entries("potential")[name]
                heavy = isinstance(entry, PairPotential) and entry.expr is None
                cases += [KitCase(kind, name, c, c in EXPENSIVE or (heavy and c in COMPILING),
                                  opts) for c in POTENTIAL_CHECKS]
            else:
                cases.append(KitCase(kind, name, "", kind in SLOW_KINDS, opts))
    return [c for c in cases if c.id not in skipped and c.name not in skipped]


def parametrize_with_checks(plugin: str, *, examples: Mapping[str, Mapping[str, Any]] | None = None,
                            skip: Iterable[str] = (), known: Mapping[str, str] | None = None
                            ) -> Any:
    """A ``pytest.mark.parametrize("case", ...)`` over :func:`plugin_checks` (slow cases
    marked ``slow``); the test calls ``case()``.

    Parameters
    ----------
    plugin, examples, skip
        As :func:`plugin_checks`.
    known
        ``{case id: reason}`` of known defects: those cases are expected to fail with
        ``CheckFailed`` (strict ``xfail``: once fixed, they fail until removed from here).
    """
    import pytest

    from poissonkit.testing.report import CheckFailed

    known = dict(known or {})
    cases = plugin_checks(plugin, examples=examples, skip=skip)
    params = []
    for c in cases:
        marks = [pytest.mark.slow] if c.slow else []
        if c.id in known:
            marks.append(pytest.mark.xfail(reason=known[c.id], raises=CheckFailed, strict=True))
        params.append(pytest.param(c, id=c.id, marks=marks))
    return pytest.mark.parametrize("case", params)

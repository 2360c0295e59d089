"""Integrator options, checked and listed the same way from Python, scenes and the command line.

Every integrator's registry entry declares its options (:meth:`IntegratorEntry.options
<poissonkit.plugin.IntegratorEntry.options>`: name, type, default, doc, allowed values).
:func:`check_options` validates a mapping against them (``solve(options=...)``, a scene's
``[run.options]``), :func:`parse_option_text` turns the text of ``--option NAME=VALUE`` into a
value of the declared type, and :func:`option_table` / :func:`describe_options` list them (for
``poissonkit plugins``, ``run --help`` and the numerics docs).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any

from poissonkit.errors import InputError, UnknownNameError

if TYPE_CHECKING:
    from poissonkit.plugin.contributions import IntegratorEntry, IntegratorOption

__all__ = ["UnknownOptionError", "check_options", "describe_option", "describe_options",
           "option_table", "options_markdown", "options_text", "parse_option_text",
           "parse_option_items"]

_TRUE = ("true", "yes", "on", "1")
_FALSE = ("false", "no", "off", "0")


class UnknownOptionError(UnknownNameError, InputError):
    """An option the integrator does not declare. Both an
    :class:`~poissonkit.errors.UnknownNameError` (as before) and an
    :class:`~poissonkit.errors.InputError` (bad input); the message lists the valid options."""

    def __init__(self, entry: IntegratorEntry, name: str, where: str = "") -> None:
        super().__init__(f"option of integrator {entry.name!r}", name,
                         (o.name for o in entry.options()))
        valid = describe_options(entry) or "  none"
        prefix = f"{where}: " if where else ""
        self.args = (f"{prefix}unknown option {name!r} of integrator {entry.name!r}; valid "
                     f"options:\n{valid}",)


def describe_option(option: IntegratorOption) -> str:
    """One line: ``name (type, default ...; one of ...): doc``."""
    facts = [option.type]
    if option.default is not None:
        facts.append(f"default {option.default!r}")
    if option.unit:
        facts.append(option.unit)
    if option.choices:
        facts.append("one of " + ", ".join(map(repr, option.choices)))
    return f"{option.name} ({'; '.join(facts)}): {option.doc}"


def describe_options(entry: IntegratorEntry, indent: str = "  ") -> str:
    """Every option of ``entry``, one :func:`describe_option` line each ('' if none)."""
    return "\n".join(indent + describe_option(o) for o in entry.options())


def option_table(entries: Iterable[IntegratorEntry] | None = None
                 ) -> list[tuple[str, IntegratorOption]]:
    """``(integrator name, option)`` for every option of every registered integrator (or of
    ``entries``), in registry order: the table ``poissonkit plugins`` and the docs print."""
    if entries is None:
        from poissonkit.plugin.registry import integrators

        entries = integrators().values()
    return [(e.name, o) for e in entries for o in e.options()]


def check_options(entry: IntegratorEntry, given: Mapping[str, Any], where: str = ""
                  ) -> dict[str, Any]:
    """``given`` validated against ``entry``'s declared options (types, choices), defaults
    filled in: the keyword arguments of its factory.

    Raises
    ------
    UnknownOptionError
        For a name the entry does not declare (an :class:`~poissonkit.errors.InputError`
        listing the valid options).
    InputError
        For a value of the wrong type or outside the declared choices.
    """
    known = {o.name for o in entry.options()}
    for name in given:
        if name not in known:
            raise UnknownOptionError(entry, str(name), where)
    try:
        return entry.resolve_params(dict(given))
    except InputError as exc:
        if not where:
            raise
        raise InputError(f"{where}: {exc}") from None


def parse_option_text(entry: IntegratorEntry, name: str, text: str, where: str = "--option"
                      ) -> Any:
    """The value of the text ``text`` for option ``name`` of ``entry``, in its declared type
    (``int``, ``float``, ``bool``: true/false/yes/no/on/off/1/0, ``str`` as written,
    ``vector``: comma-separated numbers). Range and choices are checked by
    :func:`check_options`."""
    options = {o.name: o for o in entry.options()}
    if name not in options:
        raise UnknownOptionError(entry, name, where)
    kind = options[name].type
    value = text.strip()
    try:
        if kind == "int":
            return int(value)
        if kind == "float":
            return float(value)
        if kind == "vector":
            return tuple(float(v) for v in value.split(","))
    except ValueError:
        raise InputError(f"{where} {name}={text}: {entry.name}'s option {name!r} is {kind}, "
                         f"got {text!r}") from None
    if kind == "bool":
        if value.lower() in _TRUE:
            return True
        if value.lower() in _FALSE:
            return False
        raise InputError(f"{where} {name}={text}: {entry.name}'s option {name!r} is bool "
                         "(true or false)")
    return value


def parse_option_items(entry: IntegratorEntry, items: Iterable[str], where: str = "--option"
                       ) -> dict[str, Any]:
    """``NAME=VALUE`` items (``--option``, repeatable) as typed option values of ``entry``."""
    out: dict[str, Any] = {}
    for item in items:
        name, sep, text = item.partition("=")
        if not sep or not name.strip():
            raise InputError(f"{where} takes NAME=VALUE, got {item!r}; options of "
                             f"{entry.name}:\n{describe_options(entry) or '  none'}")
        out[name.strip()] = parse_option_text(entry, name.strip(), text, where)
    return out


def _grouped(entries: Iterable[IntegratorEntry] | None
             ) -> dict[tuple[IntegratorOption, ...], list[str]]:
    """The integrators (default: every registered one) with options, grouped by their options
    (integrators declaring the same options share a group), in registry order."""
    if entries is None:
        from poissonkit.plugin.registry import integrators

        entries = integrators().values()
    groups: dict[tuple[IntegratorOption, ...], list[str]] = {}
    for entry in entries:
        if entry.options():
            groups.setdefault(entry.options(), []).append(entry.name)
    return groups


def options_text(entries: Iterable[IntegratorEntry] | None = None) -> str:
    """The options of every registered integrator (or of ``entries``) as text, integrators
    with the same options grouped: the list ``run --help`` and ``poissonkit plugins`` show."""
    groups = _grouped(entries)
    lines = ["integrator options (--option NAME=VALUE on the command line, [run.options] in a "
             "scene, solve(options=...) in Python):"]
    for options, names in groups.items():
        lines.append(f"  {', '.join(names)}:")
        lines.extend("    " + describe_option(o) for o in options)
    return "\n".join(lines)


#: The markers around the generated options table in ``docs/numerics.md``.
DOCS_MARKERS = ("<!-- integrator-options: generated by poissonkit.numerics.solve_options -->",
                "<!-- end of integrator-options -->")


def options_markdown(entries: Iterable[IntegratorEntry] | None = None) -> str:
    """The options of every registered integrator as a Markdown table (``docs/numerics.md``,
    between :data:`DOCS_MARKERS`; ``python -m poissonkit.numerics.solve_options`` prints it)."""
    groups = _grouped(entries)
    rows = ["| integrators | option | type | default | allowed values | meaning |",
            "|---|---|---|---|---|---|"]
    for options, names in groups.items():
        who = ", ".join(f"`{n}`" for n in names)
        for o in options:
            allowed = ", ".join(f"`{c!r}`" for c in o.choices) or "any"
            doc = o.doc.replace("|", "\\|")
            rows.append(f"| {who} | `{o.name}` | {o.type} | `{o.default!r}` | {allowed} | {doc} |")
            who = ""
    return "\n".join(rows)


if __name__ == "__main__":  # the table of docs/numerics.md: poissonkit's own integrators
    from poissonkit.numerics.hooks import poissonkit_integrators

    print(options_markdown(poissonkit_integrators()))

"""A scene's ``[run.options]`` table: the integrator's own options, checked against its
registry entry (:mod:`poissonkit.numerics.solve_options`).

.. code-block:: toml

    [run]
    method = "wisdom_holman"
    step = 8.64e5
    duration = 3.15576e9

    [run.options]
    table = "10_6_4"

Every error is a :class:`~poissonkit.errors.SceneError` whose message starts with
``run.options``; an unknown name lists the options the integrator takes.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from poissonkit.errors import InputError, SceneError

if TYPE_CHECKING:
    from poissonkit.numerics.runspec import RunSpec

__all__ = ["run_options", "with_cli_options"]


def run_options(raw: Any, method: str) -> Mapping[str, Any]:
    """The ``[run.options]`` table ``raw`` validated for integrator ``method`` (its typed
    values as given; defaults are left to the integrator). ``None``: no options."""
    if raw is None:
        return {}
    if not isinstance(raw, Mapping):
        raise SceneError(f"run.options: must be a table of the integrator's options "
                         f"(e.g. [run.options] table = \"10_6_4\"), got {type(raw).__name__}")
    from poissonkit.numerics.solve_options import check_options, describe_options
    from poissonkit.plugin import integrator

    entry = integrator(method)  # the method itself was checked before
    declared = {o.name: o for o in entry.options()}
    given = dict(raw)
    for name, value in given.items():
        option = declared.get(name)
        # TOML reads table = 10_6_4 as the integer 1064: say to quote it
        if option is not None and option.type == "str" and not isinstance(value, str):
            raise SceneError(f"run.options.{name}: {method}'s option {name!r} is text; quote "
                             f"it ({name} = \"...\"), got {value!r}")
    try:
        check_options(entry, given)
    except InputError as exc:
        raise SceneError(f"run.options: {exc}\noptions of {method}:\n"
                         f"{describe_options(entry) or '  none'}") from None
    return given


def with_cli_options(spec: RunSpec, items: Sequence[str] | None, scene_method: str | None = None
                     ) -> RunSpec:
    """``spec`` with the ``--option NAME=VALUE`` items added to its options (they win over the
    scene's ``[run.options]``), all checked against the integrator ``spec.method``.

    The scene's options belong to the scene's method: when ``--method`` chose another one
    (``scene_method`` differs from ``spec.method``) only the command line's options apply.
    Errors are :class:`~poissonkit.errors.InputError` listing the integrator's options.
    """
    from dataclasses import replace

    from poissonkit.numerics.solve_options import check_options, parse_option_items
    from poissonkit.plugin import integrator

    kept = dict(spec.options) if scene_method in (None, spec.method) else {}
    if not items and len(kept) == len(spec.options):
        return spec
    entry = integrator(spec.method)
    merged = {**kept, **parse_option_items(entry, items or ())}
    check_options(entry, merged, "--option")
    return replace(spec, options=merged)

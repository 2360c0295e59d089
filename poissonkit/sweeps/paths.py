"""Parameter paths of a scene file: normalising them and checking that they name a field.

A sweep sets one number per path (``bodies.right.r.0``, ``run.step``,
``interactions.params.screening_length``). :func:`check_path` refuses a path that names no field
of the scene schema or no parameter of the potential or assembly it addresses, so a misspelt path
stops a sweep before any run starts instead of failing at every point.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

from poissonkit.errors import SceneError


class SweepPathError(SceneError):
    """A swept parameter path that names no field of the scene.

    Parameters
    ----------
    path
        The path as given.
    reason
        What is wrong with it.
    available
        Names that would be valid at the failing segment (listed in the message).
    """

    def __init__(self, path: str, reason: str, available: Iterable[str] = ()) -> None:
        self.path = path
        self.available = sorted(set(available))
        msg = f"sweep parameter {path!r}: {reason}"
        if self.available:
            msg += "; available: " + ", ".join(self.available)
        super().__init__(msg)


def _is_index(seg: str) -> bool:
    return seg.lstrip("-").isdigit()


def normalise(path: str) -> list[str]:
    """Segments of ``path`` with the shorthand ``interactions.<k>.<param>`` (or
    ``interactions.<k>.params.<param>``) expanded to ``interactions.pair.<k>.params.<param>``."""
    from poissonkit.scene.schema import PAIR_KEYS

    segs = path.split(".")
    if len(segs) >= 3 and segs[0] == "interactions" and _is_index(segs[1]):
        rest = segs[3:] if len(segs) > 3 and segs[2] == "params" else segs[2:]
        if rest and rest[0] not in PAIR_KEYS:
            segs = ["interactions", "pair", segs[1], "params", *rest]
    return segs


def _entry_params(kind: str, name: object) -> list[str] | None:
    """Parameter names of registry entry ``name`` of ``kind`` (``None`` if it is not known:
    the scene's own validation reports that)."""
    from poissonkit.plugin.manager import entries

    if not isinstance(name, str):
        return None
    entry = entries(kind).get(name)
    return None if entry is None else [p.name for p in entry.params]


def _body_fields() -> list[str]:
    from poissonkit.scene.bodies import declared_attributes
    from poissonkit.scene.schema import BODY_KEYS

    return [k for k in BODY_KEYS if k not in ("name", "fixed")] + list(declared_attributes())


def _field(path: str, key: str, allowed: Sequence[str], where: str) -> None:
    if key not in allowed:
        raise SweepPathError(path, f"{where} has no field {key!r}", allowed)


def _pair_potential(data: Mapping[str, object], index: str) -> object:
    """The potential of ``[[interactions.pair]]`` entry ``index`` (its own, or the scene's)."""
    inter = data.get("interactions", {})
    if not isinstance(inter, Mapping):
        return None
    pairs = inter.get("pair", [])
    own = None
    if isinstance(pairs, list) and -len(pairs) <= int(index) < len(pairs):
        entry = pairs[int(index)]
        own = entry.get("potential") if isinstance(entry, Mapping) else None
    return own if own is not None else inter.get("potential")


def check_path(data: Mapping[str, object], path: str) -> list[str]:
    """Check that ``path`` names a numeric field of the parsed scene ``data``.

    Allowed: ``bodies.<name or index>.<field>[.<component>]`` (a body field, a body attribute a
    registered potential declares, or the ``spin`` shorthand), ``defaults.<field>``,
    ``run.<key>``, ``interactions.cutoff``, ``interactions.params.<p>``,
    ``interactions.pair.<k>.params.<p>`` (shorthand ``interactions.<k>.<p>``),
    ``assembly.params.<p>``, ``assembly.overrides.<field>``, ``planner.<key>``; ``<p>`` must
    be a parameter of the potential or assembly the scene names there.

    Returns
    -------
    list of str
        The normalised segments.

    Raises
    ------
    SweepPathError
        Naming the path, the segment that is wrong and what would be valid there.
    """
    from poissonkit.scene.schema import INTERACTION_KEYS, PLANNER_KEYS, RUN_KEYS, TOP_KEYS

    segs = normalise(path)
    names = [s for s in segs if not _is_index(s)]
    if not path or any(not s for s in segs):
        raise SweepPathError(path, "empty segment")
    top = segs[0]
    if top not in TOP_KEYS:  # name and description pass: setting them says "not a number"
        raise SweepPathError(path, f"the scene has no section {top!r}", TOP_KEYS)
    if top == "bodies":
        if len(segs) < 3:
            raise SweepPathError(path, "give bodies.<name>.<field> (e.g. bodies.<name>.mass)")
        _field(path, segs[2], [*_body_fields(), "spin"], "a body")
    elif top == "defaults":
        _field(path, names[1] if len(names) > 1 else "", _body_fields(), "[defaults]")
    elif top == "run":
        _field(path, names[1] if len(names) > 1 else "", RUN_KEYS, "[run]")
    elif top == "planner":
        _field(path, names[1] if len(names) > 1 else "", PLANNER_KEYS, "[planner]")
    elif top == "interactions":
        key = segs[1] if len(segs) > 1 else ""
        _field(path, key, [k for k in INTERACTION_KEYS if k not in ("potential", "pairs")],
               "[interactions]")
        if key == "params":
            inter = data.get("interactions", {})
            _check_param(path, segs[2:], "potential",
                         inter.get("potential") if isinstance(inter, Mapping) else None,
                         "interactions")
        elif key == "pair":
            if len(segs) < 5 or not _is_index(segs[2]) or segs[3] != "params":
                raise SweepPathError(path, "give interactions.pair.<k>.params.<parameter>")
            _check_param(path, segs[4:], "potential", _pair_potential(data, segs[2]),
                         f"interactions.pair.{segs[2]}")
    elif top == "assembly":
        key = segs[1] if len(segs) > 1 else ""
        _field(path, key, ["params", "overrides"], "[assembly]")
        if key == "params":
            assembly = data.get("assembly", {})
            _check_param(path, segs[2:], "assembly",
                         assembly.get("name") if isinstance(assembly, Mapping) else None,
                         "assembly")
        else:
            _field(path, names[2] if len(names) > 2 else "", _body_fields(),
                   "[assembly.overrides]")
    return segs


def _check_param(path: str, rest: Sequence[str], kind: str, entry: object, where: str) -> None:
    """``rest[0]`` is a parameter of registry entry ``entry`` (a ``kind``)."""
    if not rest:
        raise SweepPathError(path, f"give {where}.params.<parameter>")
    known = _entry_params(kind, entry)
    if entry is None:
        raise SweepPathError(path, f"{where} names no {kind}, so it has no parameters")
    if known is not None and rest[0] not in known:
        raise SweepPathError(path, f"{rest[0]!r} is not a parameter of the {kind} {entry!r}",
                             known)

"""What a run was made from, for ``summary.json``: versions, command line, options, the scene
itself (a copy of the file's text, or the registered scene's name and parameters) and units.

A summary carrying these keys is enough to run the same scene again
(``poissonkit run --from-summary OUT/summary.json``, :func:`rerun_options`).
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from poissonkit.errors import InputError
from poissonkit.numerics.units import Scales

if TYPE_CHECKING:
    from poissonkit.report.rerun_schema import OptionType

#: Options of ``poissonkit run`` that describe where and how the files are written, not the
#: run itself: a re-run takes them from its own command line.
OUTPUT_OPTIONS = frozenset({"out", "overwrite", "no_progress", "no_plots", "resume",
                            "checkpoint_every", "from_summary", "command", "func", "verbose",
                            "quiet"})

#: Version of the provenance keys' layout (``provenance_format`` in ``summary.json``).
FORMAT = 1

JSONValue = None | bool | int | float | str | list["JSONValue"] | dict[str, "JSONValue"]


def versions() -> dict[str, JSONValue]:
    """``{"poissonkit": version, "python": ..., "numpy": ..., "numba": ..., "plugins": [{name,
    source, version, status, error}, ...]}`` for every plugin poissonkit loaded
    (:func:`poissonkit.plugin.manager.loaded_reports`: the hooks a run did not use are not
    called for this); ``numba`` is ``None`` when it is missing."""
    import platform
    from importlib.metadata import PackageNotFoundError, version

    import numpy as np

    from poissonkit._version import __version__
    from poissonkit.plugin.manager import loaded_reports

    try:
        numba: str | None = version("numba")
    except PackageNotFoundError:
        numba = None
    plugins: list[JSONValue] = [
        {"name": r.name, "source": r.source, "version": r.version, "status": r.status,
         "error": r.error} for r in loaded_reports()]
    return {"poissonkit": __version__, "python": platform.python_version(),
            "numpy": np.__version__, "numba": numba, "plugins": plugins}


def options_of(args: argparse.Namespace) -> dict[str, JSONValue]:
    """Every resolved option of the command (``vars(args)``), JSON values only."""
    out: dict[str, JSONValue] = {}
    for key, value in sorted(vars(args).items()):
        if callable(value):  # argparse's dispatch function
            continue
        if isinstance(value, (list, tuple)) and all(isinstance(v, str) for v in value):
            out[key] = list(value)  # repeatable options (``--param``) stay lists
        else:
            out[key] = (value if isinstance(value, (bool, int, float, str, type(None)))
                        else str(value))
    return out


def scene_source(scene: str | Path | None) -> dict[str, JSONValue]:
    """Where the scene came from.

    Parameters
    ----------
    scene
        A scene file (``Path``), a registered scene's name, or ``None`` for the default scene.

    Returns
    -------
    dict
        For a file: ``kind="file"``, its absolute ``path``, ``text`` (a full copy), ``sha256``
        and the ``resolved`` scene (assembly, potential and their parameters as validated).
        For a registered scene: ``kind="registered"`` and its ``name`` (``None``: the default).
    """
    if not isinstance(scene, Path):
        return {"kind": "registered", "name": scene}
    text = scene.read_text(encoding="utf-8")
    out: dict[str, JSONValue] = {
        "kind": "file", "path": str(scene.resolve()), "name": scene.name, "text": text,
        "sha256": hashlib.sha256(text.encode("utf-8")).hexdigest()}
    from poissonkit.scene.loader import loads_scene

    resolved = loads_scene(text, source=str(scene))
    out["resolved"] = _jsonable(dataclasses.asdict(resolved)) \
        if dataclasses.is_dataclass(resolved) else None
    return out


#: SI unit of each kind of quantity.
SI_UNITS: Mapping[str, str] = {
    "length": "m", "mass": "kg", "time": "s", "momentum": "kg m s-1",
    "angular_momentum": "kg m2 s-1", "energy": "J", "alpha": "kg-1 m-2", "inertia": "kg m2",
    "force": "N", "torque": "N m", "velocity": "m s-1", "frequency": "s-1", "dimensionless": "1"}


def units(scales: Scales | None) -> dict[str, JSONValue]:
    """SI value of one internal unit of each kind (``{"length": 0.01, ...}``, SI units named
    in ``"si_units"``); all 1 for a system in SI units."""
    s = scales if scales is not None else Scales()
    return {"internal_unit_in_si": {k: float(s.unit(k)) for k in SI_UNITS},
            "si_units": dict(SI_UNITS),
            "system_in_si": scales is None}


def provenance(args: argparse.Namespace, scene: str | Path | None, scales: Scales | None,
               argv: Sequence[str] | None = None) -> dict[str, JSONValue]:
    """The provenance keys of ``summary.json``.

    Returns
    -------
    dict
        ``provenance_format``, ``versions``, ``command_line`` (``sys.argv``), ``options``,
        ``scene_source`` (:func:`scene_source`) and ``units`` (:func:`units`).
    """
    return {"provenance_format": FORMAT, "versions": versions(),
            "command_line": list(sys.argv if argv is None else argv),
            "options": options_of(args), "scene_source": scene_source(scene),
            "units": units(scales)}


def rerun_options(summary: Mapping[str, object], scene_dir: Path,
                  schema: Mapping[str, OptionType] | None = None) -> dict[str, object]:
    """Options that run the scene of ``summary`` again, as it ran.

    Parameters
    ----------
    summary
        A ``summary.json`` document written by ``poissonkit run``.
    scene_dir
        Folder where a scene file's copy is written (the copy is run, not the original path,
        so a moved or edited file does not change the re-run).
    schema
        The type of every option ``run`` has (:func:`poissonkit.report.rerun_schema.schema_of`
        of its parser); without it, only lists are checked.

    Returns
    -------
    dict
        The run options of the summary (output options left out, :data:`OUTPUT_OPTIONS`),
        with ``scene`` set to the copy or the registered name.

    Raises
    ------
    InputError
        If the summary has no provenance (written by an older poissonkit), an unknown option,
        a value of the wrong type, a scene copy whose checksum does not match or a scene name
        that is not a plain file name (:mod:`poissonkit.report.rerun_schema`).
    """
    from poissonkit.report.rerun_schema import check_options, check_scene_source

    options = summary.get("options")
    source = summary.get("scene_source")
    if not isinstance(options, dict) or not isinstance(source, dict):
        raise InputError("--from-summary: the summary has no 'options'/'scene_source' (written "
                         "by a poissonkit without provenance); run the scene again by hand")
    if schema is not None:
        options = check_options(options, schema)
    out = {k: v for k, v in options.items() if k not in OUTPUT_OPTIONS}
    for key, value in out.items():
        if isinstance(value, list) and not all(isinstance(v, str) for v in value):
            raise InputError(f"--from-summary: option {key!r} must be a list of strings, got "
                             f"{value!r}")
    scene = check_scene_source(source)
    if scene["kind"] == "file":
        copy = scene_dir / str(scene["name"])
        try:
            copy.write_text(str(scene["text"]), encoding="utf-8")
        except (OSError, UnicodeError) as exc:
            raise InputError(f"--from-summary: cannot write the scene's copy ({exc})") from None
        out["scene"] = str(copy)
    else:
        out["scene"] = scene["name"]
    return out


def _jsonable(value: object) -> JSONValue:
    if isinstance(value, Mapping):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, (bool, int, float, str, type(None))):
        return value
    return str(value)

"""Scenes a sweep can run: any TOML scene file, and registered scenes through their plugin.

A sweep scene is a small picklable description (sent to every worker) with three steps:

* :meth:`prepare` builds what every run shares -- the system and its compiled kernels --
  once per worker process (:mod:`poissonkit.sweeps.execute` caches it
  by :attr:`key`);
* :meth:`check` validates a parameter path on the client, before any work is sent;
* :meth:`run` integrates one point and classifies its fate, returning a :class:`RunRecord`
  that the outcome registry (:mod:`poissonkit.sweeps.outcomes`) reduces to numbers.

Fates: ``bounded`` (the run reached its end), ``collision`` (two bodies' shapes touched, or the
integration broke down at a close encounter), ``escape`` (a body went farther than ``escape``
times the initial size of the system from the centre of mass).
"""

from __future__ import annotations

import copy
import hashlib
import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from poissonkit.contracts import SweepScene
from poissonkit.errors import InputError, SceneError, UnknownNameError

if TYPE_CHECKING:
    from poissonkit.numerics.nbody import NBodySystem
    from poissonkit.numerics.solution import Solution
    from poissonkit.numerics.units import Scales
    from poissonkit.scene.bodies import BodyModel
    from poissonkit.scene.schema import Scene

#: Codes of the ``fate`` outcome (stored as integers; ``-1`` marks a point not computed).
FATES: tuple[str, ...] = ("bounded", "collision", "escape")


@dataclass
class RunRecord:
    """One finished run, as the outcome functions see it.

    Attributes
    ----------
    solution
        The :class:`~poissonkit.numerics.solution.Solution`, cut at the first collision.
    fate
        One of :data:`FATES`.
    fate_time
        Time of the collision / escape [s] (``nan`` if bounded).
    distance
        Smallest centre distance between two bodies at each saved state [m].
    time_unit
        SI value of the internal time unit [s].
    energy_unit, angular_momentum_unit
        SI values of the internal units [J], [kg m^2/s].
    megno_inputs
        ``(system, y0, t_end, method, step)`` for the chaos indicator's nearby run.
    """

    solution: Solution
    fate: str
    fate_time: float
    distance: np.ndarray
    time_unit: float
    energy_unit: float
    angular_momentum_unit: float
    megno_inputs: tuple[object, ...] = ()


def record_units(scales: Scales | None) -> tuple[float, float, float]:
    """SI values ``(time, energy, angular momentum)`` of the internal units of ``scales``
    (``1, 1, 1`` for a system integrated in SI numbers): the units a :class:`RunRecord`
    carries."""
    if scales is None:
        return 1.0, 1.0, 1.0
    return scales.time, scales.energy, scales.unit("angular_momentum")


def cut_solution(sol: Solution, k: int) -> Solution:
    """The solution up to (excluding) saved state ``k``: the part before a contact."""
    from dataclasses import replace

    return replace(sol, t=np.asarray(sol.t)[:k], y=np.asarray(sol.y)[:k])


# ------------------------------------------------------------------------------ TOML scenes

_SPIN = "spin"


def _descend(node: object, seg: str, where: str) -> int | str:
    """The key or index of segment ``seg`` in the TOML table or array ``node``."""
    if isinstance(node, list):
        if seg.lstrip("-").isdigit():
            k = int(seg)
            if not -len(node) <= k < len(node):
                raise SceneError(f"{where}: index {k} out of range (0..{len(node) - 1})")
            return k
        names = [e.get("name") for e in node if isinstance(e, Mapping)]
        if seg in names:
            return names.index(seg)
        raise UnknownNameError(f"entry of {where}", seg,
                               [str(n) for n in names if n is not None] or
                               [str(i) for i in range(len(node))])
    if isinstance(node, Mapping):
        return seg
    raise SceneError(f"{where}: is a value, cannot go into {seg!r}")


def set_path(data: dict[str, Any], path: str, value: float) -> None:
    """Set the number at ``path`` in a parsed scene mapping (in place).

    Segments are table keys, array indices or the ``name`` of an array entry
    (``bodies.right.r.0``). Shorthands: ``bodies.<name>.spin`` sets the angular momentum
    ``m = spin * nu/|nu|`` [kg m^2/s] (spin about the body's own axis) and
    ``interactions.<k>.<param>`` means ``interactions.pair.<k>.params.<param>``.
    Unknown keys are allowed only where the scene schema allows them; the scene is validated
    after all values are set (:func:`poissonkit.scene.scene_from_mapping`).
    """
    from poissonkit.sweeps.paths import normalise

    segs = normalise(path)
    node: Any = data
    where = ""
    for depth, seg in enumerate(segs[:-1]):
        key = _descend(node, seg, where or "scene")
        where = f"{where}.{seg}" if where else seg
        if isinstance(node, Mapping) and key not in node:
            # allow creating a missing table only where the next segment names a field
            node[key] = {}
        node = node[key]
        if (depth == 1 and segs[0] == "bodies" and segs[-1] == _SPIN and len(segs) == 3):
            nu = node.get("nu", data.get("defaults", {}).get("nu"))
            if nu is None:
                raise SceneError(f"{path}: body has no axis nu, so it has no spin")
            n = math.sqrt(sum(float(x) ** 2 for x in nu))
            if n == 0:
                raise SceneError(f"{path}: body axis nu is zero")
            node["m"] = [float(value) * float(x) / n for x in nu]
            return
    last = segs[-1]
    key = _descend(node, last, where or "scene")
    if isinstance(node, list):
        old = node[key]
    else:
        old = node.get(key, None)
    if isinstance(old, (list, dict)):
        raise SceneError(f"{path}: is a {'table' if isinstance(old, dict) else 'vector'}; "
                         "address one number (e.g. append .0 for x)")
    if isinstance(old, bool) or isinstance(old, str):
        raise SceneError(f"{path}: holds {old!r}, not a number")
    if isinstance(old, int) and not isinstance(old, bool) and float(value).is_integer():
        value = int(value)  # integer fields (counts) stay integers
    node[key] = value


#: SI units of the scene fields a sweep may vary (by the last key of the path).
FIELD_UNITS: Mapping[str, str] = {
    "mass": "kg", "alpha": "1/(kg m^2)", "inertia": "kg m^2", "r": "m", "p": "kg m/s",
    "nu": "1", "m": "kg m^2/s", "spin": "kg m^2/s", "moment": "A m^2", "magnetization": "A/m",
    "radius": "m", "length": "m", "half_length": "m", "step": "s", "duration": "s", "tol": "1",
    "cutoff": "m", "spacing": "m", "mu0": "T m/A",
}


def declared_attributes() -> dict[str, list[str]]:
    """Body attributes registered potentials declare (see
    :func:`poissonkit.scene.bodies.declared_attributes`)."""
    from poissonkit.scene.bodies import declared_attributes as declared

    return declared()


def attribute_unit(attr: str) -> str:
    """SI unit of a declared body attribute: the unit of the first potential parameter that
    reads it (``"1"`` if none says)."""
    from poissonkit.plugin.contributions import PairPotential
    from poissonkit.plugin.manager import entries

    for entry in entries("potential").values():
        if not isinstance(entry, PairPotential):
            continue
        for name, read, _which in entry.body_params:
            unit = next((p.unit for p in entry.params if p.name == name), "")
            if read == attr and unit:
                return unit
    return "1"


@dataclass(frozen=True)
class TomlScene:
    """A scene file (``docs/scenes.md``) whose numbers are addressed by path.

    Parameters
    ----------
    text
        The TOML text.
    source
        Where it came from (for messages and the dataset's attributes).
    escape
        Escape distance as a multiple of the initial size of the system (largest distance of a
        moving body from the moving bodies' centre of mass; at least the largest body size).
    """

    text: str
    source: str = ""
    escape: float = 10.0
    fixed: Mapping[str, float] = field(default_factory=dict)

    @classmethod
    def from_file(cls, path: str | Path, *, escape: float = 10.0,
                  fixed: Mapping[str, float] | None = None) -> TomlScene:
        """Read a scene file (errors as :func:`poissonkit.scene.load_scene`)."""
        from poissonkit.scene import load_scene

        load_scene(path)  # validates the file, typed errors naming the field
        return cls(Path(path).read_text(encoding="utf-8"), source=str(path), escape=escape,
                   fixed={} if fixed is None else fixed)

    def __post_init__(self) -> None:
        if not (math.isfinite(self.escape) and self.escape > 1):
            raise InputError(f"scene sweep: escape must be > 1, got {self.escape!r}")
        for path in self.fixed:  # a misspelt fixed path would otherwise fail every point
            self.check(path)

    @property
    def raw(self) -> dict[str, Any]:
        """The parsed TOML mapping."""
        try:
            return tomllib.loads(self.text)
        except tomllib.TOMLDecodeError as exc:
            raise SceneError(f"invalid TOML in {self.source or 'scene'}: {exc}") from None

    @property
    def name(self) -> str:
        """The scene's name."""
        return str(self.raw.get("name", "scene"))

    @property
    def key(self) -> str:
        """Identifies what :meth:`prepare` builds (the worker cache key)."""
        fixed = repr(sorted((str(k), float(v)) for k, v in self.fixed.items()))
        return "toml:" + hashlib.sha256((self.text + fixed).encode()).hexdigest()[:16]

    def settings(self) -> dict[str, object]:
        """Attributes recorded in the dataset."""
        run = self.raw.get("run", {})
        return {"scene": self.name, "scene_source": self.source, "scene_toml": self.text,
                "method": run.get("method", "splitting4"), "step": run.get("step", math.nan),
                "step_units": "s", "tol": run.get("tol", math.nan),
                "duration_s": run.get("duration", math.nan), "escape_factor": self.escape}

    def check(self, path: str) -> str:
        """Validate ``path`` by its place in the scene schema and by setting it in a copy.

        The path must name a numeric field of the schema, or a parameter of the potential or
        assembly the scene names (:func:`poissonkit.sweeps.paths.check_path`); a path the file
        leaves out is then accepted, and the scene itself is validated per point. Raises
        :class:`~poissonkit.sweeps.paths.SweepPathError`, :class:`SceneError` or
        :class:`UnknownNameError` naming the path.
        """
        from poissonkit.sweeps.paths import check_path

        data = self.raw
        check_path(data, path)
        node: Any = data
        present = True
        try:
            for seg in path.split("."):
                node = node[_descend(node, seg, "scene")]
        except (KeyError, IndexError, TypeError):
            present = False
        segs = [x for x in path.split(".") if not x.lstrip("-").isdigit()]
        if not present and not (segs[-1] in FIELD_UNITS or (len(segs) > 1 and segs[-2] ==
                                                              "params")
                                or segs[-1] in declared_attributes()):
            raise SceneError(f"{path}: not in scene {self.name!r} (give the path of a number, "
                             "e.g. bodies.<name>.mass, bodies.<name>.r.0, run.step)")
        set_path(copy.deepcopy(data), path, 1.0)
        return path

    def units(self, path: str) -> str:
        """SI units of the values of ``path`` (from its field name, or for a body attribute a
        potential declares, from that potential's parameter)."""
        segs = [s for s in path.split(".") if not s.lstrip("-").isdigit()]
        if not segs:
            return "1"
        return FIELD_UNITS.get(segs[-1]) or attribute_unit(segs[-1])

    def scene_with(self, values: Mapping[str, float]) -> Scene:
        """The validated :class:`~poissonkit.scene.Scene` with ``values`` set."""
        from poissonkit.scene import scene_from_mapping

        data = self.raw
        for k, v in {**self.fixed, **values}.items():
            set_path(data, k, float(v))
        return scene_from_mapping(data, source=self.source)

    def prepare(self) -> dict[str, object]:
        """Build the scene once: its internal units, and its kernels compiled by a short run.

        Every point is then built in these same units, so points that differ only in geometry,
        initial state, masses or run settings share the compiled kernels (kernels are keyed by
        the potential and its parameters in internal units, see
        :class:`~poissonkit.numerics.nbody.NBodySystem`); a swept potential parameter or magnet
        moment compiles once per distinct value.
        """
        from poissonkit.numerics.solver import solve
        from poissonkit.scene.build import build_run

        spec = build_run(self.scene_with({}))
        h = spec.step if spec.step is not None else spec.t_end / 1000
        solve(spec.system, spec.y0, 2 * h, method=spec.method, step=spec.step,
              tol=spec.tol, options=spec.options)  # compile now
        return {"scene": spec.name, "scales": spec.system.scales}

    def run(self, prep: Mapping[str, object], values: Mapping[str, float]) -> RunRecord:
        """Integrate one point and classify its fate (shape contact, escape)."""
        from poissonkit.numerics.events import Escape
        from poissonkit.numerics.solver import solve
        from poissonkit.scene.build import build_scene

        scene = self.scene_with(values)
        # the units of the first point, so every point shares its compiled kernels
        built = build_scene(scene, cast("Scales | None", prep["scales"]))  # from prepare()
        system, y0, t_end, step, models = (built.system, built.y0, built.t_end, built.step,
                                           built.bodies)
        L = system.scales.length if system.scales is not None else 1.0
        moving = [b for b in models if not b.fixed]
        r0 = np.array([b.r for b in moving], dtype=float).reshape(-1, 3) / L
        spread = [float(np.max(np.linalg.norm(r0 - r0.mean(axis=0), axis=1)))] if len(r0) \
            else []  # every body fixed: nothing moves, nothing escapes
        size = max(spread + [b.bounding_radius / L for b in models])
        events = (Escape(self.escape * size),) if len(moving) > 1 else ()
        fate, fate_t = "bounded", math.nan
        # an integration that breaks down raises: the point is recorded as failed, with the
        # message (typically a singular force at an unresolved encounter)
        sol = solve(system, y0, t_end, method=scene.run.method, step=step, tol=scene.run.tol,
                    events=events, options=scene.run.options)  # [run.options] of the scene
        if sol.events:
            fate, fate_t = sol.events[0].kind, float(sol.events[0].time)
        pos = _all_positions(system, models, np.asarray(sol.y))
        touch = _contact_index(models, pos)
        if touch is not None:
            fate, fate_t = "collision", float(sol.t[touch])
            keep = max(touch + 1 if np.all(np.isfinite(pos[touch])) else touch, 1)
            sol = cut_solution(sol, keep)
            pos = pos[:keep]
        r = pos[:, :, :3]
        d = np.linalg.norm(r[:, :, None, :] - r[:, None, :, :], axis=-1)
        iu = np.triu_indices(len(models), 1)
        dist = d[:, iu[0], iu[1]].min(axis=1) if iu[0].size else np.full(len(pos), np.nan)
        tu, eu, ju = record_units(system.scales)
        return RunRecord(sol, fate, fate_t * tu if math.isfinite(fate_t) else math.nan, dist,
                         tu, eu, ju, (system, y0, float(sol.t[-1]), scene.run.method, step))


def _all_positions(system: NBodySystem, models: list[BodyModel], y: np.ndarray) -> np.ndarray:
    """Positions [m] of every body (fixed ones included) and axes, per saved state:
    shape ``(n, bodies, 6)`` = ``(r, nu)``."""
    parts = system.unpack(y, si=True)
    n = y.shape[0]
    out = np.zeros((n, len(models), 6))
    mk = tk = 0
    for k, b in enumerate(models):
        if b.fixed:
            out[:, k, :3] = b.r
            if b.nu is not None:
                out[:, k, 3:] = np.asarray(b.nu) / np.linalg.norm(b.nu)
        else:
            out[:, k, :3] = parts["r"][:, mk]
            mk += 1
            if b.is_top:
                out[:, k, 3:] = parts["nu"][:, tk]
                tk += 1
    return out


def _contact_index(models: list[BodyModel], pos: np.ndarray) -> int | None:
    """First saved state where two bodies' shapes touch (cylinders, balls), or ``None``."""
    from poissonkit.scene.geometry import overlapping, shape_of

    bound = np.array([b.bounding_radius for b in models])
    if not np.any(bound > 0):
        return None
    finite = np.all(np.isfinite(pos.reshape(len(pos), -1)), axis=1)
    for i in range(len(models)):
        for j in range(i + 1, len(models)):
            if bound[i] == 0 and bound[j] == 0:
                continue
            gap = np.linalg.norm(pos[:, i, :3] - pos[:, j, :3], axis=1)
            near = np.nonzero(~finite | (gap <= bound[i] + bound[j]))[0]
            for s in near:  # exact shape test only where the bounding spheres meet
                if not finite[s]:
                    return int(s)
                a, b = models[i], models[j]
                sa = shape_of(pos[s, i, :3], pos[s, i, 3:] if a.is_top else None,
                              a.magnet.get("radius", 0.0), a.magnet.get("half_length", 0.0))
                sb = shape_of(pos[s, j, :3], pos[s, j, 3:] if b.is_top else None,
                              b.magnet.get("radius", 0.0), b.magnet.get("half_length", 0.0))
                if overlapping(sa, sb):
                    return int(s)
    return None


def sweep_scene(scene: SweepScene | str | Path, **kw: object) -> SweepScene:
    """A sweep scene from a registered scene name, a TOML path or a ready sweep scene.

    A registered scene (by name, e.g. ``"seed000"`` of the magnets
    plugin) is swept through its entry's ``sweep`` factory, which receives ``kw``; a file is
    wrapped in a :class:`TomlScene`. A :class:`~poissonkit.contracts.SweepScene` (a
    :class:`TomlScene` or a plugin's sweep scene) is returned as it is.

    Raises
    ------
    SceneError
        If the file does not exist or is invalid (naming the field), or the registered scene
        cannot be swept.
    UnknownNameError
        If ``scene`` is neither a file nor a registered scene name.
    """
    if isinstance(scene, SweepScene):
        return scene
    if isinstance(scene, Path) or (isinstance(scene, str)
                                   and (scene.endswith(".toml") or Path(scene).exists())):
        return TomlScene.from_file(scene, **{k: v for k, v in kw.items()
                                             if k in ("escape", "fixed")})
    if isinstance(scene, str):
        from poissonkit.plugin import registry

        entry = registry.scene(scene)
        if entry.sweep is None:
            raise SceneError(f"scene {scene!r} has no sweep support; sweep its TOML file instead")
        made = entry.sweep(**kw)
        if not isinstance(made, SweepScene):
            raise SceneError(f"scene {scene!r}: its sweep factory returned "
                             f"{type(made).__name__}, not a sweep scene (key, settings, check, "
                             "units, prepare, run)")
        return made
    raise InputError(f"scene must be a registered scene name, a scene file path or a sweep "
                     f"scene, got {scene!r}")

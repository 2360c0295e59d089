"""``check_potential``: a pair potential against the contract of
:class:`~poissonkit.plugin.PairPotential` (see ``docs/plugins.md``, "Testing a plugin").

Each check is a function ``check(setup, findings, options)``; :data:`POTENTIAL_CHECKS` lists
them in order and :data:`EXPENSIVE` those that compile an N-body system (seconds on a warm
cache, minutes on a cold one). Tolerances are relative to the size of the quantity compared
(the force, torque or energy scale of the configuration) and stated in each message.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from poissonkit.plugin.contributions import PairPotential
from poissonkit.testing.checks_kick import check_kick
from poissonkit.testing.checks_runtime import check_runtime_params
from poissonkit.testing.geometry import PairConfig, configurations, energy, loads, numerical_loads
from poissonkit.testing.lookup import findings_for
from poissonkit.testing.potential_setup import Options, Setup, setup
from poissonkit.testing.report import Findings


def _scale(u: float, force: np.ndarray, t1: np.ndarray, t2: np.ndarray, r: float) -> float:
    """The size mismatches are measured against: the largest load, or ``|U|/r``."""
    return max(float(np.linalg.norm(force)), float(np.linalg.norm(t1)) / r,
               float(np.linalg.norm(t2)) / r, abs(u) / r, 1e-300)


def check_declaration(s: Setup, out: Findings, opt: Options) -> None:
    """Units of every float parameter, a valid orientation, ``body_params`` that name declared
    parameters, an ``expr``, ``kernel`` or ``param_kernel``; advice without ``energy_scale``."""
    e = s.entry
    names = {p.name for p in e.params}
    for p in e.params:
        if p.type == "float" and not p.unit:
            out.add("declaration", f"float parameter {p.name!r} declares no unit (Param(..., "
                                   f"unit=...); SI, e.g. 'm', 'J', 'A m^2')")
    if e.orientation not in ("both", "first", "second", "none"):
        out.add("declaration", f"orientation {e.orientation!r} is not one of both, first, "
                               "second, none")
    for name, attr, which in e.body_params:
        if name not in names:
            out.add("declaration", f"body_params names {name!r} (from attribute {attr!r}), "
                                   f"which is not a parameter ({', '.join(sorted(names))})")
        if which not in (1, 2):
            out.add("declaration", f"body_params entry {name!r}: body must be 1 or 2, got "
                                   f"{which!r}")
    if e.body_params and e.expr is None:
        out.add("declaration", "body_params need an expr (a kernel-only potential cannot read "
                               "its parameters from the bodies)")
    if e.expr is None and e.kernel is None and e.param_kernel is None:
        out.add("declaration", "gives neither expr, kernel nor param_kernel")
    if e.energy_scale is None:
        out.advise("declares no energy_scale: automatic units use the largest |U| instead")


def check_gradient(s: Setup, out: Findings, opt: Options) -> None:
    """Force and torques (from the kernel's partials) are minus the gradients of its energy:
    central differences in the position of body 2 and rotations of both axes."""
    f = s.kernel()
    worst = (0.0, "")
    for cfg in configurations(opt.samples, s.distances, opt.seed):
        u, force, t1, t2 = loads(f, cfg)
        fd_f2, _, fd_t1, fd_t2 = numerical_loads(f, cfg)
        r = float(np.linalg.norm(cfg.r))
        scale = _scale(u, force, t1, t2, r)
        for what, a, b, per in (("force on body 2", force, fd_f2, 1.0),
                                ("torque on body 1", t1, fd_t1, r),
                                ("torque on body 2", t2, fd_t2, r)):
            err = float(np.linalg.norm(a - b)) / per / scale
            if not math.isfinite(err) or err > worst[0]:
                worst = (err if math.isfinite(err) else math.inf, f"{what} at {cfg.describe()}")
    if worst[0] > opt.rtol:
        out.add("gradient", f"{worst[1]} is not minus the gradient of U: off by "
                            f"{worst[0]:.3g} relative to the loads (tolerance {opt.rtol:g}, "
                            "central finite differences)")


def check_orientation(s: Setup, out: Findings, opt: Options) -> None:
    """The declared orientation: no partial in a cosine the potential says it ignores."""
    ignored = {"none": (1, 2, 3), "first": (2, 3), "second": (1, 3), "both": ()}.get(
        s.entry.orientation, ())
    if not ignored:
        return
    f = s.kernel()
    for cfg in configurations(opt.samples, s.distances, opt.seed + 1):
        vals = [float(v) for v in f(*cfg.invariants())]
        size = max(abs(vals[1]) * cfg.invariants()[0], abs(vals[0]), 1e-300)
        for k in ignored:
            if abs(vals[k + 1]) > opt.exact * size:
                out.add("orientation", f"declared orientation {s.entry.orientation!r} but "
                                       f"U_c{k} = {vals[k + 1]:.3g} at {cfg.describe()}")
                return


def check_pair_symmetry(s: Setup, out: Findings, opt: Options) -> None:
    """Exchanging the bodies (and their parameters) leaves U unchanged:
    ``U(r, c1, c2, c3; p1, p2) = U(r, −c2, −c1, c3; p2, p1)``; Newton's third law and the
    total angular momentum of the pair's loads."""
    f = s.kernel()
    g = s.kernel(s.swapped_params()) if s.swap else None
    worst, where = 0.0, ""
    third = (0.0, "")
    for cfg in configurations(opt.samples, s.distances, opt.seed + 2):
        u, force, t1, t2 = loads(f, cfg)
        r = float(np.linalg.norm(cfg.r))
        scale = _scale(u, force, t1, t2, r)
        _, fd_f1, _, _ = numerical_loads(f, cfg)
        # Newton's third law from the energy: the force on body 1 is minus the one on body 2
        err3 = float(np.linalg.norm(fd_f1 + force)) / scale
        # the loads carry no net angular momentum: T1 + T2 + r x F2 = 0
        errl = float(np.linalg.norm(t1 + t2 + np.cross(cfg.r, force))) / (r * scale)
        third = max(third, (max(err3, errl), cfg.describe()))
        if g is not None:
            mirror = PairConfig(-cfg.r, cfg.nu2, cfg.nu1)
            err = abs(energy(g, mirror) - u) / max(abs(u), scale * r)
            if err > worst:
                worst, where = err, cfg.describe()
    if worst > opt.exact:
        out.add("pair_symmetry", f"U changes when the two bodies (and their parameters "
                                 f"{', '.join(sorted(k for k in s.swap if k.endswith('1')))}"
                                 f" ↔ …2) are exchanged: by {worst:.3g} relative at {where} "
                                 f"(tolerance {opt.exact:g})")
    if third[0] > opt.rtol:
        out.add("third_law", f"the loads break Newton's third law or carry angular momentum: "
                             f"{third[0]:.3g} relative at {third[1]} (tolerance {opt.rtol:g})")


def check_body_params(s: Setup, out: Findings, opt: Options) -> None:
    """Every parameter of ``body_params`` is read by the kernel: a 10 % change of its value
    changes U or a partial at some configuration."""
    base = s.kernel()
    cfgs = list(configurations(3, s.distances, opt.seed + 3))
    for name, attr, which in s.entry.body_params:
        if name not in s.params:
            continue
        changed = dict(s.params, **{name: float(s.params[name]) * 1.1})
        try:
            g = s.kernel(changed)
        except Exception as exc:  # noqa: BLE001 - reported as the defect
            out.add("body_params", f"{name!r} (attribute {attr!r} of body {which}): changing "
                                   f"it fails: {type(exc).__name__}: {exc}")
            continue
        if all(np.allclose(base(*c.invariants()), g(*c.invariants()), rtol=1e-14, atol=0)
               for c in cfgs):
            out.add("body_params", f"body_params names {name!r} (attribute {attr!r} of body "
                                   f"{which}) but the kernel does not read it: U and its "
                                   "partials are unchanged when it changes by 10 %")


def check_pickle(s: Setup, out: Findings, opt: Options) -> None:
    """The entry travels to Dask workers: cloudpickle (what Dask uses) round-trips it and the
    copy gives the same energy."""
    import pickle

    try:
        import cloudpickle
        dumps = cloudpickle.dumps
    except ImportError:  # pragma: no cover - dask brings cloudpickle
        dumps = pickle.dumps
    try:
        copy = pickle.loads(dumps(s.entry))
    except Exception as exc:  # noqa: BLE001
        out.add("pickle", f"cannot be pickled for Dask workers: {type(exc).__name__}: {exc}")
        return
    if not isinstance(copy, PairPotential) or copy.name != s.entry.name:
        out.add("pickle", "the unpickled copy is not the same potential")


PotentialCheck = Callable[[Setup, Findings, Options], None]


#: Every potential check by name, in the order they run.
POTENTIAL_CHECKS: dict[str, PotentialCheck] = {
    "declaration": check_declaration,
    "gradient": check_gradient,
    "orientation": check_orientation,
    "pair_symmetry": check_pair_symmetry,
    "body_params": check_body_params,
    "runtime_params": check_runtime_params,
    "pickle": check_pickle,
    "kick": check_kick,
}
#: The checks that compile an N-body system.
EXPENSIVE = frozenset({"kick"})
#: The checks that compile the potential's own kernels.
COMPILING = frozenset({"gradient", "orientation", "pair_symmetry", "body_params",
                       "runtime_params"})


def check_potential(potential: PairPotential | str, *, params: Mapping[str, Any] | None = None,
                    distances: tuple[float, float] | None = None,
                    checks: Sequence[str] | None = None, options: Options | None = None
                    ) -> None:
    """Check a pair potential; raise :class:`CheckFailed` listing every defect.

    Parameters
    ----------
    potential
        The :class:`~poissonkit.plugin.PairPotential` or its registered name.
    params
        Example parameters (SI); missing required floats get 1.0 (first body) and 1.25
        (second body), the others their defaults.
    distances
        ``(min, max)`` centre distances sampled [m] (default: 3 to 6 times the largest
        length parameter, or 3 to 6 m).
    checks
        Names of :data:`POTENTIAL_CHECKS` to run (default: all).
    options
        :class:`Options` (samples, seed, tolerances).

    Raises
    ------
    CheckFailed
        Naming the potential, each failed check, what failed and by how much.
    """
    entry, out = findings_for(potential, "potential", PairPotential)
    opt = options or Options()
    try:
        s = setup(entry, params, distances)
    except Exception as exc:  # noqa: BLE001 - the parameters themselves are a finding
        out.add("setup", f"no example parameters: {type(exc).__name__}: {exc}")
        out.raise_if_any()
        return
    for name in checks or POTENTIAL_CHECKS:
        if name not in POTENTIAL_CHECKS:
            from poissonkit.errors import UnknownNameError

            raise UnknownNameError("potential check", name, POTENTIAL_CHECKS)
        with out.guard(name):
            POTENTIAL_CHECKS[name](s, out, opt)
    out.raise_if_any()

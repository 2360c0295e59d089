"""The kick of a pair potential inside the N-body numerics: three bodies interacting by it in
an :class:`~poissonkit.numerics.nbody.NBodySystem` (SI, no internal units). The forces sum to
zero, the loads carry no net angular momentum, the energy is that of the pair kernel summed
over the pairs and does not change under a common rotation and translation, and a body
without an attribute the potential reads from it gives the documented error."""

from __future__ import annotations

from typing import Any

import numpy as np

from poissonkit.errors import InputError
from poissonkit.testing.geometry import PairConfig, energy, rotation, unit
from poissonkit.testing.potential_setup import Options, Setup
from poissonkit.testing.report import Findings

#: the bodies' per-body values: FIRST, SECOND and a third
_VALUES = (1.0, 1.25, 1.1)


def _bodies(s: Setup, drop: str | None = None) -> tuple[list[Any], dict[str, Any]]:
    """Three bodies carrying the attributes ``body_params`` read (``drop`` left out of the
    third body) and the pair parameters that are not read from the bodies."""
    from poissonkit.numerics.nbody import Body

    attrs = {attr for _, attr, _ in s.entry.body_params}
    tops = s.entry.orientation != "none"
    bodies = []
    for k, v in enumerate(_VALUES):
        extra = {a: v for a in attrs if a not in ("mass", "alpha") and not (k == 2 and a == drop)}
        mass = v if "mass" in attrs else 1.0
        bodies.append(Body(f"b{k}", mass, alpha=1.0 if tops else None, attributes=extra))
    bound = {n for n, _, _ in s.entry.body_params}
    params = {k: v for k, v in s.params.items() if k not in bound}
    return bodies, params


def _system(s: Setup, drop: str | None = None) -> Any:
    from poissonkit.numerics.nbody import Interaction, NBodySystem

    bodies, params = _bodies(s, drop)
    pairs = [Interaction(i, j, s.entry, params) for i, j in ((0, 1), (0, 2), (1, 2))]
    return NBodySystem(bodies, pairs)


def _pair_params(s: Setup, i: int, j: int) -> dict[str, Any]:
    """The constant-kernel parameters of the pair (i, j) with the bodies' own values."""
    out = dict(s.params)
    for name, attr, which in s.entry.body_params:
        v = _VALUES[i if which == 1 else j]
        out[name] = v
    return out


def check_kick(s: Setup, out: Findings, opt: Options) -> None:
    """See the module doc string."""
    rng = np.random.default_rng(opt.seed + 5)
    lo, hi = s.distances
    pos = np.array([[0.0, 0.0, 0.0], [lo * 1.1, 0.0, 0.0], [0.5 * lo, 0.9 * lo, 0.2 * lo]])
    pos += rng.normal(scale=0.05 * lo, size=pos.shape)
    axes = np.array([unit(v) for v in rng.normal(size=(3, 3))])
    system = _system(s)
    tops = s.entry.orientation != "none"
    zeros = np.zeros((3, 3))

    def state(p: np.ndarray, a: np.ndarray) -> np.ndarray:
        return system.pack(p, zeros, axes=a if tops else None,
                           angular_momenta=zeros if tops else None)

    y = state(pos, axes)
    F, T, U = system.forces(y)
    F, T = np.array(F, float), np.array(T, float)
    size = max(float(np.abs(F).max()), float(np.abs(T).max()) / lo, abs(U) / lo, 1e-300)
    net_f = float(np.linalg.norm(F.sum(axis=0))) / size
    net_l = float(np.linalg.norm(np.cross(pos, F).sum(axis=0) + T.sum(axis=0))) / (hi * size)
    if max(net_f, net_l) > opt.exact * 100:
        out.add("kick", f"the kick changes the total linear momentum ({net_f:.3g}) or angular "
                        f"momentum ({net_l:.3g}) relative to the loads (tolerance "
                        f"{opt.exact * 100:g})")
    pair_sum = sum(energy(s.kernel(_pair_params(s, i, j)),
                          PairConfig(pos[j] - pos[i], axes[i], axes[j]))
                   for i, j in ((0, 1), (0, 2), (1, 2)))
    e0 = float(system.energy(y))
    if abs(e0 - pair_sum) > opt.exact * 100 * max(abs(pair_sum), size * lo):
        out.add("kick", f"the N-body energy {e0:.6g} J is not the sum of the pair energies "
                        f"{pair_sum:.6g} J (the bodies' attributes are not what the kernel reads)")
    R = rotation(np.array([0.3, -0.5, 0.8]), 0.7)
    shift = np.array([0.3, -0.2, 0.5]) * hi
    e1 = float(system.energy(state(pos @ R.T + shift, axes @ R.T)))
    if abs(e1 - e0) > opt.exact * 100 * max(abs(e0), size * lo):
        out.add("invariance", f"the energy changes under a common rotation and translation: "
                              f"{e0:.6g} → {e1:.6g} J")
    _check_missing_attribute(s, out)


def _check_missing_attribute(s: Setup, out: Findings) -> None:
    """A body without an attribute the potential reads: the documented InputError naming the
    body and the attribute."""
    for attr in sorted({a for _, a, _ in s.entry.body_params} - {"mass", "alpha"}):
        try:
            _system(s, drop=attr)
        except InputError as exc:
            if attr not in str(exc) or "b2" not in str(exc):
                out.add("body_params", f"a body without {attr!r} fails with a message that does "
                                       f"not name the body and the attribute: {exc}")
            continue
        except Exception as exc:  # noqa: BLE001
            out.add("body_params", f"a body without {attr!r} raises {type(exc).__name__}, "
                                   f"not InputError: {exc}")
            continue
        out.add("body_params", f"a body without {attr!r} is accepted silently")

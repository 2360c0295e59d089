"""Magnet parameters of a pair from what a user knows of each magnet.

``pair_interaction`` accepts, for every magnet potential, the per-body quantities ``moment``,
``magnetization``, ``radius`` and ``length`` (full height) whether or not the potential takes
them: moments and magnetisations are converted through the cylinder volume ``pi a² h`` where
the potential needs the other one, a dumbbell given ``length`` gets ``half_length = length/2``,
and sizes the potential does not take are dropped (they served the overlap check).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from poissonkit.errors import InputError

#: Per-body quantities every magnet potential accepts besides its own parameters.
MAGNET_QUANTITIES: tuple[str, ...] = ("moment", "magnetization", "radius", "length")


def complete_params(needed: tuple[str, ...], given: Mapping[str, Any]) -> dict[str, Any]:
    """The parameters of a potential taking ``needed`` from ``given`` (suffixed names).

    Derives ``moment<i>`` / ``magnetization<i>`` / ``half_length<i>`` where needed and not
    given, then drops the magnet quantities the potential does not take; any other name is
    left for the caller to report.
    """
    out = dict(given)
    for i in ("1", "2"):
        m, mu, a, h = (out.get("magnetization" + i), out.get("moment" + i),
                       out.get("radius" + i), out.get("length" + i))
        if a is not None and h is not None:
            try:
                volume = math.pi * float(a) ** 2 * float(h)
            except (TypeError, ValueError, OverflowError):
                raise InputError(f"radius{i} and length{i} must be finite numbers") from None
            try:
                if volume > 0:
                    if "moment" + i in needed and mu is None and m is not None:
                        out["moment" + i] = float(m) * volume
                    if "magnetization" + i in needed and m is None and mu is not None:
                        out["magnetization" + i] = float(mu) / volume
                if "half_length" + i in needed and out.get("half_length" + i) is None:
                    out["half_length" + i] = 0.5 * float(h)
            except (TypeError, ValueError, OverflowError):
                raise InputError(f"moment{i} / magnetization{i} must be finite numbers") from None
        elif "half_length" + i in needed and out.get("half_length" + i) is None and h is not None:
            try:
                out["half_length" + i] = 0.5 * float(h)
            except (TypeError, ValueError, OverflowError):
                raise InputError(f"length{i} must be a finite number, got {h!r}") from None
    extra = {q + i for q in MAGNET_QUANTITIES for i in ("1", "2")}
    return {k: v for k, v in out.items() if k in needed or k not in extra}

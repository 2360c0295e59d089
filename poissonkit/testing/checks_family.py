"""``check_model_family``: a model family against :class:`~poissonkit.plugin.ModelFamily`.

Truth is the family's own most exact model (its most expensive one, trusted to :data:`EXACT_TOL`): on random orientations at
distances where the cheapest model is in use, each cheaper model's force must differ from the
exact model's by no more than its declared error estimate times the force scale at that distance
(the largest exact force over the orientations sampled), times :data:`SLACK`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from poissonkit.plugin.contributions import ModelFamily
from poissonkit.testing.geometry import configurations
from poissonkit.testing.lookup import findings_for
from poissonkit.testing.report import Findings

#: Allowance over the estimate for round-off.
SLACK = 1.0 + 1e-9
#: Relative accuracy assumed of the most exact model itself (quadratures): a cheaper model's
#: error is compared with its estimate plus this.
EXACT_TOL = 1e-8


def _forces(model: str, cfgs: list[Any], b1: Mapping[str, Any], b2: Mapping[str, Any]
            ) -> np.ndarray:
    from poissonkit.pairs import pair_interaction

    per_body = {f"{k}1": v for k, v in b1.items()} | {f"{k}2": v for k, v in b2.items()}
    return np.array([pair_interaction(model, c.r.tolist(), c.nu1.tolist(), c.nu2.tolist(),
                                      **per_body).force for c in cfgs])


def _declaration(f: ModelFamily, out: Findings) -> None:
    from poissonkit.plugin import entries

    known = entries("potential")
    for m in f.models:
        if m not in known:
            out.add("declaration", f"model {m!r} is not a registered potential")
    if f.costs:
        if len(f.costs) != len(f.models):
            out.add("declaration", f"{len(f.costs)} costs for {len(f.models)} models")
        elif any(b < a for a, b in zip(f.costs, f.costs[1:])):
            out.add("cost_order", f"models are not ordered by cost, cheapest first: "
                                  f"{dict(zip(f.models, f.costs))}")
    for m in f.defaults:
        if m not in f.models:
            out.add("declaration", f"default model {m!r} is not one of the models")
    if len(f.models) < 2:
        out.add("declaration", "a family needs at least two models")


def _distances(f: ModelFamily, b1: Mapping[str, Any], b2: Mapping[str, Any], length: float,
               out: Findings) -> list[float]:
    """Distances where the cheapest model's estimate is between 1e-5 and 0.5 (it is in use),
    checking on the way that every estimate does not increase with ``r``."""
    grid = [length * 2 ** (k / 4) for k in range(80)]
    used = []
    for m in f.models:
        est = [float(f.estimate(m, r, b1, b2)) for r in grid]
        for (r0, e0), (r1, e1) in zip(zip(grid, est), zip(grid[1:], est[1:])):
            if e1 > e0 * (1 + 1e-12) and math.isfinite(e1):
                out.add("estimate", f"the estimate of {m!r} increases with r: {e0:.3g} at "
                                    f"{r0:.4g} m, {e1:.3g} at {r1:.4g} m")
                break
        if m == f.models[0]:
            used = [r for r, e in zip(grid, est) if 1e-5 <= e <= 0.5]
    return used[:: max(1, len(used) // 4)][:4]


def check_model_family(family: ModelFamily | str, *,
                       bodies: tuple[Mapping[str, Any], Mapping[str, Any]] | None = None,
                       samples: int = 6, seed: int = 0) -> None:
    """Check a model family; raise :class:`CheckFailed` listing every defect.

    Parameters
    ----------
    family
        The :class:`~poissonkit.plugin.ModelFamily` or its registered name (its models must be
        registered potentials).
    bodies
        The two bodies' attributes (those ``reads`` names, SI); default 1.0 for each.
    samples
        Random orientations per distance.
    seed
        Seed of the orientations.

    Raises
    ------
    CheckFailed
        Naming the family and, per model, the distance and how far the true error exceeds the
        estimate.
    """
    f, out = findings_for(family, "model_family", ModelFamily, "model family")
    with out.guard("declaration"):
        _declaration(f, out)
    b1, b2 = bodies if bodies is not None else ({q: 1.0 for q in f.reads},) * 2
    if not f.applies(b1, b2):
        out.add("applies", f"does not apply to the example bodies {dict(b1)}, {dict(b2)}: "
                           "pass bodies= that it models")
        out.raise_if_any()
    length = min((float(v) for v in (*b1.values(), *b2.values())
                  if isinstance(v, (int, float)) and v > 0), default=1.0)
    with out.guard("estimate"):
        exact = max(f.models, key=f.cost)
        for r in _distances(f, b1, b2, length, out):
            cfgs = list(configurations(samples, (r, r), seed))
            truth = _forces(exact, cfgs, b1, b2)
            scale = float(np.max(np.linalg.norm(truth, axis=1)))
            for m in f.models:
                if m == exact:
                    continue
                est = float(f.estimate(m, r, b1, b2))
                if not math.isfinite(est):
                    continue
                err = float(np.max(np.linalg.norm(_forces(m, cfgs, b1, b2) - truth,
                                                  axis=1))) / scale
                if err > est * SLACK + EXACT_TOL:
                    out.add("estimate", f"{m!r} at r = {r:.4g} m: true force error {err:.3g} "
                                        f"(relative to the largest force) exceeds its estimate "
                                        f"{est:.3g} (exact model {exact!r})")
            if f.energy_bound is not None:
                from poissonkit.pairs import pair_interaction

                bound = float(f.energy_bound(r, b1, b2))
                per_body = {f"{k}1": v for k, v in b1.items()} | {
                    f"{k}2": v for k, v in b2.items()}
                worst = max(abs(pair_interaction(exact, c.r.tolist(), c.nu1.tolist(), c.nu2.tolist(),
                                                 **per_body).energy) for c in cfgs)
                if worst > bound * SLACK:
                    out.add("energy_bound", f"|U| = {worst:.3g} J at r = {r:.4g} m exceeds the "
                                            f"declared bound {bound:.3g} J")
    out.raise_if_any()

"""Chaos indicator of a run: MEGNO from two nearby runs (a shadow orbit, renormalised).

MEGNO (Cincotta & Simó 2000) is ``Y(t) = (2/t) ∫_0^t s (δ'·δ)/|δ|² ds`` for a tangent vector
``δ``, and its running mean ``<Y>(t) = (1/t) ∫_0^t Y(s) ds``. For quasi-periodic (regular) motion
``|δ|`` grows linearly and ``<Y> → 2``; for chaotic motion ``<Y> ≈ λ t / 2`` grows without bound
(λ the largest Lyapunov exponent); for stable periodic orbits ``<Y> → 0``.

Here ``δ`` is the difference between the run and a *shadow* run started ``δ₀`` away (relative,
in the internal, nondimensional state), integrated by the same method with the same fixed step
so their saved times coincide. ``(δ'·δ)/|δ|² = d ln|δ|/dt``, so with saved states
``Y(t_n) = (2/t_n) Σ s̄_i (ln|δ_i| − ln|δ_{i−1}|)``. The shadow is pulled back to distance ``δ₀``
after every chunk (Benettin renormalisation), keeping ``δ`` in the linear regime. This needs no
variational equations, so it works for every system and integrator with a fixed step.

A run with a single saved state (cut at its first sample, e.g. a collision at ``t = 0``) has no
separation history: ``<Y>`` is undefined there and :func:`megno` returns NaN (documented in
``docs/sweeps.md``). Each chunk starts where the previous one ended (its last saved time), so
the chunk's span ``n h`` can fall short of ``n`` steps by round-off; the solver takes a step
longer than the span by round-off as the whole span
(:data:`~poissonkit.numerics.solver.STEP_SPAN_RTOL`).
"""

from __future__ import annotations

import math
import re
import numpy as np

from poissonkit.contracts import HasLayout, System
from poissonkit.errors import InputError
from poissonkit.traits import offers


def _axis_slices(system: System, dim: int) -> list[slice]:
    """Where the unit axes ``nu`` of tops sit in the state (from the system's layout)."""
    layout = list(system.layout) if offers(system, HasLayout) else []
    if len(layout) != dim:
        return []
    return [slice(k, k + 3) for k, name in enumerate(layout)
            if re.search(r"(^|[._])nu\d*_x$", name)]


def _on_leaf(y: np.ndarray, axes: list[slice]) -> np.ndarray:
    """``y`` with every top's axis scaled back to unit length (the shadow stays on the
    symplectic leaf ``|nu| = 1`` that structure-preserving integrators require)."""
    for s in axes:
        y[s] /= np.linalg.norm(y[s])
    return y


def megno(system: System, y0: np.ndarray, t_end: float, method: str = "splitting6",
          step: float | None = None, *, delta0: float = 1e-8, chunks: int = 50,
          seed: int = 12345) -> float:
    """Mean MEGNO ``<Y>(t_end)`` of the orbit of ``y0`` (two nearby runs).

    Parameters
    ----------
    system, y0, t_end, method, step
        As :func:`poissonkit.numerics.solve`; ``step`` is required (saved times of the two runs
        must coincide).
    delta0
        Initial and renormalised separation, relative to ``max(1, |y0|)``.
    chunks
        Renormalisations over the run (the separation grows at most ``e^{λ t_end/chunks}``
        between them).
    seed
        Seed of the random direction of the initial separation.

    Returns
    -------
    float
        ``<Y>`` at ``t_end``: about 2 for regular motion, growing with time for chaotic motion;
        NaN when nothing past the first state could be compared (a run cut at its first
        sample, or a separation that is not finite or vanishes at once).

    Raises
    ------
    InputError
        Without a fixed ``step`` or with a non-positive duration.
    """
    from poissonkit.numerics.solver import solve

    if step is None or not step > 0:
        raise InputError("megno needs a fixed step (two runs on the same time grid)")
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"megno: duration must be > 0, got {t_end!r}")
    y = np.array(y0, dtype=float)
    scale = max(1.0, float(np.linalg.norm(y)))
    d0 = float(delta0) * scale
    direction = np.random.default_rng(seed).standard_normal(y.size)
    axes = _axis_slices(system, y.size)
    shadow = _on_leaf(y + d0 * direction / np.linalg.norm(direction), axes)
    n_steps = max(1, int(round(t_end / step)))
    per = max(1, math.ceil(n_steps / max(1, int(chunks))))
    t = 0.0
    log_prev = math.log(d0)
    offset = 0.0  # accumulated log growth removed by renormalisations
    ysum = 0.0  # ∫ s dln|δ|
    ybar_sum = 0.0  # ∫ Y ds
    done = 0
    while done < n_steps:
        n = min(per, n_steps - done)
        t1 = t + n * step
        h = step
        a = solve(system, y, t1, method=method, step=h, t0=t)
        b = solve(system, shadow, t1, method=method, step=h, t0=t)
        m = min(len(a.t), len(b.t))
        ta = np.asarray(a.t)[:m]
        diff = np.linalg.norm(np.asarray(a.y)[:m] - np.asarray(b.y)[:m], axis=1)
        if not np.all(np.isfinite(diff)) or np.any(diff == 0):
            break
        logs = np.log(diff) + offset
        prev_t = t
        for ti, li in zip(ta[1:], logs[1:]):
            ysum += 0.5 * (prev_t + ti) * (li - log_prev)
            y_now = 2.0 * ysum / ti
            ybar_sum += y_now * (ti - prev_t)
            prev_t, log_prev = ti, li
        y = np.asarray(a.y)[m - 1].copy()
        sep = np.asarray(b.y)[m - 1] - y
        norm = float(np.linalg.norm(sep))
        shadow = _on_leaf(y + sep * (d0 / norm), axes)
        offset += math.log(norm / d0)
        t = float(ta[-1])
        done += n
        if m < min(len(a.t), len(b.t)) or t < t1 - 0.5 * step:
            break  # a run stopped early (event)
    return ybar_sum / t if t > 0 else math.nan

"""Whether a Wisdom–Holman run stayed in the method's regime, read from its saved states.

The splitting ``H = H_K + H_I`` is accurate while the interaction part ``H_I`` is small against
the Kepler part and the step resolves the fastest Kepler motion. It leaves that regime without
any error being raised -- the energy error grows while the run still looks "bounded" -- in two
ways, both tested here:

* **step above the pericentre time scale.** At a pericentre passage the kick between exact Kepler
  drifts acts on a motion swept faster than the step resolves (the error term grows as
  ``(h ω_p)²``). Flagged when ``h ω_p`` exceeds :data:`PERICENTRE_STEPS` (fewer than ``2π``
  steps per orbit of the pericentre's angular velocity). Passages are found in the saved states
  (the radial velocity ``x'·u'`` of a Jacobi body changing from negative to non-negative
  between two saved states, so a passage between saves is seen too) and measured on the
  osculating Kepler orbit of the state before them (``μ = G η_i``, pericentre
  ``q = L²/(μ (1 + e))``, angular velocity there ``ω_p = L/q²``).
* **close approach to the central body.** Body ``i ≥ 2`` moves in ``H_K`` about the barycentre
  ``R_{i−1}`` of the bodies inside it; the central body sits ``δ = |R_{i−1} − r_0|`` from that
  point, and ``H_I`` holds the difference between its true pull and the pull from ``R_{i−1}``,
  an expansion in ``δ/d`` (``d`` the body's distance). Flagged when ``δ/d`` exceeds
  :data:`CLOSE_RATIO` at a saved state or at the osculating pericentre of a passage: the body
  came close to the central body against the scale of the inner orbits, ``H_I`` is no longer
  small. (For the innermost body ``δ = 0``: its pull from the central body is in ``H_K``
  exactly, at any distance; only the step test applies.)

With two bodies and gravity alone ``H_I = 0``: the method is exact and nothing is tested.

The check reads saved states after the run: it never touches the compiled loop, so every
trajectory is bit-identical with and without it. Runs that save few states (a large
``save_every`` with several orbits between saves, a streamed run) are checked on what was kept.
"""

from __future__ import annotations

import numpy as np

#: Flag a pericentre passage whose step ``h`` exceeds ``PERICENTRE_STEPS / ω_p``.
PERICENTRE_STEPS = 1.0
#: Flag a body whose distance ``d`` falls below ``δ / CLOSE_RATIO`` (``δ`` the central body's
#: offset from the barycentre of the inner bodies).
CLOSE_RATIO = 0.1
#: Saved states handled at once (bounds the memory of the check).
_BLOCK = 4096


def _jacobi_rows(y: np.ndarray, m: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Jacobi positions and velocities (bodies ``1 … n−1``) of saved states ``y (rows, 6n)``
    (layout ``r_i, p_i`` per body): ``x'_i = r_i − R_{i−1}``, ``u'_i = v_i − V_{i−1}``; and the
    central body's offset ``|R_{i−1} − r_0|`` from each inner barycentre."""
    n = m.shape[0]
    s = y.reshape(len(y), n, 2, 3)
    r = s[:, :, 0]
    v = s[:, :, 1] / m[None, :, None]
    eta = np.cumsum(m)
    com_r = np.cumsum(m[None, :, None] * r, axis=1) / eta[None, :, None]
    com_v = np.cumsum(m[None, :, None] * v, axis=1) / eta[None, :, None]
    offset = np.linalg.norm(com_r[:, :-1] - r[:, :1], axis=-1)
    return r[:, 1:] - com_r[:, :-1], v[:, 1:] - com_v[:, :-1], offset


def _orbit(x: np.ndarray, u: np.ndarray, mu: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Osculating pericentre ``q`` and angular velocity there ``ω_p`` of Jacobi rows."""
    L = np.linalg.norm(np.cross(x, u), axis=-1)
    energy = 0.5 * np.einsum("...k,...k", u, u) - mu / np.linalg.norm(x, axis=-1)
    e = np.sqrt(np.maximum(0.0, 1.0 + 2.0 * energy * L * L / (mu * mu)))
    q = L * L / (mu * (1.0 + e))
    with np.errstate(divide="ignore", invalid="ignore"):
        omega = np.where(q > 0, L / (q * q), np.inf)  # a radial orbit: no time scale
    return q, omega


def _worst(y: np.ndarray, m: np.ndarray, mu: np.ndarray, h: float
           ) -> tuple[np.ndarray, np.ndarray]:
    """Per Jacobi body: the largest ``h ω_p`` at a pericentre passage and the largest
    ``δ/d`` (at saved states and passages' pericentres)."""
    worst_step = np.zeros(mu.shape)
    worst_close = np.zeros(mu.shape)
    for a in range(0, len(y) - 1, _BLOCK):
        x, u, offset = _jacobi_rows(y[a:a + _BLOCK + 1], m)
        with np.errstate(divide="ignore", invalid="ignore"):
            close = offset / np.linalg.norm(x, axis=-1)
        worst_close = np.maximum(worst_close, np.nan_to_num(close, nan=0.0).max(axis=0))
        radial = np.einsum("rik,rik->ri", x, u)
        passage = (radial[:-1] < 0) & (radial[1:] >= 0)  # (rows-1, bodies)
        if not passage.any():
            continue
        q, omega = _orbit(x[:-1], u[:-1], mu[None, :])
        worst_step = np.maximum(worst_step, np.where(passage, h * omega, 0.0).max(axis=0))
        with np.errstate(divide="ignore", invalid="ignore"):
            at_q = np.where(passage & (q > 0), offset[:-1] / q, 0.0)
        worst_close = np.maximum(worst_close, at_q.max(axis=0))
    return worst_step, worst_close


def regime_problems(y: np.ndarray, m: np.ndarray, G: float, h: float,
                    names: tuple[str, ...] = (), *, exact: bool = False) -> list[str]:
    """What took a Wisdom–Holman run out of its regime ([] if nothing).

    Parameters
    ----------
    y
        Saved states, shape ``(rows, 6 n)`` (positions and momenta of point masses).
    m, G
        Masses and the gravitational constant (internal units); body 0 is the central mass.
    h
        The step taken.
    names
        Body names for the messages (default ``body i``).
    exact
        The split is exact (two bodies, gravity alone): nothing to report.
    """
    y = np.asarray(y, dtype=float)
    if exact or y.ndim != 2 or len(y) < 2 or m.shape[0] < 2 or not np.all(np.isfinite(y)):
        return []  # nothing to compare, or a run that already failed loudly
    mu = G * np.cumsum(m)[1:]
    worst_step, worst_close = _worst(y, m, mu, h)
    out = []
    for i in range(mu.shape[0]):
        who = names[i + 1] if len(names) == m.shape[0] else f"body {i + 1}"
        if worst_step[i] > PERICENTRE_STEPS:
            out.append(f"step above the pericentre time scale: {who} passed pericentre with "
                       f"step × angular velocity there = {worst_step[i]:.3g} rad "
                       f"(> {PERICENTRE_STEPS:g})")
        if worst_close[i] > CLOSE_RATIO:
            out.append(f"close approach to the central body: {who} came within "
                       f"{1 / worst_close[i]:.3g} times the central body's offset from the "
                       f"inner bodies' barycentre (< {1 / CLOSE_RATIO:g})")
    return out

"""Seed 000 as runs: the built-in scene of ``poissonkit run`` and its printed table."""

from __future__ import annotations

import math

import mpmath

from poissonkit.errors import InputError
from poissonkit_magnets.seed000.orbit import circular_orbit, initial_state, metadata, scales
from poissonkit_magnets.seed000.table import parameter_table
from poissonkit_magnets.seed000.two_body import two_body_system


def default_run(*, periods: float = 20.0, method: str = "splitting6", step: float | None = None,
                tol: float | None = None, spin_ratio: float = 20.0, tilt: float = 0.0,
                radius_factor: float = 1.0, momentum_factor: float = 1.0):
    """The built-in scene of ``poissonkit run``: the seed orbit as a :class:`RunSpec`.

    The system is the seed's own 18-variable centre-of-mass form
    (:class:`~poissonkit.numerics.twobody.TwoBodySystem`, reduced mass, state
    ``(r, p, ν', m', ν'', m'')``): it is what the seed integrates, its plots are in the relative
    coordinate ``r`` anyway, and it is the smallest state (18 instead of 24 numbers, one pair)
    for the speed comparisons. :func:`nbody_system` gives the same scene as a general N-body
    system (two tops) and :func:`nbody_state` converts states; a test checks they agree.

    Parameters
    ----------
    periods
        Duration in orbital periods (internal time ``2 pi periods``).
    method, step, tol
        Integrator registry name; fixed step (internal time) or tolerance. Without either, a
        fixed-step method uses ``T_orb/200`` and an adaptive one its own default tolerance.
    spin_ratio, tilt, radius_factor, momentum_factor
        See :func:`initial_state`.
    """
    from poissonkit.numerics.runspec import RunSpec

    if not (math.isfinite(periods) and periods > 0):
        raise InputError(f"seed000: periods must be > 0, got {periods!r}")
    t = parameter_table()
    o = circular_orbit(table=t)
    system = two_body_system(t, o)
    y0 = initial_state(spin_ratio=spin_ratio, tilt=tilt, radius_factor=radius_factor,
                       momentum_factor=momentum_factor, orbit=o, table=t)
    if step is None and tol is None:
        from poissonkit.numerics.workprecision import method_kind

        if method_kind(method) == "step":  # adaptive methods use their own default tolerance
            step = 2 * math.pi / 200
    meta = metadata(t, o, periods=periods, spin_ratio=spin_ratio, tilt=tilt,
                    radius_factor=radius_factor, momentum_factor=momentum_factor,
                    system="TwoBodySystem (seed eq. 20, 18 variables, reduced mass)")
    return RunSpec(name="seed000", system=system, y0=y0, t_end=2 * math.pi * periods,
                   method=method, step=step, tol=tol, metadata=meta)


def scene_run(*, periods: float = 20.0, duration: float | None = None,
              method: str = "splitting6", step: float | None = None, tol: float | None = None,
              tilt: float = 0.0, spin_ratio: float = 20.0):
    """The registered ``seed000`` scene: :func:`default_run` with run options in SI.

    This is what ``poissonkit run`` (no argument, or ``poissonkit run seed000``) calls through
    the scene registry.

    Parameters
    ----------
    periods
        Duration in orbital periods (ignored if ``duration`` is given).
    duration
        Duration [s]; converted with the orbital period ``T_orb``.
    method, tol
        Integrator registry name and tolerance of adaptive methods.
    step
        Fixed step [s]; converted to the internal time unit ``1/omega_orb``. Default ``T_orb/200``
        for fixed-step methods.
    tilt, spin_ratio
        See :func:`initial_state`.

    Returns
    -------
    RunSpec
        The seed orbit, ready for :func:`poissonkit.solve`.
    """
    if duration is not None:
        periods = duration / float(circular_orbit().period)
    if step is not None:  # seconds -> internal time (unit 1/omega_orb)
        step = step / float(scales().time)
    return default_run(periods=periods, method=method, step=step, tol=tol, tilt=tilt,
                       spin_ratio=spin_ratio)


def main() -> None:  # pragma: no cover - convenience
    """Print the seed's table and orbit."""
    t = parameter_table()
    for line in t.lines():
        print(line)
    o = circular_orbit(table=t)
    print(f"R_orb = {mpmath.nstr(o.radius, 20)} m  ({o.configuration}, axes normal to the orbit)")
    print(f"P_orb = {mpmath.nstr(o.momentum, 20)} N*s")
    print(f"T_orb = {mpmath.nstr(o.period, 20)} s")

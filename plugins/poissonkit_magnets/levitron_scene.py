"""The registered ``levitron`` scene (``poissonkit run levitron``, ``poissonkit sweep levitron``)."""

from __future__ import annotations

from poissonkit.plugin.contributions import Param, SceneEntry


def _load(**params):
    from poissonkit_magnets.levitron import scene_run

    return scene_run(**params)


def _outcome(spec, t, y, events):
    from poissonkit_magnets.levitron import spec_outcome

    return spec_outcome(spec, t, y, events)


def _sweep(**options):
    from poissonkit_magnets.levitron_sweep import LevitronScene

    return LevitronScene(**options)


#: The Levitron: a 22 g magnetised top spinning above a ferrite ring, in gravity.
LEVITRON_SCENE = SceneEntry(
    name="levitron",
    doc="Levitron: a magnetised top (22 g, 0.6 A m^2) hovering above a ferrite ring magnet "
        "(exact field) in gravity; linearly stable for about 800-1680 rpm (docs/levitron.md); "
        "stops when the top touches the base.",
    params=(
        Param("spin_rpm", "float", "spin of the top about its axis [rpm]", 1200.0, unit="rpm",
              positive=True),
        Param("mass", "float", "mass of the top [kg]", 0.022, unit="kg", positive=True),
        Param("polarization", "float", "polarisation mu0 M of the base ring [T]", 0.265,
              unit="T", positive=True),
        Param("moment", "float", "magnetic moment of the top [A m^2]", 0.60, unit="A m^2",
              positive=True),
        Param("I1", "float", "moment of inertia of the top about a transverse axis [kg m^2]",
              1.15e-6, unit="kg m^2", positive=True),
        Param("I3", "float", "moment of inertia of the top about its symmetry axis [kg m^2]",
              2.10e-6, unit="kg m^2", positive=True),
        Param("inner_radius", "float", "inner radius of the base ring [m]", 0.008, unit="m",
              positive=True),
        Param("outer_radius", "float", "outer radius of the base ring [m]", 0.040, unit="m",
              positive=True),
        Param("thickness", "float", "thickness of the base ring (top face at z = 0) [m]", 0.010,
              unit="m", positive=True),
        Param("g", "float", "gravitational acceleration [m/s^2]", 9.81, unit="m/s^2",
              positive=True),
        Param("top_radius", "float", "radius of the ball standing for the top in contact with "
              "the base [m]", 0.003, unit="m", positive=True),
        Param("offset", "float", "initial horizontal displacement [m]", 5e-4, unit="m"),
        Param("axis_tilt", "float", "initial tilt of the axis [rad]", 0.005, unit="rad"),
        Param("duration", "float", "duration [s]", 2.0, unit="s", positive=True),
        Param("step", "float", "fixed step [s]", 2e-4, unit="s", positive=True),
        Param("method", "str", "integrator registry name", "splitting4"),
        Param("tol", "float", "tolerance of adaptive methods", positive=True, optional=True),
        Param("field", "str", "base field: 'exact' (two exact cylinders) or 'magpylib' "
              "(tabulated CylinderSegment)", "exact"),
        Param("contact", "str", "'stop' when the top touches the base (its fate: fall or "
              "flip), or 'ignore'", "stop"),
    ),
    load=_load,
    sweep=_sweep,
    outcome=_outcome,
)

"""Every contribution of the built-in plugins passes ``poissonkit.testing`` (the kit checks its
authors' own code first). The fast checks (potentials' gradients, symmetry, parameters,
assemblies) run by default, but for potentials with their own compiled kernels (quadratures,
node loops: tens of seconds to compile on a cold cache); the kick of each potential, the model family, the fields, the
integrators, the scenes and the outcomes integrate or compile whole systems and are ``slow``.

The examples give SI values of realistic magnets (a 2.5 mm × 20 mm NdFeB rod, 0.155 A m²),
different for the two bodies so that a swap of the bodies that forgets their parameters shows.
"""

from __future__ import annotations

from poissonkit.testing import parametrize_with_checks

M = 1.58e6  # A/m, NdFeB
ROD = {"radius": 1.25e-3, "length": 0.02}
MAGNETS = {
    "dipole": {"params": {"moment1": 0.155, "moment2": 0.12}},
    "dumbbell": {"params": {"moment1": 0.155, "moment2": 0.12, "half_length1": 0.01,
                            "half_length2": 0.008}},
    "dumbbell_octupole": {"params": {"moment1": 0.155, "moment2": 0.12, "radius1": 1.25e-3,
                                     "length1": 0.02, "radius2": 1e-3, "length2": 0.016}},
    "cylinder": {"params": {"magnetization1": M, "magnetization2": 0.9 * M, "radius1": 1.25e-3,
                            "length1": 0.02, "radius2": 1e-3, "length2": 0.016}},
    "dipole_cylinder_field": {"params": {"magnetization1": M, "radius1": 1.25e-3,
                                         "length1": 0.02, "moment2": 0.12}},
    "dumbbell_cylinder_field": {"params": {"magnetization1": M, "radius1": 1.25e-3,
                                           "length1": 0.02, "moment2": 0.12,
                                           "half_length2": 0.008}},
    "dipole_loop": {"params": {"current1": 10.0, "radius1": 0.01, "moment2": 0.12}},
    "loops": {"params": {"current1": 10.0, "current2": 8.0, "radius1": 0.01,
                         "radius2": 0.008}},
    "superconducting_rings": {"params": {"flux1": 1e-6, "flux2": 8e-7, "radius1": 0.01,
                                         "radius2": 0.008, "wire_radius1": 1e-4,
                                         "wire_radius2": 1e-4}},
    "magnets": {"bodies": ({**ROD, "moment": 0.155}, {"radius": 1e-3, "length": 0.016,
                                                      "moment": 0.12})},
    "magpylib": {"params": {"class": "Cylinder", "params": {"polarization": [0.0, 0.0, 1.0],
                                                            "dimension": [0.05, 0.01]}}},
    "current_loop": {"params": {"current": 10.0, "radius": 0.5}},
    "field:cylinder": {},  # not the potential's example: unit sizes, points 2-4 m away
}
NBODY = {"random_cluster": {"params": {"min_distance": 0.1}}}


@parametrize_with_checks("magnets", examples=MAGNETS)
def test_magnets_pass_the_kit(case):
    case()


@parametrize_with_checks("nbody", examples=NBODY)
def test_nbody_passes_the_kit(case):
    case()


@parametrize_with_checks("core-fields")
def test_core_fields_pass_the_kit(case):
    case()


@parametrize_with_checks("core-integrators")
def test_core_integrators_pass_the_kit(case):
    case()


@parametrize_with_checks("core-outcomes")
def test_core_outcomes_pass_the_kit(case):
    case()

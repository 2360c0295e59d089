"""The plugin against poissonkit's kit: every contribution it registers, every check."""

from poissonkit.testing import parametrize_with_checks

#: Example values (SI) of the contributions whose parameters have no defaults; the two bodies
#: differ, so that a swap of the bodies that forgot their parameters would show.
EXAMPLES = {
    "lennard_jones": {"params": {"epsilon": 1.65e-21, "sigma": 3.4e-10}},
    "finite_dipole": {"params": {"charge1": 1e-8, "charge2": 1.2e-8, "dipole_length1": 5e-3,
                                 "dipole_length2": 4e-3}},
    "point_dipole": {"params": {"charge1": 1e-8, "charge2": 1.2e-8, "dipole_length1": 5e-3,
                                "dipole_length2": 4e-3}},
    "electric_dipoles": {"bodies": ({"charge": 1e-8, "dipole_length": 5e-3},
                                    {"charge": 1.2e-8, "dipole_length": 4e-3})},
    "harmonic_trap": {"params": {"omega": 2.0, "centre": (0.1, 0.0, -0.2)}},
}


@parametrize_with_checks("lennard_jones", examples=EXAMPLES)
def test_kit(case):
    case()

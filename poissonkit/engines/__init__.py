"""Other engines that run a built scene: LAMMPS for single runs past one machine.

This layer sits between the scenes and the reports: it may import the leaves, the symbolic
layer, the numerics and the scenes, never the reports or the commands. An engine returns a
:class:`~poissonkit.numerics.solution.Solution` in poissonkit's state layout and internal
units, which the run command writes like any other run.
"""

from poissonkit.engines.lammps import can_express, lammps_forces, run_lammps

__all__ = ["can_express", "lammps_forces", "run_lammps"]

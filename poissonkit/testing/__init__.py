"""A kit for plugin authors: check each contribution the way scikit-learn's
``check_estimator`` checks an estimator.

One entry point per kind of contribution, each taking the registry entry or its registered
name and raising :class:`CheckFailed` (an ``AssertionError``) that lists every defect found —
the contribution, the check, what failed and by how much:

==========================  =====================================================================
:func:`check_potential`     force and torque are minus the gradients of U (finite differences),
                            pair symmetry, Newton's third law, the kick conserves momentum,
                            rotation/translation invariance, ``body_params`` read, the parameter
                            kernel equals the constant kernel, no recompilation for a run-time
                            parameter, units declared, picklable for Dask
:func:`check_model_family`  the error estimates bound the true error against the most exact
                            model; models ordered by cost; estimates non-increasing in ``r``
:func:`check_field`         force and torque are the gradient of ``U(r, ν)``; the declared
                            attribute is read
:func:`check_integrator`    the declared order by step halving on a problem with a known
                            solution; the declared capabilities work
:func:`check_assembly`      deterministic, every declared parameter validated
:func:`check_scene`         deterministic, runs clean (energy within tolerance, no overlap)
:func:`check_outcome`       declared dtype, unit and fill; computes a value on a real run
==========================  =====================================================================

:func:`parametrize_with_checks` turns them into parametrised pytest tests, so a plugin's test
file is three lines; :mod:`poissonkit.testing.strategies` holds hypothesis strategies for
bodies, configurations and brackets. See ``docs/plugins.md``, "Testing a plugin".
"""

from __future__ import annotations

from poissonkit.testing.checks_family import check_model_family
from poissonkit.testing.checks_field import check_field
from poissonkit.testing.checks_integrator import check_integrator
from poissonkit.testing.checks_outcome import check_outcome
from poissonkit.testing.checks_potential import check_potential
from poissonkit.testing.checks_scene import check_assembly, check_scene
from poissonkit.testing.parametrize import parametrize_with_checks, plugin_checks
from poissonkit.testing.report import CheckFailed, Defect, KitWarning

__all__ = ["CheckFailed", "Defect", "KitWarning", "check_assembly", "check_field",
           "check_integrator", "check_model_family", "check_outcome", "check_potential",
           "check_scene", "parametrize_with_checks", "plugin_checks"]

"""Reports of a run: ``summary.json``, the trajectory (npz) and figures in the style of seed 000.

* :func:`diagnostics` — energy error, Casimir drift, momentum drifts over time, from any system
  exposing ``energy``, ``casimirs``, ``angular_momentum`` (and optionally ``linear_momentum``).
* :func:`write_summary`, :func:`write_trajectory` — files of ``poissonkit run``.
* :mod:`poissonkit.report.plots` — the seed's MATLAB figures (imported lazily: matplotlib).
"""

from poissonkit.report.summary import Diagnostics, diagnostics, write_summary, write_trajectory

__all__ = ["Diagnostics", "diagnostics", "write_summary", "write_trajectory"]

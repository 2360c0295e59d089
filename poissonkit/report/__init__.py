"""Reports of a run: ``summary.json``, the trajectory (npz) and figures in the style of seed 000.

* :func:`diagnostics` — energy error, Casimir drift, momentum drifts over time, as defined once
  in :mod:`poissonkit.numerics.diagnostics` (absolute, relative and the scale of each).
* :func:`write_summary`, :func:`write_trajectory` — files of ``poissonkit run`` (atomic,
  :mod:`poissonkit.files.atomic`); :mod:`poissonkit.report.run_output` writes all of a run's
  files in commit order (the summary document: :mod:`~poissonkit.report.run_summary`, the
  trajectory files: :mod:`~poissonkit.report.run_files`);
* :func:`invariant_report` — only the invariants a system really has, absolute and relative;
* :func:`streamed_diagnostics` — diagnostics of a trajectory streamed to disk in parts.
* :mod:`poissonkit.report.figures` — the plot registry: which figures a run gets (two-body
  figures of :mod:`~poissonkit.report.plots`, N-body ones of
  :mod:`~poissonkit.report.nbody_plots`, drifts of :mod:`~poissonkit.report.drift_plot`);
  imported lazily (matplotlib).
"""

from poissonkit.report.summary import (Diagnostics, conserved_quantities, diagnostics,
                                       invariant_report, streamed_diagnostics, write_summary,
                                       write_trajectory)

__all__ = ["Diagnostics", "conserved_quantities", "diagnostics", "invariant_report",
           "streamed_diagnostics", "write_summary", "write_trajectory"]

"""Work-precision points carry the unified ``max_rel_energy_error`` (docs/numerics.md,
"Diagnostics"); truth: hand-written energies and CSV files."""

from __future__ import annotations

import numpy as np

from poissonkit.numerics import workprecision as wp


class Column0:
    def energy(self, y):
        return np.asarray(y, dtype=float)[..., 0]


def test_energy_error_of_rows_and_of_columns_is_the_diagnostics_one():
    t = np.arange(3.0)
    y = np.array([[-8.0, 1.0], [-6.0, 1.0], [-9.0, 1.0]])  # |ΔH| max 2, |H(0)| 8
    assert wp._max_rel_energy_error(Column0(), t, y) == 0.25
    assert wp._max_rel_energy_error(Column0(), t, y.T) == 0.25  # solvers saving columns


def test_points_csv_uses_the_new_name_and_reads_old_files(tmp_path):
    p = wp.WorkPoint("splitting2", "step", 0.1, 10, 0.5, 1e-6, 3e-9)
    assert p.max_energy_error == p.max_rel_energy_error == 3e-9
    wp.write_csv(tmp_path / "new.csv", [p])
    assert "max_rel_energy_error" in (tmp_path / "new.csv").read_text().splitlines()[0]
    assert wp.read_csv(tmp_path / "new.csv") == [p]
    (tmp_path / "old.csv").write_text(
        "method,kind,setting,steps,wall_time,final_error,max_energy_error,note\n"
        "splitting2,step,0.1,10,0.5,1e-06,3e-09,\n")
    assert wp.read_csv(tmp_path / "old.csv") == [p]

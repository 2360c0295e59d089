"""Diagnostics of a streamed run evaluate each saved state's energy once.

A large system's energy costs as much as a force evaluation: the summary of a 10⁵-body run
used to evaluate every saved state twice (once per part, once more for the kept rows) and the
first state twice more. Truth: the energy error recomputed here with plain numpy from the
rows, and a count of the rows whose energy was asked for.
"""

from __future__ import annotations

import numpy as np
import pytest

from poissonkit.report import streamed_diagnostics


class CountingSpinner:
    """A free top, ``H = |m|² / 2``, Casimir ``|m|²`` (state = m), counting energy rows."""

    def __init__(self) -> None:
        self.rows = 0

    def energy(self, y):
        y = np.atleast_2d(np.asarray(y, dtype=float))
        self.rows += y.shape[0]
        return 0.5 * np.sum(y ** 2, axis=-1)

    def casimirs(self, y):
        return np.sum(np.atleast_2d(np.asarray(y)) ** 2, axis=-1)[..., None]


def write_parts(folder, t, y, sizes):
    folder.mkdir()
    lo = 0
    for k, n in enumerate(sizes):
        np.savez(folder / f"part-{k:06d}.npz", t=t[lo:lo + n], y=y[lo:lo + n])
        lo += n


@pytest.mark.parametrize("sizes, plot_rows", [((11,), 20000), ((7, 5, 9), 20000),
                                              ((7, 5, 9), 6), ((4, 4, 4), 3)])
def test_each_saved_energy_is_evaluated_once(tmp_path, sizes, plot_rows):
    rng = np.random.default_rng(3)
    n = sum(sizes)
    t = np.arange(float(n))
    y = 1.0 + 1e-3 * rng.standard_normal((n, 3))
    write_parts(tmp_path / "parts", t, y, sizes)
    system = CountingSpinner()
    diag, t_kept, y_kept = streamed_diagnostics(system, tmp_path / "parts", plot_rows=plot_rows)
    # every row once, plus the first state ahead of each later part
    assert system.rows == n + len(sizes) - 1
    H = 0.5 * np.sum(y ** 2, axis=1)
    rel = np.abs(H - H[0]) / abs(H[0])
    every = max(1, -(-n // plot_rows))
    keep = sorted(set(range(0, n, every)) | {n - 1})
    np.testing.assert_array_equal(t_kept, t[keep])
    np.testing.assert_array_equal(y_kept, y[keep])
    np.testing.assert_allclose(diag.energy_error, rel[keep], rtol=1e-12, atol=0)
    assert diag.maxima()["max_rel_energy_error"] == pytest.approx(rel.max(), rel=1e-12)
    assert diag.energy_reference == H[0]

"""The run command speaks in its own flags and units: the step message, the progress bar.

Truth used: the CLI's step flag is ``--step`` in the scene's time unit (seconds here) while ``solve`` takes ``step=`` in
internal units; a bar over a run of ``T`` internal units with ``time_unit`` seconds per unit
ends at ``T * time_unit`` seconds, shown to three significant digits.
"""

from __future__ import annotations

import math
import re

import pytest

from poissonkit import cli
from poissonkit.errors import InputError, MissingStepError
from poissonkit.numerics.integrators.base import bar_decimals, progress_bar, progress_in_seconds


def test_fixed_step_method_with_tol_names_the_cli_flag_and_seconds(tmp_path, capsys):
    code = cli.main(["run", "seed000", "--tol", "1e-8", "--out", str(tmp_path / "o"),
                     "--no-progress"])
    assert code == 1
    err = capsys.readouterr().err
    assert "splitting6 is a fixed-step method" in err
    assert "--step TIME (in s, the scene's time unit" in err and "adaptive" in err
    assert "internal time unit" not in err and "step=..." not in err


def test_the_python_api_keeps_its_own_step_message():
    from poissonkit.numerics.integrators.base import check_step

    with pytest.raises(MissingStepError, match=r"give step=\.\.\. \(internal time unit\)") as e:
        check_step(None, 1.0, "splitting6")
    assert isinstance(e.value, InputError) and e.value.method == "splitting6"


@pytest.mark.parametrize("total, decimals", [(0.741, 3), (1.0, 2), (125.66370614359172, 0),
                                             (12.566, 1), (0.002, 5), (5e4, 0)])
def test_bar_decimals_give_three_significant_digits(total, decimals):
    assert bar_decimals(total) == decimals
    shown = f"{total:.{decimals}f}"
    assert len(shown.replace(".", "").lstrip("0")) in (3, len(str(int(round(total)))))


def _bar_text(capsys) -> str:
    return capsys.readouterr().err.replace("\r", "\n")


def test_progress_bar_counts_seconds_inside_progress_in_seconds():
    total = 40 * math.pi  # internal units of 20 seed periods
    unit = 0.741 / total
    with progress_in_seconds(unit):
        bar = progress_bar(True, total, "splitting6")
        assert bar is not None
        bar.update(total / 2)
        line = str(bar)
        bar.close()
    assert f"{total / 2 * unit:.3f}/0.741 s" in line, line  # half of 0.741 s
    assert "125.66" not in line
    bar = progress_bar(True, total, "splitting6")  # outside: internal time, same digits rule
    assert bar is not None
    bar.update(total / 2)
    line = str(bar)
    bar.close()
    assert "63/126 t" in line, line


def test_run_shows_the_bar_in_seconds(tmp_path, capsys):
    code = cli.main(["run", "two_magnets", "--duration", "0.002", "--out", str(tmp_path / "o"),
                     "--no-plot"])
    assert code == 0
    text = _bar_text(capsys)
    assert re.search(r"/0\.00200 s", text), text
    assert not re.search(r"/\d+\.\d{6,}", text), text  # no 17-digit internal totals

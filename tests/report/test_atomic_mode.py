"""Files written atomically get the mode of any file the user creates (not mkstemp's 0600)."""

from __future__ import annotations

import os
import stat

from poissonkit.report import atomic


def test_atomic_files_have_the_umask_mode(tmp_path):
    mask = os.umask(0o022)
    os.umask(mask)
    path = atomic.write_text(tmp_path / "summary.json", "{}\n")
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~mask
    plain = tmp_path / "plain.txt"
    plain.write_text("x")
    assert stat.S_IMODE(path.stat().st_mode) == stat.S_IMODE(plain.stat().st_mode)

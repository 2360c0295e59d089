"""File-writing utilities below every other layer: atomic writes and injected kill points.

* :mod:`poissonkit.files.atomic` — a file has either its complete new content or is absent;
* :mod:`poissonkit.files.killpoints` — the test hook that kills the process at a named phase.

They import nothing of poissonkit but :mod:`poissonkit.errors`, so the numerics (checkpoints,
the kernel cache), the reports and the commands all write through them without importing one
another.
"""

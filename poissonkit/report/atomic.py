"""Atomic file writes; moved to :mod:`poissonkit.files.atomic` (this path keeps working)."""

from poissonkit.files.atomic import (OutputExistsError, atomic_path, prepare_output_dir,
                                     remove_stale_temps, write_bytes, write_json, write_text)

__all__ = ["OutputExistsError", "atomic_path", "prepare_output_dir", "remove_stale_temps",
           "write_bytes", "write_json", "write_text"]

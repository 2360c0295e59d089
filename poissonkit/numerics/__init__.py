"""Numerics: compiled right-hand sides, integrators, diagnostics, work-precision reports."""

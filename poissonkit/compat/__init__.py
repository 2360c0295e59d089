"""PoissonGeometry-compatible front end (filled by the compat layer)."""

"""Fuzz tests. The counts of inputs each target tried (``fuzzkit.COUNTS``) are printed in the
terminal summary by ``tests/conftest.py``, which also sums them over xdist's workers (the
controlling process loads no conftest below ``tests/``)."""

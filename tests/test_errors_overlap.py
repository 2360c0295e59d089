"""One overlap error: the pair calculator and the N-body systems raise the same class."""

from poissonkit import errors
from poissonkit.numerics.nbody import OverlapError as NBodyOverlap
from poissonkit.pairs import OverlapError as PairOverlap


def test_one_overlap_error_class() -> None:
    assert PairOverlap is NBodyOverlap is errors.OverlapError
    assert issubclass(errors.OverlapError, errors.InputError)

"""What a check found: :class:`Defect` rows collected by a :class:`Findings` and raised
together as :class:`CheckFailed` (an ``AssertionError``, so pytest shows it as a failure)."""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field


@dataclass(frozen=True)
class Defect:
    """One thing a contribution got wrong.

    Attributes
    ----------
    check
        The name of the check (``"gradient"``, ``"pair_symmetry"``, ...).
    message
        What failed, with the configuration and by how much.
    """

    check: str
    message: str

    def __str__(self) -> str:
        return f"[{self.check}] {self.message}"


class CheckFailed(AssertionError):
    """A contribution failed the kit: every defect found, one per line.

    Attributes
    ----------
    contribution
        ``"kind 'name'"`` of the contribution checked.
    defects
        The :class:`Defect` rows.
    """

    def __init__(self, contribution: str, defects: list[Defect]) -> None:
        self.contribution = contribution
        self.defects = tuple(defects)
        lines = "\n".join(f"  - {d}" for d in defects)
        super().__init__(f"{contribution} fails {len(defects)} check"
                         f"{'s' if len(defects) != 1 else ''} of poissonkit.testing:\n{lines}")


class KitWarning(UserWarning):
    """Advice of the kit that is not a defect (e.g. no ``energy_scale`` declared)."""


@dataclass
class Findings:
    """The defects of one contribution, collected check by check.

    An unexpected exception inside one check is itself a defect of that check (named, with the
    exception), so the other checks still run and report.
    """

    contribution: str
    defects: list[Defect] = field(default_factory=list)

    def add(self, check: str, message: str) -> None:
        """Record a defect of ``check``."""
        self.defects.append(Defect(check, message))

    def advise(self, message: str) -> None:
        """A :class:`KitWarning` naming the contribution."""
        warnings.warn(f"{self.contribution}: {message}", KitWarning, stacklevel=3)

    @contextmanager
    def guard(self, check: str) -> Iterator[None]:
        """Run one check; an exception it raises becomes a defect of ``check``."""
        try:
            yield
        except CheckFailed:
            raise
        except Exception as exc:  # noqa: BLE001 - any failure of the contribution is a finding
            self.add(check, f"raised {type(exc).__name__}: {exc}")

    def raise_if_any(self) -> None:
        """Raise :class:`CheckFailed` listing every defect (nothing if there is none)."""
        if self.defects:
            raise CheckFailed(self.contribution, self.defects)


def relative(a: float, b: float, scale: float) -> float:
    """``|a − b| / scale`` (``inf`` for a non-finite value): the size of a mismatch."""
    import math

    d = abs(a - b)
    return d / scale if math.isfinite(d) and scale > 0 else (0.0 if d == 0 else math.inf)

"""The outcome of a Jacobi identity check (:func:`poissonkit.structure.jacobi.check_jacobi`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import sympy as sp

from poissonkit._display import TitledRows, latex_aligned, latex_text

Key = tuple[int, int, int]


@dataclass(frozen=True)
class JacobiResult(TitledRows):
    """Outcome of :func:`check_jacobi`.

    Attributes
    ----------
    is_poisson
        Whether the Jacobi identity holds (exactly, or with the stated false-positive bound).
    method
        ``"exact"`` or ``"random"`` (what actually ran).
    failures
        ``{(i, j, k): residual}`` for ``i < j < k`` (0-based) where ``Jac^{ijk} != 0``: an
        expression (exact) or the exact value at the failing point (random).
    false_positive_bound
        Upper bound of the probability that a non-Poisson bivector passed (0 for exact).
    seconds
        Wall time of the check.
    coords
        The coordinates, for readable reports.
    trials
        Number of random points (random method).
    note
        Anything the reader should know (method chosen, constraint handling).
    """

    is_poisson: bool
    method: str
    failures: Mapping[Key, sp.Expr] = field(default_factory=dict)
    false_positive_bound: float = 0.0
    seconds: float = 0.0
    coords: tuple[sp.Symbol, ...] = ()
    trials: int = 0
    note: str = ""

    def __bool__(self) -> bool:
        return self.is_poisson

    def named_failures(self) -> dict[str, sp.Expr]:
        """Failures keyed by coordinate names, e.g. ``"Jac(x1, x2, x3)"``."""
        out = {}
        for (i, j, k), v in self.failures.items():
            names = [str(self.coords[t]) if self.coords else str(t) for t in (i, j, k)]
            out[f"Jac({', '.join(names)})"] = v
        return out

    # ------------------------------------------------------------------ display
    def _title(self) -> str:
        if not self.is_poisson:
            return f"Jacobi identity: FAILS ({len(self.failures)} non-zero component(s))"
        extra = "" if self.method == "exact" else \
            f", false-positive probability <= {self.false_positive_bound:.1e}"
        return f"Jacobi identity: holds ({self.method}, {self.seconds:.3g} s{extra})"

    def _rows(self) -> list[tuple[str, str]]:
        rows = [(k, str(v)) for k, v in self.named_failures().items()]
        return rows + ([("note", self.note)] if self.note else [])

    def _verdict(self) -> bool:
        return self.is_poisson

    def _repr_latex_(self) -> str:
        """The non-zero Jacobiator components as LaTeX equations (or that it vanishes)."""
        if self.is_poisson:
            return latex_aligned([("\\operatorname{Jac}", f"0 \\quad {latex_text(self._title())}")])
        rows = []
        for (i, j, k), v in self.failures.items():
            names = ", ".join(sp.latex(self.coords[t]) if self.coords else str(t)
                              for t in (i, j, k))
            rows.append((f"\\operatorname{{Jac}}({names})", sp.latex(v)))
        return latex_aligned(rows)


__all__ = ["JacobiResult", "Key"]

"""Degree bounds of expressions for the Schwartz–Zippel false-positive bound.

A :class:`_Degree` bounds an expression written ``num / den``: the total degree of ``num`` and
the denominator's distinct factors ``{key: (degree, multiplicity)}``, plus the distinct
square-root bases (each doubles the degree of the final norm). The randomized checks evaluate
the same expression tree once with values and once with these records
(:class:`~poissonkit.structure.randompoints.RandomPoints`).
"""

from __future__ import annotations

__all__: list[str] = []


class _Degree:
    """Upper bounds for a rational expression written ``num / den``: ``num`` total degree and the
    denominator's distinct factors ``{key: (degree, multiplicity)}``; ``radicals`` are the
    distinct square-root bases (each doubles the degree of the final norm)."""

    __slots__ = ("den", "num", "radicals")

    def __init__(self, num: int, den: dict | None = None, radicals: frozenset = frozenset()):
        self.num = num
        self.den = den or {}
        self.radicals = radicals

    def den_degree(self) -> int:
        return sum(d * k for d, k in self.den.values())

    def __add__(self, other):
        other = _as_degree(other)
        den = dict(self.den)
        for key, (d, k) in other.den.items():
            den[key] = (d, max(k, den.get(key, (d, 0))[1]))
        total = sum(d * k for d, k in den.values())
        num = max(self.num + total - self.den_degree(), other.num + total - other.den_degree())
        return _Degree(num, den, self.radicals | other.radicals)

    __radd__ = __add__

    def __sub__(self, other):
        return self + other

    __rsub__ = __sub__

    def __neg__(self):
        return self

    def __mul__(self, other):
        other = _as_degree(other)
        den = dict(self.den)
        for key, (d, k) in other.den.items():
            den[key] = (d, den.get(key, (d, 0))[1] + k)
        return _Degree(self.num + other.num, den, self.radicals | other.radicals)

    __rmul__ = __mul__

    def __pow__(self, k: int):
        return _Degree(self.num * k, {key: (d, m * k) for key, (d, m) in self.den.items()},
                       self.radicals)

    def inverse(self, key) -> _Degree:
        return _Degree(self.den_degree(), {key: (self.num, 1)} if self.num else {},
                       self.radicals)

    def bound(self) -> int:
        """Degree of the numerator after taking the norm over the square roots."""
        return max(self.num, 1) * 2 ** len(self.radicals)


def _as_degree(x) -> _Degree:
    return x if isinstance(x, _Degree) else _Degree(0)

"""Hypothesis strategies for the objects poissonkit takes: unit axes, pair configurations,
bodies, N-body configurations and Poisson brackets.

Import this module only where hypothesis is installed (it is in the ``test`` extra);
``import poissonkit.testing`` does not need it::

    from hypothesis import given
    from poissonkit.testing import strategies as pks

    @given(pks.pair_configurations(distances=(0.01, 0.1)))
    def test_my_potential_is_finite(cfg):
        ...
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

try:
    from hypothesis import strategies as st
except ImportError as exc:  # pragma: no cover - the test extra brings hypothesis
    from poissonkit.errors import PoissonkitError

    raise PoissonkitError("poissonkit.testing.strategies needs hypothesis: "
                          "pip install 'poissonkit[test]' (or pip install hypothesis)") from exc

from poissonkit.testing.geometry import PairConfig

_COMPONENT = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)


def unit_vectors() -> st.SearchStrategy[np.ndarray]:
    """Unit 3-vectors (components drawn in ``[-1, 1]``, normalised; nearly zero draws are
    rejected)."""
    return (st.tuples(_COMPONENT, _COMPONENT, _COMPONENT)
            .map(lambda v: np.array(v, float))
            .filter(lambda v: float(np.linalg.norm(v)) > 1e-3)
            .map(lambda v: v / np.linalg.norm(v)))


def pair_configurations(distances: tuple[float, float] = (3.0, 6.0)
                        ) -> st.SearchStrategy[PairConfig]:
    """Two bodies: ``r = r2 − r1`` with ``|r|`` in ``distances`` [m] and unit axes."""
    lo, hi = distances
    return st.builds(lambda d, e, n1, n2: PairConfig(e * d, n1, n2),
                     st.floats(lo, hi, allow_nan=False), unit_vectors(), unit_vectors(),
                     unit_vectors())


def bodies(attributes: Mapping[str, tuple[float, float]] | None = None, *, top: bool = True,
           mass: tuple[float, float] = (0.1, 10.0), name: str = "b") -> st.SearchStrategy[Any]:
    """:class:`~poissonkit.numerics.nbody.Body` objects (a top with ``1/I`` in [0.1, 10] when
    ``top``) whose ``attributes`` (name → range, SI) are drawn uniformly."""
    from poissonkit.numerics.nbody import Body

    attrs = dict(attributes or {})
    values = st.fixed_dictionaries({k: st.floats(lo, hi, allow_nan=False)
                                    for k, (lo, hi) in attrs.items()})
    alpha = st.floats(0.1, 10.0) if top else st.none()
    return st.builds(lambda m, a, extra: Body(name, m, alpha=a, attributes=extra),
                     st.floats(*mass, allow_nan=False), alpha, values)


def configurations(n: int, *, min_distance: float = 1.0, box: float = 10.0
                   ) -> st.SearchStrategy[np.ndarray]:
    """``(n, 3)`` positions in the cube ``[-box/2, box/2]³`` [m], every two at least
    ``min_distance`` apart (draws that crowd are rejected: keep ``box`` generous)."""
    coord = st.floats(-box / 2, box / 2, allow_nan=False)
    points = st.lists(st.tuples(coord, coord, coord), min_size=n, max_size=n)

    def spread(p: list[tuple[float, float, float]]) -> bool:
        a = np.array(p, float)
        d = np.linalg.norm(a[:, None] - a[None, :], axis=-1) + np.eye(n) * 2 * min_distance
        return bool(d.min() >= min_distance)

    return points.filter(spread).map(lambda p: np.array(p, float))


def brackets(names: Sequence[str] = ("so(3)", "se(3)", "sl(2)", "heisenberg(1)")
             ) -> st.SearchStrategy[Any]:
    """Lie–Poisson bivectors of classical Lie algebras
    (:func:`poissonkit.structure.lie_algebras.lie_algebra`), with random real scalings of the
    bracket (a Poisson bivector times a constant is Poisson)."""
    from poissonkit.structure.lie_algebras import lie_algebra

    scale = st.sampled_from([1, 2, -1, 3])
    return st.builds(lambda name, k: lie_algebra(name).bivector * k, st.sampled_from(list(names)),
                     scale)


__all__ = ["bodies", "brackets", "configurations", "pair_configurations", "unit_vectors"]

"""The one sampler and zero test of the randomized symbolic checks.

Truth: the Schwartz–Zippel bound computed by hand from its statement (degree times the largest
point mass, to the power of the trials); square-root identities known by hand
(``sqrt(2) sqrt(3) = sqrt(6)``, ``sqrt(8) = 2 sqrt(2)``); and a polynomial with one known root,
whose false-positive rate at sampled points must stay below the stated bound.
"""

from __future__ import annotations

from fractions import Fraction

import pytest
import sympy as sp

from poissonkit.structure import casimirs, jacobi, randompoints
from poissonkit.structure.randompoints import RandomPoints
from poissonkit.structure.sampling import (
    SAMPLE_RANGE,
    PointStream,
    Sampler,
    false_positive_bound,
    false_positive_fraction,
    is_zero_at_point,
)


def test_draws_are_reproducible_and_independent_of_order():
    a, b = Sampler(7), Sampler(7)
    first = [a.integer(k, 0) for k in ("x", "y", "z")]
    second = [b.integer(k, 0) for k in ("z", "y", "x")][::-1]
    assert first == second
    assert Sampler(7).integer("x", 1) != Sampler(7).integer("x", 0) or \
        Sampler(7).integer("y", 1) != Sampler(7).integer("y", 0)
    assert Sampler(8).integer("x", 0) != Sampler(7).integer("x", 0) or \
        Sampler(8).integer("y", 0) != Sampler(7).integer("y", 0)


def test_fresh_seed_is_recorded_and_reproduces_the_draws():
    s = Sampler()
    assert isinstance(s.seed, int)
    assert Sampler(s.seed).rational("q", 3) == s.rational("q", 3)


def test_range_and_signs():
    s = Sampler(1)
    ints = [s.integer(f"v{i}", i) for i in range(300)]
    assert all(abs(v) <= SAMPLE_RANGE for v in ints)
    assert any(v < 0 for v in ints) and any(v > 0 for v in ints)
    assert all(1 <= s.integer(f"p{i}", i, sign=1) <= SAMPLE_RANGE for i in range(100))
    assert all(-SAMPLE_RANGE <= s.integer(f"n{i}", i, sign=-1) <= -1 for i in range(100))
    r = s.rational("x", 0)
    assert r == sp.Rational(s.integer("x", 0), SAMPLE_RANGE) and abs(r) <= 1


def test_point_stream_walks_the_sampler_points():
    stream = PointStream(Sampler(3))
    stream.next_point()
    v0 = stream.value("x")
    stream.next_point()
    assert (v0, stream.value("x")) == (Sampler(3).rational("x", 0), Sampler(3).rational("x", 1))


def test_bound_is_schwartz_zippel_by_hand():
    D, t, N = 54, 3, 10**6
    assert false_positive_fraction(D, t) == Fraction(D, 2 * N + 1) ** t
    assert false_positive_fraction(D, t, signed=False) == Fraction(D, N) ** t
    assert false_positive_bound(D, t) == pytest.approx(float(Fraction(D, 2 * N + 1) ** t))
    assert false_positive_fraction(10 * N, 2) == 1  # a useless bound is capped at 1


def test_zero_test_is_exact_on_square_roots():
    assert is_zero_at_point(sp.sqrt(2) * sp.sqrt(3) - sp.sqrt(6))
    assert is_zero_at_point(sp.sqrt(8) - 2 * sp.sqrt(2))
    assert not is_zero_at_point(sp.sqrt(2) + sp.sqrt(3) - sp.sqrt(5 + 2 * sp.sqrt(6)) + 1)
    assert not is_zero_at_point(sp.sqrt(2) - sp.Rational(1414213562373095, 10**15))
    assert is_zero_at_point(0) and not is_zero_at_point(sp.Rational(1, 10**30))


def test_rate_of_false_positives_stays_below_the_bound():
    # x - a vanishes at one of 2N+1 values: over many points the rate must be ~1/(2N+1)
    s = Sampler(11)
    a = s.integer("x", 17)
    hits = sum(s.integer("x", i) == a for i in range(2000))
    assert hits <= 2  # index 17 itself, and a repeat only with probability ~1e-3


def test_every_randomized_check_uses_the_one_sampler():
    assert jacobi.SAMPLE_RANGE == randompoints.SAMPLE_RANGE == SAMPLE_RANGE
    x, y = sp.symbols("x y", real=True)
    pts = RandomPoints((x, y), seed=5)
    assert pts.value(x, 0) == Sampler(5).rational("x", 0)
    r = casimirs.rank(casimirs.Bivector.from_components({(1, 2): x * y}, (x, y)), seed=5)
    assert int(r) == 2 and "seed 5" in r.note

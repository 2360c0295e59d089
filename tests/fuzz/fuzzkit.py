"""Shared pieces of the fuzz tests: settings, outcome accounting, code-execution payloads.

Property checked by every target (issue "fuzzed inputs"): an input either works or raises a
:class:`~poissonkit.errors.PoissonkitError` subclass whose message names the offending field;
never another exception, never a hang (hypothesis ``deadline`` per example, pytest-timeout per
test), never a silent NaN in a returned result, never code execution (payloads that would
create a marker file if any string reached ``eval``/``exec``/``os.system``).

The default suite runs a bounded number of derandomized examples per target; the ``slow`` tests
run :data:`SLOW_EXAMPLES` random examples per target. Counts of inputs tried, typed errors and
anything else are kept in :data:`COUNTS` and printed in pytest's terminal summary.
"""

from __future__ import annotations

import math
import os
import tempfile
from collections import Counter
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

from poissonkit.errors import PoissonkitError

#: Examples per target in the default suite (all targets together well under a minute).
DEFAULT_EXAMPLES = int(os.environ.get("POISSONKIT_FUZZ_EXAMPLES", "120"))
#: Examples per target in the slow run.
SLOW_EXAMPLES = int(os.environ.get("POISSONKIT_FUZZ_SLOW_EXAMPLES", "10000"))
#: Per-example time limit (ms): far below a hang, above a cold numba compile of a potential on a
#: loaded 2-core machine (19 s measured; the first example of a target may compile).
DEADLINE_MS = 60_000

_COMMON = dict(deadline=DEADLINE_MS, database=None, print_blob=True,
               suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much,
                                      HealthCheck.data_too_large,
                                      HealthCheck.function_scoped_fixture])
#: Default suite: reproducible (derandomized), bounded.
FAST = settings(max_examples=DEFAULT_EXAMPLES, derandomize=True, **_COMMON)
#: Slow suite: fresh random examples each run.
SLOW = settings(max_examples=SLOW_EXAMPLES, **_COMMON)

#: ``{target: Counter(tried=, ok=, typed_error=)}``; anything else fails the test at once.
COUNTS: dict[str, Counter] = {}

MARKER_DIR = Path(tempfile.mkdtemp(prefix="poissonkit-fuzz-"))
MARKER = MARKER_DIR / "code-was-executed"


def payloads(marker: Path = MARKER) -> list[str]:
    """Strings that create ``marker`` if anything evaluates them as Python."""
    m = str(marker)
    return [
        f"__import__('os').system('touch {m}')",
        f"open('{m}', 'w')",
        f"exec(\"open('{m}', 'w')\")",
        f"eval(\"__import__('os').system('touch {m}')\")",
        f"x1 + __import__('os').system('touch {m}')",
        f"sin(__import__('pathlib').Path('{m}').touch())",
        f"Integer(__import__('os').system('touch {m}'))",
        f"Symbol('x').__class__.__init__.__globals__['os'].system('touch {m}')",
        f"(lambda: __import__('os').system('touch {m}'))()",
        "().__class__.__bases__[0].__subclasses__()",
        f"[__import__('os').system('touch {m}') for _ in (1,)]",
        f"x1; __import__('os').system('touch {m}')",
        f"Float(\"__import__('os').system('touch {m}')\")",
        f"Symbol(\"__import__('os').system('touch {m}')\")",
        f"__builtins__['open']('{m}', 'w')",
    ]


def outcome(target: str, run: Callable[[], Any], fields: Iterable[str] = ()) -> Any:
    """Run one fuzz input; return the result, or ``None`` after a typed error.

    ``fields``: names of which at least one must appear in a typed error's message (the
    field the mutation touched); empty: not checked. Any exception that is not a
    :class:`PoissonkitError` propagates and fails the test; so does a marker file.
    """
    c = COUNTS.setdefault(target, Counter())
    c["tried"] += 1
    try:
        result = run()
    except PoissonkitError as exc:
        assert not MARKER.exists(), "a payload was executed"
        names = [f for f in fields if f]
        if names:
            msg = str(exc)
            assert any(f in msg for f in names), (
                f"{type(exc).__name__} does not name the field ({names}): {msg}")
        c["typed_error"] += 1
        return None
    except BaseException:
        c["other"] += 1
        raise
    assert not MARKER.exists(), "a payload was executed"
    c["ok"] += 1
    return result


def assert_finite(values: Any, what: str) -> None:
    """No NaN or infinity in a returned numeric result."""
    arr = np.asarray(values, dtype=float)
    assert np.all(np.isfinite(arr)), f"non-finite value in {what}: {arr}"


def special_floats() -> list[float]:
    """Values every numeric field is tried with."""
    return [math.nan, math.inf, -math.inf, 0.0, -0.0, -1.0, 1e-320, 1e308, -1e308, 5e-324]


slow = pytest.mark.slow

"""Saying so when kernels compile: a one-line notice with an estimate of how long it takes.

The first run of a scene type compiles its kernels (numba), which takes seconds to minutes;
later runs load them from the disk cache in about a second. :func:`compile_notice` wraps the
first, one-step solve of ``poissonkit run``: if it is still busy after :data:`NOTICE_AFTER`
seconds (a cold cache), it prints ``compiling kernels (first run of this scene type; about N s
...)``; a warm start prints nothing.

The estimates are the compile CPU times measured per kind of scene (cold − warm runs of
``benchmarks/bench_scene_compile.py``, docs/performance.md "Issue 28: compile time per scene",
quiet 2-core machine), rounded up.
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from typing import TYPE_CHECKING, TextIO

from poissonkit.contracts import HasBodies, HasExternalFields
from poissonkit.traits import offers

if TYPE_CHECKING:
    from poissonkit.numerics.runspec import RunSpec

#: Seconds the first solve may take before the notice is printed (a warm start loads every
#: kernel from the cache in less).
NOTICE_AFTER = 2.0

#: Compile CPU seconds per kind of scene, rounded up (docs/performance.md, issue 28, quiet
#: machine; Wisdom–Holman: a Sun–Jupiter–Saturn scene, CPU time on a loaded machine).
COMPILE_SECONDS: Mapping[str, int] = {
    "two-body": 3,          # seed000: TwoBodySystem, splitting
    "n-body": 15,           # two_magnets, magnet_chain: NBodySystem, splitting
    "planned": 22,          # planned_cluster: mixed magnet models
    "fields": 28,           # levitron: a magpylib field, gravity
    "wisdom_holman": 30,    # point masses, Wisdom–Holman loop
}


def scene_kind(spec: RunSpec) -> str:
    """The key of :data:`COMPILE_SECONDS` that describes ``spec`` best."""
    if spec.method.startswith("wisdom_holman"):
        return "wisdom_holman"
    if offers(spec.system, HasExternalFields) and spec.system.external_fields:
        return "fields"
    if (spec.metadata or {}).get("plan") is not None:
        return "planned"
    return "n-body" if offers(spec.system, HasBodies) else "two-body"


def compile_message(spec: RunSpec) -> str:
    """The notice: what compiles and about how long it takes."""
    seconds = COMPILE_SECONDS[scene_kind(spec)]
    return (f"compiling kernels (first run of this scene type with {spec.method}; about "
            f"{seconds} s on an idle 2-core machine, longer under load; later runs load them "
            "from the cache) ...")


@contextmanager
def compile_notice(spec: RunSpec, enabled: bool = True, stream: TextIO | None = None,
                   after: float = NOTICE_AFTER) -> Iterator[None]:
    """Print :func:`compile_message` to ``stream`` (stderr) if the block is still running
    ``after`` seconds from its start; nothing when it ends sooner or ``enabled`` is false."""
    if not enabled:
        yield
        return
    out = stream if stream is not None else sys.stderr

    def notice() -> None:
        print(compile_message(spec), file=out, flush=True)

    timer = threading.Timer(after, notice)
    timer.daemon = True
    timer.start()
    try:
        yield
    finally:
        timer.cancel()

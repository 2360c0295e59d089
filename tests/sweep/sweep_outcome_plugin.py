"""A third-party plugin for the sweep tests: its own sweep scene and its own outcome.

The scene integrates nothing: a point's record carries the swept value ``x`` as its distance,
so the plugin outcome ``test_twice_min`` of a point must be exactly ``2 x``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from poissonkit.errors import UnknownNameError
from poissonkit.plugin.contributions import OutcomeEntry
from poissonkit.plugin.hookspecs import hookimpl
from poissonkit.sweeps.targets import RunRecord


def twice_min(record: RunRecord) -> float:
    return 2.0 * float(np.min(record.distance))


TWICE_MIN = OutcomeEntry(name="test_twice_min", doc="twice the smallest distance of the run",
                         dtype="f8", unit="m", fill=math.nan, compute=twice_min)


@dataclass(frozen=True)
class EchoScene:
    """A sweep scene with one parameter ``x`` [m], echoed as the run's distance."""

    @property
    def key(self) -> str:
        return "echo"

    def settings(self) -> dict[str, object]:
        return {"scene": "echo"}

    def check(self, path: str) -> str:
        if path != "x":
            raise UnknownNameError("echo parameter", path, ["x"])
        return path

    def units(self, path: str) -> str:
        return "m"

    def prepare(self) -> Mapping[str, object]:
        return {}

    def run(self, prep: Mapping[str, object], values: Mapping[str, float]) -> RunRecord:
        return RunRecord(None, "bounded", math.nan, np.array([float(values["x"])]),  # type: ignore[arg-type]
                         1.0, 1.0, 1.0)


@hookimpl
def poissonkit_outcomes() -> list[OutcomeEntry]:
    return [TWICE_MIN]

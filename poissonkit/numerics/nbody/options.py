"""Validation of what :class:`~poissonkit.numerics.nbody.NBodySystem` is given.

The bodies and the numeric options are checked here, before anything is scaled or compiled;
every mistake raises :class:`~poissonkit.errors.InputError` naming the argument (numbers are
checked by the shared validators of :mod:`poissonkit.validation`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from poissonkit.errors import InputError
from poissonkit.numerics.nbody.bodies import Body
from poissonkit.validation import count, positive_number

#: Fewest members of a cell-listed :class:`AllPairs` for which the parallel pair loop is used
#: by default. On an idle 2-core machine the two loops break even near 1000 bodies and the
#: parallel one is 1.3× faster at 2200 (``benchmarks/bench_nbody_parallel.py``); the margin
#: keeps small systems off the thread pool.
PARALLEL_MIN_BODIES = 1500


class Options(NamedTuple):
    """The checked numeric options of a system (SI, as given)."""

    cutoff: float | None
    smooth_cutoff: float | None
    skin: float | None
    parallel: bool
    parallel_min_bodies: int


def check_bodies(bodies: Sequence[Body]) -> tuple[Body, ...]:
    """``bodies`` as a tuple of :class:`Body` with unique names, at least one.

    Raises
    ------
    InputError
        If there is no body, an entry is not a :class:`Body` or two share a name.
    """
    bodies = tuple(bodies)
    if not bodies:
        raise InputError("NBodySystem needs at least one body")
    for b in bodies:
        if not isinstance(b, Body):
            raise InputError(f"bodies must be Body objects, got {type(b).__name__}")
    names = [b.name for b in bodies]
    if len(set(names)) != len(names):
        raise InputError(f"body names must be unique, got {names}")
    return bodies


def check_options(cutoff: object, smooth_cutoff: object, skin: object, parallel: object,
                  parallel_min_bodies: object) -> Options:
    """The options of :class:`~poissonkit.numerics.nbody.NBodySystem`, checked.

    Raises
    ------
    InputError
        If the cutoff or the skin is not a positive finite number, a smooth cutoff does not lie
        in ``(0, cutoff)``, a smooth cutoff or a skin is given without a cutoff, ``parallel`` is
        not a bool or ``parallel_min_bodies`` not a count.
    """
    cut = None if cutoff is None else positive_number(cutoff, "cutoff")
    rs = None
    if smooth_cutoff is not None:
        if cut is None:
            raise InputError("smooth_cutoff needs a cutoff")
        rs = positive_number(smooth_cutoff, "smooth_cutoff")
        if not rs < cut:
            raise InputError(f"smooth_cutoff must be in (0, cutoff = {cut}), got "
                             f"{smooth_cutoff!r}")
    s = None
    if skin is not None:
        if cut is None:
            raise InputError("skin needs a cutoff")
        if not isinstance(skin, (int, float, np.integer, np.floating)):  # "0.3" is no length
            raise InputError(f"skin must be a positive number, got {skin!r}")
        s = positive_number(skin, "skin")
    if not isinstance(parallel, (bool, np.bool_)):
        raise InputError(f"parallel must be True or False, got {parallel!r}")
    n_min = count(PARALLEL_MIN_BODIES if parallel_min_bodies is None else parallel_min_bodies,
                  "parallel_min_bodies", 0)
    return Options(cut, rs, s, bool(parallel), n_min)

"""Fuzzing the kernel cache folder: damaged, swapped and foreign entries.

A folder holding the entries of four kernels (two signatures, values told apart only by their
closures) is damaged before each example: data and index files swapped between kernels, copied
over each other, truncated at any byte, overwritten with random bytes or single flipped bytes,
emptied, deleted. New dispatchers of every kernel are then called. Property: each returns the
value its own code computes (an entry of another kernel is never run) and nothing raises — the
cache may only cost time (``poissonkit.numerics.jit``).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fuzzkit import FAST, SLOW, outcome, slow
from poissonkit.numerics import jit as jitmod
from poissonkit.numerics.jit import jit


def _scaled(k: float):
    @jit
    def f(x):
        return k * x

    return f


def _pair(k: float):
    @jit
    def f(x, y):
        return k * x + y

    return f


#: (factory, closure value, arguments, expected result)
KERNELS = [(_scaled, 2.0, (1.5,), 3.0), (_scaled, 3.0, (1.5,), 4.5),
           (_pair, 2.0, (1.5, 1.0), 4.0), (_pair, 5.0, (1.5, 1.0), 8.5)]


@pytest.fixture(scope="module")
def pristine(tmp_path_factory) -> Path:
    """A cache folder with the entries of every kernel in :data:`KERNELS`."""
    root = tmp_path_factory.mktemp("pristine")
    mp = pytest.MonkeyPatch()
    mp.setenv(jitmod.CACHE_ENV, str(root))
    try:
        for make, k, args, want in KERNELS:
            assert make(k)(*args) == want
    finally:
        mp.undo()
    assert len(list(root.rglob("*.nbc"))) == len(KERNELS)
    return root


OPS = ["swap", "copy", "truncate", "random", "flip", "empty", "delete"]


@st.composite
def damage(draw):
    """A list of (operation, file kind, first file, second file, position, bytes) steps."""
    steps = []
    for _ in range(draw(st.integers(1, 4))):
        steps.append((draw(st.sampled_from(OPS)), draw(st.sampled_from(["nbc", "nbi"])),
                      draw(st.integers(0, 3)), draw(st.integers(0, 3)),
                      draw(st.floats(0, 1)), draw(st.binary(min_size=0, max_size=64))))
    return steps


def _apply(folder: Path, steps) -> None:
    for op, kind, a, b, pos, blob in steps:
        files = sorted(folder.rglob(f"*.{kind}"))
        if not files:
            continue
        fa, fb = files[a % len(files)], files[b % len(files)]
        if not fa.exists():
            continue
        data = fa.read_bytes()
        cut = int(pos * len(data))
        if op == "swap" and fb.exists() and fa != fb:
            other = fb.read_bytes()
            fb.write_bytes(data)
            fa.write_bytes(other)
        elif op == "copy" and fb.exists():
            fb.write_bytes(data)
        elif op == "truncate":
            fa.write_bytes(data[:cut])
        elif op == "random":
            fa.write_bytes(data[:cut] + blob)
        elif op == "flip" and data:
            i = min(cut, len(data) - 1)
            fa.write_bytes(data[:i] + bytes([data[i] ^ 0xFF]) + data[i + 1:])
        elif op == "empty":
            fa.write_bytes(b"")
        elif op == "delete":
            fa.unlink()


def _check(pristine: Path, tmp: Path, steps) -> None:
    folder = tmp / "cache"
    shutil.rmtree(folder, ignore_errors=True)
    shutil.copytree(pristine, folder)
    _apply(folder, steps)
    mp = pytest.MonkeyPatch()
    mp.setenv(jitmod.CACHE_ENV, str(folder))
    try:
        for make, k, args, want in KERNELS:
            got = outcome("kernel cache entries", lambda: make(k)(*args))
            assert got == want, f"{make.__name__}({k}){args} gave {got}, not {want}"
    finally:
        mp.undo()


@pytest.mark.timeout(600)
@settings(FAST, max_examples=min(FAST.max_examples, 20))  # each example compiles a few kernels
@given(damage())
def test_damaged_cache_entries(pristine, tmp_path_factory, steps):
    _check(pristine, tmp_path_factory.mktemp("c"), steps)


def test_pristine_entries_are_hits(pristine, tmp_path):
    # positive control: undamaged, every kernel is loaded, not compiled
    folder = tmp_path / "cache"
    shutil.copytree(pristine, folder)
    mp = pytest.MonkeyPatch()
    mp.setenv(jitmod.CACHE_ENV, str(folder))
    try:
        for make, k, args, want in KERNELS:
            f = make(k)
            assert f(*args) == want and jitmod.cache_stats(f) == (1, 0)
    finally:
        mp.undo()


@slow
@pytest.mark.timeout(7200)
@SLOW
@given(damage())
def test_damaged_cache_entries_slow(pristine, tmp_path_factory, steps):
    _check(pristine, tmp_path_factory.mktemp("c"), steps)

"""The kit fails a broken potential with a message naming each defect (force off its gradient
by 1 %, an asymmetric pair term, a body attribute the kernel does not read, a parameter that
changes the compiled code), and passes the same potential without the defect."""

from __future__ import annotations

import pytest
from broken_potentials import (
    ALL_BROKEN,
    ASYMMETRIC,
    FORCE_OFF,
    GOOD,
    RECOMPILES,
    UNREAD_ATTRIBUTE,
)

from poissonkit.testing import CheckFailed, check_potential

FAST = ("declaration", "gradient", "orientation", "pair_symmetry", "body_params",
        "runtime_params", "pickle")


def _defects(entry, checks=FAST):
    with pytest.raises(CheckFailed) as info:
        check_potential(entry, checks=checks)
    return info.value


def test_a_correct_potential_passes():
    check_potential(GOOD, checks=FAST)


def test_a_force_one_percent_off_its_gradient_is_named_with_its_size():
    failed = _defects(FORCE_OFF)
    assert "gradient" in {d.check for d in failed.defects}
    text = str(failed)
    assert "kit_force_off" in text and "force on body 2" in text
    # "off by 0.01 relative": the 1 % appears as the size of the mismatch
    (line,) = [d.message for d in failed.defects if d.check == "gradient"]
    size = float(line.split("off by ")[1].split()[0])
    assert 0.005 < size < 0.02


def test_an_asymmetric_pair_term_is_named():
    failed = _defects(ASYMMETRIC)
    assert [d.check for d in failed.defects] == ["pair_symmetry"]
    assert "exchanged" in str(failed) and "q1" in str(failed)


def test_a_body_attribute_the_kernel_does_not_read_is_named():
    failed = _defects(UNREAD_ATTRIBUTE)
    messages = [d.message for d in failed.defects if d.check == "body_params"]
    assert any("'size1'" in m and "does not read it" in m for m in messages)
    assert any("'size2'" in m for m in messages)


def test_a_parameter_that_changes_the_compiled_code_is_named():
    failed = _defects(RECOMPILES)
    assert [d.check for d in failed.defects] == ["runtime_params"]
    assert "'k'" in str(failed) and "compiles a new kernel" in str(failed)


def test_every_defect_of_one_potential_is_listed():
    failed = _defects(ALL_BROKEN)
    checks = {d.check for d in failed.defects}
    assert {"gradient", "pair_symmetry", "body_params", "runtime_params"} <= checks
    assert str(failed).startswith("potential 'kit_all_broken' fails")


@pytest.mark.slow
def test_the_kick_of_a_correct_potential_passes():
    # three bodies in an NBodySystem: momentum, invariance, the energy against the pair kernel
    # summed over the pairs, the documented error for a body without 'charge'
    check_potential(GOOD, checks=("kick",))

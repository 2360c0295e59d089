"""The pieces NBodySystem is built from: input checks, scaling and the kernel table.

Nothing here compiles a kernel: the constructor's checks, the scaled constants and the table
are compared with values worked out by hand.
"""

from __future__ import annotations

import numpy as np
import pytest

from poissonkit.errors import InputError
from poissonkit.numerics.nbody import AllPairs, Body, Interaction, NBodySystem
from poissonkit.numerics.nbody.assemble import _source
from poissonkit.numerics.nbody.options import PARALLEL_MIN_BODIES, check_options
from poissonkit.numerics.nbody.scaling import body_arrays, units_of
from poissonkit.numerics.nbody.table import kernel_table
from poissonkit.numerics.units import Scales


@pytest.mark.parametrize("kw", [
    {"cutoff": "far"}, {"cutoff": -1.0}, {"cutoff": True},
    {"cutoff": 1.0, "smooth_cutoff": 1.0}, {"cutoff": 1.0, "smooth_cutoff": -0.5},
    {"smooth_cutoff": 0.5}, {"skin": 0.1}, {"cutoff": 1.0, "skin": "0.1"},
    {"parallel": 1}, {"parallel_min_bodies": 2.5}, {"parallel_min_bodies": -1},
])
def test_bad_options_raise_input_errors(kw):
    args = {"cutoff": None, "smooth_cutoff": None, "skin": None, "parallel": True,
            "parallel_min_bodies": None} | kw
    with pytest.raises(InputError):
        check_options(**args)


def test_options_are_returned_as_plain_numbers():
    o = check_options(np.float64(2.0), 1, np.int64(1), np.bool_(False), None)
    assert o == (2.0, 1.0, 1.0, False, PARALLEL_MIN_BODIES)
    assert type(o.skin) is float and type(o.parallel) is bool


def test_bodies_are_scaled_into_slots():
    sc = Scales(length=2.0, mass=4.0, time=3.0)
    bodies = [Body("a", 8.0, alpha=0.5), Body("f", 1.0, fixed=True, position=(2.0, 4.0, 6.0)),
              Body("b", 2.0)]
    arr = body_arrays(bodies, units_of(sc))
    assert arr.moving == (0, 2) and arr.tops == (0,)
    assert arr.body_slot.tolist() == [0, -1, 1] and arr.top_slot.tolist() == [0, -1, -1]
    np.testing.assert_array_equal(arr.mass, [2.0, 0.5])        # m / M
    np.testing.assert_array_equal(arr.alpha, [0.5 * 4.0 * 4.0])  # alpha M L²
    np.testing.assert_array_equal(arr.fixed_pos[1], [1.0, 2.0, 3.0])  # r / L


def test_the_kernel_table_shares_kernels_and_lists_pairs():
    bodies = [Body(n, 1.0) for n in "abc"]
    inter = [Interaction("a", "b", "gravity", {"G": 1.0}), Interaction(1, 2, "gravity",
                                                                       {"G": 1.0}),
             AllPairs("gravity", {"G": 2.0})]
    kt = kernel_table(bodies, inter, 1.0, 1.0, False, True)
    # equal values share a kernel number, G = 2 gets its own (its value is a table entry)
    assert len(kt.kerns) == 2 and kt.set_kernel == [1]
    assert kt.radial_pairs == [(0, 1, 0), (1, 2, 0)] and kt.pairs == []
    assert kt.set_members == [0, 1, 2] and kt.set_offsets == [0, 3]
    assert kt.set_central == [1] and kt.gravity_g == [2.0]
    # the run-time values sit in the last row, the masses (bound attributes) above it
    assert sorted(kt.table[-1, list(kt.param_cols)].tolist()) == [1.0, 2.0]
    assert kt.table[:3, kt.attr_cols["mass"]].tolist() == [1.0, 1.0, 1.0]


def test_a_system_keeps_its_unknown_body_error():
    from poissonkit.errors import UnknownNameError

    with pytest.raises(UnknownNameError):
        NBodySystem([Body("a", 1.0), Body("b", 1.0)], [Interaction("a", "zz", "gravity")])


def test_the_generated_kick_pushes_each_term_after_evaluating_it():
    """r and ν are constant in a kick: term k is cleared, evaluated and pushed in turn, so the
    kick of a sum is the kicks of its terms (what makes the field kick exact)."""
    src = _source(2)
    kick = src[src.index("def kick("):src.index("def kick_compensated(")]
    body = [ln.strip() for ln in kick.splitlines()[1:] if ln.strip()]
    assert body == ["gather_i(y, data, work)",
                    "clear(data, work)", "t0_i(data, work)", "push_plain(y, y, h, data, work)",
                    "clear(data, work)", "t1_i(data, work)", "push_plain(y, y, h, data, work)"]
    comp = src[src.index("def kick_compensated("):]
    assert comp.count("push_compensated(y, c, h, data, work)") == 2

"""``pair_interaction``: parameter handling, registry contract and typed errors."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from poissonkit.errors import InputError, PoissonkitError, UnknownNameError
from poissonkit.pairs import OverlapError, cylinder_gap, pair_interaction
from poissonkit.plugin import potential

A, H, M = 1.25e-3, 20e-3, 1.58359e6
Z = (0.0, 0.0, 1.0)


def test_registered_names_and_parameters_follow_the_architecture_table():
    root = Path(__file__).resolve().parents[2]
    text = (root / "docs" / "architecture.md").read_text()
    table = text[text.index("## Magnet potential names and parameters"):]
    rows = re.findall(r"^\| `(\w+)` \| (.+) \|$", table, flags=re.M)
    assert {name for name, _ in rows} >= {"dipole", "dumbbell", "dumbbell_octupole", "cylinder"}
    for name, cell in rows:
        documented = set(re.findall(r"`(\w+)`", cell.split("—")[0].split(";")[0]))
        declared = {p.name for p in potential(name).params}
        assert documented <= declared, (name, documented - declared)
        assert "mu0" in declared
        required = {p.name for p in potential(name).params if p.default is None}
        assert required <= documented, (name, required - documented)


def test_moment_and_magnetization_shorthands_agree():
    rvec, n2 = (0.01, 0.02, 0.04), (0.6, 0.0, 0.8)
    mu = M * math.pi * A * A * H
    for model in ("dipole", "dumbbell", "dumbbell_octupole", "cylinder"):
        a = pair_interaction(model, rvec, Z, n2, magnetization=M, radius=A, length=H)
        b = pair_interaction(model, rvec, Z, n2, moment=mu, radius=A, length=H)
        assert a.energy == pytest.approx(b.energy, rel=1e-13)
        assert np.allclose(a.force, b.force, rtol=1e-13, atol=0)


def test_dumbbell_from_length_puts_poles_on_the_end_faces():
    mu = 0.15
    a = pair_interaction("dumbbell", (0.01, 0, 0.04), Z, Z, moment=mu, length=H)
    b = pair_interaction("dumbbell", (0.01, 0, 0.04), Z, Z, moment=mu, half_length=H / 2)
    assert a.energy == b.energy


def test_registered_kernels_match_direct_evaluation():
    from poissonkit.numerics.potentials import compile_potential
    from poissonkit_magnets.models import evaluate

    point = (0.03, 0.3, 0.5, 0.8)
    for name, params in (("dumbbell", dict(moment1=0.1, moment2=0.2, half_length1=0.01,
                                           half_length2=0.004)),
                         ("cylinder", dict(magnetization1=M, magnetization2=M, radius1=A,
                                           radius2=A, length1=H, length2=H))):
        entry = potential(name)
        kern = compile_potential(entry, params)
        want = evaluate(name, entry.resolve_params(params), *point)
        assert np.allclose(kern(*point), want, rtol=1e-12, atol=0)


def test_gap_between_cylinders_is_exact_in_simple_placements():
    z, x = np.array(Z), np.array([1.0, 0, 0])
    assert cylinder_gap(np.array([0, 0, 0.025]), z, z, A, H, A, H) == pytest.approx(0.005, rel=1e-9)
    assert cylinder_gap(np.array([0.004, 0, 0]), z, z, A, H, A, H) == pytest.approx(0.0015, rel=1e-9)
    # T: body 2 lies along x; its end face at x - h/2 faces body 1's side at radius a
    assert cylinder_gap(np.array([0.015, 0, 0]), z, x, A, H, A, H) == pytest.approx(
        0.015 - H / 2 - A, rel=1e-9)
    assert cylinder_gap(np.array([0.0, 0, 0.019]), z, z, A, H, A, H) == 0.0 or \
        cylinder_gap(np.array([0.0, 0, 0.019]), z, z, A, H, A, H) < 1e-12


@pytest.mark.parametrize("kwargs,err", [
    (dict(model="dipole", r=(0, 0, 0)), InputError),
    (dict(model="dipole", nu1=(0, 0, 2)), InputError),
    (dict(model="dipole", nu1=(0, 0, 0)), InputError),
    (dict(model="dipole", r=(0, 1)), InputError),
    (dict(model="dipole", r=(0, float("nan"), 1)), InputError),
    (dict(model="quadrupole"), UnknownNameError),
    (dict(model="cylinder", r=(0, 0, 0.019)), OverlapError),
    (dict(model="dipole", r=(0.002, 0, 0)), OverlapError),
    (dict(model="auto"), InputError),
    (dict(model="dipole", tol=0.1), InputError),
])
def test_bad_input_raises_typed_errors(kwargs, err):
    args = dict(model="cylinder", r=(0, 0, 0.05), nu1=Z, nu2=Z)
    args.update(kwargs)
    params = dict(magnetization=M, radius=A, length=H)
    if "tol" in args:
        params["tol"] = args.pop("tol")
    with pytest.raises(err) as info:
        pair_interaction(args["model"], args["r"], args["nu1"], args["nu2"], **params)
    assert isinstance(info.value, PoissonkitError)


def test_bad_parameters_name_the_parameter():
    with pytest.raises(InputError, match="radius1"):
        pair_interaction("cylinder", (0, 0, 0.05), Z, Z, magnetization=M, radius1=-A, radius2=A,
                         length=H)
    with pytest.raises(UnknownNameError, match="available"):
        pair_interaction("dipole", (0, 0, 0.05), Z, Z, moment=1.0, colour=3)
    with pytest.raises(InputError, match="moment"):
        pair_interaction("dipole", (0, 0, 0.05), Z, Z, moment=1.0, moment1=2.0)
    with pytest.raises(InputError, match="moment2"):
        pair_interaction("dipole", (0, 0, 0.05), Z, Z, moment1=1.0)


def test_coinciding_dumbbell_poles_are_rejected():
    with pytest.raises(OverlapError, match="poles"):
        pair_interaction("dumbbell", (0, 0, 0.02), Z, Z, moment=1.0, half_length=0.01)


def test_result_is_frozen():
    out = pair_interaction("dipole", (0, 0, 0.1), Z, Z, moment=0.155)
    with pytest.raises(Exception):
        out.energy = 0.0  # type: ignore[misc]
    with pytest.raises(ValueError):
        out.force[0] = 1.0
    # coaxial head-to-tail dipoles attract: F_z = -3 mu0 m^2 / (2 pi r^4)
    assert out.force[2] == pytest.approx(-3 * 4e-7 * math.pi * 0.155 ** 2 / (2 * math.pi * 1e-4),
                                         rel=1e-12)


def test_gap_solver_sees_a_shallow_overlap_where_projections_stall():
    """Alternating projections alone stopped at a 2.3e-7 m 'gap' here; the point ``p`` lies
    inside both cylinders (checked by hand below), so they overlap and the gap is 0."""
    d = np.array([0.00286215272301578, -0.0002983514479855422, -0.007181162440633968])
    n1 = np.array([0.4240197655771679, 0.08927763208823554, 0.901241778219697])
    n2 = np.array([-0.5961312043223734, 0.4136988690366563, 0.6880994353950219])
    p = np.array([-0.00086576, 0.00086079, -0.00305685])
    for centre, axis in ((np.zeros(3), n1), (d, n2)):
        q = p - centre
        z = q @ axis
        assert abs(z) < H / 2 and np.linalg.norm(q - z * axis) < A
    assert cylinder_gap(d, n1 / np.linalg.norm(n1), n2 / np.linalg.norm(n2), A, H, A, H) == 0.0
    with pytest.raises(OverlapError):
        pair_interaction("dipole", d, n1 / np.linalg.norm(n1), n2 / np.linalg.norm(n2),
                         moment=0.1, radius=A, length=H)


def test_auto_asks_the_magnet_family_which_uses_the_one_fidelity_estimator():
    from poissonkit_magnets.fidelity import cheapest_model, estimated_error

    n2 = np.array([0.6, 0.0, 0.8])
    for dist in (0.03, 0.05, 0.1, 0.3):
        for tol in (1e-2, 1e-4):
            r = dist * np.array([0.0, 0.6, 0.8])
            out = pair_interaction("auto", r, Z, n2, magnetization=M, radius=A, length=H, tol=tol)
            assert out.model == cheapest_model(tol, dist, A, H)
            assert out.estimated_error == estimated_error(out.model, dist, A, H)

"""Kernels compiled without numba's reference counts (issue 33: tops on the lean path).

The kernels of a sum of force terms that allocate nothing (listed pairs, all pairs without
cutoff, the direct sum, external fields) are compiled without reference counts
(:mod:`poissonkit.numerics.nbody.assemble`). Checked here: which systems get them; that their
forces and torques are the closed-form ones of two point dipoles (independent truth); that a
kick, the right-hand side and the energy are the same bits as the kernels compiled with the
counts; that the potential and field dispatchers go without counts unless a kernel allocates;
and that many calls from Python and from a compiled loop leave the arrays intact.
"""

from __future__ import annotations

import numpy as np
import pytest

from poissonkit import field
from poissonkit.numerics.jit import jit
from poissonkit.numerics.nbody import AllPairs, Body, Interaction, NBodySystem
from poissonkit.numerics.nbody.loops import _build_kernels
from poissonkit.numerics.nbody.pairkernels import _dispatcher

MU0 = 4e-7 * np.pi
MOMENT = (0.3, 0.2)


def _dipoles(fixed: bool = False, **kw: object) -> tuple[NBodySystem, np.ndarray]:
    """Two dipole tops (SI, unit masses and ``alpha``), optionally a fixed third one."""
    bodies = [Body("a", 1.0, 1.0), Body("b", 1.0, 1.0)]
    inter: list[Interaction | AllPairs] = [
        Interaction(0, 1, "dipole", {"moment1": MOMENT[0], "moment2": MOMENT[1]})]
    if fixed:
        bodies.append(Body("pin", 1.0, 1.0, fixed=True, position=(0.0, 0.4, 0.1),
                           axis=(0.0, 0.0, 1.0)))
        inter.append(Interaction(1, 2, "dipole", {"moment1": 0.2, "moment2": 0.1}))
    s = NBodySystem(bodies, inter, **kw)
    nu = np.array([[0.3, -0.5, 0.8], [-0.6, 0.2, 0.7]])
    y = s.pack([[0.01, -0.02, 0.03], [0.21, 0.05, -0.04]], [[0.1, 0.0, -0.2], [0.0, 0.3, 0.1]],
               nu, [[0.01, 0.02, -0.03], [0.0, -0.01, 0.02]], normalize=True)
    return s, y


def _closed_form(y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Force on b, torques on a and b, energy of two point dipoles (Jackson 5.56, τ = m × B)."""
    r1, r2, n1, n2 = y[0:3], y[6:9], y[12:15], y[18:21]
    m1, m2 = MOMENT[0] * n1, MOMENT[1] * n2
    d = r2 - r1
    r = np.linalg.norm(d)
    e = d / r
    k = MU0 / (4 * np.pi)
    u = k / r**3 * (m1 @ m2 - 3 * (m1 @ e) * (m2 @ e))
    f2 = 3 * k / r**4 * ((m1 @ e) * m2 + (m2 @ e) * m1 + (m1 @ m2) * e
                         - 5 * (m1 @ e) * (m2 @ e) * e)
    b_at_2 = k / r**3 * (3 * (m1 @ e) * e - m1)
    b_at_1 = k / r**3 * (3 * (m2 @ e) * e - m2)
    return f2, np.cross(m1, b_at_1), np.cross(m2, b_at_2), float(u)


def _counted(s: NBodySystem):
    extra = ()
    if s.fields:
        from poissonkit.numerics.fields.compose import field_term

        extra = (field_term(s._field_kerns),)
    return _build_kernels(*_dispatcher(s._kerns, s._rkerns), verlet=s.skin is not None,
                          extra=extra, cells=s.cutoff is not None, counted=True)


def _uncounted(kernel: object) -> bool:
    return kernel.targetoptions.get("_nrt") is False


def test_which_systems_go_without_reference_counts():
    from poissonkit.numerics.fields.compose import field_dispatcher

    s, _ = _dipoles()
    assert all(_uncounted(k) for k in (s.kernels.kick, s.kernels.kick_compensated,
                                       s.kernels.rhs, s.kernels.energy))
    # the potential's dispatchers too: the registry's dipole allocates nothing
    assert all(_uncounted(d) for d in _dispatcher(s._kerns, s._rkerns))
    with_field = s.with_fields([field("uniform", B=[0.0, 0.01, 0.02])])
    assert _uncounted(with_field.kernels.kick)
    assert _uncounted(field_dispatcher(with_field._field_kerns))
    # a cutoff builds a cell list (it allocates): the counts stay
    cut, _ = _dipoles(cutoff=1.0)
    assert not _uncounted(cut.kernels.kick) and not _uncounted(cut.kernels.rhs)
    planets = NBodySystem([Body("s", 1.0), Body("p", 1e-3)], [AllPairs("gravity", {"G": 1.0})])
    assert _uncounted(planets.kernels.rhs)


def test_forces_and_torques_are_those_of_two_point_dipoles():
    s, y = _dipoles()
    out = np.empty_like(y)
    s.kernels.rhs(y, s.data, s.work(), out)
    f2, t1, t2, u = _closed_form(y)
    scale = np.linalg.norm(f2)
    assert np.allclose(out[9:12], f2, rtol=0, atol=1e-13 * scale)
    assert np.allclose(out[3:6], -f2, rtol=0, atol=1e-13 * scale)
    tscale = max(np.linalg.norm(t1), np.linalg.norm(t2))
    assert np.allclose(out[15:18], t1, rtol=0, atol=1e-13 * tscale)
    assert np.allclose(out[21:24], t2, rtol=0, atol=1e-13 * tscale)
    kinetic = 0.5 * (y[3:6] @ y[3:6] + y[9:12] @ y[9:12] + y[15:18] @ y[15:18]
                     + y[21:24] @ y[21:24])
    assert float(s.energy(y)) == pytest.approx(kinetic + u, rel=1e-13)


def test_a_kick_is_the_same_bits_as_with_reference_counts():
    """The default suite's share of the next test: one kick (the rest compiles ~50 s cold)."""
    s, y = _dipoles(fixed=True)
    got = []
    for k in (s.kernels, _counted(s)):
        yk = y.copy()
        k.kick(yk, 1e-3, s.data, s.work())
        got.append(yk)
    assert got[0].tobytes() == got[1].tobytes() and not np.array_equal(got[0], y)


@pytest.mark.slow
@pytest.mark.parametrize("case", ["listed", "fixed", "all_pairs", "field"])
def test_same_bits_as_the_kernels_with_reference_counts(case: str):
    if case == "all_pairs":
        s = NBodySystem([Body(f"t{k}", 1.0, 1.0) for k in range(4)],
                        [AllPairs("dipole", {"moment1": 0.2, "moment2": 0.2})])
        rng = np.random.default_rng(1)
        y = s.pack(np.arange(12.0).reshape(4, 3) * 0.07 + 0.01 * rng.standard_normal((4, 3)),
                   rng.standard_normal((4, 3)), rng.standard_normal((4, 3)),
                   rng.standard_normal((4, 3)), normalize=True)
    else:
        s, y = _dipoles(fixed=case == "fixed")
        if case == "field":
            s = s.with_fields([field("gravity", g=[0.0, 0.0, -9.81])])
    new, old = s.kernels, _counted(s)
    assert _uncounted(new.kick) and not _uncounted(old.kick)
    got = []
    for k in (new, old):
        yk, ck = y.copy(), np.zeros_like(y)
        k.kick(yk, 1e-3, s.data, s.work())
        k.kick_compensated(yk, ck, 1e-3, s.data, s.work())
        r = np.empty_like(y)
        k.rhs(y, s.data, s.work(), r)
        w = s.work()
        u = k.forces(y, s.data, w)
        got.append([yk, ck, r, np.array([k.energy(y, s.data, s.work()), u]), w.F, w.T])
    for a, b in zip(*got):
        assert a.tobytes() == b.tobytes()


def test_many_calls_from_python_and_from_a_compiled_loop():
    s, y = _dipoles(fixed=True)
    kick = s.kernels.kick

    @jit
    def loop(y, data, work, n):
        for _ in range(n):
            kick(y, 1e-6, data, work)

    data, work = s.data, s.work()
    y1, y2 = y.copy(), y.copy()
    for _ in range(2000):
        kick(y1, 1e-6, data, work)
    loop(y2, data, work, 2000)
    assert y1.tobytes() == y2.tobytes()
    # the arrays the kernels read are still the system's own, unchanged and usable
    assert np.array_equal(s.data.fixed_pos[2], [0.0, 0.4, 0.1])
    assert np.isfinite(float(s.energy(y1)))


def test_a_potential_that_allocates_still_compiles_and_agrees():
    """A user's numba kernel may allocate arrays: it is compiled with reference counts even
    when the pair loop that calls it is not (and gives the sympy form's numbers)."""
    import numba
    import sympy as sp

    @numba.njit
    def gas(r, c1, c2, c3):
        w = np.array([c3 - 3.0 * c1 * c2, r ** -3])  # allocates
        return (w[0] * w[1], -3.0 * w[0] * w[1] / r, -3.0 * c2 * w[1], -3.0 * c1 * w[1],
                w[1])

    r, c1, c2, c3 = sp.symbols("r c1 c2 c3", real=True)
    out = []
    for pot in (gas, (c3 - 3 * c1 * c2) / r**3):
        s = NBodySystem([Body("a", 1.0, 1.0), Body("b", 1.0, 1.0)], [Interaction(0, 1, pot)])
        assert _uncounted(s.kernels.rhs)
        # its dispatcher keeps the counts (a failure without them is not repeated to the
        # counted compilation); the sympy form's goes without
        assert _uncounted(_dispatcher(s._kerns, s._rkerns)[0]) is (pot is not gas)
        y = s.pack([[0.0, 0.0, 0.0], [1.1, 0.3, -0.2]], np.zeros((2, 3)),
                   [[0.0, 0.6, 0.8], [1.0, 0.0, 0.0]], [[0.1, 0.0, 0.0], [0.0, 0.2, 0.0]])
        rhs = s.rhs(0.0, y)
        out.append(np.append(rhs, s.energy(y)))
    assert np.allclose(out[0], out[1], rtol=1e-13, atol=1e-15)


def test_a_field_kernel_that_allocates_keeps_its_counts():
    """The field dispatcher goes without counts unless its kernel allocates; either way it
    gives the field's energy and gradient (here ``U = c g z``: a uniform weight)."""
    import numba

    from poissonkit.numerics.fields.compose import field_dispatcher

    @numba.njit
    def weight(x, y, z, n0, n1, n2, c, P):
        return (c * P[0] * z, 0.0, 0.0, c * P[0], 0.0, 0.0, 0.0)

    @numba.njit
    def weight_via_array(x, y, z, n0, n1, n2, c, P):
        g = np.array([0.0, 0.0, c * P[0]])  # allocates
        return (g[2] * z, g[0], g[1], g[2], 0.0, 0.0, 0.0)

    for kernel, counted in ((weight, False), (weight_via_array, True)):
        d = field_dispatcher((kernel,))
        assert _uncounted(d) is not counted
        got = d(0, 0.1, 0.2, 0.5, 0.0, 0.0, 1.0, 2.0, np.array([9.81]))
        assert got == pytest.approx((2.0 * 9.81 * 0.5, 0.0, 0.0, 2.0 * 9.81, 0.0, 0.0, 0.0),
                                    rel=1e-15)

"""The compiled-kernel contract shared by every numerics system, and small numba helpers.

A system usable by the compiled integrators exposes ``kernels`` (a :class:`Kernels`), ``data``
(a ``NamedTuple`` of numpy arrays / numbers passed to every kernel, read by name) and ``work()``
(fresh scratch arrays, also a ``NamedTuple``).
All kernels are numba ``njit`` functions with these signatures:

* ``rhs(y, data, work, out)`` — writes ``ẏ`` into ``out``;
* ``drift(y, h, data)`` — exact flow of the kinetic part for time ``h``, in place (may be a
  no-op placeholder for systems that are not split);
* ``kick(y, h, data, work)`` — exact flow of the potential part for time ``h``, in place;
* ``energy(y, data, work) -> float``;
* ``min_distance(y, data, work) -> float`` — smallest distance between two bodies (``inf`` if
  there is none), for collision events and adaptive steps;
* ``max_radius(y, data) -> float`` — largest distance of a moving body from the centre of mass
  of the moving bodies, for escape events;
* ``jac(y, data, work, out)`` — optional Jacobian ``∂ẏ/∂y`` (``None`` when not available);
* ``forces(y, data, work) -> float`` — optional: the potential's forces and torques into the
  system's work arrays, returning the potential energy ``U``; N-body systems write every body's
  rows into ``work.F``, ``work.T``, the two-body system writes ``(ṗ, ṁ', ṁ'')`` into
  ``work.partials``; used by integrators that split the Hamiltonian differently (Wisdom–Holman,
  the time-transformed splitting).
* ``drift_compensated(y, c, h, data)``, ``kick_compensated(y, c, h, data, work)`` — optional:
  the same flows with every increment added by Kahan-compensated summation
  (:func:`kahan_add`); ``c`` (same shape as ``y``) carries the rounding error of the sums so
  far, the state being ``y − c``. ``None`` when the system has no compensated kernels.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple, cast

import numba
import numpy as np
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic

from poissonkit.contracts import CompiledFunction
from poissonkit.numerics.linalg import gauss_solve  # noqa: F401  (the one LU solver; importable here as before)


class Kernels(NamedTuple):
    """The compiled functions of one system (see the module docstring); the built-in
    implementation of :class:`poissonkit.contracts.CompiledKernels`."""

    rhs: CompiledFunction
    drift: CompiledFunction
    kick: CompiledFunction
    energy: CompiledFunction
    min_distance: CompiledFunction
    max_radius: CompiledFunction
    jac: CompiledFunction | None = None
    splittable: bool = True
    forces: CompiledFunction | None = None
    drift_compensated: CompiledFunction | None = None
    kick_compensated: CompiledFunction | None = None


@numba.njit(cache=True, error_model="numpy", inline="always")
def _unit_axis(y, mbase):
    """``(|m|, m/|m|)`` of ``m = y[mbase:mbase+3]`` (``(0, 0, 0, 0)`` for ``m = 0``)."""
    m0 = y[mbase]
    m1 = y[mbase + 1]
    m2 = y[mbase + 2]
    mm = math.sqrt(m0 * m0 + m1 * m1 + m2 * m2)
    if mm == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    return mm, m0 / mm, m1 / mm, m2 / mm


@numba.njit(cache=True, error_model="numpy")
def rotate_slot(y, base, mbase, theta_per_norm):
    """In-place Rodrigues rotation of ``y[base:base+3]`` about ``y[mbase:mbase+3]``."""
    mm, k0, k1, k2 = _unit_axis(y, mbase)
    if mm == 0.0:
        return
    th = theta_per_norm * mm
    c = math.cos(th)
    s = math.sin(th)
    n0 = y[base]
    n1 = y[base + 1]
    n2 = y[base + 2]
    kd = (k0 * n0 + k1 * n1 + k2 * n2) * (1.0 - c)
    x0 = k1 * n2 - k2 * n1
    x1 = k2 * n0 - k0 * n2
    x2 = k0 * n1 - k1 * n0
    y[base] = n0 * c + x0 * s + k0 * kd
    y[base + 1] = n1 * c + x1 * s + k1 * kd
    y[base + 2] = n2 * c + x2 * s + k2 * kd


@intrinsic
def _inverse_powers4(typingctx, x0, x1, x2, x3):
    """``(1/√x_k for k < 4, 1/(x_k √x_k) for k < 4)``: eight floats from four, in one 4-lane
    vector (one ``vsqrtpd`` and two ``vdivpd`` instead of four square roots and eight
    divisions, which queue on the one divider).

    Each lane is the IEEE-rounded ``sqrt``, product and quotient, so every value has the bits
    of ``1.0 / math.sqrt(x)`` and ``1.0 / (x * math.sqrt(x))``; divisions are unchecked
    (``1/0 = inf``, as ``error_model="numpy"``). For pair kernels that sum over pairs of
    poles or charges (four distances per pair of bodies).
    """
    f8 = types.float64
    sig = types.UniTuple(f8, 8)(f8, f8, f8, f8)

    def codegen(context, builder, signature, args):
        vec = ir.VectorType(ir.DoubleType(), 4)
        lane = [ir.Constant(ir.IntType(32), k) for k in range(4)]
        x = ir.Constant(vec, ir.Undefined)
        for k, a in enumerate(args):
            x = builder.insert_element(x, a, lane[k])
        sqrt = cgutils.get_or_insert_function(builder.module, ir.FunctionType(vec, [vec]),
                                              "llvm.sqrt.v4f64")
        root = builder.call(sqrt, [x])
        one = ir.Constant(vec, [1.0] * 4)
        inv = builder.fdiv(one, root)
        inv3 = builder.fdiv(one, builder.fmul(x, root))
        out = [builder.extract_element(v, lane[k]) for v in (inv, inv3) for k in range(4)]
        return context.make_tuple(builder, signature.return_type, out)

    return sig, codegen


#: :func:`_inverse_powers4` as its callers see it (numba supplies ``typingctx`` itself); the
#: same object, typed for the checker
inverse_powers4 = cast("Callable[[float, float, float, float], tuple[float, float, float, "
                       "float, float, float, float, float]]", _inverse_powers4)


@numba.njit(cache=True, error_model="numpy", inline="always")
def plain_add(y, c, i, inc):
    """``y[i] += inc`` (``c`` unused): the uncompensated counterpart of :func:`kahan_add`, so
    that one kernel source, given either, compiles to the plain or the compensated sum."""
    y[i] += inc


@numba.njit(cache=True, error_model="numpy", inline="always")
def pair_forces(u, ur, u1, u2, u3, ex, ey, ez, inv, c1, c2, a0, a1, a2, b0, b1, b2):
    """``(U, f, τ_i, τ_j)`` (ten floats) of a pair from the partials of ``U(r, c1, c2, c3)``.

    ``e = (ex, ey, ez)`` is the unit vector from body i to body j, ``inv = 1/r``, ``a = ν_i``,
    ``b = ν_j``, ``c1 = (e, a)``, ``c2 = (e, b)`` (:mod:`poissonkit.conventions`). ``f`` is the
    force on j (Zub's seed, eq. 20; −f on i): the projections ``(ν − c e)/r`` come from
    ``∂c/∂r_j``. The torques are ``τ_i = U_c1 e × a − U_c3 a × b`` and
    ``τ_j = U_c2 e × b + U_c3 a × b``. Inlined into every pair kernel (the N-body pair term and
    the two-body kick), so all compute these numbers with the same operations.
    """
    w0 = a1 * b2 - a2 * b1
    w1 = a2 * b0 - a0 * b2
    w2 = a0 * b1 - a1 * b0
    return (u,
            -(ur * ex + (u1 * (a0 - c1 * ex) + u2 * (b0 - c2 * ex)) * inv),
            -(ur * ey + (u1 * (a1 - c1 * ey) + u2 * (b1 - c2 * ey)) * inv),
            -(ur * ez + (u1 * (a2 - c1 * ez) + u2 * (b2 - c2 * ez)) * inv),
            u1 * (ey * a2 - ez * a1) - u3 * w0,
            u1 * (ez * a0 - ex * a2) - u3 * w1,
            u1 * (ex * a1 - ey * a0) - u3 * w2,
            u2 * (ey * b2 - ez * b1) + u3 * w0,
            u2 * (ez * b0 - ex * b2) + u3 * w1,
            u2 * (ex * b1 - ey * b0) + u3 * w2)


@numba.njit(cache=True, error_model="numpy", inline="always")
def kahan_add(y, c, i, inc):
    """``y[i] += inc`` with Kahan's compensated summation (Comm. ACM 8 (1965) 40).

    ``c[i]`` holds what the additions so far added too much, so ``y[i] − c[i]`` is the sum to
    about one rounding of the result whatever the number of increments (plain ``+=`` loses one
    rounding per step, which dominates long runs at small steps).
    """
    v = inc - c[i]
    t = y[i] + v
    c[i] = (t - y[i]) - v
    y[i] = t


@numba.njit(cache=True, error_model="numpy", inline="always")
def rotate_slot_compensated(y, c, base, mbase, theta_per_norm):
    """:func:`rotate_slot` written as an increment ``ν += −(1 − cos θ)(ν − (k·ν)k) + sin θ k × ν``
    added with :func:`kahan_add` (``1 − cos θ = 2 sin²(θ/2)``, free of cancellation): a small
    rotation changes ``ν`` by a small increment, whose rounding the compensation keeps."""
    mm, k0, k1, k2 = _unit_axis(y, mbase)
    if mm == 0.0:
        return
    th = theta_per_norm * mm
    sh = math.sin(0.5 * th)
    omc = 2.0 * sh * sh
    s = math.sin(th)
    n0 = y[base]
    n1 = y[base + 1]
    n2 = y[base + 2]
    kn = k0 * n0 + k1 * n1 + k2 * n2
    kahan_add(y, c, base, -omc * (n0 - kn * k0) + s * (k1 * n2 - k2 * n1))
    kahan_add(y, c, base + 1, -omc * (n1 - kn * k1) + s * (k2 * n0 - k0 * n2))
    kahan_add(y, c, base + 2, -omc * (n2 - kn * k2) + s * (k0 * n1 - k1 * n0))


@numba.njit(cache=True, error_model="numpy")
def copy_row_compensated(src, comp, dst, row):
    """``dst[row, :] = src − comp`` (the state of a compensated loop)."""
    for i in range(src.shape[0]):
        dst[row, i] = src[i] - comp[i]


@numba.njit(cache=True, error_model="numpy")
def no_drift(y, h, data):
    """Placeholder drift for systems that are not split (never called by the splitting)."""
    return


@numba.njit(cache=True, error_model="numpy")
def all_finite(y):
    """True if every entry of ``y`` is finite."""
    for i in range(y.shape[0]):
        if not np.isfinite(y[i]):
            return False
    return True


@numba.njit(cache=True, error_model="numpy")
def copy_into(src, dst):
    """``dst[:] = src`` for 1-D arrays (explicit loop: cheap to compile)."""
    for i in range(src.shape[0]):
        dst[i] = src[i]


@numba.njit(cache=True, error_model="numpy")
def copy_row(src, dst, row):
    """``dst[row, :] = src``."""
    for i in range(src.shape[0]):
        dst[row, i] = src[i]


@numba.njit(cache=True, error_model="numpy")
def zero2(a):
    """``a[:, :] = 0``."""
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            a[i, j] = 0.0

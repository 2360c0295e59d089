"""Deformed e(3) brackets of the non-holonomic survey (seed 001), in ``[v]_eps`` form.

Exact formulas: the survey's equations cited on each function. Every matrix here is written with
``[v]_eps`` (``[v]_eps[i, j] = eps_ijk v_k``, :func:`~poissonkit.structure.blocks.eps_matrix`);
the survey prints some of them with the standard hat ``v^ = -[v]_eps``, i.e. as the overall
negative. Variables are ``(gamma, M)`` (or ``(gamma, K)``), coordinates named like
:func:`~poissonkit.structure.e3`: ``gamma_x, gamma_y, gamma_z, M_x, M_y, M_z``.

Flow sign: the survey's body-frame systems read ``X = g^{-1} {H, x} = -g^{-1} P dH``; with
poissonkit's ``X = N P dH`` (:mod:`poissonkit.conventions`) take the multiplier ``N = -1/g``
(see :func:`chaplygin_ball_system`).

Functions ``g``, ``f``, ``phi`` of ``gamma`` may be given as

* ``None``: an undefined sympy function ``g(gamma_x, gamma_y, gamma_z)`` (results hold for all g);
* a sympy expression in the ``gamma`` symbols (see :func:`gamma_symbols`) and parameters;
* a string, parsed with the allow-list parser (names: the gamma coordinates);
* a callable ``g(gamma) -> expression`` receiving the three gamma symbols.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import sympy as sp

from poissonkit.errors import DimensionError, InputError
from poissonkit.structure._expr import as_expr
from poissonkit.structure.bivector import Bivector
from poissonkit.structure.blocks import eps_matrix
from poissonkit.structure.parsing import parse_expression

_AXES = ("x", "y", "z")

FunctionSpec = sp.Expr | str | Callable[..., sp.Expr] | float | int | None


def gamma_symbols(names: tuple[str, str] = ("gamma", "M")) -> tuple[tuple[sp.Symbol, ...],
                                                                     tuple[sp.Symbol, ...]]:
    """The coordinate symbols ``(gamma, M)`` used by every bracket of this module."""
    if len(names) != 2 or not all(isinstance(n, str) and n for n in names):
        raise InputError(f"names must be two non-empty strings, got {names!r}")
    if names[0] == names[1]:
        raise InputError(f"the two vector names must differ, got {names!r}")
    g = tuple(sp.Symbol(f"{names[0]}_{a}", real=True) for a in _AXES)
    m = tuple(sp.Symbol(f"{names[1]}_{a}", real=True) for a in _AXES)
    return g, m


def _dot(a: Sequence, b: Sequence) -> sp.Expr:
    return sum((x * y for x, y in zip(a, b)), sp.Integer(0))


def _function_of(spec: FunctionSpec, name: str, gamma: Sequence[sp.Symbol],
                 forbidden: Sequence[sp.Symbol]) -> sp.Expr:
    """Read a user function of ``gamma`` (see module docstring)."""
    if spec is None:
        return sp.Function(name)(*gamma)
    if isinstance(spec, str):
        expr = parse_expression(spec, gamma)
    elif callable(spec) and not isinstance(spec, sp.Basic):
        expr = as_expr(spec(tuple(gamma)), f"{name} (value returned by the callable)")
    else:
        try:
            expr = sp.sympify(spec, strict=True)
        except sp.SympifyError:
            raise InputError(f"{name} must be an expression, string or callable, "
                             f"got {type(spec).__name__}") from None
    bad = expr.free_symbols & set(forbidden)
    if bad:
        raise InputError(f"{name} must be a function of gamma only, but depends on "
                         f"{', '.join(sorted(map(str, bad)))}")
    return expr


def _vector(spec, name: str, default: str, positive: bool = False) -> tuple[sp.Expr, ...]:
    if spec is None:
        return tuple(sp.Symbol(f"{default}{i}", positive=positive or None, real=True)
                     for i in (1, 2, 3))
    try:
        vals = tuple(sp.sympify(v, strict=True) if not isinstance(v, sp.Basic) else v for v in spec)
    except (TypeError, sp.SympifyError):
        raise InputError(f"{name} must be a sequence of three numbers or symbols") from None
    if len(vals) != 3:
        raise DimensionError(f"{name} must have 3 components, got {len(vals)}")
    return vals


def _scalar(spec, name: str, positive: bool = True) -> sp.Expr:
    if spec is None:
        return sp.Symbol(name, positive=positive or None, real=True)
    try:
        return spec if isinstance(spec, sp.Basic) else sp.sympify(spec, strict=True)
    except sp.SympifyError:
        raise InputError(f"{name} must be a number or symbol, got {spec!r}") from None


def _assemble(gamma, M, upper: sp.Matrix, lower: sp.Matrix) -> Bivector:
    """``[[0, upper], [upper, lower]]`` on ``(gamma, M)`` (upper = g Gamma is symmetric-free)."""
    mat = sp.zeros(6, 6)
    mat[0:3, 3:6] = upper
    mat[3:6, 0:3] = upper
    mat[3:6, 3:6] = lower
    return Bivector.from_matrix(mat, tuple(gamma) + tuple(M))


# ---------------------------------------------------------------------- families
def p_gf(g: FunctionSpec = None, f: FunctionSpec = None, phi: FunctionSpec = 0,
         names: tuple[str, str] = ("gamma", "M")) -> Bivector:
    """The family ``P_{g,f}`` of survey (22)/(23) with Remark 5's term.

    ``{gamma_i, gamma_j} = 0``, ``{M_i, gamma_j} = g eps_ijk gamma_k``,
    ``{M_i, M_j} = eps_ijk [g M_k + ((grad g, M) - g f (gamma, M) + phi) gamma_k]``.
    Poisson for all ``g, f, phi``; Casimirs ``(gamma, gamma)`` and ``(gamma, M)``.

    Parameters
    ----------
    g, f, phi
        Functions of ``gamma`` (module docstring). ``g=None`` and ``f=None`` give undefined
        functions ``g(gamma)``, ``f(gamma)``; ``phi=None`` an undefined ``phi(gamma)``.
        Defaults: ``g`` and ``f`` undefined, ``phi = 0`` (pass ``f=0`` for ``P_{g,0}``).
    names
        Names of the two vectors (coordinates ``gamma_x, ..., M_z``).
    """
    gamma, M = gamma_symbols(names)
    g_ = _function_of(g, "g", gamma, M)
    f_ = _function_of(f, "f", gamma, M)
    phi_ = _function_of(phi, "phi", gamma, M)
    grad_g = [sp.diff(g_, c) for c in gamma]
    G = eps_matrix(gamma)
    scalar = _dot(grad_g, M) - g_ * f_ * _dot(gamma, M) + phi_
    return _assemble(gamma, M, g_ * G, g_ * eps_matrix(M) + scalar * G)


def chaplygin_g(gamma: Sequence[sp.Expr], a: Sequence[sp.Expr], d: sp.Expr) -> sp.Expr:
    """``g = sqrt(1 - d (gamma, A gamma))`` of the Chaplygin ball (survey (34)–(40))."""
    return sp.sqrt(1 - d * sum((ai * gi**2 for ai, gi in zip(a, gamma)), sp.Integer(0)))


def _ball_parameters(I, d, a) -> tuple[tuple[sp.Expr, ...], sp.Expr]:
    d_ = _scalar(d, "d")
    if a is not None:
        if I is not None:
            raise InputError("give either the moments of inertia I or A's diagonal a, not both")
        return _vector(a, "a", "a", positive=True), d_
    I_ = _vector(I, "I", "I", positive=True)
    return tuple(1 / (Ii + d_) for Ii in I_), d_


def chaplygin_ball(I=None, d=None, a=None, names: tuple[str, str] = ("gamma", "M")) -> Bivector:
    """Chaplygin-ball bracket ``P_g``, survey (38)/(39).

    ``P_g = [[0, g Gamma], [g Gamma, g [M]_eps - (d (M, A gamma)/g) Gamma]]`` with
    ``A = diag(a_i)``, ``a_i = 1/(I_i + d)``, ``g = sqrt(1 - d (gamma, A gamma))``. Equal to
    ``P_{g,0}`` because ``grad g = -d A gamma / g``.

    Parameters
    ----------
    I
        Principal moments ``(I1, I2, I3)`` (numbers or symbols; default positive symbols).
    d
        ``m b^2`` (default a positive symbol ``d``).
    a
        Instead of ``I``: the diagonal of ``A`` directly (symbols or numbers).
    names
        Vector names.
    """
    gamma, M = gamma_symbols(names)
    a_, d_ = _ball_parameters(I, d, a)
    g = chaplygin_g(gamma, a_, d_)
    Ag = [ai * gi for ai, gi in zip(a_, gamma)]
    G = eps_matrix(gamma)
    return _assemble(gamma, M, g * G, g * eps_matrix(M) - (d_ * _dot(M, Ag) / g) * G)


def chaplygin_gyrostat(S=None, I=None, d=None, a=None,
                       names: tuple[str, str] = ("gamma", "M")) -> Bivector:
    """Chaplygin-ball gyrostat bracket ``P_sg``, survey (49).

    ``P_sg = [[0, g Gamma], [g Gamma, g [M + S]_eps - (d (M, A gamma)/g) Gamma]]`` (the
    correction uses ``(M, A gamma)``, not ``(M + S, A gamma)``). Casimirs ``(gamma, gamma)``
    and ``(gamma, M + S)``. ``S`` is the constant gyrostatic momentum (default symbols S1..S3).
    """
    gamma, M = gamma_symbols(names)
    a_, d_ = _ball_parameters(I, d, a)
    S_ = _vector(S, "S", "S")
    g = chaplygin_g(gamma, a_, d_)
    Ag = [ai * gi for ai, gi in zip(a_, gamma)]
    MS = [m + s for m, s in zip(M, S_)]
    G = eps_matrix(gamma)
    return _assemble(gamma, M, g * G, g * eps_matrix(MS) - (d_ * _dot(M, Ag) / g) * G)


def veselova(a=None, b=None, names: tuple[str, str] = ("gamma", "K")) -> Bivector:
    """Veselova bracket ``P_v``, survey (65), in ``(gamma, K)``.

    ``{K_i, K_j} = eps_ijk (g K_k + gamma_k ((K, grad g) - b/g))``, ``{K_i, gamma_j} =
    g eps_ijk gamma_k`` with ``g = (gamma, A gamma)^{1/2}``, ``grad g = A gamma / g``.

    Parameters
    ----------
    a
        Diagonal of ``A = I^{-1}`` (default symbols a1..a3).
    b
        The value of the Casimir ``(gamma, K)`` on the level considered (a number or symbol):
        ``P_{g,0}`` plus the Remark-5 term ``phi = -b/g``. ``None`` (default) uses the function
        ``b = (gamma, K)``, i.e. ``P_{g,f}`` with ``f = g^{-2}``; both are Poisson.
    names
        Vector names.
    """
    gamma, K = gamma_symbols(names)
    a_ = _vector(a, "a", "a", positive=True)
    Ag = [ai * gi for ai, gi in zip(a_, gamma)]
    g = sp.sqrt(_dot(gamma, Ag))
    if b is None:
        # P_{g, g^-2} written out: (K, grad g) - g f (gamma, K) = ((K, A gamma) - (gamma, K))/g.
        # The plugin's Veselova system uses this matrix as it is, so its expression tree (and
        # hence every number computed from it) stays as the survey's (65) reads.
        G = eps_matrix(gamma)
        lower = g * eps_matrix(K) + (_dot(K, Ag) - _dot(gamma, K)) / g * G
        return _assemble(gamma, K, g * G, lower)
    b_ = _scalar(b, "b", positive=False)
    if b_.free_symbols & set(gamma + K):
        raise InputError("b must be a constant (use b=None for the function (gamma, K))")
    return p_gf(g, 0, -b_ / g, names)


def veselova_gyrostat(a=None, k=None, names: tuple[str, str] = ("gamma", "K")) -> Bivector:
    """Veselova gyrostat bracket ``P_k``, survey (70), in ``(gamma, K)``.

    ``P_k = g [[0, Gamma], [Gamma, [K + k]_eps + S Gamma]]``,
    ``S = (A K - K - k, gamma)/(A gamma, gamma)``, ``g = (A gamma, gamma)^{1/2}``.
    Casimirs ``(gamma, gamma)``, ``(K + k, gamma)``.

    Parameters
    ----------
    a
        Diagonal of ``A`` (default symbols a1..a3).
    k
        Constant rotor momentum (default symbols k1..k3).
    """
    gamma, K = gamma_symbols(names)
    a_ = _vector(a, "a", "a", positive=True)
    k_ = _vector(k, "k", "k")
    Ag = [ai * gi for ai, gi in zip(a_, gamma)]
    g = sp.sqrt(_dot(Ag, gamma))
    AKKk = [ai * Ki - Ki - ki for ai, Ki, ki in zip(a_, K, k_)]
    S = _dot(AKKk, gamma) / _dot(Ag, gamma)
    G = eps_matrix(gamma)
    Kk = [Ki + ki for Ki, ki in zip(K, k_)]
    return _assemble(gamma, K, g * G, g * eps_matrix(Kk) + g * S * G)


def canonical_deformation(g: FunctionSpec = None, names: tuple[str, str] = ("q", "p")) -> Bivector:
    """Deformed canonical bracket, survey (42).

    ``{q_i, q_j} = 0``, ``{q_i, p_j} = g(q) delta_ij``, ``{p_i, p_j} = p_i d_j g - p_j d_i g``
    on ``(q_x, q_y, q_z, p_x, p_y, p_z)``: the push-forward of the canonical bracket under
    ``(q, p) -> (q, g(q) p)``. ``g`` as in the module docstring (default undefined ``g(q)``).
    """
    q, p = gamma_symbols(names)
    g_ = _function_of(g, "g", q, p)
    dg = [sp.diff(g_, c) for c in q]
    mat = sp.zeros(6, 6)
    for i in range(3):
        mat[i, 3 + i] = g_
        mat[3 + i, i] = -g_
        for j in range(3):
            mat[3 + i, 3 + j] = p[i] * dg[j] - p[j] * dg[i]
    return Bivector.from_matrix(mat, q + p)


def deform(P: Bivector, Q: Bivector | sp.Matrix, check: bool = True, **jacobi_options) -> Bivector:
    """Declare a deformation ``P + Q`` of a bivector; by default prove it is Poisson.

    Parameters
    ----------
    P
        The bivector to deform.
    Q
        The deformation: a :class:`Bivector` on the same coordinates or an antisymmetric matrix.
    check
        Run :func:`~poissonkit.structure.jacobi.check_jacobi` on the sum and raise
        :class:`~poissonkit.errors.NotPoissonError` if it fails.
    jacobi_options
        Passed to ``check_jacobi`` (``method``, ``constraints``, ...).

    Raises
    ------
    DimensionError
        ``Q`` lives on other coordinates / has the wrong size.
    NotPoissonError
        ``check`` is true and ``P + Q`` is not Poisson.
    """
    from poissonkit.structure.jacobi import require_poisson

    if not isinstance(P, Bivector):
        raise InputError(f"deform: P must be a Bivector, got {type(P).__name__}")
    if not isinstance(Q, Bivector):
        Q = Bivector.from_matrix(Q, P.coords)
    out = P + Q
    if check:
        require_poisson(out, **jacobi_options)
    return out


def chaplygin_ball_system(I=None, d=None, a=None, S=None):
    """The Chaplygin ball (or its gyrostat, ``S`` given) as a conformally Hamiltonian system.

    ``X = -g^{-1} P_g dH`` with ``H = (M, omega)/2`` (survey (40)): structure
    ``P_g`` (``P_sg``), multiplier ``N = -1/g``. Claimed Casimirs ``(gamma, gamma)``,
    ``(gamma, M + S)``, integrals ``H1 = (M, omega)``, ``H2 = (M + S, M + S)``, measure
    ``1/g``, original equations (34)/(49): ``Mdot = (M + S) x omega``, ``gammadot = gamma x
    omega``, ``omega = A M + d (M, A gamma)/g^2 A gamma``.
    """
    from poissonkit.structure.system import HamiltonianSystem

    gamma, M = gamma_symbols()
    a_, d_ = _ball_parameters(I, d, a)
    gyro = S is not None
    S_ = _vector(S, "S", "S") if gyro else (sp.Integer(0),) * 3
    P = chaplygin_gyrostat(S_, a=a_, d=d_) if gyro else chaplygin_ball(a=a_, d=d_)
    g = chaplygin_g(gamma, a_, d_)
    Ag = [ai * gi for ai, gi in zip(a_, gamma)]
    MAg = _dot(M, Ag)
    omega = [ai * mi + d_ * MAg / g**2 * agi for ai, mi, agi in zip(a_, M, Ag)]
    H1 = _dot(M, [ai * mi for ai, mi in zip(a_, M)]) + d_ * MAg**2 / g**2
    MS = [m + s for m, s in zip(M, S_)]
    Mdot = sp.Matrix(MS).cross(sp.Matrix(omega))
    gdot = sp.Matrix(gamma).cross(sp.Matrix(omega))
    original = {c: v for c, v in zip(gamma + M, list(gdot) + list(Mdot))}
    return HamiltonianSystem(
        structure=P, hamiltonian=H1 / 2, multiplier=-1 / g,
        casimirs={"(gamma,gamma)": _dot(gamma, gamma), "(gamma,M+S)": _dot(gamma, MS)},
        integrals={"H1=(M,omega)": H1, "H2=(M+S,M+S)": _dot(MS, MS)},
        measure=1 / g, name="chaplygin_gyrostat" if gyro else "chaplygin_ball",
        doc="Chaplygin ball on a plane, survey (34)-(40)" + (", gyrostat (49)" if gyro else ""),
        original=original, constraints=())


__all__ = [
    "canonical_deformation", "chaplygin_ball", "chaplygin_ball_system", "chaplygin_g",
    "chaplygin_gyrostat", "deform", "gamma_symbols", "p_gf", "veselova", "veselova_gyrostat",
]

"""Conventions of poissonkit, stated once.

Every module links here instead of restating these rules; ``tests/test_conventions.py`` pins them.

Bivectors and brackets
----------------------
* A bivector ``P`` on coordinates ``x = (x_1, ..., x_n)`` is stored as its antisymmetric matrix
  ``P[i, j] = {x_i, x_j}``.
* The Poisson bracket is ``{F, G} = sum_ij P[i, j] dF/dx_i dG/dx_j`` (``= dF . P . dG``).
* The Hamiltonian vector field of ``H`` is ``X_H = P dH``, with components
  ``X_H^i = sum_j P[i, j] dH/dx_j = {x_i, H}``; the equations of motion are ``xdot = {x, H}``.
  A conformally Hamiltonian field is ``X = N(x) P dH`` (survey eq. (7)).
* The PoissonGeometry package uses the opposite sign, ``X_h = {h, .} = -P dh``; that sign lives
  only in :mod:`poissonkit.compat`.

Lie–Poisson blocks
------------------
* ``lie_poisson(C)`` for structure constants ``C[i][j][k]`` is ``{x_i, x_j} = sum_k C[i][j][k] x_k``.
* e(3) in seed 000's order ``(nu, m)``: ``{m_i, m_j} = eps_ijk m_k``, ``{m_i, nu_j} = eps_ijk nu_k``,
  ``{nu_i, nu_j} = 0``. In the survey's order ``(gamma, M)`` the same bracket with
  ``L = M``, ``gamma = nu``. With ``xdot = {x, H}`` this gives the *space-frame* equations
  ``mdot = dH/dm x m + dH/dnu x nu``, ``nudot = dH/dm x nu`` (seed 000 eq. (20)).
  The survey's body-frame Euler–Poisson equations are ``xdot = {H, x} = -P dH``: its
  non-holonomic systems are declared with the multiplier that says so (``N = -1/g`` etc.).
* The eps-matrix of a vector: ``[v]_eps[i, j] = eps_ijk v_k``, so ``[v]_eps w = w x v``.

Schouten bracket and Jacobi
---------------------------
* For bivectors ``A, B``:
  ``[A, B]^{ijk} = -sum_m (B^{mk} d_m A^{ij} + A^{mk} d_m B^{ij}) + cyclic(i, j, k)``
  (survey eq. (4)). With this sign ``[P, P]^{ijk} = 2 Jac^{ijk}`` where
  ``Jac^{ijk} = sum_m (P^{im} d_m P^{jk} + P^{jm} d_m P^{ki} + P^{km} d_m P^{ij})``
  ``= {x_i, {x_j, x_k}} + cyclic``. ``P`` is Poisson iff ``[P, P] = 0``.
* Pinned oracle: for ``Q = [[0, y1 y2, 0], [-y1 y2, 0, y3], [0, -y3, 0]]``,
  ``[Q, Q]^{123} = -2 y1 y3`` and ``Jac^{123} = -y1 y3``.
* Schouten bracket of a bivector with a vector field ``[P, X] = -L_X P`` (so that ``X`` is a
  Poisson vector field iff ``[P, X] = 0``); the Lichnerowicz coboundary is ``d_P A = [P, A]``.

Classical Lie algebras (``lie_algebra(name)``, ``lie_poisson(name)``)
----------------------------------------------------------------------
* Coordinates on ``g*`` are ``x_a = <mu, E_a>`` for the stated basis ``E_a`` of ``g`` (matrices of
  the defining representation), and ``{x_a, x_b} = sum_c C[a][b][c] x_c`` with
  ``[E_a, E_b] = sum_c C[a][b][c] E_c`` (the "+" Lie–Poisson bracket, as ``lie_poisson(C)``).
* Pairing: ``mu`` is represented by the matrix ``X`` in ``g`` with
  ``<mu, Y> = kappa Re tr(X^H Y)`` for all ``Y`` in ``g`` (``X^H = X^T`` for real algebras);
  the standard invariants are ``tr(X^k)`` (``tr(H^k)``, ``H = -i X``, for ``u``, ``su``) and
  the Pfaffian. ``E_ij`` is the matrix unit; indices are 1-based and joined in names
  (``x_12``), separated for size > 9 (``x_1_12``).
* ``gl(n)``: ``E_ij``, coordinates ``x_ij = X_ij``; ``kappa = 1``.
* ``sl(n)``: ``E_ij`` (``i != j``) and ``E_ii - I/n`` (``i < n``); ``X`` is traceless with
  ``X_ij = x_ij`` and ``X_nn = -(x_11 + ... + x_(n-1)(n-1))``; ``kappa = 1``.
* ``so(p,q)`` (``so(n) = so(n,0)``; ``eta = diag(1_p, -1_q)``): ``B_ij = E_ij - eta_i eta_j E_ji``
  (``i < j``; rotations inside a definite block, boosts ``E_ij + E_ji`` across), coordinates
  ``m_ij``; ``X_ij = m_ij``, ``X_ji = -eta_i eta_j m_ij``; ``kappa = 1/2``; Pfaffian
  ``Pf(X eta)``. ``so(3)`` uses the hat-map basis ``J_a`` (``J_a w = e_a x w``), coordinates
  ``(m_x, m_y, m_z)``, ``X = hat(m)``: exactly :func:`~poissonkit.structure.so3`.
* ``sp(2n)`` (``X^T J + J X = 0``, ``J = [[0, I], [-I, 0]]``): ``E_ij - E_(n+j)(n+i)``,
  ``E_i(n+j) + E_j(n+i)`` and ``E_(n+i)j + E_(n+j)i`` (``i <= j``), coordinates ``a_ij``,
  ``b_ij``, ``c_ij`` with ``X = [[a, b], [c, -a^T]]``, ``b``, ``c`` symmetric; ``kappa = 1/2``.
* ``u(n)``, ``su(n)``: ``i (E_ij + E_ji)`` (``i <= j``; ``su``: ``2 i (E_ii - I/n)`` on the
  diagonal, ``i < n``) and ``E_ji - E_ij`` (``i < j``), coordinates ``s_ij``, ``a_ij``; the
  Hermitian ``H = -i X`` has ``H_ij = s_ij + i a_ij`` (``i < j``), ``H_ii = s_ii``;
  ``kappa = 1/2``.
* ``e(n)`` / ``se(n)``: ``(n+1) x (n+1)`` matrices ``[[R, v], [0, 0]]``: translations
  ``T_i = E_i(n+1)`` and the rotations of ``so(n)``; ``e(n)`` puts translations first
  (coordinates ``nu_i``, ``m_ij``; ``e(3)`` is :func:`~poissonkit.structure.e3`, ``(nu, m)``),
  ``se(n)`` rotations first (``L_ij``, ``P_i``; ``se(3)`` is
  :func:`~poissonkit.structure.se3`). No invariant trace form: no ``X``.
  Their ``invariants()`` (``floor((n+1)/2)`` of them, the index of ``e(n)``) are named, with
  ``nu`` the translation and ``M`` (``M_ij = m_ij``) the rotation part and
  ``Y = [[M, nu], [-nu^T, 0]]`` (size ``n + 1``): ``|nu|^2`` (``|P|^2`` for ``se(n)``);
  for ``n = 3`` ``(nu, m)`` (``(L, P)``); for ``n >= 4`` ``D_k`` (``k = 2 .. floor(n/2)``),
  the sum of the principal ``2k``-minors of ``Y`` that contain the last index
  (``D_1 = |nu|^2``); for odd ``n >= 5`` ``Pf(Y)``, with ``Pf(Y)^2 = det Y``.
* ``heisenberg(n)``: ``Q_i = E_1(1+i)``, ``P_i = E_(1+i)(n+2)``, ``Z = E_1(n+2)`` in
  ``(n+2) x (n+2)`` matrices, coordinates ``q_i, p_i, z``: ``{q_i, p_j} = delta_ij z``.

Casimir normal form (``find_casimirs``)
---------------------------------------
* Monomial order ``grlex`` with the coordinates in the order of ``P.coords``. Each generator
  has primitive integer coefficients (``Z[parameters]`` with parameters) and a positive leading
  coefficient, and is reduced against the products of lower-degree generators and the other
  generators of its degree; ``relations`` are polynomials in ``C_1, C_2, ...`` in the same form.

Text expressions (``parse_expression``; every argument that accepts text)
-------------------------------------------------------------------------
* Names: a name the caller declares — a coordinate, a parameter (``params=``) — always means
  that symbol, even ``I``, ``E``, ``S``, ``N`` or ``pi``; any identifier may be declared,
  Unicode (``α``) and Python keywords (``lambda``) included (in Python's normal form, NFKC).
  Undeclared, ``pi`` is π (:data:`TEXT_CONSTANTS`) and the names of :data:`UNDECLARED_NAMES`
  are refused with a hint: an undeclared ``I`` never silently becomes √−1, ``E`` never Euler's
  number (write ``exp(1)``). Other undeclared names are refused, listing the allowed ones.
* Numbers: in exact contexts (the default of the symbolic layer) a decimal is the rational it
  denotes — ``0.1`` is 1/10, ``2.5e-3`` is 1/400 — so brackets and Jacobi checks stay exact;
  ``parse_expression(..., exact=False)`` keeps sympy floats (:data:`EXACT_DECIMALS`).

Rigid bodies and N-body states
------------------------------
* A symmetric top carries ``(nu, m)``: unit symmetry axis and angular momentum, both in the
  space frame; kinetic energy ``alpha |m|^2 / 2`` with ``alpha = 1 / I_perp``.
* N-body state order: ``r_1, p_1, ..., r_N, p_N`` then ``nu_1, m_1, ..., nu_K, m_K`` for the
  K bodies with orientation (tops); point masses carry no ``(nu, m)``. Compiled right-hand sides
  document their exact layout in their docstring.
* Pair geometry (seed 000): ``r = r_j - r_i``, ``e = r/|r|``, ``c' = (e, nu_i)``,
  ``c'' = (e, nu_j)``, ``c''' = (nu_i, nu_j)``; ``F`` is the force on body j; torques are about
  each body's own centre.
* Two-body centre-of-mass form: ``x = (r, p, nu', m', nu'', m'')`` in R^18, reduced mass ``mu``.
* External fields (``docs/fields.md``): a one-body energy ``U(r, nu)`` of a body at ``r`` with
  axis ``nu`` gives the force ``-dU/dr`` and the torque ``mdot = dU/dnu x nu`` (orthogonal to
  ``nu``); a magnet of moment ``mu`` along ``nu`` has ``U = -mu nu . B(r)``, force
  ``mu grad(nu . B)``, torque ``mu nu x B``.

Units
-----
* Public numbers are SI (m, kg, s, A, T). ``mu0 = 4 pi 1e-7`` (the seed's value, not CODATA).
* Numerics nondimensionalise internally (length, mass and time scales chosen per scene) and
  convert back; reports state both where it matters.

Unit systems of scenes (``[units]``, :mod:`poissonkit.numerics.unitsystem`)
--------------------------------------------------------------------------
* A scene may declare ``length``, ``time`` and ``mass`` units by REBOUND's names (any case):
  ``m cm mm km AU pc``, ``s min hr day yr kyr Myr Gyr``, ``kg g Msun Mearth Mjupiter``; or
  ``G = <number>`` alone for N-body units (no SI meaning; gravity uses that ``G``). Absent:
  SI. Inputs are read in the scene's units, converted once to SI for the numerics, and every
  output (messages, progress, summary, trajectory, figures) is converted back.
* Constants: ``G`` CODATA 2018 (:data:`NEWTON_G`); astronomical unit IAU 2012 B2, exactly
  149 597 870 700 m; parsec IAU 2015 B2, ``648000/pi`` au; day 86 400 s; Julian year
  365.25 days; solar mass ``M_sun = GM_sun / G`` with the nominal solar mass parameter of
  IAU 2015 B3, ``GM_sun = 1.3271244e20 m^3 s^-2`` (Earth ``3.986004e14``, Jupiter
  ``1.2668653e17``, same resolution). So ``G`` in AU, day, Msun is
  ``GM_sun day^2 / au^3 = 2.959122082e-4`` (as the nominal value makes it: what is
  known to 10 digits is ``GM``, not ``G`` or ``M``.
* Displayed prefixes never collide with unit symbols: lengths beyond km switch to AU or to
  scientific notation, never "Tm" (read as tesla) or "Gm".
"""

from __future__ import annotations

import math

#: Vacuum permeability used throughout (seed 000's value, exactly 4 pi 1e-7).
MU0: float = 4.0e-7 * math.pi

#: Newton's constant (CODATA 2018) [m³/(kg s²)].
NEWTON_G: float = 6.67430e-11

#: Sign of the Hamiltonian vector field: X_H = HAMILTONIAN_SIGN * P dH.
HAMILTONIAN_SIGN: int = 1

#: Factor in [P, P] = SCHOUTEN_JACOBI_FACTOR * Jac.
SCHOUTEN_JACOBI_FACTOR: int = 2

#: Names of the invariants of e(n) (n >= 4; se(n) says |P|^2) in ``invariants()``: D_k for
#: k = 2 .. floor(n/2), and Pf(Y) for odd n (module notes).
EUCLID_INVARIANTS: tuple[str, str, str] = ("|nu|^2", "D_{k}", "Pf(Y)")

#: Names of the four pair invariants of seed 000, as used in symbolic potentials.
PAIR_INVARIANTS: tuple[str, str, str, str] = ("r", "c1", "c2", "c3")

# ---- unit systems of scenes (see "Unit systems of scenes" above)
#: Astronomical unit (IAU 2012 Resolution B2, exact) [m].
ASTRONOMICAL_UNIT: float = 149_597_870_700.0
#: Parsec (IAU 2015 Resolution B2, exact: 648000/pi au) [m].
PARSEC: float = 648_000.0 / math.pi * ASTRONOMICAL_UNIT
#: Day [s].
DAY: float = 86_400.0
#: Julian year, 365.25 days [s].
JULIAN_YEAR: float = 365.25 * DAY
#: Nominal solar mass parameter (IAU 2015 Resolution B3) [m³/s²].
GM_SUN: float = 1.3271244e20
#: Nominal terrestrial and jovian mass parameters (IAU 2015 Resolution B3) [m³/s²].
GM_EARTH: float = 3.986004e14
GM_JUPITER: float = 1.2668653e17
#: Solar mass GM_SUN / NEWTON_G [kg].
SOLAR_MASS: float = GM_SUN / NEWTON_G

#: Names refused in text unless declared (sympy's parser would read them as I = √−1, E = e,
#: S = the singleton registry, N = numeric evaluation).
UNDECLARED_NAMES: tuple[str, ...] = ("I", "E", "S", "N")

#: Constants text may name without declaring them (a declared name takes precedence).
TEXT_CONSTANTS: tuple[str, ...] = ("pi",)

#: Decimals in text are exact rationals (``0.1`` = 1/10) unless ``exact=False``.
EXACT_DECIMALS: bool = True

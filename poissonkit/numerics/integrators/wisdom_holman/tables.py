"""Coefficient tables of the splittings for systems with one dominant mass (``H = A + εB``).

``A`` is the Kepler part (exact drift), ``εB`` the interaction (exact kick). A step is the
symmetric composition ``e^{c_0 h A} e^{d_0 h B} e^{c_1 h A} … e^{d_{s−1} h B} e^{c_s h A}``,
given by the drift fractions ``c`` (``s + 1``) and kick fractions ``d`` (``s``).

Sources (coefficients copied to 40 digits from REBOUND's ``src/integrator_saba.c`` and
``src/integrator_whfast.c``, H. Rein et al., GPL; they reproduce the papers' tables):

* ``SABA_n`` — J. Laskar & P. Robutel, Celest. Mech. Dyn. Astron. 80 (2001) 39: Gauss–Legendre
  nodes and weights, error ``O(ε h^{2n} + ε² h²)``. Built in
  :func:`saba_coefficients` below.
* ``ABA(10,4)``, ``ABA(8,6,4)``, ``ABA(10,6,4)``, ``ABAH(8,4,4)``, ``ABAH(8,6,4)``,
  ``ABAH(10,6,4)`` — S. Blanes, F. Casas, A. Farrés, J. Laskar, J. Makazaga & A. Murua,
  Appl. Numer. Math. 68 (2013) 58 ("New families of symplectic splitting methods for numerical
  integration in dynamical astronomy"), Tables 2–3: generalised order ``(r_1, r_2, r_3)`` means
  error ``O(ε h^{r_1} + ε² h^{r_2} + ε³ h^{r_3})``.
* Symplectic correctors of J. Wisdom, M. Holman & J. Touma, Fields Inst. Commun. 10 (1996) 217,
  as in WHFast (H. Rein & D. Tamayo, MNRAS 452 (2015) 376): the Wisdom–Holman map
  ``K = e^{hA/2} e^{hB} e^{hA/2}`` is conjugated by a corrector ``C`` made of operators
  ``Z(a, b) = e^{aA} e^{−bB} e^{−2aA} e^{bB} e^{aA}``, removing the ``ε h^k`` error terms up to
  order ``k`` = 3, 5, 7, 11 or 17 (the ``ε² h²`` term stays).
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np

from poissonkit.errors import InputError

#: ``g_n`` of the ``ε² h²`` error term of ``SABA_n`` (Laskar & Robutel 2001, Table 1).
CORRECTOR_G = {
    1: 1.0 / 12.0,
    2: (2.0 - math.sqrt(3.0)) / 24.0,
    3: (54.0 - 13.0 * math.sqrt(15.0)) / 648.0,
    4: 0.003396775048208601331532157783492144,
}


def saba_coefficients(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Drift fractions ``c`` (``n + 1``) and kick fractions ``d`` (``n``) of ``SABA_n``.

    Drifts go from node to node of the ``n``-point Gauss–Legendre rule on ``[0, 1]`` (and to the
    ends), kicks carry its weights; ``Σ c = Σ d = 1`` and the scheme is symmetric.
    """
    if n not in CORRECTOR_G:
        raise InputError(f"Wisdom–Holman stages must be 1 … 4, got {n!r}")
    c, d = _saba_table(n)
    return np.array(c), np.array(d)


@cache
def _saba_table(n: int) -> tuple[tuple[float, ...], tuple[float, ...]]:
    x, w = np.polynomial.legendre.leggauss(n)  # costly next to a short run: computed once
    x = 0.5 * (x + 1.0)
    c = np.diff(np.concatenate([[0.0], x, [1.0]]))
    return tuple(c.tolist()), tuple((0.5 * w).tolist())

# Half tables as in REBOUND: ``c_half`` / ``d_half`` hold the distinct drift / kick fractions
# of the first half of the symmetric step, ``kicks`` is the number of kicks per step.
_BLANES: dict[str, tuple[int, tuple[float, ...], tuple[float, ...]]] = {
    "10_4": (7, (
        0.04706710064597250612947887637243678556564, 0.1847569354170881069247376193702560968574,
        0.2827060056798362053243616565541452479160, -0.01453004174289681837857815229683813033908,
    ), (
        0.1188819173681970199453503950853885936957, 0.2410504605515015657441667865901651105675,
        -0.2732866667053238060543113981664559460630, 0.8267085775712504407295884329818044835997,
    )),
    "8_6_4": (7, (
        0.0711334264982231177779387300061549964174, 0.241153427956640098736487795326289649618,
        0.521411761772814789212136078067994229991, -0.333698616227678005726562603400438876027,
    ), (
        0.183083687472197221961703757166430291072, 0.310782859898574869507522291054262796375,
        -0.0265646185119588006972121379164987592663, 0.0653961422823734184559721793911134363710,
    )),
    "10_6_4": (8, (
        0.03809449742241219545697532230863756534060, 0.1452987161169137492940200726606637497442,
        0.2076276957255412507162056113249882065158, 0.4359097036515261592231548624010651844006,
        -0.6538612258327867093807117373907094120024,
    ), (
        0.09585888083707521061077150377145884776921, 0.2044461531429987806805077839164344779763,
        0.2170703479789911017143385924306336714532, -0.01737538195906509300561788011852699719871,
    )),
    "h8_4_4": (6, (
        0.2741402689434018761640565440378637101205, -0.1075684384401642306251105297063236526845,
        -0.0480185025906016926911954171508475065370, 0.7628933441747280943044988056386148982021,
    ), (
        0.6408857951625127177322491164716010349386, -0.8585754489567828565881283246356000103664,
        0.7176896537942701388558792081639989754277,
    )),
    "h8_6_4": (8, (
        0.06810235651658372084723976682061164571212, 0.2511360387221033233072829580455350680082,
        -0.07507264957216562516006821767601620052338,
        -0.009544719701745007811488218957217113269121,
        0.5307579480704471776340674235341732001443,
    ), (
        0.1684432593618954534310382697756917558148, 0.4243177173742677224300351657407231801453,
        -0.5858109694681756812309015355404036521923, 0.4930499927320125053698281000239887162321,
    )),
    "h10_6_4": (9, (
        0.04731908697653382270404371796320813250988, 0.2651105235748785159539480036185693201078,
        -0.009976522883811240843267468164812380613143,
        -0.05992919973494155126395247987729676004016,
        0.2574761120673404534492282264603316880356,
    ), (
        0.1196884624585322035312864297489892143852, 0.3752955855379374250420128537687503199451,
        -0.4684593418325993783650820409805381740605, 0.3351397342755897010393098942949569049275,
        0.2766711191210800975049457263356834696055,
    )),
}

#: Generalised order ``(r_1, r_2, r_3)``: error ``O(ε h^{r_1} + ε² h^{r_2} + ε³ h^{r_3})``.
TABLE_ORDERS: dict[str, tuple[int, ...]] = {
    "10_4": (10, 4), "8_6_4": (8, 6, 4), "10_6_4": (10, 6, 4),
    "h8_4_4": (8, 4, 4), "h8_6_4": (8, 6, 4), "h10_6_4": (10, 6, 4),
}


def blanes_coefficients(table: str) -> tuple[np.ndarray, np.ndarray]:
    """Drift fractions ``c`` and kick fractions ``d`` of a Blanes et al. (2013) method.

    Parameters
    ----------
    table
        One of ``"10_4"``, ``"8_6_4"``, ``"10_6_4"`` (``ABA`` methods) or ``"h8_4_4"``,
        ``"h8_6_4"``, ``"h10_6_4"`` (``ABAH``).

    Returns
    -------
    c, d
        ``c`` has one entry more than ``d``; both are symmetric and sum to 1.

    Raises
    ------
    InputError
        For an unknown table name.
    """
    if table not in _BLANES:
        raise InputError(f"unknown Wisdom–Holman table {table!r}; choose one of "
                         f"{', '.join(sorted(_BLANES))}")
    kicks, ch, dh = _BLANES[table]
    # unfold as REBOUND does: drift j uses index j up to the middle, then mirrors
    c = [ch[j if j <= kicks // 2 else kicks - j] for j in range(kicks)] + [ch[0]]
    d = [dh[j if j <= (kicks - 1) // 2 else kicks - j - 1] for j in range(kicks)]
    return np.array(c), np.array(d)


# --------------------------------------------------------------------------- WHT96 correctors
_A1 = 0.41833001326703777398908601289259374469640768464934  # a_k = k a_1 (a_1 = √(7/40))
_B = {
    3: (-0.024900596027799867499350357910273437184309981229127,),
    5: (-0.0083001986759332891664501193034244790614366604097090,
        0.041500993379666445832250596517122395307183302048545),
    7: (0.0024926811426922105779030593952776964450539008582219,
        -0.018270923246702131478062356884535264841652263842597,
        0.053964399093127498721765893493510877532452806339655),
    11: (0.00020361579647854651301632818774633716473696537436847,
         -0.0023487215292295354188307328851055489876255097419754,
         0.012309078592019946317544564763237909911330686448336,
         -0.038121613681288650508647613260247372125243616270670,
         0.072593394748842738674253180742744961827622366521517),
    17: (-0.0000043347415473373580190650223498124944896789841432241,
         0.000076436355227935738363241846979413475106795392377415,
         -0.00063599983075817658983166881625078545864140848560259,
         0.0033132577069380655655490196833451994080066801611459,
         -0.012071760822342291062449751726959664253913904872527,
         0.032422198864713580293681523029577130832258806467604,
         -0.065192863576377893658290760803725762027864651086787,
         0.093056103771425958591541059067553547100903397724386),
}
#: Orders of the symplectic correctors available.
CORRECTOR_ORDERS = tuple(sorted(_B))


def corrector_operators(order: int) -> np.ndarray:
    """The ``Z(a, b)`` operators of the WHT96 symplectic corrector of ``order``, in step units.

    Returns an array of rows ``(a, b)``, applied first to last; the corrector (processed →
    physical coordinates) is the sequence with ``b`` as given, its approximate inverse
    (physical → processed, at the start) the same sequence with ``−b`` — as WHFast does
    (``reb_whfast_apply_corrector`` with ``inv = ∓1``).

    Raises
    ------
    InputError
        For an order other than 3, 5, 7, 11, 17.
    """
    if order not in _B:
        raise InputError(f"symplectic corrector order must be one of "
                         f"{', '.join(map(str, CORRECTOR_ORDERS))}, got {order!r}")
    bs = _B[order]
    k = len(bs)
    if order == 3:  # Z(a_1, b_31) Z(−a_1, −b_31)
        return np.array([[_A1, bs[0]], [-_A1, -bs[0]]])
    # Z(−a_k, b_{k1}) … Z(−a_1, b_{kk}), then Z(a_1, −b_{kk}) … Z(a_k, −b_{k1})
    rows = [(-(k - j) * _A1, bs[j]) for j in range(k)]
    rows += [((j + 1) * _A1, -bs[k - 1 - j]) for j in range(k)]
    return np.array(rows)

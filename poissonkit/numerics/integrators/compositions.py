"""High-order splitting tables beyond order 8: coefficients and citations only (pure data).

Two kinds of tables, both built from the exact kinetic (drift) and potential (kick) flows of
:mod:`poissonkit.numerics.integrators.splitting`, which turns them into
:class:`~poissonkit.numerics.integrators.splitting.Scheme` objects and registers them by name:

* ``splitting10_ss`` — Sofroniou & Spaletta's s35odr10: the symmetric composition of 35 Strang
  steps of order 10 (M. Sofroniou, G. Spaletta, Derivation of symmetric composition constants
  for symmetric integrators, Optim. Methods Softw. 20 (2005) 597–613). Order 10 for any ``T + V``
  (composition of a symmetric second-order step); 35 kicks and 36 drifts per step.
* ``splitting8_bce`` — Blanes, Casas & Escorihuela-Tomàs's 19-stage symmetric Runge–Kutta–Nyström
  splitting of order 8 (S. Blanes, F. Casas, A. Escorihuela-Tomàs, Runge–Kutta–Nyström symplectic
  splitting methods of order 8, Appl. Numer. Math. 182 (2022) 14–27): drift first, 20 drifts and
  19 kicks per step. Its order holds on systems with ``{V, {V, {V, T}}} = 0``, which every
  splittable system here satisfies (see the splitting module doc). Two of its coefficients
  (``a_1 = 0.0505805``, ``a_2 = 0.149999``) are free parameters fixed by the authors; the others
  solve the order conditions for them.

The 32-digit s35odr10 weights are those of SUNDIALS ARKODE (``arkode_sprk.c``,
``ARKODE_SPRK_SOFRONIOU_10_36``), which agree with the 26 digits of the paper; the order-8 RKN
coefficients are the paper's (30 digits), as in the authors' published tables. The orders are
verified numerically in the tests (error ratios under step halving against high-precision
truth).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["TABLES", "HighOrderTable"]


@dataclass(frozen=True)
class HighOrderTable:
    """One table: either Strang-step composition weights or drift/kick coefficients.

    Attributes
    ----------
    name
        Integrator name.
    order
        Classical order (for ``nystrom`` tables on ``T + V`` systems with
        ``{V, {V, {V, T}}} = 0``).
    reference
        Where the coefficients come from.
    doc
        One-line description for the integrator registry.
    weights
        Composition weights ``w`` of ``S(w_m h) … S(w_0 h) … S(w_m h)`` (Strang steps), all of
        them; empty for drift/kick tables.
    a, b
        Drift and kick coefficients ``φ_T(a_0 h) φ_V(b_0 h) … φ_T(a_s h)``; empty for
        compositions.
    nystrom
        True for Runge–Kutta–Nyström tables.
    """

    name: str
    order: int
    reference: str
    doc: str
    weights: tuple[float, ...] = ()
    a: tuple[float, ...] = ()
    b: tuple[float, ...] = ()
    nystrom: bool = False


def _mirror(outer_to_inner: tuple[float, ...], centre: float) -> tuple[float, ...]:
    return (*outer_to_inner, centre, *reversed(outer_to_inner))


#: s35odr10 weights from the outside in; the central weight follows from Σ w = 1
_SS10 = (0.078795722521686419263907679337684, 0.31309610341510852776481247192647,
         0.027918383235078066109520273275299, -0.22959284159390709415121339679655,
         0.13096206107716486317465685927961, -0.26973340565451071434460973222411,
         0.074973343155891435666137105641410, 0.11199342399981020488957508073640,
         0.36613344954622675119314812353150, -0.39910563013603589787862981058340,
         0.10308739852747107731580277001372, 0.41143087395589023782070411897608,
         -0.0048663605831352617621956593099771, -0.39203335370863990644808193642610,
         0.051942502962449647037182904015976, 0.050665090759924496335874344156866,
         0.049674370639729879054568800279461)
#: the paper's central weight, 0.049317735759594537917680008339338, is 1 − 2 Σ of the others
_SS10_CENTRE = 1.0 - 2.0 * math.fsum(_SS10)

#: order-8 RKN drifts a_1..a_9 and kicks b_1..b_9 from the outside in; a_10 (two central
#: drifts) and b_10 (one central kick) follow from Σ a = Σ b = 1
_BCE8_A = (0.0505805, 0.149999, -0.0551795510771615573511026950361,
           0.423755898835337951482264998051, -0.213495353584659048059672194633,
           -0.0680769774574032619111630736274, 0.227917056974013435948887201671,
           -0.235373619381058906524740047732, 0.387413869179878047816794031058)
_BCE8_B = (0.129478606560536730662493794395, 0.222257260092671143423043559581,
           -0.0577514893325147204757023246320, -0.0578312262103924910221345032763,
           0.103087297437175356747933252265, -0.140819612554090768205554103887,
           0.0234462603492826276699713718626, 0.134854517356684096617882205068,
           0.0287973821073779306345172160211)
_BCE8_AC = 0.5 - math.fsum(_BCE8_A)
_BCE8_BC = 1.0 - 2.0 * math.fsum(_BCE8_B)

_SS = ("M. Sofroniou, G. Spaletta, Derivation of symmetric composition constants for symmetric "
       "integrators, Optim. Methods Softw. 20 (2005) 597–613, s35odr10")
_BCE = ("S. Blanes, F. Casas, A. Escorihuela-Tomàs, Runge–Kutta–Nyström symplectic splitting "
        "methods of order 8, Appl. Numer. Math. 182 (2022) 14–27, 19-stage ABA method")

#: The tables by name (registered in :data:`~poissonkit.numerics.integrators.splitting.SCHEMES`).
TABLES: dict[str, HighOrderTable] = {t.name: t for t in (
    HighOrderTable(
        "splitting10_ss", 10, _SS,
        "Order-10 Sofroniou–Spaletta composition (s35odr10, Optim. Methods Softw. 20 (2005) 597): "
        "35 Strang stages of the exact sub-flows (35 force evaluations per step); order 10 on "
        "every splittable system.",
        weights=_mirror(_SS10, _SS10_CENTRE)),
    HighOrderTable(
        "splitting8_bce", 8, _BCE,
        "Order-8 Blanes–Casas–Escorihuela Runge–Kutta–Nyström splitting (Appl. Numer. Math. 182 "
        "(2022) 14): 19 force evaluations per step (drift first); at equal cost far more "
        "accurate than the order-8 Strang composition. Its order uses {V,{V,{V,T}}} = 0, true "
        "for every splittable system.",
        a=(*_BCE8_A, _BCE8_AC, _BCE8_AC, *reversed(_BCE8_A)),
        b=_mirror(_BCE8_B, _BCE8_BC), nystrom=True),
)}

"""Built-in plugin registering poissonkit's own integrators (``poissonkit_integrators`` hook)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from poissonkit.contracts import Integrator
from poissonkit.numerics.integrators import capabilities as caps
from poissonkit.numerics.integrators.capabilities import Traits
from poissonkit.plugin.contributions import IntegratorEntry, Param
from poissonkit.plugin.hookspecs import hookimpl

#: A registry parameter's value (see :class:`~poissonkit.plugin.contributions.Param`).
Option = float | int | str | bool
Factory = Callable[..., Integrator]

def _entry(traits: Traits, name: str, doc: str, factory: Factory,
           params: tuple[Param, ...] = (), order: int = 0,
           choices: dict[str, tuple[Any, ...]] | None = None) -> IntegratorEntry:
    """A registry entry whose family, capabilities and (unless the member states its own)
    order come from the family's one declaration ``traits``."""
    return IntegratorEntry(name=name, doc=doc, params=params, factory=factory,
                           order=order or traits.order, family=traits.family,
                           capabilities=traits.capabilities, choices=dict(choices or {}))


_SPLIT_PARAMS = (
    Param("adaptive", "bool", "time-symmetrised distance-based step for close encounters", False),
    Param("reference_distance", "float",
          "d_ref of the adaptive step factor (internal length; 0 = initial smallest distance)",
          0.0),
    Param("iterations", "int", "fixed-point iterations of the symmetrised adaptive step", 1),
    Param("compensated", "bool",
          "Kahan-compensated summation of every drift and kick increment: removes the round-off "
          "floor (~1e-10) of long runs at small steps for ~1.2x the time per step",
          False),
)

_SPLIT_DOCS = {
    2: "Strang splitting of the exact kinetic (drift + free rotation) and potential (kick) flows.",
    4: "Order-4 Suzuki fractal composition (5 Strang stages) of the exact sub-flows.",
    6: "Order-6 Kahan–Li composition (s9odr6, 9 Strang stages) of the exact sub-flows.",
    8: "Order-8 Kahan–Li composition (s15odr8, 15 Strang stages) of the exact sub-flows.",
}


def _splitting(order: int, scheme: str | None = None) -> Factory:
    def factory(**params: Option) -> Integrator:
        from poissonkit.numerics.integrators.splitting import Splitting

        return Splitting(order=order, scheme=scheme, **params)
    return factory


#: Optimised Runge–Kutta–Nyström tables (coefficients and citations in
#: poissonkit.numerics.integrators.splitting.SCHEMES); name -> (order, doc)
_RKN_DOCS = {
    "splitting4_bm": (4, "Order-4 Blanes–Moan SRKN_6^b (J. Comput. Appl. Math. 142 (2002) 313): "
                         "optimised Runge–Kutta–Nyström splitting, 6 force evaluations per step "
                         "(7 kicks, first same as last)."),
    "splitting6_bm": (6, "Order-6 Blanes–Moan SRKN_14^a (J. Comput. Appl. Math. 142 (2002) 313): "
                         "optimised Runge–Kutta–Nyström splitting, 14 force evaluations per step "
                         "(drift first)."),
}


def _logh(order: int) -> Factory:
    def factory(**params: Option) -> Integrator:
        from poissonkit.numerics.integrators.time_transformed import TimeTransformedSplitting

        return TimeTransformedSplitting(order=order, **params)
    return factory


_LOGH_PARAMS = (
    Param("shift", "float", "constant C of ln(C - V), internal energy unit; C - V must stay "
          "positive (0 = Mikkola-Tanikawa logarithmic Hamiltonian, for V < 0)", 0.0),
    Param("exponent", "float", "k of dt/ds = ((C - V0)/(C - V))^k: 1 = logarithmic Hamiltonian "
          "(1/r potentials), about 1/2 for dipolar 1/r^3 encounters", 1.0),
    Param("track_kinetic", "bool", "carry T + p_t by each kick's work instead of recomputing it "
          "from the momenta: removes the round-off floor of fast spins (T >> |V|)", False),
)

_LOGH_DOCS = {
    2: "Time-transformed leapfrog",
    4: "Order-4 (Suzuki) composition of the time-transformed leapfrog",
    6: "Order-6 (Kahan–Li s9odr6) composition of the time-transformed leapfrog",
    8: "Order-8 (Kahan–Li s15odr8) composition of the time-transformed leapfrog",
    10: "Order-10 (Sofroniou–Spaletta s35odr10, the weights of splitting10_ss; 35 force "
        "evaluations per step) composition of the time-transformed leapfrog",
}

#: how a scene reaches TimeTransformedSplitting.for_close_approach, the order-10 preset
_LOGH10_PRESET = (" The close-approach tuning (fewest force evaluations per accuracy on "
                  "eccentric approaches of tops, docs/performance.md) is logh10 with "
                  "track_kinetic = true and shift = 3|V(y0)| (exponent 1): in a scene, "
                  "method = \"logh10\" with those options; in Python, "
                  "TimeTransformedSplitting.for_close_approach(system, y0).")


def _scipy(method: str) -> Factory:
    def factory(**params: Option) -> Integrator:
        from poissonkit.numerics.integrators.scipy_ivp import ScipyIVP

        return ScipyIVP(method=method, **params)
    return factory


def _wisdom_holman(corrector: bool) -> Factory:
    def factory(**params: Option) -> Integrator:
        from poissonkit.numerics.integrators.wisdom_holman import WisdomHolman

        return WisdomHolman(corrector=corrector, **params)
    return factory


def _midpoint(**params: Option) -> Integrator:
    from poissonkit.numerics.integrators.midpoint import ImplicitMidpoint

    return ImplicitMidpoint(**params)


def _discrete_gradient(**params: Option) -> Integrator:
    from poissonkit.numerics.integrators.discrete_gradient import DiscreteGradient

    return DiscreteGradient(**params)


_SCIPY_PARAMS = (
    Param("atol", "float", "absolute tolerance (0 = same as tol)", 0.0),
    Param("max_step", "float", "largest step, internal time unit (0 = unlimited)", 0.0),
)


@hookimpl
def poissonkit_integrators() -> list[IntegratorEntry]:
    """poissonkit's integrators: splittings, implicit midpoint, scipy baselines."""
    out = [
        _entry(caps.SPLITTING, f"splitting{p}",
               _SPLIT_DOCS[p] + " Compiled time loop; fixed step (give step=); preserves |ν|, "
               "(ν, m), total linear and angular momentum to round-off; symplectic on each leaf.",
               _splitting(p), _SPLIT_PARAMS, order=p)
        for p in (2, 4, 6, 8)
    ]
    out += [
        _entry(caps.SPLITTING, name, doc + " Exact sub-flows as splitting2–8, so the same "
               "invariants hold to round-off; its order uses {V,{V,{V,T}}} = 0, true for every "
               "splittable system.", _splitting(p, name), _SPLIT_PARAMS, order=p)
        for name, (p, doc) in _RKN_DOCS.items()
    ]
    from poissonkit.numerics.integrators.compositions import TABLES  # pure data, no numba

    out += [
        _entry(caps.SPLITTING, t.name, t.doc + " Exact sub-flows as splitting2–8, so the same "
               "invariants hold to round-off.", _splitting(t.order, t.name), _SPLIT_PARAMS,
               order=t.order)
        for t in TABLES.values()
    ]
    out.extend(
        _entry(
            caps.TIME_TRANSFORMED, f"logh{p}",
            _LOGH_DOCS[p] + " in the logarithmic Hamiltonian ln(T + p_t) − ln(C − V) "
            "(Mikkola & Tanikawa 1999; Preto & Tremaine 1999): exact drifts and kicks for "
            "rescaled times, so the physical step shrinks where the potential well is deep "
            "(close encounters); step = fictitious-time step (= physical step at the start). "
            "Preserves |ν|, (ν, m), total linear and angular momentum to round-off; symplectic "
            "in extended phase space, energy error bounded. TwoBodySystem and NBodySystem."
            + (_LOGH10_PRESET if p == 10 else ""), _logh(p), _LOGH_PARAMS, order=p)
        for p in (2, 4, 6, 8, 10))
    wh_doc = ("Wisdom–Holman splitting in Jacobi coordinates (exact Kepler drifts, interaction "
              "kicks; SABA_n of Laskar & Robutel 2001) for point masses around one dominant "
              "body 0, with AllPairs('gravity'). Fixed step; symplectic; total momenta to "
              "round-off; energy error O(eps h^2n + eps^2 h^2), eps = planet/star mass ratio. "
              "Compiled loop on the shared driver: located events, checkpoints, streaming. "
              "table= picks a Blanes et al. (2013) method (e.g. 10_6_4), correctors= a "
              "Wisdom-Holman-Touma symplectic corrector (as WHFast).")
    from poissonkit.numerics.integrators.discrete_gradient import GRADIENTS
    from poissonkit.numerics.integrators.wisdom_holman.tables import (CORRECTOR_G, CORRECTOR_ORDERS,
                                                                      TABLE_ORDERS)

    wh_choices = {"stages": tuple(sorted(CORRECTOR_G)), "correctors": (0, *CORRECTOR_ORDERS)}
    out.append(_entry(
        caps.WISDOM_HOLMAN, "wisdom_holman", wh_doc + " stages=1 is the classical WH map (as "
        "WHFast).", _wisdom_holman(False),
        (Param("stages", "int", "kicks per step n = 1 ... 4 (SABA_n)", 1, positive=True),
         Param("table", "str", "Blanes et al. 2013 method instead of SABA_n: 10_4, "
               "8_6_4, 10_6_4, h8_4_4, h8_6_4, h10_6_4 ('' = SABA_n)", ""),
         Param("correctors", "int", "order 3, 5, 7, 11 or 17 of the Wisdom-Holman-Touma "
               "symplectic corrector (stages=1, as WHFast; 0 = none)", 0)),
        order=2, choices={**wh_choices, "table": ("", *sorted(TABLE_ORDERS))}))
    out.append(_entry(
        caps.WISDOM_HOLMAN, "wisdom_holman_corrected", wh_doc + " With the SABAC_n corrector: "
        "error O(eps h^2n + eps^2 h^4), 3 extra force evaluations per step.",
        _wisdom_holman(True),
        (Param("stages", "int", "kicks per step n = 2 ... 4 (SABAC_n)", 4, positive=True),
         Param("correctors", "int", "order 3, 5, 7, 11 or 17 of the Wisdom-Holman-Touma "
               "symplectic corrector (stages=1; 0 = none)", 0)),
        order=4, choices=wh_choices))
    out.append(_entry(
        caps.MIDPOINT, "midpoint",
        "Implicit midpoint rule (order 2, symmetric); preserves all quadratic invariants. "
        "Any compiled system, including deformed brackets; Newton with the generated Jacobian, "
        "else fixed-point iteration.", _midpoint,
        (Param("tol", "float", "iteration tolerance (relative)", 1e-14, positive=True),
         Param("max_iterations", "int", "iteration limit per step", 50, positive=True),
         Param("newton", "bool", "use Newton's method when a Jacobian exists", True))))
    out.append(_entry(
        caps.DISCRETE_GRADIENT, "discrete_gradient",
        "Energy-preserving discrete-gradient method (order 2, symmetric) for any compiled "
        "symbolic system x' = N P grad H: x' = x + h S(midpoint) grad_bar H(x, x') with the "
        "average vector field (exact Gauss-Legendre quadrature, polynomial H) or Gonzalez's "
        "midpoint discrete gradient (any H); H conserved to round-off, linear and quadratic "
        "Casimirs too, other Casimirs to O(h^2). Cohen & Hairer 2011; McLachlan, Quispel & "
        "Robidoux 1999.", _discrete_gradient,
        (Param("gradient", "str", "discrete gradient: auto (avf for polynomial H, else "
               "gonzalez), avf or gonzalez", "auto"),
         Param("tol", "float", "Newton tolerance relative to the step's increment",
               1e-14, positive=True),
         Param("max_iterations", "int", "iteration limit per step", 50, positive=True),
         Param("newton", "bool", "Newton's method with the field's Jacobian at the "
               "midpoint (else fixed-point iteration)", True)),
        choices={"gradient": GRADIENTS}))
    for method, order, doc in (
            ("RK45", 5, "scipy solve_ivp RK45 (Dormand–Prince 5(4)), adaptive; baseline."),
            ("DOP853", 8, ("scipy solve_ivp DOP853 (Dormand–Prince 8(5,3)), adaptive; "
                           "baseline and high-accuracy reference.")),
            ("Radau", 5, "scipy solve_ivp Radau IIA (order 5), implicit, for stiff problems."),
            ("LSODA", 0, "scipy solve_ivp LSODA (Adams/BDF switching), variable order.")):
        out.append(_entry(caps.SCIPY, method.lower(), doc + " Tolerance: tol (rtol; atol "
                          "defaults to tol).", _scipy(method), _SCIPY_PARAMS, order=order))
    return out

"""The outcome of a Hamiltonisation search: solutions, or a certificate that there is none
within the ansatz (see :mod:`poissonkit.structure.hamiltonize` for the method)."""

from collections.abc import Mapping
from dataclasses import dataclass, field

import sympy as sp

from poissonkit.structure.bivector import Bivector
from poissonkit.structure.hamiltonize_problem import Ansatz, HamiltonizationProblem

#: Outcomes of a search (:attr:`HamiltonizeResult.status`).
_STATUSES = ("found", "no_linear_solution", "no_multiplier", "no_jacobi_solution",
             "jacobi_unsolved")

__all__ = ["Certificate", "HamiltonizeResult", "result_record"]


@dataclass(frozen=True)
class Certificate:
    """Why no bracket of the ansatz exists.

    Attributes
    ----------
    kind
        ``"linear"``: ``combination`` of the linear conditions reads ``0 = value``;
        ``"multiplier"``: the linear conditions force the multiplier ansatz ``mu`` to vanish;
        ``"jacobi"``: the Jacobi equations in the free parameters have reduced Groebner basis
        ``[1]`` (or, without free parameters, a non-zero coefficient ``equations[0]``).
    combination
        For ``"linear"``: ``{(condition, monomial): weight}``; the weighted sum of those
        equations has zero left-hand side and non-zero right-hand side. Re-checked exactly.
    equations
        For ``"jacobi"``: the polynomial equations in the parameters (or the offending
        non-zero coefficients).
    text
        A sentence for reports.
    """

    kind: str
    combination: Mapping[tuple, sp.Expr] = field(default_factory=dict)
    equations: tuple[sp.Expr, ...] = ()
    text: str = ""


@dataclass(frozen=True)
class HamiltonizeResult:
    """Outcome of :func:`hamiltonize`.

    Attributes
    ----------
    status
        ``"found"``; ``"no_linear_solution"`` / ``"no_multiplier"`` / ``"no_jacobi_solution"``
        (proved: see ``certificate``); ``"jacobi_unsolved"`` (too many free parameters for the
        Jacobi step, or sympy found no real solution of a system whose ideal is not ``[1]``;
        ``jacobi_equations`` lists it, nothing is claimed).
    ansatz
        The space searched (``ansatz.describe()``).
    problem
        The problem (field, Hamiltonian, Casimirs, measure).
    multiplier
        ``N`` (an expression; in the free parameters for a polynomial multiplier ansatz).
    family
        The bivector solving the linear conditions, with free parameters ``t1, t2, ...``
        (``None`` for a search over combinations of integrals: its linear family is one copy
        of the bracket per integral, see :mod:`~poissonkit.structure.hamiltonize_span`).
    parameters
        The free parameters of ``family`` (for a span search also the unknown coefficients
        ``c2, c3, ...`` of ``H``).
    jacobi_equations
        Polynomial equations in ``parameters`` equivalent to ``[P, P] = 0`` on ``family``
        (a reduced Groebner basis when solved; empty if Jacobi holds identically).
    solutions
        The Poisson members: one :class:`Bivector` per solution component (free parameters
        that stay free remain symbols), each paired with its multiplier in ``multipliers``.
    multipliers
        ``N`` for each entry of ``solutions`` (``None`` without a Hamiltonian).
    hamiltonians
        ``H`` for each entry of ``solutions``: the given Hamiltonian, or the combination of the
        integrals found by a span search (unknown coefficients ``c2, c3, ...`` that stay free
        remain symbols).
    integral_casimirs
        For each entry of ``solutions``: a basis of the constant-coefficient combinations of
        the given integrals that are Casimirs of that bracket, each as ``{integral name:
        coefficient}`` (empty without integrals).
    certificate
        Proof of non-existence within the ansatz, or ``None``.
    stats
        Sizes and timings: unknowns, equations, rank, seconds per phase.
    """

    status: str
    ansatz: Ansatz
    problem: HamiltonizationProblem
    multiplier: sp.Expr | None = None
    family: Bivector | None = None
    parameters: tuple[sp.Symbol, ...] = ()
    jacobi_equations: tuple[sp.Expr, ...] = ()
    solutions: tuple[Bivector, ...] = ()
    multipliers: tuple[sp.Expr, ...] = ()
    certificate: Certificate | None = None
    hamiltonians: tuple[sp.Expr | None, ...] = ()
    integral_casimirs: tuple[tuple[Mapping[str, sp.Expr], ...], ...] = ()
    stats: Mapping[str, object] = field(default_factory=dict)

    @property
    def found(self) -> bool:
        """Whether a Poisson bivector of the ansatz was found."""
        return self.status == "found"

    @property
    def proved_absent(self) -> bool:
        """Whether non-existence within the ansatz is proved (``certificate`` says how)."""
        return self.status in ("no_linear_solution", "no_multiplier", "no_jacobi_solution")

    def __repr__(self) -> str:
        """Several lines: :meth:`summary`, what the free parameters are, and the brackets."""
        lines = [self.summary()]
        if self.parameters:
            names = ", ".join(map(str, self.parameters))
            lines.append(f"  free parameters {names}: arbitrary constants of the family\n"
                         "    that solves the linear conditions (each value gives a bracket of "
                         "the ansatz);\n    one left in a solution below stays free in it")
        for k, P in enumerate(self.solutions[:4]):
            rows = "; ".join("[" + ", ".join(map(str, P.matrix.row(i))) + "]"
                             for i in range(P.matrix.rows))
            lines.append(f"  solution [{k}]: P = [{rows}] in ({', '.join(map(str, P.coords))})")
        if len(self.solutions) > 4:
            lines.append(f"  ... {len(self.solutions) - 4} more in .solutions")
        lines.append("  (.status, .solutions, .multipliers, .hamiltonians, .parameters, "
                     ".certificate)")
        return "\n".join(lines)

    __str__ = __repr__

    def summary(self) -> str:
        """A short human-readable report: what was searched, found or ruled out."""
        coords = self.problem.coords
        title = f" of {self.problem.name}" if self.problem.name else ""
        lines = [f"Hamiltonisation search{title}",
                 f"  ansatz     : {self.ansatz.describe(coords)}"]
        cond = []
        if self.problem.hamiltonian is not None:
            cond.append("X = N P dH")
        elif self.problem.hamiltonian_span:
            cond.append("X = N P dH, H = sum c_k I_k over ("
                        + ", ".join(self.problem.hamiltonian_span) + ")")
        if self.problem.casimirs or self.problem.casimir_differentials:
            cond.append("Casimirs " + ", ".join([*self.problem.casimirs,
                                                 *self.problem.casimir_differentials]))
        cond.append("[P,P] = 0")
        lines.append(f"  conditions : {'; '.join(cond)}")
        if self.multiplier is not None:
            lines.append(f"  multiplier : N = {self.multiplier}")
        st = self.stats
        lines.append(f"  linear     : {st.get('unknowns')} unknowns, {st.get('equations')} "
                     f"equations, rank {st.get('rank')}, {len(self.parameters)} free parameters")
        if self.found:
            lines.append(f"  result     : {len(self.solutions)} Poisson component(s)")
            for k, P in enumerate(self.solutions):
                H = self.hamiltonians[k] if k < len(self.hamiltonians) else None
                used = {str(s) for e in P.matrix for s in e.free_symbols}
                if H is not None:
                    used |= {str(s) for s in H.free_symbols}
                free = sorted(used & {str(t) for t in self.parameters})
                mult = "" if self.multipliers[k] is None else f"; N = {self.multipliers[k]}"
                lines.append(f"    [{k}] free parameters: {', '.join(free) or 'none'}{mult}")
                if self.problem.hamiltonian_span and k < len(self.hamiltonians):
                    lines.append(f"        H = {self.hamiltonians[k]}")
                if k < len(self.integral_casimirs) and self.integral_casimirs[k]:
                    lines.append("        Casimirs among the integrals: " + ", ".join(
                        " + ".join(f"({v})*{n}" for n, v in comb.items())
                        for comb in self.integral_casimirs[k]))
        elif self.certificate is not None:
            lines.append(f"  result     : no bracket in this ansatz. {self.certificate.text}")
        else:
            lines.append(f"  result     : {self.status} ({len(self.jacobi_equations)} "
                         "Jacobi equations left unsolved; nothing is claimed)")
        return "\n".join(lines)


def result_record(res: HamiltonizeResult) -> dict:
    """A JSON-ready dict of a :class:`HamiltonizeResult` (expressions as strings)."""
    rec: dict = {"name": res.problem.name, "status": res.status, "found": res.found,
                 "proved_absent": res.proved_absent,
                 "ansatz": res.ansatz.describe(res.problem.coords),
                 "multiplier": None if res.multiplier is None else str(res.multiplier),
                 "parameters": [str(t) for t in res.parameters],
                 "jacobi_equations": [str(e) for e in res.jacobi_equations],
                 "stats": dict(res.stats)}
    coords = res.problem.coords
    rec["solutions"] = [
        {"N": None if N is None else str(N),
         "brackets": {f"{coords[i]},{coords[j]}": str(P.matrix[i, j])
                      for i in range(len(coords)) for j in range(i + 1, len(coords))
                      if P.matrix[i, j] != 0}}
        for P, N in zip(res.solutions, res.multipliers)]
    for k, sol in enumerate(rec["solutions"]):
        if k < len(res.hamiltonians) and res.hamiltonians[k] is not None:
            sol["H"] = str(res.hamiltonians[k])
        if k < len(res.integral_casimirs):
            sol["integral_casimirs"] = [{n: str(v) for n, v in comb.items()}
                                        for comb in res.integral_casimirs[k]]
    if res.certificate is not None:
        rec["certificate"] = {"kind": res.certificate.kind, "text": res.certificate.text,
                              "combination": {f"{k[0]} [{k[1]}]": str(v) for k, v in
                                              res.certificate.combination.items()},
                              "equations": [str(e) for e in res.certificate.equations]}
    return rec

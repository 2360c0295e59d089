"""``poissonkit verify``: Jacobi identity, brackets, rank and Casimirs of a Poisson structure.

``poissonkit verify NAME`` checks a registered structure or system (``--list`` shows them);
``poissonkit verify FILE.json`` checks a bivector in PoissonGeometry's dict format::

    {"dim": 3, "bivector": {"1,2": "x3", "1,3": "-x2", "2,3": "x1"}}

with coordinates ``x1 .. xn`` (or an optional ``"coords": [...]`` list, and ``"params": [...]``
naming symbolic parameters the entries may use). Strings are parsed with the allow-list parser,
never evaluated. For a Hamiltonian system the report also checks the claimed Casimirs,
integrals, invariant measure, original equations and the entry's own claims.

Time budget. Every check runs in a worker process (:mod:`multiprocessing`, ``fork``) that is
terminated when the wall-clock budget ``--timeout`` (default :data:`DEFAULT_TIMEOUT` s, shared
by all checks of one report) runs out: sympy cannot be interrupted cooperatively, so a check
that has not finished is reported as *undecided within the budget* instead of running on.
``--timeout 0`` removes the budget (checks then run in this process, one after the other);
``--method exact`` asks for symbolic proofs of everything.

Entries tagged ``"almost-poisson"`` carry a bracket that is deliberately not Poisson (an
almost-Poisson bracket kept because ``xdot = N P dH`` reproduces the equations of motion): for
them a failing Jacobi identity is the expected verdict, and a passing one is a failed claim.

Exit codes (:data:`EXIT_CODES`): 0 the structure is Poisson (or, for an almost-Poisson entry,
is not) and every claim holds; 1 not Poisson, or a claimed property fails; 2 error (bad input,
or a check raised: an unverified claim never passes); 3 nothing failed but some claim was
undecided within the time budget.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import re
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from decimal import Decimal
from fractions import Fraction
from pathlib import Path
from typing import Any

import sympy as sp

from poissonkit._display import html_table, latex_table
from poissonkit.errors import InputError, ParseError, PoissonkitError

#: Keys a JSON structure file may contain.
JSON_KEYS = ("dim", "bivector", "coords", "variable", "params", "name")
#: Largest dimension a JSON structure may declare: the Jacobi identity has ``dim^3/6``
#: components, and ``"dim": 10**9`` must be refused, not allocated.
MAX_DIM = 200

EXIT_OK, EXIT_FAILED, EXIT_ERROR, EXIT_UNDECIDED = 0, 1, 2, 3
#: Exit code of ``poissonkit verify`` for each report status.
EXIT_CODES = {"ok": EXIT_OK, "failed": EXIT_FAILED, "error": EXIT_ERROR,
              "undecided": EXIT_UNDECIDED}
#: Default wall-clock budget (s) of all checks of one report: with loading and the system's
#: construction every registered entry then finishes within a minute on two cores.
DEFAULT_TIMEOUT = 40.0
#: Tag of registry entries whose bracket is deliberately not Poisson.
ALMOST_POISSON_TAG = "almost-poisson"
#: Above this many operations in ``P`` (``sympy.count_ops``), ``--method auto`` checks Jacobi
#: at random rational points (on the constraint set, if any) instead of symbolically: the
#: Routh sphere's bracket (~48000 operations) took more than 39 min exactly modulo its
#: constraint, ~10 s at points.
AUTO_POINTS_OPS = 2500


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``poissonkit verify``."""
    parser.add_argument("target", nargs="?", help="registered structure/system name or a .json file")
    parser.add_argument("--list", action="store_true", help="list registered structures and systems")
    parser.add_argument("--json", action="store_true", help="machine-readable output")
    parser.add_argument("--casimir-degree", type=int, default=2, metavar="N",
                        help="search polynomial Casimirs up to this degree (0: skip; default 2)")
    parser.add_argument("--method", choices=("auto", "exact", "random"), default="auto",
                        help="method of the Jacobi and field checks (default auto: exact, or "
                             "exact arithmetic at random rational points for large expressions)")
    parser.add_argument("--seed", type=int, default=None, help="seed of random checks")
    parser.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT, metavar="SECONDS",
                        help="wall-clock budget of all checks; checks still running are "
                             f"reported undecided (exit {EXIT_UNDECIDED}) (default "
                             f"{DEFAULT_TIMEOUT:g}; 0: no limit)")
    parser.add_argument("--equations", action="store_true",
                        help="also print the equations of motion xdot = N P dH")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                        help="parameter of a registered entry (repeatable)")
    parser.add_argument("--hamiltonize", nargs="?", type=int, const=-1, default=None,
                        metavar="DEGREE",
                        help="instead of checking the stated bracket, search one from the "
                             "equations of motion (survey ansatz, coefficients of degree "
                             "DEGREE; without a value: degrees 1..4 until found)")


# ---------------------------------------------------------------------------------- loading
def _parse_key(key: Any) -> tuple[int, int]:
    if isinstance(key, (list, tuple)):
        parts = list(key)
    else:
        parts = [p for p in re.split(r"[\s,()]+", str(key)) if p]
    try:
        idx = tuple(int(p) for p in parts)
    except ValueError:
        raise InputError(f"bivector key {key!r} is not a pair of 1-based indices") from None
    if len(idx) != 2:
        raise InputError(f"bivector key {key!r} must name two indices")
    if min(idx) < 1:
        raise InputError(f"bivector key {key!r}: indices are 1-based (zero or negative given)")
    return idx  # type: ignore[return-value]


def load_structure_json(source: str | Path | dict) -> tuple[str, Any]:
    """Read a bivector in PoissonGeometry's dict format (a path or an already-loaded dict).

    Returns
    -------
    (name, Bivector)

    Raises
    ------
    InputError, ParseError, DimensionError
        Malformed file, unknown keys, unknown symbols or unsafe expressions.
    """
    from poissonkit.structure.bivector import Bivector
    from poissonkit.structure.parsing import parse_expression

    if isinstance(source, dict):
        data, name = source, str(source.get("name", "structure"))
    else:
        path = Path(source)
        try:
            data = json.loads(path.read_text())
        except OSError as exc:
            raise InputError(f"cannot read {path}: {exc.strerror}") from None
        except json.JSONDecodeError as exc:
            raise ParseError(f"{path}: invalid JSON ({exc.msg}, line {exc.lineno})") from None
        name = path.name
    if not isinstance(data, dict):
        raise InputError("structure file must hold a JSON object")
    unknown = set(data) - set(JSON_KEYS)
    if unknown:
        raise InputError(f"unknown key(s) {sorted(unknown)}; allowed: {', '.join(JSON_KEYS)}")
    if "bivector" not in data or not isinstance(data["bivector"], dict):
        raise InputError('structure file needs a "bivector" object {"i,j": "expression"}')
    coords = data.get("coords")
    dim = data.get("dim")
    if coords is not None:
        if not isinstance(coords, list) or not all(isinstance(c, str) for c in coords):
            raise InputError('"coords" must be a list of names')
        for c in coords:
            if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", c):
                raise InputError(f'"coords": coordinate name {c!r} is not an identifier')
        if dim is not None and dim != len(coords):
            raise InputError(f'"dim" = {dim} but "coords" has {len(coords)} names')
        dim = len(coords)
        if not 2 <= dim <= MAX_DIM:
            raise InputError(f'"coords" must name 2 to {MAX_DIM} coordinates, got {dim}')
    if coords is None and dim is None:
        raise InputError('structure file needs "dim" (an integer) or "coords" (a list of names)')
    if not isinstance(dim, int) or isinstance(dim, bool) or not 2 <= dim <= MAX_DIM:
        raise InputError(f'"dim" must be an integer from 2 to {MAX_DIM}, got {dim!r}')
    if coords is None:
        var = data.get("variable", "x")
        if not isinstance(var, str) or not re.fullmatch(r"[A-Za-z][A-Za-z_]*", var):
            raise InputError(f'"variable" must be a name, got {var!r}')
        coords = [f"{var}{i}" for i in range(1, dim + 1)]
    syms = [sp.Symbol(c, real=True) for c in coords]
    params = data.get("params", [])
    if not isinstance(params, list) or not all(isinstance(p, str) for p in params):
        raise InputError('"params" must be a list of names')
    extra = {}
    for p in params:
        if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", p) or p in coords:
            raise InputError(f'"params": parameter name {p!r} is not a new identifier')
        extra[p] = sp.Symbol(p, real=True)
    comps = {}
    for key, value in data["bivector"].items():
        i, j = _parse_key(key)
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            raise ParseError(f"component {key!r}: expected an expression string, got {value!r}")
        try:
            comps[(i, j)] = parse_expression(str(value), syms, extra)
        except ParseError as exc:  # name the component, not only the text
            hint = (f' (coordinates {coords[0]}..{coords[-1]} from "dim", "coords" or "variable"; '
                    'declare symbolic parameters in "params")') if "not allowed" in str(exc) \
                else ""
            raise ParseError(f"bivector component {key!r}: {exc}{hint}") from None
    try:
        return name, Bivector.from_components(comps, syms)
    except InputError as exc:  # DimensionError, ParseError, ...: keep the type
        raise type(exc)(f"bivector: {exc}") from None


def _coerce_param(text: str) -> tuple[str, Any]:
    if "=" not in text:
        raise InputError(f"--param expects NAME=VALUE, got {text!r}")
    key, value = text.split("=", 1)
    value = value.strip()
    if "," in value:
        return key.strip(), tuple(v.strip() for v in value.split(","))
    return key.strip(), value


#: Largest decimal exponent of a parameter value (``1e1000``); larger ones are refused.
MAX_EXPONENT = 1000
_FRACTION = re.compile(r"[+-]?\d+\s*/\s*\d+")


def exact_number(text: str, name: str = "parameter") -> sp.Rational:
    """The exact rational a decimal or fraction text means: ``"0.3333" -> 3333/10000``.

    Parameters are used as written, never as the rational of their binary float
    (``3333333333333333/10000000000000000`` for ``1/3``); ``"1/3"`` is one third.

    Raises
    ------
    InputError
        If ``text`` is not a finite decimal number or a fraction of integers.
    """
    t = str(text).strip()
    try:
        if _FRACTION.fullmatch(t):
            num, den = (int(x) for x in t.split("/"))
            if den == 0:
                raise ZeroDivisionError
            return sp.Rational(num, den)
        dec = Decimal(t)  # decimals and exponents exactly, without computing them yet
        if not dec.is_finite() or abs(dec.adjusted()) > MAX_EXPONENT:
            raise ValueError  # nan, inf, and 1e999999999999 (would take hours to expand)
        value = Fraction(dec)
    except (ValueError, ZeroDivisionError, ArithmeticError):
        raise InputError(f"{name} must be a finite decimal number or a fraction, got {text!r}") \
            from None
    return sp.Rational(value.numerator, value.denominator)


def _exact_params(entry: Any, given: dict[str, Any]) -> dict[str, Any]:
    """Validate ``--param`` values with the entry's typed parameters, then hand the builder the
    exact rationals of the texts for ``float`` and ``vector`` parameters."""
    types = {p.name: p.type for p in entry.params}
    check, exact = {}, {}
    for key, value in given.items():
        kind = types.get(key)
        if kind in ("float", "vector") and isinstance(value, (str, tuple)):
            items = value if isinstance(value, tuple) else (value,)
            nums = tuple(exact_number(v, f"{entry.name}: parameter {key!r}") for v in items)
            check[key] = tuple(float(v) for v in nums) if kind == "vector" else float(nums[0])
            exact[key] = nums if kind == "vector" else nums[0]
        else:
            check[key] = value
    values = entry.resolve_params(check)  # types, signs, finiteness, unknown names
    values.update(exact)
    return values


def load_target(target: str, params: Sequence[str] = ()) -> tuple[str, str, Any]:
    """``(name, doc, Bivector | HamiltonianSystem)`` for a registry name or a JSON path."""
    from poissonkit.plugin import names, system

    if target.endswith(".json") or (Path(target).is_file() and target not in names("system")):
        name, obj = load_structure_json(target)
        return name, "bivector from " + Path(target).name, obj
    entry = system(target)
    given = dict(_coerce_param(p) for p in params)
    return entry.name, entry.doc, entry.build(**_exact_params(entry, given))


def _entry_claims(name: str) -> tuple:
    """The system-specific claims of a registered entry (none for a JSON file)."""
    from poissonkit.plugin import names, system

    return tuple(system(name).claims) if name in names("system") else ()


def _is_almost_poisson(name: str) -> bool:
    """Whether the registered entry ``name`` states that its bracket is not Poisson."""
    from poissonkit.plugin import names, system

    return name in names("system") and ALMOST_POISSON_TAG in system(name).tags


# ---------------------------------------------------------------------------------- budget
class _TimeLimit(Exception):
    """Raised by a check that gives up within its budget (reported as undecided)."""


#: The checks of the report being built; worker processes forked from this process inherit it
#: (closures cannot be pickled, their index can).
_TASKS: list[Callable[[], Any]] = []


def _describe(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {str(exc).strip()[:200]}"


def _run_task(index: int) -> tuple[str, Any]:
    """Run one check; ``(kind, value)`` with kind ``done``, ``refused`` (a typed poissonkit
    error: the check does not apply), ``error`` (a bug) or ``undecided``."""
    try:
        return "done", _TASKS[index]()
    except _TimeLimit:
        return "undecided", ""
    except PoissonkitError as exc:
        return "refused", _describe(exc)
    except Exception as exc:  # noqa: BLE001 -- a bug: report it, never call the check ok
        return "error", _describe(exc)


class BoundedChecks:
    """Zero-argument checks run in worker processes that are terminated at a deadline.

    Parameters
    ----------
    tasks
        The checks; each returns a picklable value.
    budget
        Wall-clock seconds for all of them together, from construction; ``<= 0``: no limit
        (the checks then run lazily in this process, as :meth:`result` asks for them).
    workers
        Worker processes (default: the CPU count, at most the number of tasks).

    Notes
    -----
    Uses :class:`multiprocessing.pool.Pool` with the ``fork`` start method (checks are
    closures over sympy objects; a forked worker inherits them). Where ``fork`` is not
    available the checks run in this process without a limit.
    """

    def __init__(self, tasks: Sequence[Callable[[], Any]], budget: float,
                 workers: int | None = None) -> None:
        global _TASKS
        _TASKS = list(tasks)
        self._done: dict[int, tuple[str, Any]] = {}
        self._pool = None
        self.deadline = time.monotonic() + budget if budget > 0 else None
        if self.deadline is not None and "fork" in multiprocessing.get_all_start_methods():
            n = max(1, min(workers or os.cpu_count() or 1, len(_TASKS)))
            self._pool = multiprocessing.get_context("fork").Pool(n)
            # FIFO: the first tasks start first (Jacobi and the claims before the searches)
            self._async = [self._pool.apply_async(_run_task, (i,)) for i in range(len(_TASKS))]

    def result(self, index: int) -> tuple[str, Any]:
        """``(kind, value)`` of check ``index`` (see :func:`_run_task`), waiting at most until
        the deadline; ``("undecided", "")`` if it did not finish by then."""
        if index not in self._done:
            if self._pool is None:
                self._done[index] = _run_task(index)
            else:
                wait = max(0.0, self.deadline - time.monotonic())
                try:
                    self._done[index] = self._async[index].get(timeout=wait)
                except multiprocessing.TimeoutError:
                    self._done[index] = ("undecided", "")
        return self._done[index]

    def close(self) -> None:
        """Terminate the workers (checks still running are abandoned)."""
        if self._pool is not None:
            self._pool.terminate()
            self._pool.join()
            self._pool = None

    def __enter__(self) -> BoundedChecks:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


# ---------------------------------------------------------------------------------- checks
def check_jacobi_at_points(P: Any, constraints: Sequence[Any] = (), trials: int = 3,
                           seed: int | None = None) -> dict[str, Any]:
    """Jacobi identity at random rational points (on the constraint set, if any), exactly.

    ``Jac^{ijk} = P^{im} d_m P^{jk} + cyclic`` (FORMULAS.md §0) with the derivatives taken at
    the points (:class:`~poissonkit.structure.randompoints.RandomPoints`, which also places the
    points on recognised constraint surfaces such as ``(gamma, gamma) = 1``). A non-zero value
    is an exact counterexample (a proof that ``P`` is not Poisson there); a pass carries the
    false-positive bound. Much faster than the symbolic Jacobiator of large brackets.

    Returns
    -------
    dict
        ``is_poisson``, ``method``, ``failures`` (``{"Jac(a, b, c)": value}``),
        ``false_positive_bound``, ``seconds``, ``note``.
    """
    import itertools

    from poissonkit.structure.checks import check_vanishing
    from poissonkit.structure.randompoints import RandomPoints

    t0 = time.perf_counter()
    X, M, n = P.coords, P.matrix, P.dim
    pts = RandomPoints(X, tuple(constraints), trials=trials, seed=seed)

    def term(a: int, b: int, c: int) -> sp.Expr:
        if M[b, c] == 0:
            return sp.Integer(0)
        return sp.Add(*[M[a, m] * pts.derivative(M[b, c], X[m]) for m in range(n)
                        if M[a, m] != 0])

    comps = {f"Jac({X[i]}, {X[j]}, {X[k]})": term(i, j, k) + term(j, k, i) + term(k, i, j)
             for i, j, k in itertools.combinations(range(n), 3)}
    comps = {k: v for k, v in comps.items() if v != 0}
    res = check_vanishing(comps or [sp.Integer(0)], method="random", points=pts)
    where = "on the constraint set " if constraints else ""
    at = ", ".join(f"{k} = {v}" for k, v in (res.point or {}).items())
    return {"is_poisson": bool(res.holds), "method": "random",
            "failures": {k: str(v) for k, v in res.failures},
            "false_positive_bound": res.false_positive_bound,
            "seconds": round(time.perf_counter() - t0, 4),
            "note": f"{res.trials} random rational point(s) {where}(seed {pts.seed}), exact "
                    "arithmetic" + (f"; counterexample at {at}" if at else "")}


def _jacobi_task(P: Any, method: str, seed: int | None, constraints: tuple) -> dict[str, Any]:
    """The Jacobi verdict as a JSON-ready dict (runs in a worker)."""
    from poissonkit.structure.jacobi import check_jacobi

    big = sum(sp.count_ops(e) for e in P.matrix if e != 0) > AUTO_POINTS_OPS
    has_functions = any(e.atoms(sp.core.function.AppliedUndef) for e in P.matrix)
    if not has_functions and (method == "random" and constraints or method == "auto" and big):
        return check_jacobi_at_points(P, constraints, seed=0 if seed is None else seed)
    res = check_jacobi(P, method=method, seed=seed, constraints=constraints)
    return {"is_poisson": res.is_poisson, "method": res.method,
            "failures": {k: str(v) for k, v in res.named_failures().items()},
            "false_positive_bound": res.false_positive_bound,
            "seconds": round(res.seconds, 4), "note": res.note}


class _ClaimResult:
    """Adapter of a plugin claim's ``(holds, detail, method)`` to the check-result protocol."""

    def __init__(self, outcome: Any) -> None:
        try:
            holds, detail, method = outcome
        except (TypeError, ValueError):
            raise InputError("a system claim must return (holds, detail, method)") from None
        if not isinstance(holds, bool):
            raise InputError("a system claim must return a bool as its first item")
        self.holds, self.method = holds, str(method)
        self.failures = () if holds else (("detail", str(detail)),)

    def __bool__(self) -> bool:
        return self.holds


def _claim_name(claim: Any) -> str:
    doc = (getattr(claim, "__doc__", None) or "").strip()
    return doc.splitlines()[0] if doc else getattr(claim, "__name__", "claim")


def _as_check(run: Callable[[], Any]) -> Callable[[], dict[str, Any]]:
    """A claim check returning a picklable ``{holds, method, failures}``."""
    def task() -> dict[str, Any]:
        result = run()
        out = {"holds": bool(result), "method": str(getattr(result, "method", "") or "")}
        fails = getattr(result, "failures", ())
        out["failures"] = [f"{lab} = {val}" for lab, val in list(fails)[:5]] \
            if not out["holds"] else []
        return out
    return task


def _system_claims(sys_: Any, method: str, seed: int | None,
                   claims: tuple) -> list[tuple[str, Callable[[], dict[str, Any]]]]:
    """``(what, check)`` of every claim of a HamiltonianSystem: its Casimirs, first integrals,
    invariant measure, original equations and the entry's system-specific claims."""
    from poissonkit.structure import casimirs as cas
    from poissonkit.structure import checks

    P = sys_.structure
    cons = tuple(sys_.constraints)
    how = {"method": method, "seed": seed}
    out = []
    for name, C in sys_.casimirs.items():
        out.append((f"Casimir {name}",
                    _as_check(lambda C=C: cas.is_casimir(P, C, constraints=cons))))
    for name, F in sys_.integrals.items():
        out.append((f"first integral {name}", _as_check(
            lambda F=F: checks.is_first_integral(sys_, F, constraints=cons, **how))))
    if sys_.measure is not None:
        out.append((f"invariant measure {sys_.measure}",
                    _as_check(lambda: checks.is_invariant_measure(sys_, **how))))
    if sys_.original is not None:
        out.append(("original equations = N P dH",
                    _as_check(lambda: checks.is_conformally_hamiltonian(sys_, **how))))
    for claim in claims:
        out.append((_claim_name(claim),
                    _as_check(lambda claim=claim: _ClaimResult(claim(sys_)))))
    return out


class VerifyReport(dict):
    """The report of :func:`verify`: a JSON-ready ``dict`` that also displays itself.

    ``str(report)`` is the text ``poissonkit verify`` prints; in a notebook it shows as an HTML
    table (``_repr_html_``) or a LaTeX array (``_repr_latex_``). Being a ``dict``, it goes to
    ``json.dumps`` unchanged.
    """

    def __str__(self) -> str:
        return format_report(self)

    def _repr_pretty_(self, p, cycle: bool) -> None:
        p.text("VerifyReport(...)" if cycle else str(self))

    def _rows(self) -> list[tuple[str, str]]:
        jac = self["jacobi"]
        verdict = {True: "holds", False: "FAILS", None: "UNDECIDED"}[jac["is_poisson"]]
        if self.get("almost_poisson") and jac["is_poisson"] is False:
            verdict = "fails, as the entry states (almost-Poisson bracket)"
        rows = [("dimension", str(self["dim"])),
                ("Jacobi identity", f"{verdict} ({jac['method']})")]
        rows += [(k, v) for k, v in jac["failures"].items()]
        if self.get("rank") is not None:
            rows.append(("rank (generic)", str(self["rank"])))
        if self.get("casimirs") is not None:
            rows.append((f"Casimirs (degree <= {self.get('casimir_degree')})",
                         ", ".join(self["casimirs"]) or "none"))
        for c in (self.get("system") or {}).get("checks", []):
            state = {"error": "ERROR", "undecided": "UNDECIDED"}.get(
                c.get("status", ""), "holds" if c.get("holds") else "FAILS")
            rows.append((c["what"], state))
        rows += [("note", n) for n in self.get("notes", [])]
        rows += [("undecided", u) for u in self.get("undecided", [])]
        rows += [("error", e) for e in self.get("errors", [])]
        return rows

    def _title(self) -> str:
        return f"{self.get('name') or 'structure'}: {self.get('status', '')}"

    def _repr_html_(self) -> str:
        """HTML table: Jacobi identity, rank, Casimirs and each claimed property (Jupyter)."""
        return html_table(self._title(), self._rows(), ok=bool(self.get("ok")))

    def _repr_latex_(self) -> str:
        """The same summary as a LaTeX array."""
        return latex_table([("report", self._title()), *self._rows()])


def verify(obj, name: str = "", doc: str = "", *, casimir_degree: int = 2, method: str = "auto",
           seed: int | None = None, timeout: float = DEFAULT_TIMEOUT, claims: tuple = (),
           almost_poisson: bool = False, equations: bool = False) -> VerifyReport:
    """Verify a bivector or system: Jacobi identity, brackets, rank, Casimirs, claims.

    What ``poissonkit verify`` runs, as a function; the report is a JSON-ready dict that also
    displays itself (:class:`VerifyReport`).

    Parameters
    ----------
    obj
        A :class:`~poissonkit.structure.Bivector` or
        :class:`~poissonkit.structure.HamiltonianSystem`.
    casimir_degree
        Search polynomial Casimirs up to this degree (0: skip).
    method
        ``"auto"``, ``"exact"`` or ``"random"``: method of the Jacobi and field checks.
    timeout
        Wall-clock budget (s) of all checks together (:class:`BoundedChecks`); ``<= 0``: none.
    claims
        The entry's system-specific claims (:class:`~poissonkit.plugin.SystemEntry`).
    almost_poisson
        The entry states that ``P`` is *not* Poisson (kept for integration): then a failing
        Jacobi identity is the claim that holds.
    equations
        Also form the equations of motion ``xdot = N P dH`` (can be slow for large systems).

    Returns
    -------
    VerifyReport
        ``report["status"]`` is ``"ok"``, ``"failed"`` (a property does not hold),
        ``"error"`` (a check raised: listed in ``report["errors"]``) or ``"undecided"``
        (nothing failed, some claim did not finish within the budget: ``report["undecided"]``);
        ``report["ok"]`` is true only for ``"ok"``; ``report["exit_code"]`` is
        :data:`EXIT_CODES` of the status.

    Examples
    --------
    >>> import poissonkit as pk
    >>> report = pk.verify(pk.so3(), name="so3")
    >>> report["ok"], report["casimirs"]
    (True, ['m_x**2 + m_y**2 + m_z**2'])
    """
    from poissonkit.structure.bivector import Bivector
    from poissonkit.structure.system import HamiltonianSystem

    if isinstance(obj, HamiltonianSystem):
        P, sys_ = obj.structure, obj
    elif isinstance(obj, Bivector):
        P, sys_ = obj, None
    else:
        raise InputError(f"{name or 'entry'} built a {type(obj).__name__}, "
                         "expected a Bivector or HamiltonianSystem")
    if casimir_degree < 0:
        raise InputError("casimir_degree must be >= 0")
    cons = tuple(sys_.constraints) if sys_ is not None else ()
    claim_checks = _system_claims(sys_, method, seed, claims) if sys_ is not None else []
    tasks: list[Callable[[], Any]] = [lambda: _jacobi_task(P, method, seed, cons)]
    tasks += [check for _, check in claim_checks]
    i_eq = None
    if sys_ is not None and equations:
        i_eq = len(tasks)
        tasks.append(lambda: {f"{c}dot": str(v) for c, v in zip(P.coords, sys_.vector_field())})
    from poissonkit.structure import casimirs as cas

    i_rank = i_cas = None
    if not almost_poisson:  # the searches are skipped for a bracket that is not Poisson
        i_rank = len(tasks)
        tasks.append(lambda: int(cas.rank(P, seed=0)))
    if casimir_degree > 0 and not almost_poisson:
        i_cas = len(tasks)
        tasks.append(lambda: [str(c) for c in cas.find_casimirs(P, casimir_degree)])

    brackets = {f"{{{P.coords[i]}, {P.coords[j]}}}": str(P.matrix[i, j])
                for i in range(P.dim) for j in range(i + 1, P.dim) if P.matrix[i, j] != 0}
    notes: list[str] = []
    report = VerifyReport({
        "name": name, "doc": doc, "dim": P.dim, "coords": list(P.names),
        "almost_poisson": almost_poisson, "jacobi": None, "brackets": brackets, "rank": None,
        "casimirs": None, "notes": notes, "errors": [], "undecided": [],
        "budget_seconds": timeout if timeout > 0 else None,
    })
    budget = f"{timeout:g} s" if timeout > 0 else "no budget"
    failed = False
    start = time.perf_counter()
    with BoundedChecks(tasks, timeout) as run:
        kind, value = run.result(0)
        if kind == "done":
            jac = value
            failed = jac["is_poisson"] == almost_poisson
        else:
            jac = {"is_poisson": None, "method": method, "failures": {},
                   "false_positive_bound": None, "seconds": None, "note": ""}
            if kind == "undecided":
                report["undecided"].append(f"Jacobi identity (not decided within {budget})")
            else:
                report["errors"].append(f"Jacobi identity: {value}")
        jac["as_claimed"] = None if jac["is_poisson"] is None else not failed
        report["jacobi"] = jac
        if sys_ is not None:
            entries = []
            for k, (what, _) in enumerate(claim_checks, start=1):
                kind, value = run.result(k)
                if kind == "done":
                    entry = {"what": what, "holds": value["holds"],
                             "status": "holds" if value["holds"] else "fails"}
                    if value["method"]:
                        entry["method"] = value["method"]
                    if value["failures"]:
                        entry["failures"] = value["failures"]
                    failed = failed or not value["holds"]
                elif kind == "undecided":
                    entry = {"what": what, "holds": None, "status": "undecided"}
                    report["undecided"].append(f"{what} (not decided within {budget})")
                else:  # an unverified claim is never ok
                    entry = {"what": what, "holds": False, "status": "error", "error": value}
                    report["errors"].append(f"{what}: {value}")
                entries.append(entry)
            report["system"] = {"hamiltonian": str(sys_.hamiltonian),
                                "multiplier": str(sys_.multiplier), "checks": entries}
            if i_eq is not None:
                kind, value = run.result(i_eq)
                if kind == "done":
                    report["system"]["equations_of_motion"] = value
                else:
                    notes.append(f"equations of motion: not formed ({value or budget})")
        if jac["is_poisson"] is True and i_rank is not None:
            _searches(run, i_rank, i_cas, casimir_degree, budget, report)
        elif jac["is_poisson"] is False:
            notes.append("rank and Casimirs skipped: not a Poisson structure")
    report["seconds"] = round(time.perf_counter() - start, 3)
    if report["errors"]:
        status = "error"
    elif failed:
        status = "failed"
    elif report["undecided"]:
        status = "undecided"
    else:
        status = "ok"
    report["status"], report["ok"] = status, status == "ok"
    report["exit_code"] = EXIT_CODES[status]
    return report


def _searches(run: BoundedChecks, i_rank: int, i_cas: int | None, degree: int, budget: str,
              report: dict) -> None:
    """Rank and polynomial Casimirs (informative: no claim). A typed poissonkit error (the
    search does not apply) or the budget running out becomes a note; any other exception is an
    internal error recorded in ``report["errors"]``, which makes the report not ok."""
    notes = report["notes"]
    kind, value = run.result(i_rank)
    if kind == "done":
        report["rank"] = value
    elif kind == "undecided":
        notes.append(f"rank: not computed within {budget} (--timeout)")
    elif kind == "refused":
        notes.append(f"rank: not computed ({value})")
    else:
        report["errors"].append(f"rank: internal error ({value})")
    if i_cas is None:
        return
    kind, value = run.result(i_cas)
    if kind == "done":
        report["casimirs"], report["casimir_degree"] = value, degree
    elif kind == "undecided":
        notes.append(f"Casimirs: search up to degree {degree} not finished within {budget} "
                     "(raise --timeout or lower --casimir-degree)")
    elif kind == "refused":
        notes.append(f"Casimirs: not computed ({value})")
    else:
        report["errors"].append(f"Casimirs: internal error ({value})")


# ---------------------------------------------------------------------------------- output
#: Longest expression shown in a table cell of the text report (``--json`` has them all).
CELL = 100


def _cell(text: str) -> str:
    return text if len(text) <= CELL else text[: CELL - 3] + "..."


def _verdict_lines(rep: dict) -> list[str]:
    jac = rep["jacobi"]
    lines = []
    if jac["is_poisson"] is None:
        lines.append("Jacobi identity: UNDECIDED within the budget" if any(
            u.startswith("Jacobi") for u in rep["undecided"]) else "Jacobi identity: ERROR")
    else:
        how = jac["method"] if jac["seconds"] is None else f"{jac['method']}, {jac['seconds']:.2f} s"
        if jac["is_poisson"] and jac["method"] != "exact" and jac["false_positive_bound"]:
            how += f", false-positive probability <= {jac['false_positive_bound']:.1e}"
        if jac["is_poisson"]:
            word = "OK" if not rep["almost_poisson"] else \
                "OK -- but the entry states its bracket is not Poisson: claim FAILED"
        else:
            n = len(jac["failures"])
            word = f"FAILED ({n} non-zero component(s) shown)" if not rep["almost_poisson"] \
                else "fails, as the entry states (almost-Poisson bracket)"
        lines.append(f"Jacobi identity: {word} ({how})")
        if not jac["is_poisson"]:
            for k, v in list(jac["failures"].items())[:3 if rep["almost_poisson"] else 10]:
                lines.append(f"    {k} = {_cell(v)}")
    if rep["rank"] is not None:
        lines.append(f"Rank (generic): {rep['rank']}")
    if rep["casimirs"] is not None:
        found = rep["casimirs"]
        lines.append(f"Casimirs (polynomial, degree <= {rep['casimir_degree']}): "
                     + (", ".join(found) if found else "none"))
    for c in rep.get("system", {}).get("checks", []):
        if c["status"] == "error":
            lines.append(f"{c['what']}: ERROR ({c['error']})")
            continue
        if c["status"] == "undecided":
            lines.append(f"{c['what']}: UNDECIDED within the budget")
            continue
        how = f"  ({c['method']})" if c.get("method") and c["method"] != "exact" else ""
        lines.append(f"{c['what']}: {'OK' if c['holds'] else 'FAILED'}{how}")
        lines.extend(f"    {_cell(f)}" for f in c.get("failures", []))
    return lines


def format_report(rep: Mapping[str, Any]) -> str:
    """The text form of a :func:`verify` report (what ``poissonkit verify`` prints): compact,
    verdicts first, then the brackets as a table; equations of motion only if they were formed."""
    lines: list[str] = []
    lines.append(f"{rep['name']}: {rep['doc']}")
    if rep["almost_poisson"]:
        lines.append("This entry's bracket is deliberately not Poisson (an almost-Poisson bracket "
                     "kept because X = N P dH gives the equations of motion): the expected "
                     "Jacobi verdict is a failure.")
    lines.append(f"dimension {rep['dim']}, coordinates {', '.join(rep['coords'])}")
    lines.extend(_verdict_lines(rep))
    rows = [(k[1:-1].split(", ", 1), v) for k, v in rep["brackets"].items()]
    lines.append(f"Brackets {{a, b}} of the coordinates ({len(rows)} non-zero, a before b):")
    if rows:
        wa = max(len(a) for (a, _), _ in rows)
        wb = max(len(b) for (_, b), _ in rows)
        lines.append(f"    {'a':<{wa}}  {'b':<{wb}}  {{a, b}}")
        for (a, b), v in rows:
            lines.append(f"    {a:<{wa}}  {b:<{wb}}  {_cell(v)}")
    sys_ = rep.get("system")
    if sys_:
        lines.append(f"Hamiltonian: H = {_cell(sys_['hamiltonian'])}")
        lines.append(f"Multiplier: N = {_cell(sys_['multiplier'])}   (xdot = N P dH)")
        if "equations_of_motion" in sys_:
            lines.append("Equations of motion:")
            for k, v in sys_["equations_of_motion"].items():
                lines.append(f"    {k} = {v}")
    for n in rep["notes"]:
        lines.append(f"note: {n}")
    for u in rep["undecided"]:
        lines.append(f"undecided: {u}")
    for e in rep["errors"]:
        lines.append(f"error: {e}")
    lines.append(f"result: {rep['status']} (exit {rep['exit_code']}; "
                 f"checks took {rep['seconds']:.1f} s)")
    return "\n".join(lines)


def _print_report(rep: Mapping[str, Any]) -> None:
    print(format_report(rep))


def _list_entries(as_json: bool) -> int:
    from poissonkit.plugin import entries

    items = sorted(entries("system").values(), key=lambda e: e.name)
    if as_json:
        print(json.dumps([{"name": e.name, "doc": e.doc, "tags": list(e.tags),
                           "poisson": ALMOST_POISSON_TAG not in e.tags,
                           "params": [p.name for p in e.params]} for e in items], indent=2))
        return EXIT_OK
    width = max((len(e.name) for e in items), default=0)
    for e in items:
        tags = f"  [{', '.join(e.tags)}]" if e.tags else ""
        almost = ("  (almost-Poisson bracket: not Poisson by design)"
                  if ALMOST_POISSON_TAG in e.tags else "")
        print(f"{e.name:<{width}}  {e.doc}{tags}{almost}")
    return EXIT_OK


def main(args: argparse.Namespace) -> int:
    """Run ``poissonkit verify``; the exit code is :data:`EXIT_CODES` of the report's status
    (bad input: :data:`EXIT_ERROR`)."""
    try:
        if args.list:
            return _list_entries(args.json)
        if not args.target:
            raise InputError("give a structure name or a .json file (see --list)")
        if args.casimir_degree < 0:
            raise InputError("--casimir-degree must be >= 0")
        if not args.timeout >= 0:  # also refuses NaN
            raise InputError(f"--timeout must be >= 0 seconds, got {args.timeout}")
        name, doc, obj = load_target(args.target, args.param)
        if args.hamiltonize is not None:
            return _run_hamiltonize(obj, args.hamiltonize, args.json)
        rep = verify(obj, name, doc, casimir_degree=args.casimir_degree, method=args.method,
                     seed=args.seed, timeout=args.timeout, claims=_entry_claims(name),
                     almost_poisson=_is_almost_poisson(name),
                     equations=getattr(args, "equations", False))
    except PoissonkitError as exc:
        print(f"poissonkit verify: error: {exc}", file=sys.stderr)
        return EXIT_ERROR
    if args.json:
        print(json.dumps(rep, indent=2, default=str))
    else:
        _print_report(rep)
    return rep["exit_code"]


def _run_hamiltonize(obj: Any, degree: int, as_json: bool) -> int:
    """``verify NAME --hamiltonize``: print the search result; 0 iff a bracket was found."""
    from poissonkit.structure.hamiltonize import hamiltonize, result_record

    if degree < -1:
        raise InputError("--hamiltonize DEGREE must be >= 0")
    for d in ([degree] if degree >= 0 else [1, 2, 3, 4]):
        res = hamiltonize(obj, degree=d)
        if res.found:
            break
    print(json.dumps(result_record(res), indent=2, default=str) if as_json else res.summary())
    return 0 if res.found else 1

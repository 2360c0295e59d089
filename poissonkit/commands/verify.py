"""``poissonkit verify``: Jacobi identity, brackets, rank and Casimirs of a Poisson structure.

``poissonkit verify NAME`` checks a registered structure or system (``--list`` shows them);
``poissonkit verify FILE.json`` checks a bivector in PoissonGeometry's dict format::

    {"dim": 3, "bivector": {"1,2": "x3", "1,3": "-x2", "2,3": "x1"}}

with coordinates ``x1 .. xn`` (or an optional ``"coords": [...]`` list, and ``"params": [...]``
naming symbolic parameters the entries may use). Strings are parsed with the allow-list parser,
never evaluated. For a Hamiltonian system the report also checks the claimed Casimirs,
integrals, invariant measure and original equations. Exit code 0 when everything holds, 1 when
the structure is not Poisson, a claimed property fails, or a check raised (status "error": an
unverified claim never passes).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import re
import signal
import threading
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import sympy as sp

from poissonkit._display import html_table, latex_table
from poissonkit.errors import InputError, ParseError, PoissonkitError

#: Keys a JSON structure file may contain.
JSON_KEYS = ("dim", "bivector", "coords", "variable", "params", "name")


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
    parser.add_argument("--timeout", type=float, default=30.0, metavar="SECONDS",
                        help="time limit of the rank/Casimir search (default 30; 0: none)")
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
                raise InputError(f"coordinate name {c!r} is not an identifier")
        if dim is not None and dim != len(coords):
            raise InputError(f'"dim" = {dim} but {len(coords)} coordinates given')
        dim = len(coords)
    if not isinstance(dim, int) or isinstance(dim, bool) or dim < 2:
        raise InputError(f'"dim" must be an integer >= 2, got {dim!r}')
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
            raise InputError(f"parameter name {p!r} is not a new identifier")
        extra[p] = sp.Symbol(p, real=True)
    comps = {}
    for key, value in data["bivector"].items():
        i, j = _parse_key(key)
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            raise ParseError(f"component {key!r}: expected an expression string, got {value!r}")
        comps[(i, j)] = parse_expression(str(value), syms, extra)
    return name, Bivector.from_components(comps, syms)


def _coerce_param(text: str) -> tuple[str, Any]:
    if "=" not in text:
        raise InputError(f"--param expects NAME=VALUE, got {text!r}")
    key, value = text.split("=", 1)
    value = value.strip()
    if "," in value:
        return key.strip(), tuple(v for v in value.split(","))
    return key.strip(), value


def load_target(target: str, params: list[str] = ()) -> tuple[str, str, Any]:
    """``(name, doc, Bivector | HamiltonianSystem)`` for a registry name or a JSON path."""
    from poissonkit.plugin import names, system

    if target.endswith(".json") or (Path(target).is_file() and target not in names("system")):
        name, obj = load_structure_json(target)
        return name, "bivector from " + Path(target).name, obj
    entry = system(target)
    given = dict(_coerce_param(p) for p in params)
    values = entry.resolve_params(given)
    return entry.name, entry.doc, entry.build(**values)


def _entry_claims(name: str) -> tuple:
    """The system-specific claims of a registered entry (none for a JSON file)."""
    from poissonkit.plugin import names, system

    return tuple(system(name).claims) if name in names("system") else ()


# ---------------------------------------------------------------------------------- checks
class _TimeLimit(Exception):
    pass


@contextlib.contextmanager
def _time_limit(seconds: float):
    """Interrupt pure-Python work after ``seconds`` (main thread on POSIX only; else no limit)."""
    usable = (seconds > 0 and hasattr(signal, "SIGALRM")
              and threading.current_thread() is threading.main_thread())
    if not usable:
        yield
        return

    def handler(signum, frame):
        raise _TimeLimit

    old = signal.signal(signal.SIGALRM, handler)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def _describe(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {str(exc).strip()[:200]}"


def _casimir_section(P, degree: int, report: dict, notes: list[str], timeout: float) -> None:
    """Rank and polynomial Casimirs (informative). A typed poissonkit error (the search does not
    apply) becomes a note; any other exception is an internal error recorded in
    ``report["errors"]``, which makes the report not ok."""
    from poissonkit.structure import casimirs as cas

    try:
        with _time_limit(timeout):
            report["rank"] = int(cas.rank(P, seed=0))
    except _TimeLimit:  # before Exception: _TimeLimit is one
        notes.append(f"rank: not computed within {timeout:g} s (--timeout)")
    except PoissonkitError as exc:
        notes.append(f"rank: not computed ({_describe(exc)})")
    except Exception as exc:  # noqa: BLE001 -- a bug: keep the report, never call it ok
        report["errors"].append(f"rank: internal error ({_describe(exc)})")
    if degree > 0:
        try:
            with _time_limit(timeout):
                found = cas.find_casimirs(P, degree)
            report["casimirs"] = [str(c) for c in found]
            report["casimir_degree"] = degree
        except _TimeLimit:
            notes.append(f"Casimirs: search up to degree {degree} not finished within "
                         f"{timeout:g} s (raise --timeout or lower --casimir-degree)")
        except PoissonkitError as exc:
            notes.append(f"Casimirs: not computed ({_describe(exc)})")
        except Exception as exc:  # noqa: BLE001 -- a bug: keep the report, never call it ok
            report["errors"].append(f"Casimirs: internal error ({_describe(exc)})")


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


def _system_section(sys_, report: dict, notes: list[str], method: str = "auto",
                    seed: int | None = None, claims: tuple = ()) -> bool:
    """Check the claims of a HamiltonianSystem; returns True if all hold.

    A claim whose check raises is recorded with ``status: "error"`` (and the error message) and
    counts as not holding: an unverified claim must never make the report ok. ``method`` is
    passed to the field checks (``"auto"``: exact proofs, or exact arithmetic at random
    rational points for large expressions — the method is reported per check). ``claims``
    are the entry's system-specific claims (:class:`~poissonkit.plugin.SystemEntry`).
    """
    from poissonkit.structure import casimirs as cas
    from poissonkit.structure import checks

    ok = True
    P = sys_.structure
    X = sys_.vector_field()
    info: dict[str, Any] = {
        "hamiltonian": str(sys_.hamiltonian),
        "multiplier": str(sys_.multiplier),
        "equations_of_motion": {f"{c}dot": str(X[i]) for i, c in enumerate(P.coords)},
        "checks": [],
    }

    def record(what: str, run) -> None:
        nonlocal ok
        try:
            result = run()
        except _TimeLimit:
            raise
        except Exception as exc:  # noqa: BLE001 -- report the other claims; this one is unverified
            ok = False
            info["checks"].append({"what": what, "holds": False, "status": "error",
                                   "error": _describe(exc)})
            report["errors"].append(f"{what}: {_describe(exc)}")
            return
        holds = bool(result)
        ok = ok and holds
        entry = {"what": what, "holds": holds, "status": "holds" if holds else "fails"}
        if getattr(result, "method", None):
            entry["method"] = result.method
        fails = getattr(result, "failures", ())
        if not holds and fails:
            entry["failures"] = [f"{lab} = {val}" for lab, val in list(fails)[:5]]
        info["checks"].append(entry)

    cons = tuple(sys_.constraints)
    how = {"method": method, "seed": seed}
    for name, C in sys_.casimirs.items():
        record(f"Casimir {name}", lambda C=C: cas.is_casimir(P, C, constraints=cons))
    for name, F in sys_.integrals.items():
        record(f"first integral {name}",
               lambda F=F: checks.is_first_integral(sys_, F, constraints=cons, **how))
    if sys_.measure is not None:
        record(f"invariant measure {sys_.measure}",
               lambda: checks.is_invariant_measure(sys_, **how))
    if sys_.original is not None:
        record("original equations = N P dH",
               lambda: checks.is_conformally_hamiltonian(sys_, **how))
    for claim in claims:
        record(_claim_name(claim), lambda claim=claim: _ClaimResult(claim(sys_)))
    report["system"] = info
    return ok


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
        rows = [("dimension", str(self["dim"])),
                ("Jacobi identity", ("holds" if jac["is_poisson"] else "FAILS")
                 + f" ({jac['method']})")]
        rows += [(k, v) for k, v in jac["failures"].items()]
        if self.get("rank") is not None:
            rows.append(("rank (generic)", str(self["rank"])))
        if self.get("casimirs") is not None:
            rows.append((f"Casimirs (degree <= {self.get('casimir_degree')})",
                         ", ".join(self["casimirs"]) or "none"))
        for c in (self.get("system") or {}).get("checks", []):
            state = "ERROR" if c.get("status") == "error" else ("holds" if c.get("holds")
                                                                 else "FAILS")
            rows.append((c["what"], state))
        rows += [("note", n) for n in self.get("notes", [])]
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
           seed: int | None = None, timeout: float = 30.0, claims: tuple = ()) -> VerifyReport:
    """Verify a bivector or system: Jacobi identity, brackets, rank, Casimirs, claims.

    What ``poissonkit verify`` runs, as a function.

    Parameters
    ----------
    obj
        A :class:`~poissonkit.structure.Bivector` or a
        :class:`~poissonkit.structure.HamiltonianSystem` (whose claimed Casimirs, integrals,
        invariant measure and original equations are checked too).
    name, doc
        Identification for the report.
    casimir_degree
        Degree up to which polynomial Casimirs are searched.
    method
        ``"auto"``, ``"exact"`` or ``"random"`` (see :func:`poissonkit.check_jacobi`).
    seed
        Seed of the random checks (reproducible reports).
    timeout
        Seconds allowed for the rank and Casimir search (a note says when it was cut).
    claims
        Extra callables ``claim(system) -> (holds, detail, method)``.

    Returns
    -------
    VerifyReport
        A JSON-ready dict. ``report["ok"]`` is true when ``P`` is Poisson and every claimed
        property holds; ``report["status"]`` is ``"ok"``, ``"failed"`` (a property does not
        hold) or ``"error"`` (a check raised: listed in ``report["errors"]``; the report is
        then never ok).

    Raises
    ------
    InputError
        If ``obj`` is neither a bivector nor a system.

    Examples
    --------
    >>> import poissonkit as pk
    >>> report = pk.verify(pk.so3(), name="so3")
    >>> report["ok"], report["casimirs"]
    (True, ['m_x**2 + m_y**2 + m_z**2'])
    """
    from poissonkit.structure.bivector import Bivector
    from poissonkit.structure.jacobi import check_jacobi
    from poissonkit.structure.system import HamiltonianSystem

    if isinstance(obj, HamiltonianSystem):
        P, sys_ = obj.structure, obj
    elif isinstance(obj, Bivector):
        P, sys_ = obj, None
    else:
        raise InputError(f"{name or 'entry'} built a {type(obj).__name__}, "
                         "expected a Bivector or HamiltonianSystem")
    notes: list[str] = []
    res = check_jacobi(P, method=method, seed=seed, constraints=sys_.constraints if sys_ else ())
    brackets = {f"{{{P.coords[i]}, {P.coords[j]}}}": str(P.matrix[i, j])
                for i in range(P.dim) for j in range(i + 1, P.dim) if P.matrix[i, j] != 0}
    report = VerifyReport({
        "name": name, "doc": doc, "dim": P.dim, "coords": list(P.names),
        "jacobi": {
            "is_poisson": res.is_poisson, "method": res.method,
            "failures": {k: str(v) for k, v in res.named_failures().items()},
            "false_positive_bound": res.false_positive_bound,
            "seconds": round(res.seconds, 4), "note": res.note,
        },
        "brackets": brackets, "rank": None, "casimirs": None, "notes": notes, "errors": [],
    })
    ok = res.is_poisson
    if res.is_poisson:
        _casimir_section(P, casimir_degree, report, notes, timeout)
    else:
        notes.append("rank and Casimirs skipped: not a Poisson structure")
    if sys_ is not None:
        ok = _system_section(sys_, report, notes, method, seed, claims) and ok
    ok = ok and not report["errors"]
    report["ok"] = ok
    report["status"] = "error" if report["errors"] else ("ok" if ok else "failed")
    return report


# ---------------------------------------------------------------------------------- output
def format_report(rep: Mapping[str, Any]) -> str:
    """The text form of a report of :func:`verify` (what ``poissonkit verify`` prints)."""
    lines: list[str] = []
    jac = rep["jacobi"]
    lines.append(f"{rep['name']}: {rep['doc']}")
    lines.append(f"dimension {rep['dim']}, coordinates {', '.join(rep['coords'])}")
    if jac["is_poisson"]:
        extra = "" if jac["method"] == "exact" else \
            f", false-positive probability <= {jac['false_positive_bound']:.1e}"
        lines.append(f"Jacobi identity: OK ({jac['method']}, {jac['seconds']:.3f} s{extra})")
    else:
        lines.append(f"Jacobi identity: FAILED ({len(jac['failures'])} non-zero component(s))")
        for k, v in list(jac["failures"].items())[:20]:
            lines.append(f"    {k} = {v}")
    lines.append("Brackets of the coordinates:")
    for k, v in rep["brackets"].items():
        lines.append(f"    {k} = {v}")
    if not rep["brackets"]:
        lines.append("    (all zero)")
    if rep["rank"] is not None:
        lines.append(f"Rank (generic): {rep['rank']}")
    if rep["casimirs"] is not None:
        found = rep["casimirs"]
        lines.append(f"Casimirs (polynomial, degree <= {rep['casimir_degree']}): "
              + (", ".join(found) if found else "none"))
    sys_ = rep.get("system")
    if sys_:
        lines.append(f"Hamiltonian: H = {sys_['hamiltonian']}")
        lines.append(f"Multiplier: N = {sys_['multiplier']}   (xdot = N P dH)")
        lines.append("Equations of motion:")
        for k, v in sys_["equations_of_motion"].items():
            lines.append(f"    {k} = {v}")
        for c in sys_["checks"]:
            if c.get("status") == "error":
                lines.append(f"{c['what']}: ERROR ({c['error']})")
                continue
            how = f"  ({c['method']})" if c.get("method") and c["method"] != "exact" else ""
            lines.append(f"{c['what']}: {'OK' if c['holds'] else 'FAILED'}{how}")
            for f in c.get("failures", []):
                lines.append(f"    {f}")
    for n in rep["notes"]:
        lines.append(f"note: {n}")
    for e in rep.get("errors", []):
        lines.append(f"error: {e}")
    return "\n".join(lines)


def _print_report(rep: dict) -> None:
    print(format_report(rep))


def _list_entries(as_json: bool) -> int:
    from poissonkit.plugin import entries

    items = sorted(entries("system").values(), key=lambda e: e.name)
    if as_json:
        print(json.dumps([{"name": e.name, "doc": e.doc, "tags": list(e.tags),
                           "params": [p.name for p in e.params]} for e in items], indent=2))
        return 0
    width = max((len(e.name) for e in items), default=0)
    for e in items:
        tags = f"  [{', '.join(e.tags)}]" if e.tags else ""
        print(f"{e.name:<{width}}  {e.doc}{tags}")
    return 0


def main(args: argparse.Namespace) -> int:
    """Run ``poissonkit verify``; 0 if Poisson and all claims hold, 1 otherwise."""
    if args.list:
        return _list_entries(args.json)
    if not args.target:
        raise InputError("give a structure name or a .json file (see --list)")
    if args.casimir_degree < 0:
        raise InputError("--casimir-degree must be >= 0")
    name, doc, obj = load_target(args.target, args.param)
    if args.hamiltonize is not None:
        return _run_hamiltonize(obj, args.hamiltonize, args.json)
    rep = verify(obj, name, doc, casimir_degree=args.casimir_degree, method=args.method,
                 seed=args.seed, timeout=args.timeout, claims=_entry_claims(name))
    if args.json:
        print(json.dumps(rep, indent=2, default=str))
    else:
        _print_report(rep)
    return 0 if rep["ok"] else 1


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

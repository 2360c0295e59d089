"""``poissonkit verify``: Jacobi identity, brackets, rank and Casimirs of a Poisson structure.

``poissonkit verify NAME`` checks a registered structure or system (``--list`` shows them);
``poissonkit verify FILE.json`` checks a bivector in PoissonGeometry's dict format::

    {"dim": 3, "bivector": {"1,2": "x3", "1,3": "-x2", "2,3": "x1"}}

with coordinates ``x1 .. xn`` (or an optional ``"coords": [...]`` list, and ``"params": [...]``
naming symbolic parameters the entries may use). Strings are parsed with the allow-list parser,
never evaluated. For a Hamiltonian system the report also checks the claimed Casimirs,
integrals, invariant measure, original equations and the entry's own claims.

This module is the command line only (arguments, printing, exit codes); the checks are
:mod:`poissonkit.structure.verification` (:func:`~poissonkit.structure.verification.verify`).

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
import sys

from poissonkit.errors import InputError, PoissonkitError

# The library names this command has always exported (``poissonkit.commands.verify.verify``
# and friends keep working); new code imports them from poissonkit.structure.verification.
from poissonkit.structure.verification import (  # noqa: F401
    ALMOST_POISSON_TAG,
    AUTO_POINTS_OPS,
    DEFAULT_TIMEOUT,
    EXIT_CODES,
    EXIT_ERROR,
    EXIT_FAILED,
    EXIT_OK,
    EXIT_UNDECIDED,
    JSON_KEYS,
    MAX_DIM,
    MAX_EXPONENT,
    BoundedChecks,
    VerifyReport,
    check_jacobi_at_points,
    entry_claims,
    exact_number,
    format_report,
    is_almost_poisson,
    load_structure_json,
    load_target,
    verify,
)
from poissonkit.structure.verification.loading import Verifiable

__all__ = [
    "ALMOST_POISSON_TAG", "AUTO_POINTS_OPS", "DEFAULT_TIMEOUT", "EXIT_CODES", "EXIT_ERROR",
    "EXIT_FAILED", "EXIT_OK", "EXIT_UNDECIDED", "JSON_KEYS", "MAX_DIM", "MAX_EXPONENT",
    "BoundedChecks", "VerifyReport", "add_arguments", "check_jacobi_at_points", "exact_number",
    "format_report", "load_structure_json", "load_target", "main", "verify",
]


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



def _list_entries(as_json: bool) -> int:
    from poissonkit.plugin import entries
    from poissonkit.plugin.contributions import SystemEntry

    items = sorted((e for e in entries("system").values() if isinstance(e, SystemEntry)),
                   key=lambda e: e.name)
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
                     seed=args.seed, timeout=args.timeout, claims=entry_claims(name),
                     almost_poisson=is_almost_poisson(name),
                     equations=args.equations)
    except PoissonkitError as exc:
        print(f"poissonkit verify: error: {exc}", file=sys.stderr)
        return EXIT_ERROR
    if args.json:
        print(json.dumps(rep, indent=2, default=str))
    else:
        print(format_report(rep))
    return rep["exit_code"]


def _run_hamiltonize(obj: Verifiable, degree: int, as_json: bool) -> int:
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

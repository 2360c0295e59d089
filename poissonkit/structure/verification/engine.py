"""The verify engine: Jacobi identity, brackets, rank, Casimirs and claims of a structure.

:func:`verify` is what ``poissonkit verify`` runs and what :func:`poissonkit.verify` is. Every
check runs under one wall-clock budget
(:class:`~poissonkit.structure.verification.budget.BoundedChecks`): a check that has not
finished is reported as *undecided within the budget* instead of running on.

Entries tagged ``"almost-poisson"`` carry a bracket that is deliberately not Poisson (an
almost-Poisson bracket kept because ``xdot = N P dH`` reproduces the equations of motion): for
them a failing Jacobi identity is the expected verdict, and a passing one is a failed claim.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

from poissonkit.errors import InputError
from poissonkit.structure.verification.budget import BoundedChecks
from poissonkit.structure.verification.claims import SystemClaim, system_claims
from poissonkit.structure.verification.jacobi_verdict import jacobi_verdict
from poissonkit.structure.verification.loading import Verifiable
from poissonkit.structure.verification.report import EXIT_CODES, VerifyReport

#: Default wall-clock budget (s) of all checks of one report: with loading and the system's
#: construction every registered entry then finishes within a minute on two cores.
DEFAULT_TIMEOUT = 40.0

__all__ = ["DEFAULT_TIMEOUT", "verify"]


def verify(obj: Verifiable, name: str = "", doc: str = "", *, casimir_degree: int = 2,
           method: str = "auto", seed: int | None = None, timeout: float = DEFAULT_TIMEOUT,
           claims: Sequence[SystemClaim] = (),
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
        Wall-clock budget (s) of all checks together
        (:class:`~poissonkit.structure.verification.budget.BoundedChecks`); ``<= 0``: none.
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
        :data:`~poissonkit.structure.verification.report.EXIT_CODES` of the status.

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
    claim_checks = system_claims(sys_, method, seed, claims) if sys_ is not None else []
    tasks: list[Callable[[], object]] = [
        lambda: jacobi_verdict(P, method, constraints=cons, seed=seed).record()]
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
    start = time.perf_counter()
    with BoundedChecks(tasks, timeout) as run:
        jac, failed = _jacobi_entry(run, method, almost_poisson, budget, report)
        if sys_ is not None:
            failed = _system_entry(run, sys_, claim_checks, i_eq, budget, report) or failed
        if jac["is_poisson"] is True and i_rank is not None:
            _searches(run, i_rank, i_cas, casimir_degree, budget, report)
        elif jac["is_poisson"] is False:
            notes.append("rank and Casimirs skipped: not a Poisson structure")
    report["seconds"] = round(time.perf_counter() - start, 3)
    return _with_status(report, failed)


def _jacobi_entry(run: BoundedChecks, method: str, almost_poisson: bool, budget: str,
                  report: VerifyReport) -> tuple[dict, bool]:
    """The Jacobi verdict (check 0) as ``report["jacobi"]``, and whether it contradicts the
    entry's claim (Poisson, or almost-Poisson)."""
    failed = False
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
    return jac, failed


def _system_entry(run: BoundedChecks, sys_, claim_checks: list, i_eq: int | None, budget: str,
                  report: VerifyReport) -> bool:
    """The system's claims (checks ``1..len(claim_checks)``) and equations of motion (check
    ``i_eq``) as ``report["system"]``; whether a claim fails."""
    failed = False
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
            report["notes"].append(f"equations of motion: not formed ({value or budget})")
    return failed


def _with_status(report: VerifyReport, failed: bool) -> VerifyReport:
    """``report`` with its status, ``ok`` and exit code: an error outranks a failed claim,
    which outranks an undecided one."""
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

"""The claims a Hamiltonian system carries, as checks of a verify report.

Each claim (a Casimir, a first integral, the invariant measure, the original equations, and the
registry entry's system-specific claims) becomes a zero-argument check that returns a
picklable ``{holds, method, failures}`` (it may run in a worker process,
:class:`~poissonkit.structure.verification.budget.BoundedChecks`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Protocol

from poissonkit.errors import InputError

if TYPE_CHECKING:
    from poissonkit.structure.system import HamiltonianSystem

__all__ = ["ClaimOutcome", "ClaimRecord", "SystemClaim", "system_claims"]

#: A system-specific claim of a registry entry: ``claim(system) -> (holds, detail, method)``;
#: its docstring's first line names it.
SystemClaim = Callable[["HamiltonianSystem"], tuple[bool, str, str]]
#: What a claim check returns: ``{"holds": bool, "method": str, "failures": [str, ...]}``.
ClaimRecord = dict[str, object]


class ClaimOutcome(Protocol):
    """What a core check returns (:class:`~poissonkit.structure.checks.CheckResult`)."""

    holds: bool
    method: str
    failures: Sequence[tuple[str, object]]


class _ClaimResult:
    """Adapter of a plugin claim's ``(holds, detail, method)`` to :class:`ClaimOutcome`."""

    def __init__(self, outcome: object) -> None:
        try:
            holds, detail, method = outcome  # type: ignore[misc]
        except (TypeError, ValueError):
            raise InputError("a system claim must return (holds, detail, method)") from None
        if not isinstance(holds, bool):
            raise InputError("a system claim must return a bool as its first item")
        self.holds, self.method = holds, str(method)
        self.failures: Sequence[tuple[str, object]] = () if holds else (("detail", str(detail)),)


def _claim_name(claim: SystemClaim) -> str:
    doc = (claim.__doc__ or "").strip()
    return doc.splitlines()[0] if doc else getattr(claim, "__name__", "claim")


def _as_check(run: Callable[[], ClaimOutcome]) -> Callable[[], ClaimRecord]:
    """A claim check returning a picklable ``{holds, method, failures}``."""
    def task() -> ClaimRecord:
        result = run()
        holds = bool(result.holds)
        fails = [] if holds else [f"{lab} = {val}" for lab, val in list(result.failures)[:5]]
        return {"holds": holds, "method": str(result.method or ""), "failures": fails}
    return task


def system_claims(sys_: HamiltonianSystem, method: str, seed: int | None,
                  claims: Sequence[SystemClaim] = ()
                  ) -> list[tuple[str, Callable[[], ClaimRecord]]]:
    """``(what, check)`` of every claim of a system.

    Parameters
    ----------
    sys_
        The system: its Casimirs, first integrals, invariant measure and original equations.
    method, seed
        Method (``"auto"``, ``"exact"``, ``"random"``) and seed of the field checks
        (:mod:`poissonkit.structure.checks`); Casimirs are always proved exactly.
    claims
        The registry entry's system-specific claims.

    Returns
    -------
    list of (str, callable)
        The claim's name and a zero-argument check returning ``{holds, method, failures}``.
    """
    from poissonkit.structure import casimirs as cas
    from poissonkit.structure import checks

    P = sys_.structure
    cons = tuple(sys_.constraints)
    out = []
    for name, C in sys_.casimirs.items():
        out.append((f"Casimir {name}",
                    _as_check(lambda C=C: cas.is_casimir(P, C, constraints=cons))))
    for name, F in sys_.integrals.items():
        out.append((f"first integral {name}", _as_check(
            lambda F=F: checks.is_first_integral(sys_, F, constraints=cons, method=method,
                                                 seed=seed))))
    if sys_.measure is not None:
        out.append((f"invariant measure {sys_.measure}", _as_check(
            lambda: checks.is_invariant_measure(sys_, method=method, seed=seed))))
    if sys_.original is not None:
        out.append(("original equations = N P dH", _as_check(
            lambda: checks.is_conformally_hamiltonian(sys_, method=method, seed=seed))))
    for claim in claims:
        out.append((_claim_name(claim),
                    _as_check(lambda claim=claim: _ClaimResult(claim(sys_)))))
    return out

"""The verify report: its statuses and exit codes, its text form and its notebook display."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from poissonkit._display import TitledRows, latex_table

EXIT_OK, EXIT_FAILED, EXIT_ERROR, EXIT_UNDECIDED = 0, 1, 2, 3
#: Exit code of ``poissonkit verify`` for each report status.
EXIT_CODES = {"ok": EXIT_OK, "failed": EXIT_FAILED, "error": EXIT_ERROR,
              "undecided": EXIT_UNDECIDED}

__all__ = ["CELL", "EXIT_CODES", "EXIT_ERROR", "EXIT_FAILED", "EXIT_OK", "EXIT_UNDECIDED",
           "VerifyReport", "format_report"]


class VerifyReport(TitledRows, dict):
    """The report of :func:`verify`: a JSON-ready ``dict`` that also displays itself.

    ``str(report)`` is the text ``poissonkit verify`` prints; in a notebook it shows as an HTML
    table (``_repr_html_``) or a LaTeX array (``_repr_latex_``). Being a ``dict``, it goes to
    ``json.dumps`` unchanged.
    """

    def __str__(self) -> str:
        return format_report(self)

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

    def _verdict(self) -> bool:
        return bool(self.get("ok"))

    def _repr_latex_(self) -> str:
        """The same summary as a LaTeX array."""
        return latex_table([("report", self._title()), *self._rows()])


# ---------------------------------------------------------------------------------- output
#: Longest expression shown in a table cell of the text report (``--json`` has them all).
CELL = 100


def _cell(text: str) -> str:
    return text if len(text) <= CELL else text[: CELL - 3] + "..."


def _verdict_lines(rep: Mapping) -> list[str]:
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

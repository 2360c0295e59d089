"""Verification of Poisson structures and systems: the library behind ``poissonkit verify``.

One engine serves the command line, :func:`poissonkit.verify` and plugins (the non-holonomic
survey's report uses :func:`jacobi_verdict`). Modules, one job each:

* :mod:`.loading`: a bivector from a JSON file, or a registered entry with exact parameters;
* :mod:`.jacobi_verdict`: the Jacobi identity by the method a report uses;
* :mod:`.claims`: a system's claims as checks;
* :mod:`.budget`: one wall-clock budget for all checks (worker processes);
* :mod:`.engine`: :func:`verify`, which assembles the report;
* :mod:`.report`: statuses, exit codes, the text and notebook forms of a report.
"""

from poissonkit.structure.verification.budget import BoundedChecks, TimeLimit
from poissonkit.structure.verification.claims import ClaimOutcome, SystemClaim, system_claims
from poissonkit.structure.verification.engine import DEFAULT_TIMEOUT, verify
from poissonkit.structure.verification.jacobi_verdict import (AUTO_POINTS_OPS, JacobiVerdict,
                                                              check_jacobi_at_points,
                                                              has_undefined_functions,
                                                              jacobi_verdict)
from poissonkit.structure.verification.loading import (ALMOST_POISSON_TAG, JSON_KEYS, MAX_DIM,
                                                       MAX_EXPONENT, entry_claims, exact_number,
                                                       is_almost_poisson, load_structure_json,
                                                       load_target)
from poissonkit.structure.verification.report import (EXIT_CODES, EXIT_ERROR, EXIT_FAILED, EXIT_OK,
                                                      EXIT_UNDECIDED, VerifyReport, format_report)

__all__ = [
    "ALMOST_POISSON_TAG", "AUTO_POINTS_OPS", "DEFAULT_TIMEOUT", "EXIT_CODES", "EXIT_ERROR",
    "EXIT_FAILED", "EXIT_OK", "EXIT_UNDECIDED", "JSON_KEYS", "MAX_DIM", "MAX_EXPONENT",
    "BoundedChecks", "ClaimOutcome", "JacobiVerdict", "SystemClaim", "TimeLimit", "VerifyReport",
    "check_jacobi_at_points", "entry_claims", "exact_number", "format_report",
    "has_undefined_functions", "is_almost_poisson", "jacobi_verdict", "load_structure_json",
    "load_target", "system_claims", "verify",
]

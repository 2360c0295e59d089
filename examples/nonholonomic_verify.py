"""Check every claim of the survey for each non-holonomic system and print a report per system,
in the style of seed 000's Maple worksheet ("Jacobi identity: OK", brackets of the variables,
equations of motion, conservation laws).

Run:  python examples/nonholonomic_verify.py [NAME ...] [--points 3] [--json]
      (no NAME: every system tagged "nonholonomic"). Entries tagged "almost-poisson" state that
      their bracket is not Poisson: for them the Jacobi claim is that the identity fails.
"""

from __future__ import annotations

import argparse
import json
import sys

from poissonkit_nonholonomic.verify import format_report, verify_system

from poissonkit.plugin import entries


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="verify the survey's non-holonomic systems")
    ap.add_argument("names", nargs="*", help="registry names (default: all nonholonomic)")
    ap.add_argument("--points", type=int, default=3, help="random rational points per identity")
    ap.add_argument("--json", action="store_true", help="print JSON reports")
    args = ap.parse_args(argv)
    found = {n: e for n, e in entries("system").items() if "nonholonomic" in e.tags}
    names = args.names or sorted(found)
    all_ok = True
    for name in names:
        if name not in found:
            print(f"unknown system {name!r}; available: {', '.join(sorted(found))}")
            return 2
        entry = found[name]
        system = entry.build(**entry.resolve_params({}))
        report = verify_system(system, points=args.points,
                               almost_poisson="almost-poisson" in entry.tags)
        all_ok &= report["ok"]
        print(json.dumps(report, indent=1) if args.json else format_report(report))
        print()
    return 0 if all_ok else 1


if __name__ == "__main__":
    sys.exit(main())

"""Bit-for-bit fingerprints of runs across every kernel path, to hold a refactor to "same numbers".

Runs one short integration per kernel path a user can reach (the lean direct sum, listed pairs,
tops, cell lists serial and parallel, Verlet lists, external fields, compensated sums, every
integrator family) and every shipped and registered scene through ``poissonkit run``, and
stores the saved states. ``--compare`` reruns them and reports every array that differs in a
single bit.

    python benchmarks/fingerprint_runs.py --save before.npz     # on the old code
    python benchmarks/fingerprint_runs.py --compare before.npz  # on the new code
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import sympy as sp

from poissonkit.numerics import AllPairs, Body, Interaction, NBodySystem, solve


def planets() -> tuple[NBodySystem, np.ndarray]:
    m = np.array([1.0, 1e-3, 3e-4, 4e-5, 5e-5])
    a = np.array([0.0, 5.2, 9.5, 19.2, 30.1])
    th = np.array([0.0, 0.3, 2.0, 4.1, 5.5])
    x = np.stack([a * np.cos(th), a * np.sin(th), 0.01 * a], axis=1)
    v = np.zeros_like(x)
    v[1:] = np.stack([-np.sin(th[1:]), np.cos(th[1:]), np.zeros(4)], axis=1) \
        / np.sqrt(a[1:])[:, None]
    x -= (m[:, None] * x).sum(0) / m.sum()
    v -= (m[:, None] * v).sum(0) / m.sum()
    s = NBodySystem([Body(f"b{k}", float(mk)) for k, mk in enumerate(m)],
                    [AllPairs("gravity", {"G": 1.0})])
    return s, s.pack(x, m[:, None] * v)


def tops(n: int = 8, **kw: object) -> tuple[NBodySystem, np.ndarray]:
    """``n`` dipolar tops with a hard core on a jittered line, a fixed top, a fixed point mass
    and one listed radial pair."""
    rng = np.random.default_rng(7)
    r, c1, c2, c3 = sp.symbols("r c1 c2 c3", real=True)
    gas = (c3 - 3 * c1 * c2) / (20 * r**3) + 1 / r**9
    bodies = [Body(f"t{k}", 1.0, 1.0, attributes={"moment": 0.5}) for k in range(n)]
    bodies.append(Body("anchor", 1.0, fixed=True, position=(0.0, -3.0, 0.0)))
    bodies.append(Body("pin", 1.0, 1.0, fixed=True, position=(1.0, 2.0, 0.0), axis=(0, 0, 1)))
    inter = [AllPairs(gas, members=[*range(n), n + 1]), Interaction(0, n, 1 / r**6)]
    s = NBodySystem(bodies, inter, **kw)
    pos = np.stack([1.4 * np.arange(n), 0.15 * rng.standard_normal(n),
                    0.15 * rng.standard_normal(n)], axis=1)
    axes = rng.standard_normal((n, 3))
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    return s, s.pack(pos, 0.3 * rng.standard_normal((n, 3)), axes,
                     0.1 * rng.standard_normal((n, 3)))


def cases():
    """name -> (system, y0, t_end, solve kwargs)"""
    out = {}
    s, y = planets()
    for m, kw in (("splitting2", {}), ("splitting4", {}), ("splitting6", {}),
                  ("logh4", {}), ("wisdom_holman", {}),
                  ("wisdom_holman", {"options": {"table": "10_6_4"}}),
                  ("wisdom_holman", {"options": {"correctors": 11}}),
                  ("wisdom_holman_corrected", {}),
                  ("splitting6", {"options": {"compensated": True}}),
                  ("rk45", {"tol": 1e-9})):
        out[f"planets/{m}/{sorted(kw.get('options', {}).items())}"] = (
            s, y, 200.0, dict(method=m, step=0.5, save_every=20, **kw))
    for label, kw in (("list", {}), ("cells", {"cutoff": 2.0}),
                      ("cells_parallel", {"cutoff": 2.0, "parallel_min_bodies": 2}),
                      ("verlet", {"cutoff": 2.0, "skin": 0.3}),
                      ("smooth", {"cutoff": 2.0, "smooth_cutoff": 1.5}),
                      ("general", {"fast_path": False})):
        s, y = tops(**kw)
        for m, skw in (("splitting4", {}), ("splitting6", {"options": {"compensated": True}}),
                       ("logh2", {"options": {"shift": 1.0}}), ("midpoint", {}), ("rk45", {"tol": 1e-9})):
            if label != "list" and m in ("midpoint", "logh2"):
                continue
            out[f"tops_{label}/{m}/{sorted(skw.get('options', {}).items())}"] = (
                s, y, 2.0, dict(method=m, step=0.02, save_every=10, **skw))
    from poissonkit import field
    s, y = tops()
    sf = s.with_fields([field("gravity", g=[0.0, 0.0, -9.81]),
                        field("uniform", B=[0.0, 0.01, 0.02])])
    for m, skw in (("splitting4", {}), ("splitting6", {"options": {"compensated": True}})):
        out[f"fields/{m}/{sorted(skw.get('options', {}).items())}"] = (
            sf, y, 2.0, dict(method=m, step=0.02, save_every=10, **skw))
    return out


def run_cases(only: str | None) -> dict[str, np.ndarray]:
    res = {}
    for name, (s, y, t, kw) in cases().items():
        if only and only not in name:
            continue
        try:
            sol = solve(s, y, t, **kw)
            res[name + "#y"] = np.asarray(sol.y)
            res[name + "#t"] = np.asarray(sol.t)
        except Exception as e:  # noqa: BLE001 - a failure is a fingerprint too
            res[name + "#error"] = np.frombuffer(f"{type(e).__name__}: {e}".encode(), np.uint8)
    return res


def run_scenes(only: str | None) -> dict[str, np.ndarray]:
    listing = subprocess.run([sys.executable, "-m", "poissonkit", "scenes", "--json"],
                             capture_output=True, text=True, check=True)
    names = sorted({e["name"] for e in json.loads(listing.stdout)["scenes"]}
                   if isinstance(json.loads(listing.stdout), dict)
                   else {e["name"] for e in json.loads(listing.stdout)})
    res = {}
    for name in names:
        if only and only not in name:
            continue
        with tempfile.TemporaryDirectory() as d:
            extra = ["--periods", "2"] if name == "seed000" else []
            if name == "levitron":
                extra = ["--duration", "0.05"]
            p = subprocess.run([sys.executable, "-m", "poissonkit", "run", name, "--out", d,
                                "--no-plot", "--no-progress", *extra],
                               capture_output=True, text=True)
            res[f"scene/{name}#exit"] = np.array([p.returncode])
            npz = Path(d) / "trajectory.npz"
            if npz.exists():
                with np.load(npz) as z:
                    for k in z.files:
                        res[f"scene/{name}#{k}"] = z[k]
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--save", type=Path)
    g.add_argument("--compare", type=Path)
    ap.add_argument("--only", help="run the cases whose name contains this")
    ap.add_argument("--no-scenes", action="store_true")
    a = ap.parse_args()
    with contextlib.redirect_stderr(io.StringIO()):
        res = run_cases(a.only)
    if not a.no_scenes:
        res |= run_scenes(a.only)
    if a.save:
        np.savez(a.save, **res)
        print(f"saved {len(res)} arrays to {a.save}")
        return
    with np.load(a.compare) as ref:
        keys = sorted(set(ref.files) | set(res)) if not a.only else sorted(res)
        bad = 0
        for k in keys:
            if k not in ref.files or k not in res:
                print(f"MISSING {k}: {'old' if k not in ref.files else 'new'} has none")
                bad += 1
                continue
            x, y = ref[k], res[k]
            if x.shape != y.shape or x.dtype != y.dtype or x.tobytes() != y.tobytes():
                diff = (np.max(np.abs(x - y)) if x.shape == y.shape and x.dtype.kind == "f"
                        else "shape/dtype")
                print(f"DIFFERS {k}: max |Δ| = {diff}")
                bad += 1
        print(f"{len(keys) - bad} of {len(keys)} arrays identical to the bit")
        sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()

"""``poissonkit verify``: registry names, PoissonGeometry-style JSON files, reports, exit codes.

Truth: the structures' known Casimirs (FORMULAS.md §1: four Casimirs and rank 14 for seed 000's
18-dim bracket; §2: (gamma, gamma), (gamma, L) for e(3)), and FORMULAS.md §0's non-Poisson Q.
"""

from __future__ import annotations

import json

import pytest
import sympy as sp

from poissonkit.cli import main
from poissonkit.commands.verify import load_structure_json, verify
from poissonkit.errors import DimensionError, InputError, ParseError
from poissonkit.structure import HamiltonianSystem, e3

SO3 = {"dim": 3, "bivector": {"1,2": "x3", "1,3": "-x2", "2,3": "x1"}}
NOT_POISSON = {"dim": 3, "bivector": {"1,2": "x1*x2", "2,3": "x3"}}   # FORMULAS.md §0's Q
EVIL = "__import__('os').system('echo x')"


def write(tmp_path, data, name="s.json"):
    path = tmp_path / name
    path.write_text(json.dumps(data))
    return str(path)


def test_named_structure_report(capsys):
    assert main(["verify", "two_tops"]) == 0
    out = capsys.readouterr().out
    assert "Jacobi identity: OK" in out
    # the brackets table: a, b, {a, b}
    rows = {tuple(line.split()[:2]): " ".join(line.split()[2:]) for line in out.splitlines()
            if line.startswith("    ")}
    assert rows[("top1.m_x", "top1.m_y")] == "top1.m_z"
    assert rows[("orbit.r_x", "orbit.p_x")] == "1"
    # verdicts come before the table
    assert out.index("Rank (generic)") < out.index("Brackets")
    assert "Rank (generic): 14" in out
    for cas in ("top1.nu_x**2 + top1.nu_y**2 + top1.nu_z**2",
                "top2.m_x*top2.nu_x + top2.m_y*top2.nu_y + top2.m_z*top2.nu_z"):
        assert cas in out


def test_json_file_poisson_and_json_output(tmp_path, capsys):
    assert main(["verify", write(tmp_path, SO3), "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    assert rep["jacobi"]["is_poisson"] is True and rep["ok"] is True
    assert rep["brackets"] == {"{x1, x2}": "x3", "{x1, x3}": "-x2", "{x2, x3}": "x1"}
    assert rep["rank"] == 2
    assert [sp.sympify(c) for c in rep["casimirs"]] == [sp.sympify("x1**2 + x2**2 + x3**2")]


def test_json_file_not_poisson_exits_nonzero(tmp_path, capsys):
    assert main(["verify", write(tmp_path, NOT_POISSON)]) == 1
    out = capsys.readouterr().out
    assert "Jacobi identity: FAILED" in out
    assert "Jac(x1, x2, x3) = -x1*x3" in out
    assert main(["verify", write(tmp_path, NOT_POISSON), "--json", "--method", "random"]) == 1
    rep = json.loads(capsys.readouterr().out)
    assert rep["jacobi"]["is_poisson"] is False and rep["jacobi"]["method"] == "random"


def test_malicious_string_is_rejected(tmp_path, capsys):
    data = {"dim": 3, "bivector": {"1,2": EVIL}}
    with pytest.raises(ParseError):
        load_structure_json(data)
    assert main(["verify", write(tmp_path, data)]) != 0
    captured = capsys.readouterr()
    assert "x\n" not in captured.out            # the shell command never ran
    assert "allowed" in captured.err and "error" in captured.err


@pytest.mark.parametrize("data, error", [
    ({"dim": 3, "bivector": {"1,1": "x1"}}, InputError),                 # repeated index
    ({"dim": 3, "bivector": {"0,1": "x1"}}, InputError),                 # zero index
    ({"dim": 3, "bivector": {"1,4": "x1"}}, DimensionError),             # out of range
    ({"dim": 3, "bivector": {"1,2": "y7"}}, ParseError),                 # unknown symbol
    ({"dim": 3, "bivector": {"1,2": "x3", "2,1": "x3"}}, InputError),    # given twice
    ({"dim": 2, "coords": ["a", "b", "c"], "bivector": {}}, InputError),  # mismatched dims
    ({"dim": 3, "bivector": {"1,2": "x3"}, "extra": 1}, InputError),     # unknown key
    ({"dim": 3}, InputError),                                            # no bivector
    ({"dim": "3", "bivector": {}}, InputError),                          # dim not an int
    ({"dim": 3, "bivector": {"1,2": ["x3"]}}, ParseError),               # not a string
])
def test_bad_json_inputs_raise_typed_errors(data, error):
    with pytest.raises(error):
        load_structure_json(data)


def test_coords_and_params_in_json(tmp_path, capsys):
    data = {"coords": ["a", "b", "c"], "params": ["k"],
            "bivector": {"1,2": "k*c", "1,3": "-k*b", "2,3": "k*a"}}
    assert main(["verify", write(tmp_path, data), "--casimir-degree", "0"]) == 0
    assert "    a  b  c*k" in capsys.readouterr().out
    # unreadable input is an error (exit 2), not a "not Poisson" verdict (exit 1)
    assert main(["verify", str(tmp_path / "missing.json")]) == 2
    (tmp_path / "broken.json").write_text("{not json")
    assert main(["verify", str(tmp_path / "broken.json")]) == 2


def test_list_names_every_structure(capsys):
    assert main(["verify", "--list"]) == 0
    out = capsys.readouterr().out
    for name in ("so3", "e3", "se3", "canonical3", "two_tops", "p_gf_bracket",
                 "chaplygin_ball_bracket", "veselova_bracket", "veselova_gyrostat_bracket",
                 "chaplygin_gyrostat_bracket", "canonical_deformation"):
        assert name in out
    assert main(["verify", "--list", "--json"]) == 0
    listed = {e["name"]: e for e in json.loads(capsys.readouterr().out)}
    assert "deformed" in listed["p_gf_bracket"]["tags"]


def test_unknown_name_and_missing_target(capsys):
    assert main(["verify", "no_such_structure"]) == 2
    assert "available" in capsys.readouterr().err
    assert main(["verify"]) == 2


def test_deformed_bracket_by_name(capsys):
    assert main(["verify", "chaplygin_ball_numeric_bracket", "--param", "I=1,2,3",
                 "--param", "d=1", "--casimir-degree", "0", "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    assert rep["jacobi"]["is_poisson"] and rep["dim"] == 6


def test_system_report_checks_claims(capsys):
    P = e3("gamma_M")
    gamma, L = P.coords[:3], P.coords[3:]
    H = (L[0] ** 2 + L[1] ** 2 / 2 + L[2] ** 2 / 3) / 2 + gamma[2]
    good = HamiltonianSystem(P, H, casimirs={"(gamma,gamma)": sum(g * g for g in gamma)},
                             integrals={"H": H}, measure=sp.Integer(1), name="top")
    rep = verify(good, "top", casimir_degree=0, equations=True)
    assert rep["ok"] and all(c["holds"] for c in rep["system"]["checks"])
    assert sp.sympify(rep["system"]["equations_of_motion"]["gamma_xdot"]) != 0
    bad = HamiltonianSystem(P, H, casimirs={"L^2": sum(c * c for c in L)}, name="bad")
    rep = verify(bad, "bad", casimir_degree=0)
    assert not rep["ok"]
    assert [c["holds"] for c in rep["system"]["checks"]] == [False]


def test_every_core_registry_entry_builds_a_poisson_structure():
    # the survey states every one of these is Poisson (FORMULAS.md §1, §2, §5–§7, §9, §10)
    from poissonkit.plugin import plugin_reports, system
    from poissonkit.structure import Bivector, check_jacobi

    core = next(r for r in plugin_reports() if r.name == "core-systems")
    names = core.contributions["system"]
    assert {"se3", "p_gf_bracket", "chaplygin_ball_bracket", "veselova_gyrostat_bracket"} <= set(names)
    for name in names:
        entry = system(name)
        obj = entry.build(**entry.resolve_params({}))
        P = obj if isinstance(obj, Bivector) else obj.structure
        # exact checks of each bracket live in the deformed/jacobi tests; here the fast path
        assert check_jacobi(P, method="random", trials=1, seed=0).is_poisson, name

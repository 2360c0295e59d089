"""``poissonkit verify NAME --hamiltonize``: the search from the command line."""

from __future__ import annotations

import json

from poissonkit import cli


def _run(capsys, *argv):
    code = cli.main(["verify", *argv])
    return code, capsys.readouterr().out


def test_hamiltonize_finds_the_ball_bracket(capsys):
    code, out = _run(capsys, "nh.chaplygin_ball", "--hamiltonize", "3")
    assert code == 0
    assert "1 Poisson component" in out and "degree <= 3" in out


def test_hamiltonize_reports_a_proof_of_absence_as_json(capsys):
    code, out = _run(capsys, "nh.chaplygin_ball", "--hamiltonize", "2", "--json")
    rec = json.loads(out)
    assert code == 1
    assert rec["status"] == "no_linear_solution" and rec["proved_absent"]
    assert rec["certificate"]["combination"]


def test_hamiltonize_rejects_a_bare_bivector(capsys, tmp_path):
    path = tmp_path / "so3.json"
    path.write_text(json.dumps({"dim": 3, "bivector": {"1,2": "x3", "1,3": "-x2", "2,3": "x1"}}))
    code = cli.main(["verify", str(path), "--hamiltonize"])
    err = capsys.readouterr().err
    assert code == 2 and "error" in err and "HamiltonianSystem" in err

"""Fuzzing the files ``poissonkit run`` reads back: summaries (``--from-summary``), checkpoint
content, a finished run's folder damaged before ``--resume``, and the folder ``view`` opens.

Property (``fuzzkit``): an input works or raises a ``PoissonkitError``; never another exception,
never a hang. Per target, what "works" must mean:

* ``--from-summary``: every option accepted has the type the command's parser gives it, the
  scene name is a plain file name, and the scene copy written is the summary's text with its
  recorded sha256 (no silent acceptance of a mismatch);
* checkpoint content (a valid checksum around mutated meta and arrays): a checkpoint read back
  has every field the resume uses of the right type;
* resume of a damaged finished run: always refused, and every byte of the folder kept
  (silent data loss is a failure);
* ``view``: a page is returned only for a dataset that opens with finite positions.
"""

from __future__ import annotations

import copy
import hashlib
import io
import json
import shutil
import tempfile
from pathlib import Path

import numpy as np
import pytest
from fuzzkit import FAST, SLOW, outcome, payloads, slow
from hypothesis import given
from hypothesis import strategies as st
from strategies import values

from poissonkit import cli
from poissonkit.errors import PoissonkitError

ROOT = Path(__file__).resolve().parents[2]
TWO = ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"
RUN = ["run", str(TWO), "--duration", "0.0002", "--step", "1e-5", "--no-progress"]


@pytest.fixture(scope="module")
def finished() -> Path:
    out = Path(tempfile.mkdtemp(prefix="poissonkit-fuzz-run-")) / "out"
    assert cli.main([*RUN, "--checkpoint-every", "5", "--out", str(out)]) == 0
    return out


# --------------------------------------------------------------------- --from-summary documents
NAMES = st.one_of(st.sampled_from([5, "..", ".", "a" * 300, "a\x00b", "../x.toml", "/etc/x",
                                   "", "ok.toml", "C:\\x", None, ["x"], "scène.toml"]),
                  st.text(max_size=12))
OPTION_KEYS = ["step", "tol", "duration", "periods", "method", "save_every", "no_contact",
               "param", "tilt", "spin_ratio", "max_steps", "save_dt", "energy_tol", "scene",
               "warp", "__class__", "out", "checkpoint_every"]


@st.composite
def edited_summaries(draw, base: dict):
    doc = copy.deepcopy(base)
    for _ in range(draw(st.integers(1, 3))):
        op = draw(st.sampled_from(["option", "option", "name", "kind", "text", "sha",
                                   "drop", "root"]))
        if not (isinstance(doc["options"], dict) and isinstance(doc["scene_source"], dict)):
            op = "root"  # an earlier edit replaced a whole table: only replace again
        if op == "option":
            doc["options"][draw(st.sampled_from(OPTION_KEYS))] = draw(st.one_of(
                values, st.sampled_from(["no", "yes", "1e-5", *payloads()[:3]])))
        elif op == "name":
            doc["scene_source"]["name"] = draw(NAMES)
        elif op == "kind":
            doc["scene_source"]["kind"] = draw(st.one_of(
                st.sampled_from(["martian", "file", "registered", "", None]), values))
        elif op == "text":
            doc["scene_source"]["text"] = draw(st.one_of(st.text(max_size=30), values))
        elif op == "sha":
            doc["scene_source"]["sha256"] = draw(st.one_of(st.text(max_size=64), values))
        elif op == "drop":
            part = draw(st.sampled_from(["options", "scene_source"]))
            key = draw(st.sampled_from(sorted(doc[part]) or ["x"])) if isinstance(
                doc[part], dict) else None
            if key is not None:
                doc[part].pop(key, None)
        else:
            doc[draw(st.sampled_from(["options", "scene_source"]))] = draw(values)
    return doc


def _from_summary(doc: dict) -> None:
    from poissonkit.commands.run import _option_schema
    from poissonkit.report.provenance import OUTPUT_OPTIONS, rerun_options

    schema = _option_schema()
    with tempfile.TemporaryDirectory() as tmp:
        got = outcome("run --from-summary", lambda: rerun_options(doc, Path(tmp), schema))
        if got is None:
            return
        types = {"float": (float,), "int": (int,), "bool": (bool,), "str": (str,),
                 "strlist": (list,)}
        for key, value in got.items():
            if key == "scene" or key in OUTPUT_OPTIONS:
                continue
            kind = schema[key]
            assert (value is None and kind.nullable) or isinstance(value, types[kind.kind]), \
                (key, value)
            assert not (kind.kind == "int" and isinstance(value, bool)), (key, value)
        src = doc["scene_source"]
        if src["kind"] == "file":
            copy_path = Path(got["scene"])
            assert copy_path.parent == Path(tmp)
            assert copy_path.name == src.get("name", "scene.toml")
            text = copy_path.read_text(encoding="utf-8")
            assert hashlib.sha256(text.encode()).hexdigest() == src["sha256"]
        else:
            assert src["kind"] == "registered"


@pytest.fixture(scope="module")
def base_summary(finished) -> dict:
    return json.loads((finished / "summary.json").read_text())


@pytest.mark.timeout(600)
@FAST
@given(data=st.data())
def test_edited_summaries(base_summary, data):
    _from_summary(data.draw(edited_summaries(base_summary)))


@slow
@pytest.mark.timeout(7200)
@SLOW
@given(data=st.data())
def test_edited_summaries_slow(base_summary, data):
    _from_summary(data.draw(edited_summaries(base_summary)))


# ---------------------------------------------------------------------- checkpoint content
ARRAY_VALUES = st.one_of(
    st.sampled_from([np.array("abc"), np.zeros((2, 2)), np.float64(np.nan), np.int64(3),
                     np.array([], dtype=float), np.array([1, 2], dtype=np.int8),
                     np.array([True]), np.zeros(18), np.float64(1.5)]),
    st.lists(st.floats(), max_size=4).map(np.array))


@st.composite
def forged_checkpoints(draw, arrays: dict, meta: dict):
    arrays, meta = dict(arrays), copy.deepcopy(meta)
    for _ in range(draw(st.integers(1, 3))):
        op = draw(st.sampled_from(["meta", "meta", "array", "drop", "records", "root"]))
        if not isinstance(meta, dict) and op in ("meta", "records"):
            op = "array"  # the meta was replaced whole by an earlier edit
        if op == "meta":
            meta[draw(st.sampled_from(["problem", "nfev", "records", "method", "every",
                                       "stream_parts", "stream_rows", "x"]))] = draw(values)
        elif op == "array":
            arrays[draw(st.sampled_from(["y", "prev", "prev2", "hist", "t", "steps"]))] = \
                draw(ARRAY_VALUES)
        elif op == "drop" and arrays:
            arrays.pop(draw(st.sampled_from(sorted(arrays))), None)
        elif op == "records":
            meta["records"] = draw(st.lists(st.one_of(values, st.fixed_dictionaries(
                {"kind": values, "step": values, "time": values, "value": values})),
                max_size=3))
        else:
            meta = draw(values)
    return arrays, meta


def _forge(path: Path, arrays: dict, meta: object) -> None:
    from poissonkit.numerics.checkpoint import MAGIC

    buf = io.BytesIO()
    np.savez(buf, meta=np.array(json.dumps(meta, allow_nan=True)), **arrays)
    payload = buf.getvalue()
    path.write_bytes(MAGIC + f"{hashlib.sha256(payload).hexdigest()} {len(payload)}\n".encode()
                     + payload)


def _read_forged(real: tuple[dict, dict], forged: tuple[dict, object]) -> None:
    from poissonkit.numerics.checkpoint import read_checkpoint
    from poissonkit.numerics.events import EventRecord

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "checkpoint-000000000005.pkcp"
        _forge(path, *forged)
        got = outcome("checkpoint content", lambda: read_checkpoint(path))
    if got is None:
        return
    arrays, meta = got  # what the resume reads must convert without an exception
    float(arrays["t"]), int(arrays["steps"]), int(meta["nfev"]), int(meta["every"])
    for k in ("y", "prev", "prev2", "hist"):
        np.array(arrays[k], dtype=float)
    [EventRecord(**r) for r in meta["records"]]


@pytest.fixture(scope="module")
def real_checkpoint(finished) -> tuple[dict, dict]:
    from poissonkit.numerics.checkpoint import newest_checkpoint

    _, arrays, meta = newest_checkpoint(finished / "checkpoints")
    return arrays, meta


@pytest.mark.timeout(600)
@FAST
@given(data=st.data())
def test_forged_checkpoint_content(real_checkpoint, data):
    _read_forged(real_checkpoint, data.draw(forged_checkpoints(*real_checkpoint)))


@slow
@pytest.mark.timeout(7200)
@SLOW
@given(data=st.data())
def test_forged_checkpoint_content_slow(real_checkpoint, data):
    _read_forged(real_checkpoint, data.draw(forged_checkpoints(*real_checkpoint)))


# --------------------------------------------------------- resume of a damaged finished run
@st.composite
def damages(draw, names: list[str]):
    ops = []
    for _ in range(draw(st.integers(1, 3))):
        name = draw(st.sampled_from(names))
        op = draw(st.sampled_from(["delete", "truncate", "flip", "random", "empty", "json"]))
        ops.append((name, op, draw(st.floats(0, 1)), draw(st.binary(max_size=16)),
                    draw(values)))
    return ops


def _apply(out: Path, ops) -> None:
    for name, op, frac, junk, value in ops:
        p = out / name
        if not p.is_file():
            continue
        data = p.read_bytes()
        if op == "delete":
            p.unlink()
        elif op == "truncate":
            p.write_bytes(data[: int(frac * len(data))])
        elif op == "flip" and data:
            b = bytearray(data)
            b[min(int(frac * len(b)), len(b) - 1)] ^= 0xFF
            p.write_bytes(bytes(b))
        elif op == "random":
            p.write_bytes(junk)
        elif op == "empty":
            p.write_bytes(b"")
        elif op == "json" and name == "summary.json":
            try:
                doc = json.loads(data)
            except ValueError:  # damaged by an earlier operation: nothing to edit
                continue
            if isinstance(doc, dict):
                doc["status"] = value if frac < 0.5 else "interrupted"
                p.write_text(json.dumps(doc))


def _snapshot(out: Path) -> dict[str, bytes]:
    return {str(p.relative_to(out)): p.read_bytes() for p in sorted(out.rglob("*"))
            if p.is_file()}


def _resume_damaged(finished: Path, ops) -> None:
    from poissonkit.report.resume import prepare_resume

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out"
        shutil.copytree(finished, out)
        _apply(out, ops)
        before = _snapshot(out)
        got = outcome("resume of a damaged finished run", lambda: prepare_resume(out))
        # a finished run is never resumed, and nothing of it is removed or changed
        assert got is None, f"resumed a finished run after {ops}"
        assert _snapshot(out) == before, f"files changed after {ops}"


@pytest.fixture(scope="module")
def finished_names(finished) -> list[str]:
    return [str(p.relative_to(finished)) for p in sorted(finished.rglob("*")) if p.is_file()
            and p.suffix in (".json", ".npz", ".nc", ".pkcp")]


@pytest.mark.timeout(600)
@FAST
@given(data=st.data())
def test_resume_of_a_damaged_finished_run(finished, finished_names, data):
    _resume_damaged(finished, data.draw(damages(finished_names)))


@slow
@pytest.mark.timeout(7200)
@SLOW
@given(data=st.data())
def test_resume_of_a_damaged_finished_run_slow(finished, finished_names, data):
    _resume_damaged(finished, data.draw(damages(finished_names)))


# ------------------------------------------------------------------- view of a damaged folder
def _view_damaged(finished: Path, ops) -> None:
    from poissonkit.commands.view import page_of

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out"
        out.mkdir()
        shutil.copy(finished / "trajectory.nc", out / "trajectory.nc")
        _apply(out, ops)
        outcome("view of a damaged folder", lambda: page_of(out))


@pytest.mark.timeout(600)
@FAST
@given(data=st.data())
def test_view_of_a_damaged_folder(finished, data):
    _view_damaged(finished, data.draw(damages(["trajectory.nc"])))


@slow
@pytest.mark.timeout(7200)
@SLOW
@given(data=st.data())
def test_view_of_a_damaged_folder_slow(finished, data):
    _view_damaged(finished, data.draw(damages(["trajectory.nc"])))


def test_the_fuzzed_folder_is_a_finished_run(finished):
    """Positive control: the folder the fuzz damages resumes to a refusal as finished, and its
    files are what a finished run holds."""
    from poissonkit.report.resume import RunFinishedError, prepare_resume

    assert {"summary.json", "trajectory.npz", "trajectory.nc"} <= {p.name for p in
                                                                   finished.iterdir()}
    with pytest.raises(RunFinishedError):
        prepare_resume(finished)
    assert isinstance(RunFinishedError("x"), PoissonkitError)

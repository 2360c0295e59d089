"""Malformed verify JSON gives typed errors naming the limit: deep nesting (RecursionError
before), a 10⁶-digit integer (Python's int digit limit), a lone surrogate in an expression
(UnicodeEncodeError), too large or non-UTF-8 files."""

from __future__ import annotations

import json

import pytest

from poissonkit.errors import InputError, ParseError
from poissonkit.input_limits import MAX_DEPTH, MAX_NUMBER_DIGITS, MAX_TEXT_BYTES, loads_json
from poissonkit.structure.verification.loading import load_structure_json

SO3 = '{"dim": 3, "bivector": {"1,2": "x3", "1,3": "-x2", "2,3": "%s"}}'


def _load(tmp_path, text: str | bytes):
    p = tmp_path / "s.json"
    p.write_bytes(text if isinstance(text, bytes) else text.encode("utf-8", "surrogatepass"))
    return load_structure_json(p)


def test_deep_nesting_is_a_typed_error(tmp_path):
    deep = "[" * 100_000 + "]" * 100_000
    with pytest.raises(ParseError, match=f"deeper than the limit of {MAX_DEPTH}"):
        _load(tmp_path, '{"dim": 3, "bivector": {"1,2": %s}}' % deep)


def test_nesting_at_the_limit_is_parsed():
    ok = "[" * MAX_DEPTH + "]" * MAX_DEPTH
    assert loads_json(ok, "t") == json.loads(ok)
    with pytest.raises(InputError, match="deeper"):
        loads_json("[" + ok + "]", "t")


def test_million_digit_integer_is_a_typed_error(tmp_path):
    with pytest.raises(ParseError, match=f"1000000 digits.*limit of {MAX_NUMBER_DIGITS}"):
        _load(tmp_path, '{"dim": %s, "bivector": {}}' % ("1" * 10**6))


def test_digits_inside_strings_are_not_numbers():
    assert loads_json('{"a": "%s"}' % ("9" * 5000), "t") == {"a": "9" * 5000}


def test_lone_surrogate_escape_in_an_expression(tmp_path):
    with pytest.raises(ParseError, match="surrogate"):
        _load(tmp_path, SO3 % "x1 + \\ud800")


def test_lone_surrogate_in_a_dict_source():
    data = json.loads(SO3 % "x1")
    data["bivector"]["2,3"] = "x1\udc80"
    with pytest.raises(ParseError, match="surrogate"):
        load_structure_json(data)


def test_surrogate_pair_escape_is_valid_unicode():
    assert loads_json('"\\ud83d\\ude00"', "t") == "\U0001F600"


def test_not_utf8_and_too_large(tmp_path):
    with pytest.raises(InputError, match="not UTF-8"):
        _load(tmp_path, b'{"dim": 3, "bivector": {"1,2": "\xff"}}')
    big = tmp_path / "big.json"
    with big.open("wb") as f:
        f.truncate(MAX_TEXT_BYTES + 1)  # sparse: no disk used
    with pytest.raises(InputError, match="limit of"):
        load_structure_json(big)


def test_valid_file_still_loads(tmp_path):
    name, P = _load(tmp_path, SO3 % "x1")
    assert name == "s.json" and P.dim == 3

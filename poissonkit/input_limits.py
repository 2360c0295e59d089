"""Bounded reading of user JSON and TOML: size, nesting depth, number length, valid text.

Python's parsers fail on hostile input with errors that are not ours: ``RecursionError`` on
deep nesting (``[[[[...``), ``ValueError`` on integers longer than ``sys.get_int_max_str_digits``
(4300 digits), and strings holding lone surrogates (``"\\ud800"`` in JSON) that later fail to
encode. Every user-facing JSON or TOML reader goes through :func:`loads_json` /
:func:`loads_toml`, which check these limits first and raise the caller's typed error, naming the
limit:

* :data:`MAX_TEXT_BYTES` — size of the text (64 MiB);
* :data:`MAX_DEPTH` — nesting of arrays and objects / inline tables (64 levels);
* :data:`MAX_NUMBER_DIGITS` — digits in one number literal (1000);
* strings must be valid Unicode (no lone surrogates).
"""

from __future__ import annotations

import json
import os
import re
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from poissonkit.errors import InputError

#: Largest JSON / TOML text accepted, in bytes (a 10⁵-body scene file is ~10 MB).
MAX_TEXT_BYTES = 64 * 2**20
#: Deepest nesting of arrays and objects (inline tables) accepted.
MAX_DEPTH = 64
#: Most digits in one number literal (Python refuses integers past 4300 digits).
MAX_NUMBER_DIGITS = 1000

__all__ = ["MAX_DEPTH", "MAX_NUMBER_DIGITS", "MAX_TEXT_BYTES", "check_strings", "loads_json",
           "loads_toml", "read_text"]

# What can hide brackets or digits: strings (and TOML comments), replaced by a blank first.
_JSON_TEXT = re.compile(r'"(?:[^"\\]|\\.)*"')
_TOML_TEXT = re.compile(r'"""[\s\S]*?"""|\'\'\'[\s\S]*?\'\'\'|"(?:[^"\\\n]|\\.)*"|\'[^\'\n]*\'|#[^\n]*')
_LONG_NUMBER = re.compile(rf"[0-9][0-9_]{{{MAX_NUMBER_DIGITS},}}")
_SURROGATE = re.compile("[\ud800-\udfff]")

ErrorType = Callable[[str], InputError]


def read_text(path: str | Path, what: str, error: ErrorType = InputError) -> str:
    """The UTF-8 text of ``path``, refused past :data:`MAX_TEXT_BYTES` (before reading it).

    Raises
    ------
    InputError
        (or ``error``) If the file cannot be read, is too large or is not UTF-8.
    """
    p = Path(path)
    try:
        size = os.stat(p).st_size
        if size > MAX_TEXT_BYTES:
            raise error(f"{what} {str(p)!r}: {size} bytes, more than the limit of "
                        f"{MAX_TEXT_BYTES} bytes")
        return p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"{what} {str(p)!r} does not exist") from None
    except OSError as exc:
        raise error(f"cannot read {what} {str(p)!r}: {exc.strerror or exc}") from None
    except UnicodeDecodeError as exc:
        raise error(f"{what} {str(p)!r} is not UTF-8 text ({exc.reason} at byte "
                    f"{exc.start})") from None


def _scan(text: str, hiding: re.Pattern[str], what: str, error: ErrorType) -> None:
    """Refuse ``text`` past the size, depth and number-length limits, or with surrogates."""
    if len(text) > MAX_TEXT_BYTES:
        raise error(f"{what}: {len(text)} characters, more than the limit of {MAX_TEXT_BYTES}")
    bad = _SURROGATE.search(text)
    if bad is not None:
        raise error(f"{what}: invalid character U+{ord(bad.group()):04X} (a lone surrogate) "
                    f"at offset {bad.start()}")
    code = hiding.sub(" ", text)  # an unterminated string stays: the parser refuses it
    long = _LONG_NUMBER.search(code)
    if long is not None:
        raise error(f"{what}: a number with {len(long.group())} digits, more than the limit "
                    f"of {MAX_NUMBER_DIGITS}")
    raw = np.frombuffer(code.encode("utf-8"), dtype=np.uint8)
    step = ((raw == 91) | (raw == 123)).astype(np.int32)  # [ {
    step -= (raw == 93) | (raw == 125)                    # ] }
    if step.size and int(np.cumsum(step).max()) > MAX_DEPTH:
        raise error(f"{what}: nested deeper than the limit of {MAX_DEPTH} levels")


def check_strings(data: Any, what: str, error: ErrorType = InputError) -> None:
    """Refuse strings (values or keys) that are not valid Unicode, anywhere in ``data``.

    JSON escapes such as ``"\\ud800"`` decode to lone surrogates, which cannot be encoded;
    walked without recursion, so a deeply nested object from Python is safe too.
    """
    stack = [data]
    while stack:
        item = stack.pop()
        if isinstance(item, str):
            if _SURROGATE.search(item):
                raise error(f"{what}: string {item!r} holds a lone surrogate (not valid "
                            "Unicode)")
        elif isinstance(item, dict):
            stack.extend(item.keys())
            stack.extend(item.values())
        elif isinstance(item, (list, tuple)):
            stack.extend(item)


def _parse_int(text: str) -> int:
    # reached only by literals within MAX_NUMBER_DIGITS (the scan refuses longer ones)
    return int(text)


def loads_json(text: str, what: str, error: ErrorType = InputError) -> Any:
    """Parse JSON ``text`` within the limits of this module.

    Parameters
    ----------
    text
        The JSON document.
    what
        Names the input in messages (e.g. the file name).
    error
        The typed error to raise (an :class:`~poissonkit.errors.InputError` subclass).

    Raises
    ------
    InputError
        (or ``error``) Invalid JSON, or a limit exceeded (the message names it).
    """
    data = _parse(text, _JSON_TEXT, what, error, "JSON",
                  lambda t: json.loads(t, parse_int=_parse_int))
    check_strings(data, what, error)
    return data


def loads_toml(text: str, what: str, error: ErrorType = InputError) -> dict[str, Any]:
    """Parse TOML ``text`` within the limits of this module (see :func:`loads_json`).

    Raises
    ------
    InputError
        (or ``error``) Invalid TOML, or a limit exceeded (the message names it).
    """
    return _parse(text, _TOML_TEXT, what, error, "TOML", tomllib.loads)


def _parse(text: str, hiding: re.Pattern[str], what: str, error: ErrorType, kind: str,
           parse: Callable[[str], Any]) -> Any:
    """``parse(text)`` once the limits hold (see :func:`_scan`); every error of the parser
    raised as ``error``."""
    _scan(text, hiding, what, error)
    try:
        return parse(text)
    except json.JSONDecodeError as exc:
        raise error(f"{what}: invalid JSON ({exc.msg}, line {exc.lineno})") from None
    except tomllib.TOMLDecodeError as exc:
        raise error(f"invalid TOML in {what}: {exc}") from None
    except (ValueError, RecursionError) as exc:  # not expected after the scan; still typed
        raise error(f"{what}: unreadable {kind} ({exc})") from None

"""Scene TOML read within documented limits: deep nesting (RecursionError before), a
10⁶-digit integer (ValueError from Python's digit limit), lone surrogates, not UTF-8."""

from __future__ import annotations

import pytest

from poissonkit.errors import SceneError
from poissonkit.input_limits import MAX_DEPTH, MAX_NUMBER_DIGITS
from poissonkit.scene import load_scene
from poissonkit.scene.loader import loads_scene, scene_description


def test_deep_array_nesting():
    with pytest.raises(SceneError, match=f"deeper than the limit of {MAX_DEPTH}"):
        loads_scene("name = " + "[" * 100_000 + "]" * 100_000)


def test_deep_inline_table_nesting():
    with pytest.raises(SceneError, match="deeper"):
        loads_scene("a = " + "{b=" * 5000 + "1" + "}" * 5000)


def test_million_digit_integer():
    with pytest.raises(SceneError, match=f"digits.*limit of {MAX_NUMBER_DIGITS}"):
        loads_scene("[run]\nduration = " + "1" * 10**6)


def test_brackets_and_digits_in_strings_and_comments_are_text():
    text = ('name = "[[[[{{{{ %s"\n# ]]]]]]]] %s\ndescription = \'\'\'\n[[[[\n\'\'\'\n'
            % ("9" * 2000, "[" * 200))
    with pytest.raises(SceneError) as err:  # reaches the schema: no bodies
        loads_scene(text)
    assert "limit" not in str(err.value)


def test_lone_surrogate_text():
    with pytest.raises(SceneError, match="surrogate"):
        loads_scene('name = "a\ud800"')


def test_not_utf8_file(tmp_path):
    p = tmp_path / "s.toml"
    p.write_bytes(b'name = "\xff"\n')
    with pytest.raises(SceneError, match="not UTF-8"):
        load_scene(p)
    assert scene_description(p) == ""
    (tmp_path / "d.toml").write_text("a = " + "[" * 10_000 + "]" * 10_000)
    assert scene_description(tmp_path / "d.toml") == ""

"""Scene files (TOML text) shared by the tests, and the step that runs one through the CLI.

The bodies here are the tests' recurring ones: the seed's cylinder magnets
(:data:`CYLINDER_MAGNETS`, written as ``[defaults]`` and one ``[[bodies]]`` table each by
:func:`magnet_scene`) and the 20 g top hovering over a magnet of the field tests
(:func:`top_scene`). :func:`run_scene` writes a text to a file, runs ``poissonkit run`` on it and
returns the output folder with its ``summary.json``. Import as ``from scene_texts import ...``
(``tests/`` is on ``sys.path``).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

#: ``[defaults]`` of the seed's NdFeB cylinder magnets (2.5 mm × 20 mm, 1.58 MA/m).
CYLINDER_MAGNETS = """[defaults]
mass = 7.658e-4
inertia = 2.5827e-8
magnetization = 1.58359e6
radius = 1.25e-3
length = 0.02
"""

#: Gravity at the Earth's surface, as a ``[[fields]]`` table.
GRAVITY = """[[fields]]
source = "gravity"
g = [0.0, 0.0, -9.81]
"""

#: ``params`` of the field tests' magpylib cylinder (axial polarization 1 T, 5 cm × 1 cm).
CYLINDER_PARAMS = "params = { polarization = [0.0, 0.0, 1.0], dimension = [0.05, 0.01] }"


def bodies(*rows: tuple[str, str, str] | tuple[str, str, str, str]) -> str:
    """``[[bodies]]`` tables of ``(name, r, nu[, further lines])`` rows (vectors as TOML text)."""
    return "".join(f'[[bodies]]\nname = "{row[0]}"\nr = {row[1]}\nnu = {row[2]}\n'
                   + (row[3] + "\n" if len(row) > 3 else "") for row in rows)


def magnet_scene(name: str, *rows: tuple[str, str, str] | tuple[str, str, str, str],
                 defaults: str = CYLINDER_MAGNETS) -> str:
    """The head of a scene of magnets: its name, ``defaults`` and the bodies of ``rows``
    (:func:`bodies`); the caller appends interactions, fields and ``[run]``."""
    return f'\nname = "{name}"\n{defaults}{bodies(*rows)}'


def top_scene(name: str, field: str, *, r: str = "[0.0, 0.0, 0.03]", p: str | None = None,
              nu: str = "[0.0, 0.0, -1.0]", gravity: bool = True,
              run: str = 'method = "splitting6"\nstep = 2e-4\nduration = 0.05') -> str:
    """A 20 g top (a 0.1 A m² dipole spinning along ``-z``) at ``r`` over the source of the
    ``[[fields]]`` table whose lines are ``field``, then gravity and ``[run]`` (lines ``run``)."""
    momentum = f"p = {p}\n" if p is not None else ""
    return f'''
name = "{name}"

[[bodies]]
name = "top"
mass = 0.02
inertia = 2.0e-6
moment = 0.1
r = {r}
{momentum}nu = {nu}
m = [0.0, 0.0, -2.0e-4]

[[fields]]
{field}

{GRAVITY if gravity else ""}
[run]
{run}
'''


def run_scene(tmp_path: Path, text: str, *options: str) -> tuple[Path, dict[str, Any]]:
    """Run the scene ``text`` with ``poissonkit run`` (no progress bar, no figures) into
    ``tmp_path / "run"``; the folder and its ``summary.json``. Fails the test on a non-zero
    exit."""
    from poissonkit.cli import main as cli_main

    path = tmp_path / "scene.toml"
    path.write_text(text)
    out = tmp_path / "run"
    assert cli_main(["run", str(path), "--out", str(out), "--no-progress", "--no-plot",
                     *options]) == 0
    return out, json.loads((out / "summary.json").read_text())

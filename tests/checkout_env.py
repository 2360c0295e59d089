"""The environment of a test's subprocess: this checkout and its built-in plugins first on
``PYTHONPATH``. Import as ``from checkout_env import checkout_env`` (``tests/`` is on
``sys.path``)."""

from __future__ import annotations

import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def checkout_env(**variables: str | None) -> dict[str, str]:
    """A copy of ``os.environ`` running this checkout's poissonkit and plugins; each of
    ``variables`` set, or removed where ``None``."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), str(ROOT / "plugins"),
                                         env.get("PYTHONPATH", "")])
    for name, value in variables.items():
        if value is None:
            env.pop(name, None)
        else:
            env[name] = value
    return env

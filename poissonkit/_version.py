"""The installed version of poissonkit, a leaf module every layer may read.

``poissonkit.__version__`` is this value; modules below the package root import it from here so
that no layer imports the root package (which imports the symbolic layer) back.
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("poissonkit")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0"

__all__ = ["__version__"]

"""One entry point for numba compilation of functions built at run time, with a disk cache.

Closures specialised to one system (force loops, time loops) and functions generated from
sympy expressions are compiled through :func:`jit` and :func:`compile_generated` instead of
``numba.njit``. Their machine code is kept in a disk cache, so that a second process — a second
``poissonkit run`` of the same scene, a Dask worker, the next test session — loads it instead
of compiling again.

numba's own ``cache=True`` cannot do this: it needs a function defined in a source file, and it
identifies a closure by pickling its cell contents, which for a compiled callee includes a
random per-process id (so it never hits). Here each compiled function gets a **token**, a hash
of everything its machine code depends on:

* the function's bytecode, constants and names, and the compile options;
* the source of the whole poissonkit package and of the top-level package (a plugin) or module
  that defines the function (the globals a closure calls live there), and the numba / Python
  versions (through the cache folder);
* for a closure, the tokens of its cell contents (compiled callees by their own tokens, numbers,
  tuples and arrays by value); for generated source, the source text and the tokens of its
  namespace.

The float parameters of pair potentials and the units of an N-body system are run-time data
(:func:`poissonkit.numerics.potentials.runtime_potential`), not constants of the generated code,
so no token depends on their values: a second process with other values loads everything.

Anything without a token (an object we cannot fingerprint) keeps in-memory compilation only, as
before. The cache folder is ``$POISSONKIT_CACHE_DIR`` or ``~/.cache/poissonkit`` (``$XDG_CACHE_HOME``
respected), one sub-folder per numba and Python version; ``POISSONKIT_CACHE_DIR=off`` disables it.
A read-only folder is used for reading only, an unreadable one not at all; a corrupt or unreadable
entry is deleted if possible and compiled again. Every data file records the key (signature,
target, token) it was stored under and a checksum, both checked before numba loads it: a file that
holds another kernel's valid entry is a miss (logged at debug level), compiled again and
overwritten — the cache can make things faster, never wrong or failing.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import logging
import math
import os
import pickle
import secrets
import sys
import types
from functools import lru_cache
from pathlib import Path
from typing import Any

import numba
import numpy as np
from numba.core import caching
from numba.core.dispatcher import Dispatcher

_log = logging.getLogger(__name__)

#: Environment variable naming the cache folder (``off``, ``0`` or ``none`` disables the cache).
CACHE_ENV = "POISSONKIT_CACHE_DIR"
_OFF = {"off", "0", "none", "false", "no"}


def cache_dir() -> Path | None:
    """The kernel cache folder in use, or ``None`` when caching is disabled."""
    env = os.environ.get(CACHE_ENV)
    if env is not None and env.strip().lower() in _OFF:
        return None
    if env:
        base = Path(env).expanduser()
    else:
        xdg = os.environ.get("XDG_CACHE_HOME")
        base = (Path(xdg) if xdg else Path.home() / ".cache") / "poissonkit"
    tag = f"kernels-numba{numba.__version__}-py{sys.version_info[0]}{sys.version_info[1]}"
    return base / tag


def _unique_symbols_per_process() -> None:
    """Start numba's function-id counter at a random point in every process.

    numba names the machine code of a function ``<module>.<qualname>$<id>`` with an id counted
    from 1 in each process, and links callees as one-definition-rule symbols: two processes
    that compile the same closure with different captured values in the same order give both
    versions the *same* symbol. Loaded from the cache into a process that already holds its own
    version, a caller could then be linked to the wrong one. A random 48-bit start makes symbols
    of different processes differ (ids only have to be unique within a process).
    """
    from numba.core import bytecode

    bytecode.FunctionIdentity._unique_ids = itertools.count(secrets.randbits(48) + 1)


_unique_symbols_per_process()


# --------------------------------------------------------------------------------- tokens
def _sha(*parts: str | bytes) -> str:
    h = hashlib.sha256()
    for p in parts:
        h.update(p if isinstance(p, bytes) else p.encode())
        h.update(b"\x00")
    return h.hexdigest()


@lru_cache(maxsize=None)
def _file_digest(path: str) -> str | None:
    try:
        return _sha(Path(path).read_bytes())
    except OSError:
        return None


@lru_cache(maxsize=None)
def _tree_digest(root: Path) -> str:
    files = sorted(root.rglob("*.py"))
    return _sha(*[f"{f.relative_to(root)}:{_file_digest(str(f))}" for f in files])


def _package_digest() -> str:
    """Hash of every source file of the poissonkit package (globals of closures live there)."""
    return _tree_digest(Path(__file__).resolve().parents[1])


def _module_digest(module: str | None, filename: str) -> str | None:
    """Hash of the source tree of the top-level package defining ``module`` (a plugin's
    kernels call functions in its other files), or of the file alone for a plain module."""
    top = sys.modules.get((module or "").split(".")[0])
    init = getattr(top, "__file__", None)
    if init and Path(init).name == "__init__.py":
        return _tree_digest(Path(init).resolve().parent)
    return _file_digest(filename)


def _code_token(code: types.CodeType) -> str:
    consts = []
    for c in code.co_consts:
        consts.append(_code_token(c) if isinstance(c, types.CodeType) else repr(c))
    return _sha(code.co_code, repr(code.co_names), *consts)


def _value_token(value: Any) -> str | None:
    """Token of a closure cell or namespace value; ``None`` if it cannot be fingerprinted."""
    if isinstance(value, Dispatcher):
        return dispatcher_token(value)
    if value is None or isinstance(value, (bool, int, float, complex, str, bytes)):
        return f"{type(value).__name__}:{value!r}"
    if isinstance(value, np.generic):
        return f"{type(value).__name__}:{value!r}"
    if isinstance(value, np.ndarray):
        return _sha("ndarray", value.dtype.str, repr(value.shape),
                    np.ascontiguousarray(value).tobytes())
    if isinstance(value, tuple):
        parts = [_value_token(v) for v in value]
        if any(p is None for p in parts):
            return None
        return _sha(type(value).__qualname__, *parts)  # named tuples keep their type
    if isinstance(value, types.ModuleType) and value.__name__ in ("math", "numpy", "cmath"):
        return f"module:{value.__name__}"
    if isinstance(value, types.BuiltinFunctionType):
        return f"builtin:{getattr(value, '__module__', '')}.{value.__qualname__}"
    return None


def _function_token(func: types.FunctionType, options: dict[str, Any],
                    extra: tuple[str, ...] = ()) -> str | None:
    """Token of a plain Python function about to be compiled with ``options``."""
    cells = []
    for cell in func.__closure__ or ():
        try:
            contents = cell.cell_contents
        except ValueError:  # an unbound cell: the closure is not complete yet
            return None
        t = _value_token(contents)
        if t is None:
            return None
        cells.append(t)
    filename = func.__code__.co_filename
    file_part = (_module_digest(func.__module__, filename) if os.path.isfile(filename)
                 else "generated")
    if file_part is None:
        return None
    return _sha("v1", _package_digest(), file_part, func.__module__ or "", func.__qualname__,
                _code_token(func.__code__), repr(sorted(options.items())), *cells, *extra)


def dispatcher_token(disp: Dispatcher) -> str | None:
    """Token of a compiled function (``None``: it cannot be identified across processes).

    Our own dispatchers carry their recipe; a foreign one (a module-level ``numba.njit``
    function, e.g. a plugin's hand-written kernel) is identified by its module, name and the
    hash of its source file.
    """
    cache = getattr(disp, "_cache", None)
    if isinstance(cache, _DiskCache):
        return cache.token()
    func = disp.py_func
    if func.__closure__ is None and "<locals>" not in func.__qualname__ \
            and os.path.isfile(func.__code__.co_filename):  # not generated source
        digest = _module_digest(func.__module__, func.__code__.co_filename)
        if digest is not None:
            return _sha("module-level", func.__module__ or "", func.__qualname__, digest,
                        repr(sorted(disp.targetoptions.items())))
    return None


# --------------------------------------------------------------------------------- the cache
class _Locator(caching._CacheLocator):
    """All entries in :func:`cache_dir`; freshness is carried by the token, not file times."""

    def __init__(self, py_func: Any, py_file: str, path: Path, disambiguator: str) -> None:
        self._py_file = py_file
        self._path = str(path)
        self._disambiguator = disambiguator

    def get_cache_path(self) -> str:
        return self._path

    def get_source_stamp(self) -> str:
        return "token"

    def get_disambiguator(self) -> str:
        return self._disambiguator

    @classmethod
    def from_function(cls, py_func: Any, py_file: str) -> None:  # pragma: no cover - unused
        return None


class _Impl(caching.CompileResultCacheImpl):
    def __init__(self, py_func: Any, path: Path, token: str) -> None:
        # The base class searches locator classes by source file; ours needs none.
        self._lineno = py_func.__code__.co_firstlineno
        self._locator = _Locator(py_func, py_func.__code__.co_filename, path, token[:24])
        name = py_func.__qualname__.replace("<locals>.", "").replace("<", "").replace(">", "")
        generated = py_func.__code__.co_filename.startswith("<")
        modname = "generated" if generated else py_func.__module__.rsplit(".", 1)[-1]
        self._filename_base = self.get_filename_base(f"{modname}.{name}",
                                                     getattr(sys, "abiflags", ""))


def _key_digest(key: tuple) -> str:
    """What a data file records of the index key it was stored under: signature, target
    (codegen magic tuple) and token."""
    sig, magic, token = key
    return _sha("entry-v1", str(sig), repr(magic), token)


class _EntryMismatch(Exception):
    """A data file that does not hold the entry of its index key (a miss, not an error)."""


class _CheckedFile(caching.IndexDataCacheFile):
    """numba's index + data files, each data file tagged with the key it was stored under.

    The index is already tied to the token (its stamp), but a data file is found by name only:
    a folder whose files hold other kernels' valid entries (copied, renamed, a shared folder
    mixed up) would load foreign machine code — a wrong result or a numba ``TypingError``.
    The tag is checked before numba rebuilds anything, and so is a checksum of the entry: a
    flipped byte inside the object code still unpickles, and LLVM aborts the process on it.
    """

    def save(self, key: tuple, data: Any) -> None:
        payload = self._dump(data)
        super().save(key, (_key_digest(key), _sha(payload), payload))

    def load(self, key: tuple) -> Any:
        got = super().load(key)
        if got is None:
            return None
        if not (isinstance(got, tuple) and len(got) == 3 and got[0] == _key_digest(key)
                and isinstance(got[2], bytes) and got[1] == _sha(got[2])):
            raise _EntryMismatch(self._index_path)
        return pickle.loads(got[2])  # noqa: S301 - our own cache folder, checksum verified


class _TokenCache(caching.Cache):
    """numba's per-function file cache, keyed by our token instead of pickled closures."""

    def __init__(self, py_func: Any, path: Path, token: str) -> None:
        self._name = repr(py_func)
        self._py_func = py_func
        self._token = token
        self._impl = _Impl(py_func, path, token)
        self._cache_path = self._impl.locator.get_cache_path()
        self._cache_file = _CheckedFile(
            cache_path=self._cache_path, filename_base=self._impl.filename_base,
            source_stamp=token)
        self.enable()

    def _index_key(self, sig: Any, codegen: Any) -> tuple:
        return (sig, codegen.magic_tuple(), self._token)


class _DiskCache(caching.NullCache):
    """What a dispatcher holds: builds the file cache on first use (when the closure is
    complete and its token known) and turns every cache failure into a plain compile."""

    def __init__(self, py_func: Any, options: dict[str, Any], extra: tuple[str, ...]) -> None:
        self._py_func = py_func
        self._options = options
        self._extra = extra
        self._token: str | None = None
        self._inner: _TokenCache | None = None
        self._failed = False

    def token(self) -> str | None:
        if self._token is None:
            self._token = _function_token(self._py_func, self._options, self._extra)
        return self._token

    def _cache(self) -> _TokenCache | None:
        if self._inner is None and not self._failed:
            path = cache_dir()
            token = self.token()
            if path is None or token is None:
                self._failed = True
                return None
            try:
                self._inner = _TokenCache(self._py_func, path, token)
            except Exception:  # noqa: BLE001 - a cache that cannot be set up is just off
                self._failed = True
        return self._inner

    @property
    def cache_path(self) -> str | None:
        inner = self._cache()
        return None if inner is None else inner.cache_path

    def load_overload(self, sig: Any, target_context: Any) -> Any:
        inner = self._cache()
        if inner is None:
            return None
        try:
            return inner.load_overload(sig, target_context)
        except _EntryMismatch as exc:  # the recompile overwrites it
            _log.debug("kernel cache: %s is not the entry stored under this key; compiling",
                       exc)
            return None
        except Exception as exc:  # noqa: BLE001 - corrupt or unreadable entry: drop it, compile
            _log.debug("kernel cache: unreadable entry for %s (%s: %s); compiling",
                       self._py_func.__qualname__, type(exc).__name__, exc)
            self._discard(inner)
            return None

    def save_overload(self, sig: Any, data: Any) -> None:
        inner = self._cache()
        if inner is None:
            return
        try:
            inner.save_overload(sig, data)
        except Exception as exc:  # noqa: BLE001 - read-only or full disk: keep the compiled code
            _log.debug("kernel cache: not stored (%s: %s)", type(exc).__name__, exc)

    @staticmethod
    def _discard(inner: _TokenCache) -> None:
        index = Path(inner._cache_file._index_path)
        try:
            index.unlink()
        except OSError:
            pass


# --------------------------------------------------------------------------------- public API
def jit(func: Any = None, **options: Any) -> Any:
    """``numba.njit`` for closures and generated functions, with the disk cache.

    Use as ``@jit`` or ``@jit(inline="always", parallel=True, ...)``; options are numba's
    (``error_model="numpy"`` by default, ``cache`` is not accepted: caching is decided here).
    """
    if "cache" in options:
        raise TypeError("jit() decides caching itself; do not pass cache=")
    options.setdefault("error_model", "numpy")
    extra = tuple(options.pop("_token_extra", ()))

    def wrap(f: Any) -> Any:
        disp = numba.njit(**options)(f)
        disp._cache = _DiskCache(f, dict(options), extra)
        return disp

    return wrap if func is None else wrap(func)


def compile_generated(source: str, name: str, namespace: dict[str, Any] | None = None,
                      **options: Any) -> Any:
    """Execute generated ``source`` (our own printed code, never user strings) and return
    :func:`jit` of its function ``name``; ``namespace`` holds the names it calls."""
    # a real module name: numba re-imports it when it loads the function's environment
    ns: dict[str, Any] = {"math": math, "__name__": __name__}
    if namespace:
        ns.update(namespace)
    extra = [_sha(source)]
    for key in sorted(namespace or {}):
        t = _value_token(ns[key])
        extra.append(f"{key}={t}" if t is not None else f"{key}=<unknown {id(ns[key])}>")
    if any("<unknown" in e for e in extra):
        extra = ["uncacheable"]
    exec(compile(source, f"<poissonkit-generated {name}>", "exec"), ns)  # noqa: S102
    func = ns[name]
    func.__doc__ = "Generated by poissonkit:\n\n" + source
    disp = jit(**options, _token_extra=tuple(extra))(func)
    if extra == ["uncacheable"]:
        disp._cache = caching.NullCache()
    return disp


def cache_stats(disp: Dispatcher) -> tuple[int, int]:
    """``(disk cache hits, compilations)`` of one compiled function in this process."""
    return sum(disp._cache_hits.values()), sum(disp._cache_misses.values())


# --------------------------------------------------------------------------------- sources
def load_sources(key: str) -> dict[str, str] | None:
    """Generated sources stored under ``key`` by :func:`store_sources` (``None`` if absent,
    unreadable or corrupt: the caller then generates them again)."""
    folder = cache_dir()
    if folder is None:
        return None
    path = folder / "sources" / f"{key}.json"
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        return None
    except (OSError, ValueError, RecursionError):  # RecursionError: a nested damaged file
        _unlink(path)
        return None
    if (not isinstance(data, dict) or data.get("key") != key
            or not isinstance(data.get("sources"), dict)
            or not all(isinstance(v, str) for v in data["sources"].values())):
        _unlink(path)
        return None
    return data["sources"]


def store_sources(key: str, sources: dict[str, str]) -> None:
    """Keep generated ``sources`` (name → text) under ``key`` (atomically; errors ignored)."""
    folder = cache_dir()
    if folder is None:
        return
    from poissonkit.files.atomic import write_text

    try:
        (folder / "sources").mkdir(parents=True, exist_ok=True)
        write_text(folder / "sources" / f"{key}.json",
                   json.dumps({"key": key, "sources": sources}))
    except OSError:
        pass


def source_key(*parts: str) -> str:
    """Key of generated sources: a hash of ``parts`` and of the package source."""
    return _sha("sources-v1", _package_digest(), *parts)


def _unlink(path: Path) -> None:
    try:
        path.unlink()
    except OSError:
        pass

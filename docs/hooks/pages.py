"""mkdocs hook: the pages generated from the code at build time.

* **API reference** — one page per group of ``poissonkit.__all__`` (grouped by the subpackage
  that defines each name), rendered by mkdocstrings from the numpydoc docstrings. A public name
  is added in one place (``poissonkit/__init__.py``) and appears here; a public name without a
  docstring is a warning, so ``mkdocs build --strict`` fails.
* **Gallery** — one page per script in ``examples/`` (its docstring, the figures it writes as
  listed under ``extra.gallery_figures`` in ``mkdocs.yml``, and its source) plus the third-party
  plugin example.
* **Changelog** — ``CHANGELOG.md`` of the project root.
"""

from __future__ import annotations

import ast
import functools
import importlib.util
import logging
import sys
from pathlib import Path
from typing import Any

from mkdocs.structure.files import File, Files

# a logger under "mkdocs." so that strict mode counts its warnings
log = logging.getLogger("mkdocs.plugins.poissonkit_pages")

#: (module prefix, page slug, title, one-line introduction); the first matching prefix wins.
SECTIONS: tuple[tuple[str, str, str, str], ...] = (
    ("poissonkit.structure", "structure", "Symbolic structures and checks",
     "Bivectors and their blocks, Jacobi checks, Casimirs, first integrals, Poisson maps."),
    ("poissonkit.commands.verify", "structure", "", ""),
    ("poissonkit.numerics", "numerics", "Numerics",
     "Compiled systems, the solver and its solution."),
    ("poissonkit.pairs", "magnets", "Magnet interactions",
     "Energy, force and torques of a pair of magnets."),
    ("poissonkit.scene", "scenes", "Scenes", "Scene files and the runs built from them."),
    ("poissonkit.plugin", "registries", "Registries and plugins",
     "Integrators and everything else plugins contribute, by name."),
    ("poissonkit.errors", "errors", "Errors", "Every error poissonkit raises derives from these."),
    ("", "other", "Other", "Public names outside the groups above."),
)


_PAGES: dict[str, str] = {}


@functools.lru_cache(maxsize=None)
def _roles_module():
    spec = importlib.util.spec_from_file_location(
        "poissonkit_docs_sphinx_roles", Path(__file__).with_name("sphinx_roles.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _replace_roles(text: str) -> str:
    """Sphinx roles as inline code (the griffe extension beside this file does the same for
    the rendered docstrings)."""
    return _roles_module().replace_roles(text)


def _root(config: Any) -> Path:
    return Path(config.config_file_path).resolve().parent


def public_api() -> dict[str, str]:
    """``{public name: dotted path of its definition}`` for every name in ``poissonkit.__all__``."""
    import poissonkit

    out: dict[str, str] = {}
    for name in poissonkit.__all__:
        if name.startswith("__"):  # __version__ and the like: shown on the index page
            continue
        if name in poissonkit._LAZY:
            out[name] = f"{poissonkit._LAZY[name]}.{name}"
            continue
        obj = getattr(poissonkit, name)
        out[name] = f"{obj.__module__}.{getattr(obj, '__qualname__', name)}"
    return out


def api_sections() -> dict[str, tuple[str, str, list[tuple[str, str]]]]:
    """``{slug: (title, intro, [(name, path), ...])}`` in the order of :data:`SECTIONS`."""
    titles = {}
    for _prefix, slug, title, intro in SECTIONS:
        if title:
            titles.setdefault(slug, (title, intro))
    groups: dict[str, list[tuple[str, str]]] = {slug: [] for slug in titles}
    for name, path in public_api().items():
        slug = next(s for prefix, s, _t, _i in SECTIONS if path.startswith(prefix))
        groups[slug].append((name, path))
    return {slug: (*titles[slug], items) for slug, items in groups.items() if items}


def _check_docstrings(api: dict[str, str]) -> None:
    import poissonkit

    for name in api:
        obj = getattr(poissonkit, name)
        if not (getattr(obj, "__doc__", None) or "").strip():
            log.warning("public name poissonkit.%s has no docstring", name)
        if not isinstance(obj, type):
            continue
        # public methods and properties a class defines itself appear in its reference too
        for member, value in vars(obj).items():
            func = value.fget if isinstance(value, property) else getattr(value, "__func__", value)
            if member.startswith("_") or not (callable(func) or isinstance(value, property)):
                continue
            if not (getattr(func, "__doc__", None) or "").strip():
                log.warning("public method poissonkit.%s.%s has no docstring", name, member)


def _api_pages() -> dict[str, str]:
    sections = api_sections()
    pages: dict[str, str] = {}
    index = ["# API reference", "",
             "Everything below is importable as `import poissonkit as pk`; `pk.__all__` is "
             "exactly this list. The submodules (`poissonkit.structure`, `poissonkit.numerics`, "
             "`poissonkit.scene`, `poissonkit.plugin`, ...) hold more for the specialist. "
             "Signs, index orders and units: [Conventions](../conventions.md). "
             "`pk.__version__` is the installed version (`poissonkit --version`).", "",
             "| name | group | summary |", "|---|---|---|"]
    import poissonkit

    for slug, (title, intro, items) in sections.items():
        lines = [f"# {title}", "", intro, ""]
        for name, path in items:
            lines += [f"::: {path}", ""]
            doc = (getattr(poissonkit, name).__doc__ or "").strip().splitlines()
            summary = _replace_roles(doc[0]).replace("|", "\\|") if doc else ""
            anchor = path
            index.append(f"| [`pk.{name}`]({slug}.md#{anchor}) | {title} | {summary} |")
        pages[f"api/{slug}.md"] = "\n".join(lines)
    pages["api/index.md"] = "\n".join(index) + "\n"
    return pages


def _docstring(path: Path) -> str:
    try:
        return ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or ""
    except SyntaxError as exc:
        log.warning("example %s does not parse: %s", path.name, exc)
        return ""


def _gallery_pages(root: Path, figures: dict[str, list[str]]) -> dict[str, str]:
    examples = sorted((root / "examples").glob("*.py"))
    for name in figures:
        if not (root / "examples" / name).is_file():
            log.warning("extra.gallery_figures names %s, which is not in examples/", name)
    pages: dict[str, str] = {}
    index = ["# Gallery", "",
             "The runnable scripts in `examples/`, with the figures they write. Each page shows "
             "the script's own description, how to run it, and its source.", ""]
    for path in examples:
        doc = _docstring(path)
        if not doc:
            log.warning("example %s has no module docstring", path.name)
        title, _, body = doc.partition("\n")
        figs = figures.get(path.name, [])
        # docstrings are plain text: brackets of usage lines must not read as link references
        body = body.strip().replace("[", "\\[").replace("]", "\\]")
        lines = [f"# {path.stem}", "", f"**{title.strip()}**", "", body, ""]
        if figs:
            lines += ["## Figures", ""]
            lines += [f"![{Path(f).stem}](../{f})" + "\n" for f in figs]
        source = path.read_text(encoding="utf-8")
        lines += ["## Source", "", f"`examples/{path.name}`", "", "```python", source.rstrip(),
                  "```", ""]
        pages[f"gallery/{path.stem}.md"] = "\n".join(lines)
        index.append(f"* [**{path.stem}**]({path.stem}.md) — {title.strip()}")
        if figs:
            index.append("")
            index.append(f"    [![{path.stem}](../{figs[0]}){{ width=\"360\" }}]({path.stem}.md)")
            index.append("")
    plugin_readme = root / "examples" / "external_plugin" / "README.md"
    if plugin_readme.is_file():
        text = plugin_readme.read_text(encoding="utf-8")
        pages["gallery/external_plugin.md"] = text
        first = text.strip().splitlines()[0].lstrip("# ").strip()
        index.append(f"* [**external_plugin**](external_plugin.md) — {first}")
    pages["gallery/index.md"] = "\n".join(index) + "\n"
    return pages


def _generated(config: Any) -> dict[str, str]:
    root = _root(config)
    # document the tree being built, whatever else is installed
    for path in (str(root / "plugins"), str(root)):
        if path not in sys.path:
            sys.path.insert(0, path)
    api = public_api()
    _check_docstrings(api)
    pages = _api_pages()
    pages.update(_gallery_pages(root, dict(config.extra.get("gallery_figures") or {})))
    changelog = root / "CHANGELOG.md"
    if changelog.is_file():
        pages["changelog.md"] = changelog.read_text(encoding="utf-8")
    else:
        log.warning("CHANGELOG.md is missing")
    return pages


def _nav_entries(paths: list[str], prefix: str) -> list[Any]:
    out: list[Any] = [f"{prefix}/index.md"]
    for p in paths:
        if p.startswith(prefix + "/") and not p.endswith("/index.md"):
            out.append(p)
    return out


def on_config(config: Any) -> Any:
    """Fill the ``API reference`` and ``Gallery`` sections of the nav with the generated pages."""
    pages = _generated(config)
    _PAGES.clear()
    _PAGES.update(pages)  # reused by on_files: generated once per build
    api_titles = {f"api/{slug}.md": title for slug, (title, _i, _n) in api_sections().items()}
    for item in config.nav or []:
        if not isinstance(item, dict):
            continue
        (key, _value), = item.items()
        if key == "API reference":
            item[key] = ["api/index.md"] + [{t: p} for p, t in api_titles.items()]
        elif key == "Gallery":
            item[key] = _nav_entries(sorted(pages), "gallery")
    return config


def on_files(files: Files, config: Any) -> Files:
    """Add the generated pages to the site."""
    for src_uri, content in _PAGES.items():
        files.append(File.generated(config, src_uri, content=content))
    return files

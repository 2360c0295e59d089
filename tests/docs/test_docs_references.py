"""Every file the documentation points at exists in the repository: relative links of
``docs/**/*.md`` and ``README.md``, repository paths they name (``plugins/.../ball.py``,
``tests/...``), and upper-case project files (``CHANGELOG.md``, ``LICENSE``). A reader of the
published docs has only the repository, so a reference to a file kept elsewhere is dead."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
PAGES = sorted(DOCS.rglob("*.md")) + [ROOT / "README.md"]
#: Pages the mkdocs hook (docs/hooks/pages.py) generates at build time.
GENERATED = ("api/", "gallery/", "changelog.md")
TOP_DIRS = ("poissonkit", "plugins", "tests", "docs", "examples", "benchmarks")

LINK = re.compile(r"\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
REPO_PATH = re.compile(r"(?<![\w/.$-])((?:%s)/[\w./-]*)" % "|".join(TOP_DIRS))
PROJECT_FILE = re.compile(r"(?<![\w.-])([A-Z][A-Z_]+\.(?:md|cff|txt)|LICENSE)(?![\w.])")


def dead_links(page: Path, text: str) -> list[str]:
    """Relative link targets of ``text`` (a page at ``page``) that resolve to no file."""
    out = []
    for target in LINK.findall(text):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
            continue  # a URL (http:, mailto:) or an anchor of the same page
        path = target.split("#", 1)[0]
        rel = (page.parent / path).resolve()
        if rel.exists():
            continue
        inside_docs = DOCS in rel.parents
        if inside_docs and rel.relative_to(DOCS).as_posix().startswith(GENERATED):
            continue
        out.append(target)
    return out


def dead_paths(text: str) -> list[str]:
    """Repository paths (``plugins/...``, ``tests/...``) and project files (``FOO.md``) named
    in ``text`` that do not exist; a path ending in ``_`` names a family of files."""
    out = []
    for path in REPO_PATH.findall(text):
        path = path.rstrip(".")
        if path.endswith("_"):
            parent = ROOT / Path(path).parent
            if not list(parent.glob(Path(path).name + "*")):
                out.append(path)
        elif not (ROOT / path).exists():
            out.append(path)
    for name in PROJECT_FILE.findall(text):
        if not ((ROOT / name).exists() or (DOCS / name).exists()):
            out.append(name)
    return out


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_link_and_path_of_a_page_exists(page):
    text = page.read_text(encoding="utf-8")
    dead = dead_links(page, text) + dead_paths(text)
    assert not dead, f"{page.relative_to(ROOT)} refers to missing files: {dead}"


def test_the_checker_finds_dead_references():
    page = DOCS / "index.md"
    text = ("see FORMULAS.md §1, [magnets](magnets.md), [gone](nowhere.md#x), "
            "`plugins/poissonkit_magnets/seed000.py`, `tests/magnets/test_magnets_`, "
            "[site](https://example.org/a.md), [api](api/index.md), LICENSE and CITATION.cff, "
            "reference/MAGNETS.md")
    assert dead_links(page, text) == ["nowhere.md#x"]
    assert dead_paths(text) == ["plugins/poissonkit_magnets/seed000.py", "FORMULAS.md",
                               "MAGNETS.md"]


def test_cite_section_matches_the_package_version():
    import tomllib

    version = tomllib.loads((ROOT / "pyproject.toml").read_text("utf-8"))["project"]["version"]
    text = (DOCS / "index.md").read_text(encoding="utf-8")
    assert "## Cite this" in text and "CITATION.cff" in text
    assert f"version = {{{version}}}" in text

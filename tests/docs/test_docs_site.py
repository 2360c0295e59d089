"""The documentation site builds in strict mode, and its API reference is ``poissonkit.__all__``.

``mkdocs build --strict`` turns every warning into a failure: a dead link or image, a nav entry
without a page, a numpydoc section mkdocstrings cannot parse, a public name without a docstring
(the build hook in ``docs/hooks/pages.py`` warns). The browser test opens the built pages in
headless Chromium (marked slow). Both need the ``docs`` extra (``pip install -e ".[docs]"``).
"""

from __future__ import annotations

import importlib.util
import logging
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import poissonkit

ROOT = Path(__file__).resolve().parents[2]

# The docs tools are part of the test extra: a missing one must fail here, not skip the build.
import material  # noqa: E402,F401
import mkdocs  # noqa: E402,F401
import mkdocstrings  # noqa: E402,F401


def _hook():
    spec = importlib.util.spec_from_file_location("poissonkit_docs_hook",
                                                  ROOT / "docs" / "hooks" / "pages.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _env() -> dict[str, str]:
    env = dict(os.environ)
    paths = [str(ROOT), str(ROOT / "plugins"), env.get("PYTHONPATH", "")]
    env["PYTHONPATH"] = os.pathsep.join(p for p in paths if p)
    env["NO_MKDOCS_2_WARNING"] = "1"
    return env


def build_site(dest: Path, execute: bool = False) -> subprocess.CompletedProcess:
    """``mkdocs build --strict`` of the project into ``dest``.

    ``execute=False`` renders the tutorial notebooks from their stored outputs (the notebook
    tests execute them); the user's build, and ``execute=True``, runs them afresh (with an
    empty notebook cache beside ``dest``, so that nothing is taken from an earlier build).
    """
    env = _env() | {"POISSONKIT_DOCS_EXECUTE": "true" if execute else "false",
                    "POISSONKIT_DOCS_CACHE_DIR": str(dest.parent / "notebook-cache")}
    # no -q: it raises mkdocs' log level, so strict mode no longer sees the warnings it counts
    return subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict",
                           "-f", str(ROOT / "mkdocs.yml"), "-d", str(dest)],
                          cwd=ROOT, env=env, capture_output=True, text=True,
                          timeout=1200 if execute else 300)


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    dest = tmp_path_factory.mktemp("site")
    done = build_site(dest)
    assert done.returncode == 0, done.stdout + done.stderr
    return dest


def _documented_roots(site: Path) -> set[str]:
    """Ids of the top-level objects rendered on the API pages (mkdocstrings' h2 headings)."""
    ids: set[str] = set()
    for page in (site / "api").glob("*/index.html"):
        ids |= set(re.findall(r'<h2 id="([^"]+)" class="doc doc-heading"',
                              page.read_text(encoding="utf-8")))
    return ids


def test_site_builds_strict_and_the_api_reference_is_exactly_the_public_list(site):
    api = _hook().public_api()
    assert set(api) == {n for n in poissonkit.__all__ if not n.startswith("__")}
    assert _documented_roots(site) == set(api.values())
    # the index page links every public name
    index = (site / "api" / "index.html").read_text(encoding="utf-8")
    for name in api:
        assert f"pk.{name}</code>" in index, name


def test_gallery_has_every_example_with_its_figures_and_the_changelog_is_included(site):
    for script in (ROOT / "examples").glob("*.py"):
        page = site / "gallery" / script.stem / "index.html"
        assert page.is_file(), script.name
    stability = (site / "gallery" / "seed000_stability" / "index.html").read_text()
    assert "img/seed000-stability.png" in stability
    assert (site / "img" / "seed000-stability.png").is_file()
    changelog = (site / "changelog" / "index.html").read_text(encoding="utf-8")
    assert "Keep a Changelog" in changelog and "Unreleased" in changelog


def test_every_public_name_has_a_numpydoc_docstring():
    for name in poissonkit.__all__:
        doc = (getattr(poissonkit, name).__doc__ or "").strip()
        assert doc, f"pk.{name} has no docstring"


def test_hook_warns_about_a_public_name_without_docstring(monkeypatch, caplog):
    hook = _hook()

    def undocumented():
        pass

    class Documented:
        """A class whose method lacks a docstring."""

        def method(self):
            pass

    monkeypatch.setattr(poissonkit, "undocumented", undocumented, raising=False)
    monkeypatch.setattr(poissonkit, "Documented", Documented, raising=False)
    monkeypatch.setattr(poissonkit, "__all__", [*poissonkit.__all__, "undocumented",
                                                "Documented"])
    with caplog.at_level(logging.WARNING, logger=hook.log.name):
        hook._check_docstrings(hook.public_api())
    assert "poissonkit.undocumented has no docstring" in caplog.text
    assert "poissonkit.Documented.method has no docstring" in caplog.text
    assert "poissonkit.solve" not in caplog.text and "Solution" not in caplog.text
    # strict mode counts warnings of loggers under "mkdocs."
    assert hook.log.name.startswith("mkdocs.")


def test_a_new_lazy_name_gets_a_reference_entry_without_further_edits(monkeypatch):
    hook = _hook()
    monkeypatch.setitem(poissonkit._LAZY, "default_scene", "poissonkit.plugin.registry")
    monkeypatch.setattr(poissonkit, "__all__", [*poissonkit.__all__, "default_scene"])
    sections = hook.api_sections()
    title, _intro, items = sections["registries"]
    assert ("default_scene", "poissonkit.plugin.registry.default_scene") in items


def test_readme_names_the_docs_build_command():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert 'pip install -e ".[docs]"' in readme and "mkdocs build --strict" in readme


CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser") \
    or shutil.which("google-chrome")


def _dump_dom(url: str, profile: Path) -> str:
    done = subprocess.run(
        [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--no-first-run", f"--user-data-dir={profile}", "--virtual-time-budget=5000",
         "--dump-dom", url],
        capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout


@pytest.mark.slow
@pytest.mark.skipif(CHROMIUM is None, reason="needs chromium (apt-get install chromium)")
@pytest.mark.parametrize("page,title,needle", [
    ("index.html", "poissonkit", "poissonkit documentation"),
    ("api/numerics/index.html", "Numerics", "poissonkit.numerics.solver.solve"),
    ("gallery/seed000_stability/index.html", "seed000_stability", "seed000-stability.png"),
])
def test_built_pages_render_in_a_browser(site, tmp_path, page, title, needle):
    dom = _dump_dom((site / page).as_uri(), tmp_path / "profile")
    head = re.search(r"<title>(.*?)</title>", dom, re.S)
    assert head and title in head.group(1), head
    # the theme's script ran (it rewrites the root element's classes) and the content is there
    assert 'data-md-color-scheme' in dom or "md-header" in dom
    assert needle in dom
    body = re.sub(r"<script.*?</script>", "", dom, flags=re.S)
    for bad in ("Traceback", "404 - Not found", "Could not collect", "ERROR"):
        assert bad not in body, bad


@pytest.mark.slow
def test_the_users_docs_build_executes_the_notebooks(tmp_path):
    """Without the test's switch the build executes every notebook in a fresh kernel."""
    mkyml = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    assert "execute: !ENV [POISSONKIT_DOCS_EXECUTE, true]" in mkyml
    done = build_site(tmp_path / "site", execute=True)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "Cache hit" not in done.stdout + done.stderr
    for name in ("brackets", "magnets", "planets"):
        page = (tmp_path / "site" / "notebooks" / name / "index.html").read_text(encoding="utf-8")
        assert "Traceback" not in page, name
    assert "Casimirs up to degree 2" in (tmp_path / "site" / "notebooks" / "brackets"
                                         / "index.html").read_text(encoding="utf-8")

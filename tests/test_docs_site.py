"""The documentation site: it builds with no warning, its internal links resolve, its API page of
``WakeFilter`` says what ``help(WakeFilter)`` says, a headless browser renders its home page and that API
page (title, navigation, a figure), the reference pages state each figure once and the study pages keep
their dates.

The build needs the ``docs`` extra (``pip install ".[docs]"``) and the browser Debian's ``chromium``; without
them these tests skip, saying which is missing, except in CI (``CI=true``), where they must run and fail
instead.  ``WAKE_DOCS_HTML`` names a site already built with ``-W`` (CI builds it once, a step before pytest);
otherwise the tests build one.
"""

from __future__ import annotations

import html
import importlib.util
import inspect
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
IN_CI = os.environ.get("CI") == "true"
BUILD = f"{sys.executable} -m sphinx -W --keep-going -b html docs docs/_build/html"


def _need(ok: bool, reason: str):
    """Skip with ``reason`` unless in CI, where a missing tool is a failure."""
    if not ok:
        if IN_CI:
            pytest.fail(f"{reason} (CI=true: this check must run, and .ci/run installs what it needs)")
        pytest.skip(reason)


def _load_script(name: str):
    spec = importlib.util.spec_from_file_location(f"docs_{name}", DOCS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The built HTML site: ``$WAKE_DOCS_HTML``, or a fresh ``-W`` build of docs/."""
    prebuilt = os.environ.get("WAKE_DOCS_HTML")
    if prebuilt:
        assert (Path(prebuilt) / "index.html").is_file(), f"WAKE_DOCS_HTML={prebuilt} holds no built site"
        return Path(prebuilt)
    missing = [m for m in ("sphinx", "numpydoc", "myst_parser", "pydata_sphinx_theme")
               if importlib.util.find_spec(m) is None]
    _need(not missing, f"the docs extra is not installed ({', '.join(missing)} missing): pip install '.[docs]'")
    out = tmp_path_factory.mktemp("docs") / "html"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    proc = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
                           str(DOCS), str(out)], capture_output=True, text=True, timeout=1200, env=env, cwd=ROOT)
    assert proc.returncode == 0, f"`{BUILD}` failed:\n{proc.stderr[-4000:]}"
    assert "WARNING" not in proc.stderr, proc.stderr[-4000:]
    return out


def _text(page: str) -> str:
    """The words of an HTML page's article, markup and white space folded."""
    article = re.search(r"<article.*?</article>", page, re.S)
    body = re.sub(r"<(script|style)\b.*?</\1>", " ", article.group(0) if article else page, flags=re.S)
    return " ".join(html.unescape(re.sub(r"<[^>]+>", " ", body)).split())


def _words(text: str) -> str:
    """Plain words of reST or rendered text: roles, backticks, emphasis and punctuation spacing dropped."""
    text = re.sub(r":\w+:`~[\w.]*?(\w+)`", r"\1", text)          # :class:`~a.b.C` shows C
    text = re.sub(r":\w+:`([^`<]+?)\s*<[^>]+>`", r"\1", text)     # :ref:`title <target>` shows title
    text = re.sub(r":\w+:`([^`]+)`", r"\1", text)
    text = re.sub(r"[`*\\]", "", text)
    text = re.sub(r"(\w)\(\)", r"\1", text)                          # Sphinx writes :func: targets as f()
    text = re.sub(r"[“”\"'’]", "'", text)
    text = re.sub(r"\s*([()\[\],;:.!?=+-])\s*", r"\1", text)
    return " ".join(text.split())


# --- the build and its links -------------------------------------------------------------------------


def test_the_site_builds_and_every_page_is_there(site):
    for page in ("index.html", "getting-started.html", "api/generated/wake.WakeFilter.html",
                 "reference/design.html", "studies/design.html", "studies/dates.html", "changelog.html",
                 *(f"guide/{task}.html" for task in ("filter", "stream", "firmware", "evaluate", "report"))):
        assert (site / page).is_file(), f"the built site has no {page}"


def test_internal_links_and_anchors_resolve(site):
    broken = _load_script("check_links").broken_links(site)
    assert not broken, "broken internal links:\n" + "\n".join(broken[:40])


def test_the_link_check_finds_a_broken_page_and_a_broken_anchor(tmp_path):
    check = _load_script("check_links")
    (tmp_path / "a.html").write_text('<a href="b.html#here">ok</a><a href="b.html#gone">x</a>'
                                     '<a href="c.html">y</a><img src="f.png"><a href="https://x.org/">z</a>')
    (tmp_path / "b.html").write_text('<h2 id="here">h</h2>')
    assert check.broken_links(tmp_path) == ["a.html: b.html#gone (no anchor #gone)",
                                            "a.html: c.html (no such file)", "a.html: f.png (no such file)"]


def test_the_api_page_says_what_help_says(site):
    """``help(WakeFilter)`` and the API page come from one docstring: every section of it is on the page."""
    from numpydoc.docscrape import ClassDoc

    from wake import WakeFilter

    page = _words(_text((site / "api/generated/wake.WakeFilter.html").read_text(encoding="utf-8")))
    doc = ClassDoc(WakeFilter, config={"show_class_members": False})
    # help() prints the same docstring that the page renders
    assert _words(inspect.getdoc(WakeFilter)) in _words(re.sub(r"^ \|  ?", "", pydoc_text(WakeFilter), flags=re.M))
    checked = 0
    for paragraph in [*doc["Summary"], *" ".join(doc["Extended Summary"]).split("\n\n")]:
        if paragraph.strip():
            assert _words(paragraph) in page, f"the API page lacks: {paragraph[:80]}"
            checked += 1
    for section in ("Parameters", "Attributes", "Raises", "Warns"):
        for item in doc[section]:
            assert item.name.split(",")[0].strip() in page, f"the API page lacks {section}: {item.name}"
            for line in item.desc:
                if line.strip():
                    assert _words(line) in page, f"the API page's {item.name} lacks: {line}"
                    checked += 1
    assert checked > 40, f"only {checked} lines compared: the docstring was not parsed"


def pydoc_text(obj) -> str:
    import pydoc

    return pydoc.render_doc(obj, renderer=pydoc.plaintext)


def _python_examples():
    """``(page, block)`` for every Python block of the documentation's own pages."""
    pages = sorted(DOCS.glob("*.md")) + sorted(DOCS.glob("*/*.md"))
    return [(path.relative_to(DOCS).as_posix(), block) for path in pages
            for block in re.findall(r"```python\n(.*?)```", path.read_text(encoding="utf-8"), re.S)]


def test_the_guides_have_python_examples():
    assert {page for page, _ in _python_examples()} >= {"index.md", "getting-started.md", "guide/filter.md",
                                                         "guide/stream.md", "guide/evaluate.md", "guide/report.md"}


@pytest.mark.parametrize("page, block", _python_examples(), ids=lambda v: v if v.endswith(".md") else "")
def test_python_examples_of_the_pages_parse(page, block):
    import ast

    ast.parse(block, filename=page)


# --- the reference and the studies ------------------------------------------------------------------

#: A figure: a number with a decimal point, a thousands separator or three digits and more, or a
#: percentage; dates, version numbers and code spans are not figures.
FIGURE = re.compile(r"(?<![\w.,/-])(\d{1,3}(?:,\d{3})+|\d+\.\d+|\d{3,}|\d+(?:\.\d+)?\s?%)(?![\w.]*\d)")


def reference_figures() -> dict:
    """``{figure: [page, ...]}`` over the prose and tables of docs/reference/*.md."""
    found = {}
    for path in sorted((DOCS / "reference").glob("*.md")):
        text = re.sub(r"```.*?```", "", path.read_text(encoding="utf-8"), flags=re.S)
        text = re.sub(r"`[^`]*`|\]\([^)]*\)|<!--.*?-->|https?://\S+|\b\d{4}-\d{2}-\d{2}\b", "", text)
        for m in FIGURE.finditer(text):
            found.setdefault(m.group(1).replace(" ", ""), []).append(path.name)
    return found


def test_no_figure_is_stated_twice_in_the_reference():
    twice = {fig: pages for fig, pages in reference_figures().items() if len(pages) > 1}
    assert not twice, ("figures stated in two places of docs/reference/ (state each once, and point to it): "
                       f"{twice}")


def test_the_figure_scan_sees_figures():
    scan = FIGURE.findall("0.0688 and 1,969 instructions, 33 % of 2 windows in 0.3.0")
    assert scan == ["0.0688", "1,969", "33 %"]


def test_every_study_section_is_dated():
    """docs/studies/dates.md names every section of every study page (rerun `python docs/study_dates.py`)."""
    dates = (DOCS / "studies" / "dates.md").read_text(encoding="utf-8")
    for path in sorted((DOCS / "studies").glob("*.md")):
        if path.name in ("dates.md", "index.md"):
            continue
        text = re.sub(r"```.*?```", "", path.read_text(encoding="utf-8"), flags=re.S)
        for heading in re.findall(r"^#{2,3} (.+)$", text, re.M):
            row = re.search(rf"\[{re.escape(heading.strip().replace('|', '/'))}\]\({path.name}#[^)]*\) "
                            r"\| (\d{4}-\d{2}-\d{2}) \| (\d{4}-\d{2}-\d{2}) \|", dates)
            assert row, (f"docs/studies/dates.md does not date {path.name}, {heading!r}: "
                         "run python docs/study_dates.py")
            assert row[1] <= row[2]


# --- in a browser ------------------------------------------------------------------------------------


def _chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return shutil.which(name)
    return None


def _browse(page: Path, tmp_path: Path, *flags) -> subprocess.CompletedProcess:
    browser = _chromium()
    _need(browser is not None, "no chromium to open the built pages with: apt-get install chromium")
    cmd = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--no-first-run",
           f"--user-data-dir={tmp_path / 'profile'}", "--window-size=1280,1600", "--virtual-time-budget=5000",
           *flags, page.resolve().as_uri()]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=180)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return proc


def _screenshot(page: Path, tmp_path: Path, name: str, *flags) -> np.ndarray:
    from PIL import Image

    out = tmp_path / f"{name}.png"
    _browse(page, tmp_path, f"--screenshot={out}", *flags)
    return np.asarray(Image.open(out).convert("L"), dtype=float)


def _rendered(pixels: np.ndarray):
    """A screenshot with text and drawing on it: not one colour, and ink on a good share of it."""
    assert pixels.shape == (1600, 1280)
    assert pixels.std() > 20, "the screenshot is blank"
    assert (pixels < 200).mean() > 0.02, "the screenshot has almost nothing drawn on it"


def _dom(page: Path, tmp_path: Path) -> str:
    return _browse(page, tmp_path, "--dump-dom").stdout


def _navigation(dom: str):
    nav = re.search(r'<ul class="[^"]*\bnavbar-nav\b[^"]*">.*?</ul>', dom, re.S)
    assert nav, "no navigation bar in the rendered page"
    for entry in ("Getting started", "User guide", "API reference", "Reference", "Studies"):
        assert re.search(rf"<a [^>]*href=\"[^\"]+\"[^>]*>\s*{entry}\s*</a>", nav.group(0)), f"no {entry} in the navigation"


def test_the_home_page_renders_in_a_browser(site, tmp_path):
    from wake import __version__

    page = site / "index.html"
    dom = _dom(page, tmp_path)
    assert re.search(rf"<title>wake: real-time pathological tremor extraction .* wake {re.escape(__version__)}"
                     r"</title>", dom)
    _navigation(dom)
    figure = re.search(r'<figure[^>]*>\s*(?:<a [^>]*>)?<img [^>]*src="([^"]+)"', dom)
    assert figure, "no figure on the home page"
    from PIL import Image

    with Image.open(page.parent / figure[1]) as image:
        assert image.size[0] > 400 and image.size[1] > 300
    shot = _screenshot(page, tmp_path, "home")
    _rendered(shot)
    # the figure is drawn: the page looks different with images off, over a large area
    without = _screenshot(page, tmp_path, "home-no-images", "--blink-settings=imagesEnabled=false")
    assert (np.abs(shot - without) > 30).mean() > 0.03, "the home page's figure did not render"


def test_the_wakefilter_api_page_renders_in_a_browser(site, tmp_path):
    page = site / "api/generated/wake.WakeFilter.html"
    dom = _dom(page, tmp_path)
    assert re.search(r"<title>wake\.WakeFilter .*</title>", dom)
    _navigation(dom)
    assert re.search(r'<dt class="sig sig-object py" id="wake.WakeFilter">', dom), "no signature of WakeFilter"
    assert re.search(r"<dt[^>]*>\s*<strong>fs</strong>", dom), "no parameter list"
    assert 'class="bd-sidebar-primary' in dom, "no sidebar navigation"
    _rendered(_screenshot(page, tmp_path, "wakefilter"))

"""The documentation site (docs/): every public name documented, and the built pages show real content.

The site is the one ``.ci/run`` builds into ``docs/_build/html`` (README "Documentation"); where that is
missing or older than any of its sources, the tests build it themselves, with the same command, into a
temporary folder (about a minute on 2 cores: every gallery page is executed).  The browser tests open the
built pages in headless Chromium (found as tests/test_browser.py finds it; skipped without it): the DOM
after the page's scripts ran (``--dump-dom``) and a screenshot.
"""

import html
import inspect
import re
import subprocess
import sys
from pathlib import Path

import matplotlib.image
import numpy as np
import pytest
from sphinx.pycode import ModuleAnalyzer
from test_browser import CHROMIUM

import ngdgfric
from ngdgfric.examples import SCENES

ROOT = Path(__file__).resolve().parent.parent
BUILT = ROOT / "docs" / "_build" / "html"
SOURCES = [ROOT / "README.md", *(ROOT / "docs").glob("*.md"), *(ROOT / "docs").glob("[!_]*/**/*.md"),
           ROOT / "docs" / "conf.py",
           *(ROOT / "ngdgfric").rglob("*.py"), *(ROOT / "ngdgfric" / "data").glob("*.toml"),
           *(ROOT / "notebooks").glob("*.ipynb"), *(ROOT / "results").glob("*.md")]
WIDTH = 1200
needs_chromium = pytest.mark.skipif(CHROMIUM is None, reason="no chromium binary (Debian: apt-get install chromium)")


def docstring(name):
    """The docstring of ``ngdgfric.<name>``: its own ``__doc__`` for functions and classes (not the text a
    dataclass makes up from the signature), for data the string after its assignment in the module that
    defines it (what the API page shows, docs/conf.py)."""
    obj = getattr(ngdgfric, name)
    if inspect.isclass(obj) or callable(obj):
        doc = obj.__dict__.get("__doc__") if inspect.isclass(obj) else obj.__doc__
        return None if doc is None or doc.startswith(f"{name}(") else doc
    for module in sorted(m for m in sys.modules if m == "ngdgfric" or m.startswith("ngdgfric.")):
        if getattr(sys.modules[module], name, None) is obj and getattr(sys.modules[module], "__file__", None):
            doc = ModuleAnalyzer.for_module(module).find_attr_docs().get(("", name))
            if doc:
                return "\n".join(doc)
    return None


def words(text, count=None):
    """The words of ``text`` with markup, roles, quotes and punctuation dropped, for comparing a docstring
    (reStructuredText) with the text of its page."""
    text = html.unescape(text)
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)  # Markdown links: their text
    text = re.sub(r":[a-z]+:`~[^`]*?([^`.]*)`", r"\1", text)  # reStructuredText roles: ~a.b shows b
    text = re.sub(r":[a-z]+:`([^`]*)`", r"\1", text)
    text = re.sub(r"[`*\\|'\"\u2018\u2019\u201c\u201d]", " ", text)
    found = re.findall(r"[A-Za-z0-9][A-Za-z0-9_.^=+-]*", text)
    return found[:count] if count else found


def page_text(page):
    """The text of an HTML page: tags dropped, entities decoded."""
    return html.unescape(re.sub(r"<[^>]+>", " ", page))


def contains(haystack, needle):
    """Whether the words ``needle`` occur in this order, adjacent, in the words ``haystack``."""
    return " " + " ".join(needle) + " " in " " + " ".join(haystack) + " "


def newest_source():
    return max(path.stat().st_mtime for path in SOURCES if path.exists())


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The folder of the built site: docs/_build/html if it is newer than every source, else built now."""
    index = BUILT / "index.html"
    if index.exists() and index.stat().st_mtime > newest_source():
        return BUILT
    out = tmp_path_factory.mktemp("docs") / "html"
    result = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
                             str(ROOT / "docs"), str(out)], cwd=ROOT, capture_output=True, text=True, timeout=1200)
    assert result.returncode == 0, f"the documentation build failed:\n{result.stderr[-5000:]}"
    return out


def test_every_public_name_has_a_docstring():
    missing = [name for name in ngdgfric.__all__ if not (docstring(name) or "").strip()]
    assert not missing, f"public names without a docstring: {missing}"


@pytest.mark.slow
def test_api_pages_document_every_public_name(site):
    """Each name of ``ngdgfric.__all__`` has its entry (anchor ``ngdgfric.<name>``) on the API page, and the
    first words of its docstring are shown there."""
    page = (site / "api" / "index.html").read_text()
    for name in ngdgfric.__all__:
        anchor = page.find(f'id="ngdgfric.{name}"')
        assert anchor >= 0, f"ngdgfric.{name} is not on the API page"
        first = words(docstring(name), 8)
        shown = words(page_text(page[anchor:anchor + 20000]))
        assert contains(shown, first), f"the docstring of ngdgfric.{name} is not shown: {' '.join(first)}"
    subpackages = {"dg": ngdgfric.dg, "solvers": ngdgfric.solvers}
    for name, module in subpackages.items():
        text = words(page_text((site / "api" / f"{name}.html").read_text()))
        assert contains(text, words(module.__doc__, 10)), f"the docstring of ngdgfric.{name} is not on its page"


@pytest.mark.slow
def test_gallery_has_every_scene_and_notebook(site):
    """One executed page per shipped scene and per notebook: each has at least one figure."""
    pages = {f"gallery/{name}.html" for name in (*SCENES, "example_6_1", "example_6_2")}
    pages |= {f"gallery/notebooks/{path.stem}.html" for path in (ROOT / "notebooks").glob("*.ipynb")}
    for page in sorted(pages):
        text = (site / page).read_text()
        figures = re.findall(r'<img[^>]+src="([^"]+\.png)"', text)
        assert figures, f"{page}: no figure"
        assert "Traceback" not in page_text(text), f"{page}: an error was shown"


def chromium(site, page, tmp_path, height=2400, screenshot=True):
    """Open ``site/page`` in headless Chromium: (DOM after the scripts ran, RGB screenshot or None)."""
    flags = [CHROMIUM, "--headless", "--disable-gpu", "--no-sandbox", f"--user-data-dir={tmp_path / 'profile'}",
             "--no-first-run", "--host-resolver-rules=MAP * ~NOTFOUND", f"--window-size={WIDTH},{height}",
             "--virtual-time-budget=5000"]
    url = (site / page).as_uri()
    dom = subprocess.run([*flags, "--dump-dom", url], capture_output=True, text=True, timeout=300)
    assert dom.returncode == 0 and "</html>" in dom.stdout, f"{page}: no DOM ({dom.stderr[-2000:]})"
    rgb = None
    if screenshot:
        path = tmp_path / (page.replace("/", "_") + ".png")
        shot = subprocess.run([*flags, f"--screenshot={path}", url], capture_output=True, text=True, timeout=300)
        assert path.exists(), f"{page}: no screenshot (exit {shot.returncode}): {shot.stderr[-2000:]}"
        rgb = matplotlib.image.imread(path)[..., :3]
    return dom.stdout, rgb


def coloured(rgb):
    """Pixels with a saturated colour (figures' colour maps and lines; text and the theme are grey)."""
    return int(np.count_nonzero(rgb.max(axis=2) - rgb.min(axis=2) > 0.3))


def non_white(rgb):
    return int(np.count_nonzero(rgb.min(axis=2) < 0.9))


def readme_section(marker):
    """The text of README.md between ``<!-- docs:marker -->`` and ``<!-- /docs:marker -->``."""
    text = (ROOT / "README.md").read_text()
    return text.split(f"<!-- docs:{marker} -->")[1].split(f"<!-- /docs:{marker} -->")[0]


@pytest.mark.slow
@pytest.mark.browser
@needs_chromium
def test_pages_in_a_browser(site, tmp_path):
    # the start page: its sections and the README's "What it does"
    dom, rgb = chromium(site, "index.html", tmp_path)
    for link in ("getting_started.html", "user_guide/index.html", "api/index.html", "gallery/index.html",
                 "results/index.html"):
        assert f'href="{link}' in dom, f"index: no link to {link}"
    assert contains(words(page_text(dom)), words(readme_section("what-it-does"), 12))
    assert non_white(rgb) > 20_000, "index: the screenshot is nearly blank"
    # a user-guide page: the README section it includes
    dom, _ = chromium(site, "user_guide/methods.html", tmp_path, screenshot=False)
    assert contains(words(page_text(dom)), words(readme_section("dg-method"), 12)), "methods: README text missing"
    # the API page: the docstring of ngdgfric.solve, as a documented function with its signature
    dom, rgb = chromium(site, "api/index.html", tmp_path)
    assert 'id="ngdgfric.solve"' in dom
    assert contains(words(page_text(dom)), words(ngdgfric.solve.__doc__, 15)), "api: solve's docstring missing"
    assert non_white(rgb) > 20_000, "api: the screenshot is nearly blank"


@pytest.mark.slow
@pytest.mark.browser
@needs_chromium
def test_gallery_and_results_figures_in_a_browser(site, tmp_path):
    # a gallery page: the executed notebook's figure (the deformed body coloured by the von Mises stress)
    dom, rgb = chromium(site, "gallery/half_disk.html", tmp_path, height=2400)
    images = re.findall(r'<img[^>]+src="([^"]+\.png)"', dom)
    assert images, "gallery: no figure"
    figure = matplotlib.image.imread(site / "gallery" / images[0])[..., :3]
    assert figure.shape[0] > 200 and figure.shape[1] > 200
    assert coloured(figure) > 20_000, f"gallery: the figure {images[0]} is blank"
    # text pages have some 25 000 coloured pixels (links, highlighted code), this one some 80 000
    assert coloured(rgb) > 45_000, "gallery: the figure is not on screen"
    # a results page: the PNG files of results/ as they are in the repository
    dom, rgb = chromium(site, "results/hp.html", tmp_path, height=2400)
    images = re.findall(r'<img[^>]+src="([^"]+\.png)"', dom)
    assert len(images) >= 4, "results/hp: figures missing"
    for image in images:
        shown = (site / "results" / image).resolve()
        assert shown.read_bytes() == (ROOT / "results" / Path(image).name).read_bytes()
    assert coloured(rgb) > 100_000, "results/hp: the figures are not on screen"  # some 230 000

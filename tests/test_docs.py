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
    result = subprocess.run([sys.executable, "-m", "sphinx", "-n", "-W", "--keep-going", "-q", "-b", "html",
                             str(ROOT / "docs"), str(out)], cwd=ROOT, capture_output=True, text=True, timeout=1200)
    assert result.returncode == 0, f"the documentation build failed:\n{result.stderr[-5000:]}"
    return out


def test_every_public_name_has_a_docstring():
    missing = [name for name in ngdgfric.__all__ if not (docstring(name) or "").strip()]
    assert not missing, f"public names without a docstring: {missing}"


@pytest.mark.slow
def test_api_pages_document_every_public_name(site):
    """Each name of ``ngdgfric.__all__`` has its entry (anchor ``ngdgfric.<name>``) on one of the API pages
    (api/*.html: the topic pages), and the first words of its docstring are shown there; the pages of the
    subpackages show their module docstrings."""
    pages = {path.name: path.read_text() for path in sorted((site / "api").glob("*.html"))}
    for name in ngdgfric.__all__:
        found = [(page, text.find(f'id="ngdgfric.{name}"')) for page, text in pages.items()]
        found = [(page, anchor) for page, anchor in found if anchor >= 0]
        assert found, f"ngdgfric.{name} is not on any API page"
        page, anchor = found[0]
        first = words(docstring(name), 8)
        shown = words(page_text(pages[page][anchor:anchor + 20000]))
        assert contains(shown, first), f"the docstring of ngdgfric.{name} is not shown on {page}: {' '.join(first)}"
    import importlib  # ngdgfric.studies is not imported by ``import ngdgfric``

    for name in ("dg", "solvers", "studies"):
        module = importlib.import_module(f"ngdgfric.{name}")
        text = words(page_text((site / "api" / f"{name}.html").read_text()))
        assert contains(text, words(module.__doc__, 10)), f"the docstring of ngdgfric.{name} is not on its page"


@pytest.mark.slow
def test_the_adapt_entry_names_every_argument_a_user_passes_with_its_default(site):
    """The rendered entry of ``ngdgfric.adapt``: its signature shows each argument a user passes with the default
    the function has (numbers as a user writes them), and its Parameters list has an item for each of them."""
    page = (site / "api" / "estimators.html").read_text()
    start = page.find('id="ngdgfric.adapt"')
    entry = page[start:page.find('<dl class="py', start)]  # up to the next entry
    signature = re.sub(r"\s+", "", page_text(entry[:entry.find("</dt>")]))
    parameters = inspect.signature(ngdgfric.adapt).parameters
    shown = {"tol": "None", "rtol": "None", "theta": "0.8", "max_levels": "100", "max_ndof": "10**6", "method": "None",
             "order": "4", "estimator": "'residual'", "max_bytes": "8e9", "hp": "True"}
    for name, default in shown.items():
        assert re.search(rf"\b{name}={re.escape(default)}[,)]", signature), f"{name}={default} not in {signature}"
        assert eval(default.replace("'", '"')) == parameters[name].default  # the page shows the real default
        assert re.search(rf"<strong>{name}</strong>", entry), f"{name} has no item in adapt's Parameters"
    described = page_text(entry)
    assert re.search(r"DEFAULT_RTOL\s*=\s*1e-3", described) and re.search(r"rtol=0\s*:\s*no accuracy target", described)


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


def entry(dom, name):
    """The HTML of the API entry ``ngdgfric.<name>``: its ``<dt>`` and ``<dd>``, up to the next entry at its level."""
    start = dom.find(f'id="ngdgfric.{name}"')
    assert start >= 0, f"ngdgfric.{name}: no entry"
    start = dom.rfind("<dl", 0, start)
    depth, k = 0, start
    for tag in re.finditer(r"<(/?)dl\b", dom[start:]):
        depth += -1 if tag.group(1) else 1
        if depth == 0:
            k = start + tag.end()
            break
    return dom[start:k]


def formulas(dom):
    """How many formulas MathJax rendered in ``dom`` (its CHTML output elements)."""
    return dom.count("<mjx-container")


def raw_tex(dom):
    """TeX that was not rendered: MathJax's delimiters left in the page's text, and MathJax's error boxes (TeX it
    could not typeset, e.g. a ``\\tag`` in a ``split``)."""
    text = page_text(re.sub(r"<(script|style)\b.*?</\1>", " ", dom, flags=re.S))
    errors = [f"MathJax error: {page_text(m)}" for m in re.findall(r"<mjx-merror.*?</mjx-merror>", dom, flags=re.S)]
    return re.findall(r"\\\(|\\\)|\\\[|\\\]|\$\$", text) + errors


@pytest.mark.slow
@pytest.mark.browser
@needs_chromium
def test_landing_methods_and_adapt_render_offline(site, tmp_path):
    """The issue's three pages in headless Chromium with every host name unresolvable: the landing page shows its
    picture (a deformed scene and its contact pressure, drawn while the site was built), the methods page and
    the entry of ``adapt`` show formulas that MathJax rendered from the site's own copy (no raw TeX left), and
    the entry's Parameters section names every argument of ``adapt``."""
    dom, rgb = chromium(site, "index.html", tmp_path)
    images = re.findall(r'<img[^>]+src="([^"]+\.png)"', dom)
    assert images, "index: no picture"
    picture = matplotlib.image.imread(site / images[0])[..., :3]
    assert coloured(picture) > 20_000, f"index: the picture {images[0]} is nearly blank"
    # measured: 29 400 with the picture; the text pages testing, paper and methods 1 900, 8 700, 5 600
    assert coloured(rgb) > 15_000, "index: the picture is not on screen"
    for link in ("getting_started.html", "user_guide/methods.html", "api/index.html", "gallery/index.html",
                 "results/index.html"):
        assert f'href="{link}' in dom, f"index: no link to {link}"

    dom, rgb = chromium(site, "user_guide/methods.html", tmp_path)
    scripts = re.findall(r'<script[^>]+src="([^"]*mathjax[^"]*)"', dom)  # tex-chtml.js and the extensions it loads
    assert "../_static/mathjax/tex-chtml.js" in scripts and not [s for s in scripts if s.startswith("http")], \
        f"methods: MathJax is not loaded from the site's own copy: {scripts}"
    assert formulas(dom) >= 20, f"methods: {formulas(dom)} rendered formulas"
    assert not raw_tex(dom), f"methods: raw TeX left: {raw_tex(dom)[:5]}"
    assert non_white(rgb) > 20_000, "methods: the screenshot is nearly blank"
    for name in ("sipg", "nipg", "bassi", "brezzi", "ldg", "cg"):
        assert re.search(rf"<td[^>]*>.*?\b{name}\b", dom, flags=re.S | re.I), f"methods: {name} not in a table"

    page = next(path for path in sorted((site / "api").glob("*.html")) if 'id="ngdgfric.adapt"' in path.read_text())
    dom, _ = chromium(site, f"api/{page.name}", tmp_path, screenshot=False)
    adapt = entry(dom, "adapt")
    assert formulas(adapt) >= 3, "adapt: its formulas were not rendered"
    assert not raw_tex(adapt), f"adapt: raw TeX left: {raw_tex(adapt)[:5]}"
    parameters = page_text(adapt.split(">Parameters<", 1)[1].split(">Returns<", 1)[0])
    for name, parameter in inspect.signature(ngdgfric.adapt).parameters.items():
        shown = "**" + name if parameter.kind is inspect.Parameter.VAR_KEYWORD else name
        assert re.search(rf"(^|\s){re.escape(shown)}\s*\(", parameters) or re.search(
            rf"(^|\s){re.escape(shown)}\s*[–—-]", parameters), f"adapt: Parameters does not name {shown}"


@pytest.mark.slow
@pytest.mark.browser
@needs_chromium
def test_every_formula_on_the_site_renders(site, tmp_path):
    """Every page that loads MathJax, opened offline: no TeX left raw and no MathJax error box."""
    pages = sorted(path for path in site.rglob("*.html") if "mathjax/tex-chtml.js" in path.read_text()
                   and "_static" not in path.parts)
    assert len(pages) >= 20, f"only {len(pages)} pages with formulas"
    failed = {}
    for path in pages:
        dom, _ = chromium(site, str(path.relative_to(site)), tmp_path, screenshot=False)
        if raw_tex(dom) or not formulas(dom):
            failed[str(path.relative_to(site))] = raw_tex(dom)[:3] or "no formula rendered"
    assert not failed, f"formulas not rendered: {failed}"


USER_PAGES = ["index.html", "getting_started.html", "paper.html", "testing.html", "decisions.html", "user_guide/*.html",
              "gallery/*.html", "gallery/notebooks/*.html", "api/*.html"]
# a file that is a page of the site: name its page with a link, not its path
SITE_FILES = re.compile(r"\b(results/[\w.-]+\.md|notebooks/[\w.-]+\.ipynb|ngdgfric/[\w/.-]+\.(py|toml))\b")


@pytest.mark.slow
def test_no_page_names_an_issue_or_a_path_where_a_link_would_do(site):
    found = []
    for pattern in USER_PAGES:
        for path in sorted(site.glob(pattern)):
            html_text = re.sub(r"<(script|style)\b.*?</\1>", " ", path.read_text(), flags=re.S)
            literal_listing = re.sub(r'<div class="highlight-toml.*?</div>\s*</div>', " ", html_text, flags=re.S)
            text = page_text(literal_listing)
            found += [f"{path.relative_to(site)}: {m.group(0)!r}" for m in re.finditer(r"\bissues? \d+", text, re.I)]
            found += [f"{path.relative_to(site)}: {m.group(0)!r}" for m in SITE_FILES.finditer(text)]
    for path in sorted(site.glob("results/*.html")):
        text = page_text(path.read_text())
        found += [f"{path.relative_to(site)}: {m.group(0)!r}" for m in re.finditer(r"\bissues? \d+", text, re.I)]
    assert not found, "pages naming an issue or a file path:\n" + "\n".join(found[:40])


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

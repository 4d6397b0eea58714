"""Every page of the documentation site renders: its formulas typeset, no markup left as text, no number split.

Each HTML page of the built site (the ``site`` fixture of tests/test_docs.py) is opened in headless Chromium, offline
(every host name unresolvable), at the width of tests/test_docs.py, after a small probe script was added to a copy of
the page.  The probe waits until MathJax has typeset the page (``MathJax.startup.promise``) and its fonts are loaded,
then reads the page as the browser laid it out and writes what it found into the DOM, which ``--dump-dom`` returns:

* formulas: every ``math`` element of the page (Sphinx's and MyST's ``span.math``, ``div.math``) holds a MathJax
  output element (``mjx-container``), and there is no MathJax error (``mjx-merror``, "Math Processing Error");
* the text outside formulas, split into prose and code (``pre``, ``code``): the prose must show no TeX (a
  backslash command such as ``\\eta``, ``\\frac``, ``$...$``, ``\\(``, ``_{``), the prose and the code no role or
  MyST role left as text (``:func:`x```, ``{class}`x```), the prose no run of ``*`` used as emphasis markers
  (``*word*``, ``**``; a parameter ``**kwargs`` of the API's Parameters is code, not prose);
* tables: no number in a cell (``-1.5e-03``, ``0.38``, ``12 345``, ``2^-1``) is laid out over two lines, and no
  formula in a cell either: a Range over the number's characters (a formula's box) must have all its boxes on
  one line;
* widths: no display formula wider than its line, no paragraph, list item, table or figure reaching past the
  page's white column, no code or output line running out of its grey box unless the box scrolls or wraps it;
* one equation number per formula (not Sphinx's "(1)" next to a ``\tag{1.9}``);
* links: code in a link (the API's cross-references) has the link's colour and is not bold.

``test_the_probe_finds_planted_defects`` plants one defect of each kind into a clean page and asserts that each is
found.  The results pages (results/*.md, written by the scripts) have a test of their own.

The probe checks what the browser shows, not the HTML source, so a rule of CSS that wraps a cell inside its numbers,
or a formula MathJax could not typeset, fails here although the HTML looks right.
"""

import html
import json
import re
import shutil
import subprocess
from concurrent.futures import ThreadPoolExecutor

import pytest
from test_browser import CHROMIUM
from test_docs import WIDTH, site  # noqa: F401 (site: the fixture)

needs_chromium = pytest.mark.skipif(CHROMIUM is None, reason="no chromium binary (Debian: apt-get install chromium)")

PROBE_ID = "ngdgfric-render-probe"
PROBE = r"""
(function () {
  function closest(node, selector) {
    var element = node.nodeType === 1 ? node : node.parentElement;
    return element ? element.closest(selector) : null;
  }
  function report(result) {
    var out = document.createElement("pre");
    out.id = "%(id)s";
    out.hidden = true;
    out.textContent = JSON.stringify(result);
    document.body.appendChild(out);
  }
  // a number as a reader reads it: sign, digits, decimals, exponent, powers (2^-1), thousands in groups of three
  // (a sign only where no word precedes it: 0.70-1.47 is two numbers)
  var NUMBER = new RegExp("(?<![\\w.])(?:[-+\u2212](?=\\d))?(?:\\d{1,3}(?:[ \u00a0\u2009\u202f]\\d{3})+(?![\\d.])" +
                          "|\\d+(?:[.,]\\d+)*(?:[eE][-+\u2212]?\\d+)?(?:\\^[-+\u2212]?\\d+)?%%?)", "g");
  function lines(rects) {
    var tops = [];
    for (var i = 0; i < rects.length; i++) {
      if (rects[i].width < 0.5 || rects[i].height < 0.5) continue;
      var top = rects[i].top + rects[i].height / 2;
      if (!tops.some(function (t) { return Math.abs(t - top) < 3; })) tops.push(top);
    }
    return tops.length;
  }
  function source(formula) {  // the TeX of a typeset formula, as MathJax keeps it
    var math = window.MathJax && MathJax.startup && MathJax.startup.document;
    var item = math ? Array.from(math.math).find(function (m) {
      return m.typesetRoot === formula || formula.contains(m.typesetRoot); }) : null;
    return item ? item.math.replace(/\s+/g, " ").trim().slice(0, 60) : "";
  }
  function culprit(element) {  // the part of an element that reaches farthest right
    var best = null, right = -Infinity;
    element.querySelectorAll("*").forEach(function (child) {
      var r = child.getBoundingClientRect().right;
      if (r > right) { right = r; best = child; }
    });
    if (!best) return "";
    var formula = best.closest("mjx-container");
    return " (at " + (formula ? "the formula " + source(formula) : "<" + best.tagName.toLowerCase() + "> " +
                      best.textContent.trim().slice(0, 40)) + ")";
  }
  function probe() {
    var result = {prose: [], code: [], unrendered: [], errors: [], split: [], overflow: [], numbered: [], links: [],
                  formulas: 0};
    // the text, block by block (a number's span does not cut "2000*(1 + x)" in pieces)
    var walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT), block = null, kind = null;
    for (var node = walker.nextNode(); node; node = walker.nextNode()) {
      if (!node.data.trim() || closest(node, "script, style, mjx-container, #%(id)s, [hidden], .headerlink")) continue;
      var code = closest(node, "pre, code, kbd, samp, tt, .sig, dl.field-list > dd strong") ? result.code
                                                                                            : result.prose;
      var here = closest(node, "p, li, td, th, dt, dd, h1, h2, h3, h4, h5, h6, pre, caption, div");
      if (here === block && code === kind && code.length) code[code.length - 1] += node.data;
      else code.push(node.data);
      block = here;
      kind = code;
    }
    // display formulas wider than their line, equation numbers twice (Sphinx's and a \tag)
    document.querySelectorAll('mjx-container[display="true"]').forEach(function (formula) {
      var box = formula.getBoundingClientRect(), math = formula.firstElementChild.getBoundingClientRect();
      if (math.right > box.right + 1 || math.left < box.left - 1)
        result.overflow.push("a display formula " + Math.round(math.width) + " px wide in a line of " +
                             Math.round(box.width) + " px: " + source(formula));
    });
    document.querySelectorAll("div.math").forEach(function (element) {
      if (element.querySelector(".eqno") && element.querySelector("mjx-labels, mjx-mlabeledtr"))
        result.numbered.push(element.innerText.replace(/\s+/g, " ").trim().slice(0, 40) + ": " + source(element));
    });
    // code and output whose lines run out of their (grey) box, unless the box scrolls or wraps them; text, tables,
    // figures, formulas that reach past the edge of the page's white column (div.body, its padding included)
    var column = (document.querySelector("div.body") || document.body);
    var pageRight = column.getBoundingClientRect().right;
    column.querySelectorAll("pre, div.highlight, table, img, p, li, dt, dd").forEach(function (element) {
      for (var a = element; a && a !== column; a = a.parentElement)
        if (getComputedStyle(a).overflowX !== "visible") return;
      var past = element.scrollWidth - element.clientWidth;
      var right = element.getBoundingClientRect().right + Math.max(past, 0);
      var code = /^(PRE|DIV)$/.test(element.tagName);
      if ((code && element.clientWidth > 0 && past > 1) || right > pageRight + 1)
        result.overflow.push("<" + element.tagName.toLowerCase() + "> runs " + Math.round(code ? past :
          right - pageRight) + " px past " + (code ? "its box" : "the page") + ": " +
          element.textContent.replace(/\s+/g, " ").trim().slice(0, 60) + culprit(element));
    });
    // a cross-reference in code font looks like a link: the link's colour, not bold
    column.querySelectorAll("a[href] code").forEach(function (code) {
      var style = getComputedStyle(code);
      if (style.color !== getComputedStyle(code.closest("a")).color || parseInt(style.fontWeight, 10) >= 600)
        result.links.push(code.textContent.trim().slice(0, 40) + " (colour " + style.color + ", weight " +
                          style.fontWeight + ")");
    });
    document.querySelectorAll("span.math, div.math, .math").forEach(function (element) {
      if (!element.querySelector("mjx-container") && !closest(element, ".mathjax_ignore mjx-container"))
        result.unrendered.push(element.textContent.trim().slice(0, 80));
    });
    result.formulas = document.querySelectorAll("mjx-container").length;
    document.querySelectorAll("mjx-merror").forEach(function (e) {
      result.errors.push((e.getAttribute("data-mjx-error") || e.textContent).slice(0, 120));
    });
    if (/Math Processing Error/.test(document.body.innerText)) result.errors.push("Math Processing Error");
    document.querySelectorAll("td, th").forEach(function (cell) {
      var cellWalker = document.createTreeWalker(cell, NodeFilter.SHOW_TEXT);
      for (var text = cellWalker.nextNode(); text; text = cellWalker.nextNode()) {
        if (closest(text, "mjx-container, script, style")) continue;
        var match;
        NUMBER.lastIndex = 0;
        while ((match = NUMBER.exec(text.data)) !== null) {
          var range = document.createRange();
          range.setStart(text, match.index);
          range.setEnd(text, match.index + match[0].length);
          if (lines(range.getClientRects()) > 1)
            result.split.push(match[0] + " in the cell '" + cell.innerText.trim().slice(0, 60) + "'");
        }
      }
      cell.querySelectorAll("mjx-container").forEach(function (formula) {
        if (lines(formula.getClientRects()) > 1)
          result.split.push("a formula in the cell '" + cell.innerText.trim().slice(0, 60) + "'");
      });
    });
    report(result);
  }
  window.addEventListener("load", function () {
    var typeset = window.MathJax && window.MathJax.startup && window.MathJax.startup.promise
      ? window.MathJax.startup.promise : Promise.resolve();
    typeset.then(function () { return document.fonts.ready; }).then(probe, function (error) {
      report({failed: String(error)});
    });
  });
})();
""" % {"id": PROBE_ID}

# TeX in the prose: a control word (\eta, \frac, \mathbf; not an escape \n, \xff), MathJax's delimiters, $...$, a
# sub- or superscript group
TEX = re.compile(r"\\(?!(?:[ntr]|x[0-9a-f]{2})\b)[A-Za-z]+|\\[()\[\]]|\$\$|\$[^$\s][^$]*\$|[_^]\{")
# a role left as text: reStructuredText's :func:`x` (also :py:func:), a role that lost a backtick (:func:x`), MyST's
# {func}`x`
SPHINX_ROLES = "func|class|meth|attr|mod|math|ref|doc|data|obj|exc|term|eq|numref|const|any|download|envvar|option"
ROLE = re.compile(rf":(?:[a-z]+:)?[a-z]+:`|:(?:py:)?(?:{SPHINX_ROLES}):(?=\w)|\{{[a-z]+(?::[a-z]+)?\}}`")
# emphasis markers left as text: a run of * that is not the keyword-only marker of a signature (*, a, b), a footnote
# mark (*), a product or power 2*x, x**-2, or an operator between spaces (x ** 2); the names *args, **kwargs of the
# API's Parameters are in <strong> of a field list, read as code
STARS = re.compile(r"(?<=[(\s])\*(?=,)|\(\*\)|(?<=[\w)])\*{1,2}(?=[\w(+-])|(?<=\s)\*{1,2}(?=\s)|(\*+)")


def pages(site):  # noqa: F811 (site: the fixture's value)
    """Every HTML page of the site (not Sphinx's own search and index pages, whose text is a list of names), as
    paths relative to the site."""
    found = sorted(str(path.relative_to(site)) for path in site.rglob("*.html") if not path.relative_to(site).parts[0]
                   .startswith("_"))
    return [page for page in found if page not in ("search.html", "genindex.html", "py-modindex.html")]


@pytest.fixture(scope="module")
def probed(site, tmp_path_factory):  # noqa: F811
    """A copy of the site whose every page runs the probe (a script before ``</body>``)."""
    return probed_copy(site, tmp_path_factory.mktemp("probed") / "html")


def probed_copy(site, copy):  # noqa: F811
    """A copy of ``site`` in the folder ``copy`` whose every page runs the probe (a script before ``</body>``)."""
    shutil.copytree(site, copy, ignore=shutil.ignore_patterns("_sources", ".doctrees", "*.ipynb"))
    (copy / "_static" / "render_probe.js").write_text(PROBE)
    for page in pages(copy):
        path = copy / page
        depth = "../" * page.count("/")
        text = path.read_text()
        assert "</body>" in text, f"{page}: no </body>"
        path.write_text(text.replace("</body>", f'<script src="{depth}_static/render_probe.js"></script></body>', 1))
    return copy


def render(copy, page, profile):
    """What the probe found on ``page`` of the probed site: a dict (see PROBE)."""
    flags = [CHROMIUM, "--headless", "--disable-gpu", "--no-sandbox", f"--user-data-dir={profile}", "--no-first-run",
             "--host-resolver-rules=MAP * ~NOTFOUND", f"--window-size={WIDTH},2400", "--virtual-time-budget=10000",
             "--allow-file-access-from-files", "--dump-dom", (copy / page).as_uri()]
    dom = subprocess.run(flags, capture_output=True, text=True, timeout=300)
    found = re.search(rf'<pre id="{PROBE_ID}" hidden="">(.*?)</pre>', dom.stdout, flags=re.S)
    if not found:
        return {"failed": f"the probe did not report (exit {dom.returncode}): {dom.stderr[-500:]}"}
    return json.loads(html.unescape(found.group(1)))


def defects(result):
    """The defects of one page's probe result: a list of strings, empty when the page renders."""
    if "failed" in result:
        return [result["failed"]]
    prose, code = "\n".join(result["prose"]), "\n".join(result["code"])
    found = [f"raw TeX {m.group(0)!r}: ...{prose[max(m.start() - 40, 0):m.end() + 20]!r}" for m in TEX.finditer(prose)]
    found += [f"a role as text {m.group(0)!r}: ...{text[max(m.start() - 40, 0):m.end() + 30]!r}"
              for text in (prose, code) for m in ROLE.finditer(text)]
    found += [f"stray {stars!r}: ...{prose[max(m.start() - 40, 0):m.end() + 40]!r}"
              for m in STARS.finditer(prose) if (stars := m.group(1))]
    found += [f"formula not typeset: {tex!r}" for tex in result["unrendered"]]
    found += [f"MathJax error: {error}" for error in result["errors"]]
    found += [f"split over two lines: {split}" for split in result["split"]]
    found += [f"runs off: {overflow}" for overflow in result["overflow"]]
    found += [f"two equation numbers: {numbered}" for numbered in result["numbered"]]
    found += [f"a link that looks like text: {link}" for link in result["links"]]
    return found


def probe_site(copy, tmp_path, selected):
    """{page: defects} of the ``selected`` pages, two browsers at a time."""
    def one(item):
        k, page = item
        return page, defects(render(copy, page, tmp_path / f"profile{k % 2}_{k}"))

    with ThreadPoolExecutor(max_workers=2) as pool:
        return dict(pool.map(one, enumerate(selected)))


RESULTS = re.compile(r"^results/(?!index\.html$|verification\.html$)")
"""The pages of results/*.md (written by the scripts; checked by a test of their own)."""


def check(probed, tmp_path, selected):
    found = {page: d for page, d in probe_site(probed, tmp_path, selected).items() if d}
    assert not found, f"{len(found)} of {len(selected)} pages do not render:\n" + "\n".join(
        f"{page}: {len(d)} defects, e.g.\n    " + "\n    ".join(d[:6]) for page, d in found.items())


@pytest.mark.slow
@pytest.mark.browser
@needs_chromium
def test_every_page_renders(probed, tmp_path):
    """The landing, getting started, paper, testing and decisions pages, the user guide, the API, the gallery and
    the index pages of the results: no defect."""
    selected = [page for page in pages(probed) if not RESULTS.match(page)]
    assert len(selected) >= 40, f"only {len(selected)} pages"
    check(probed, tmp_path, selected)


@pytest.mark.slow
@pytest.mark.browser
@needs_chromium
def test_every_results_page_renders(probed, tmp_path):
    """The pages of results/*.md, as the scripts write them: no defect."""
    selected = [page for page in pages(probed) if RESULTS.match(page)]
    assert len(selected) >= 20, f"only {len(selected)} results pages"
    check(probed, tmp_path, selected)


PLANTED = {
    "raw TeX": r"<p>a penalty \eta left raw, and $u_h$ as text</p>",
    "a role as text": "<p>see :func:`ngdgfric.solve` and {class}`ngdgfric.Solution`</p>",
    "stray": "<p>an *emphasis* left as text</p>",
    "MathJax error": '<p><span class="math notranslate nohighlight">\\(\\left( x\\)</span></p>',
    "formula not typeset": '<p><span class="math notranslate nohighlight">x^2 + y^2</span> (no delimiters)</p>',
    "split over two lines": '<table class="docutils"><tr><td style="width: 2.5em">2.751e-02</td></tr></table>',
    "runs off": '<div class="highlight"><pre style="overflow: visible">' + "x = 1  # " * 40 + "</pre></div>",
    "a link that looks like text": '<p><a class="reference" href="#"><code style="font-weight: bold; color: black">'
                                   "ngdgfric.solve</code></a></p>",
}
"""Defects planted into a copy of a page, each by the words of its finding in :func:`defects`."""


@pytest.mark.slow
@pytest.mark.browser
@needs_chromium
def test_the_probe_finds_planted_defects(probed, tmp_path):
    """A copy of a page that passes, with one defect of each kind planted in its text: each is found, and the
    page as built is clean (the test fails where the page does)."""
    page = "user_guide/scenes.html"
    assert not probe_site(probed, tmp_path, [page])[page]
    text = (probed / page).read_text()
    start = text.index('<div class="body" role="main">') + len('<div class="body" role="main">')
    planted = page.replace(".html", "_planted.html")
    (probed / planted).write_text(text[:start] + "".join(PLANTED.values()) + text[start:])
    found = probe_site(probed, tmp_path, [planted])[planted]
    missed = [kind for kind in PLANTED if not any(finding.startswith(kind) for finding in found)]
    assert not missed, f"planted defects not found: {missed}; found: {found}"

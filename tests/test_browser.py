"""A notebook exported to static HTML by nbconvert shows its webgui scenes in a real browser.

The page nbconvert writes (with the widget state embedded) loads its JavaScript from public
CDNs: require.js, the widget manager @jupyter-widgets/html-manager (embed-amd.js), which loads
the anywidget front end through require.js, whose copy of ngsolve.webgui's ES module loads
webgui.js.  The test serves every one of them from local files instead, so that it needs no
CDN and cannot silently use one:

* require.js and html-manager: ``npm pack`` from the npm registry (skipped if that fails);
* anywidget's AMD front end: the ``anywidget`` Python package (nbextension/index.js);
* webgui.js: the ``webgui_jupyter_widgets`` Python package.  It is a UMD build, which would
  register itself as an anonymous require.js module on this page; wrapped so that it assigns the
  global ``webgui`` as the CDN's build does.

Headless Debian Chromium (``apt-get install chromium``; the test skips without it) renders the
page with SwiftShader WebGL and host names unresolvable, and the screenshot must show the scenes'
colour maps: many saturated pixels, which neither text nor the page's grey chrome produce.
"""

import json
import re
import shutil
import subprocess
import tarfile
from pathlib import Path

import anywidget
import matplotlib.image
import numpy as np
import pytest
import webgui_jupyter_widgets
from nbconvert import HTMLExporter
from test_notebooks import NOTEBOOKS, WIDGET_STATE, run_notebook, webgui_scenes

CHROMIUM = next((p for p in ("/usr/bin/chromium", shutil.which("chromium"), shutil.which("chromium-browser")) if p
                 and Path(p).exists()), None)
NPM_PACKAGES = {"requirejs@2.3.8": "package/require.js",
                "@jupyter-widgets/html-manager@1.0.15": "package/dist/embed-amd.js"}
WEBGUI_CDN = re.compile(r"https://cdn\.jsdelivr\.net/npm/webgui@[^\"']*/dist/webgui\.js")
WIDTH, HEIGHT = 1200, 2000
# show only the cells with widget outputs, without their code, so that the scenes are on screen
ONLY_WIDGETS = """<style>
.jp-Cell:not(:has(script[type="application/vnd.jupyter.widget-view+json"])) { display: none; }
.jp-Cell .jp-InputArea, .jp-Cell .jp-OutputArea-executeResult { display: none; }
</style>"""


def local_javascript(folder):
    """Local copies of the page's JavaScript: {"require", "html_manager", "anywidget", "webgui"}."""
    npm = shutil.which("npm")
    if npm is None:
        pytest.skip("npm not found: it fetches require.js and @jupyter-widgets/html-manager")
    result = subprocess.run([npm, "pack", "--silent", *NPM_PACKAGES], cwd=folder, capture_output=True, text=True,
                            timeout=300)
    if result.returncode != 0:
        pytest.skip(f"npm pack failed: {result.stderr.strip()[-500:]}")
    files = {}
    for key, (package, member) in zip(["require", "html_manager"], NPM_PACKAGES.items(), strict=True):
        tarball = folder / (package.lstrip("@").replace("/", "-").replace("@", "-") + ".tgz")
        files[key] = folder / Path(member).name
        with tarfile.open(tarball) as archive:
            files[key].write_bytes(archive.extractfile(member).read())
    files["anywidget"] = Path(anywidget.__file__).parent / "nbextension" / "index.js"
    umd = (Path(webgui_jupyter_widgets.__file__).parent / "js" / "webgui.js").read_text()
    files["webgui"] = folder / "webgui.js"
    files["webgui"].write_text("(function (define) {\n" + umd + "\n}).call(window, undefined);\n")
    return files


def static_page(nb, js, path):
    """Export the executed notebook with nbconvert's HTML exporter, pointed at the local JavaScript."""
    state = nb.metadata["widgets"][WIDGET_STATE]["state"]
    for model in state.values():
        if "_esm" in model["state"]:
            model["state"]["_esm"], count = WEBGUI_CDN.subn(js["webgui"].as_uri(), model["state"]["_esm"])
            assert count == 1, "ngsolve.webgui's module no longer loads webgui.js from the CDN address we replace"
    exporter = HTMLExporter(require_js_url=js["require"].as_uri(), widget_renderer_url=js["html_manager"].as_uri())
    html, _ = exporter.from_notebook_node(nb)
    require_tag = f'<script src="{js["require"].as_uri()}"></script>'
    # html-manager asks require.js for "anywidget" first and falls back to the CDN only if that fails
    config = {"paths": {"anywidget": js["anywidget"].with_suffix("").as_uri()}}
    assert html.count(require_tag) == 1 and html.count("</head>") == 1
    html = html.replace(require_tag, require_tag + f"<script>require.config({json.dumps(config)});</script>")
    html = html.replace("</head>", ONLY_WIDGETS + "</head>")
    path.write_text(html)
    return path


@pytest.mark.slow
@pytest.mark.browser
@pytest.mark.skipif(CHROMIUM is None, reason="no chromium binary (Debian: apt-get install chromium)")
def test_exported_notebook_renders_webgui(tmp_path, monkeypatch):
    js = local_javascript(tmp_path)
    nb = run_notebook(NOTEBOOKS / "example_6_2.ipynb", monkeypatch)
    scenes = len(webgui_scenes(nb))
    page = static_page(nb, js, tmp_path / "example_6_2.html")
    screenshot = tmp_path / "example_6_2.png"
    command = [CHROMIUM, "--headless", "--disable-gpu", "--no-sandbox", "--use-gl=swiftshader",
               "--enable-unsafe-swiftshader", f"--user-data-dir={tmp_path / 'profile'}", "--no-first-run",
               "--host-resolver-rules=MAP * ~NOTFOUND", f"--window-size={WIDTH},{HEIGHT}",
               "--virtual-time-budget=20000", f"--screenshot={screenshot}", page.as_uri()]
    result = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert screenshot.exists(), f"chromium wrote no screenshot (exit {result.returncode}): {result.stderr[-2000:]}"
    rgb = matplotlib.image.imread(screenshot)[..., :3]
    assert rgb.shape[:2] == (HEIGHT, WIDTH)
    non_white = int(np.count_nonzero(rgb.min(axis=2) < 0.95))
    coloured = int(np.count_nonzero(rgb.max(axis=2) - rgb.min(axis=2) > 0.3))
    # each scene's colour-mapped domain covers some 200 x 200 pixels
    print(f"{scenes} scenes: {coloured} coloured, {non_white} non-white pixels ({screenshot})")
    assert coloured > 10_000 * scenes, (f"{coloured} coloured, {non_white} non-white pixels for {scenes} scenes: "
                                        f"webgui did not render (see {screenshot})")

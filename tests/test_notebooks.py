"""Every notebook in notebooks/ runs headless at smoke size (NGDGFRIC_SMOKE=1) and draws its webgui scenes.

The notebooks are executed by nbclient in a python3 kernel with the widget state stored, as
``jupyter nbconvert --execute`` would; tests/test_browser.py renders one of them in a browser.
"""

import re
from pathlib import Path

import nbclient
import nbformat
import pytest

pytestmark = pytest.mark.slow  # every test here executes a notebook

NOTEBOOKS = Path(__file__).resolve().parent.parent / "notebooks"
WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"
WIDGET_STATE = "application/vnd.jupyter.widget-state+json"
WEBGUI = "netgen.webgui.WebGuiWidget"  # the anywidget id of ngsolve.webgui.Draw's widget
SMOKE_LEVELS = {"example_6_1": 20, "example_6_2": 20, "hp_adaptivity": 10, "scenes": 8}
"""The adaptive levels each notebook logs at smoke size: enough for its figures to show what they claim."""


def run_notebook(path, monkeypatch, timeout=300):
    """Execute the notebook at ``path`` at smoke size in its folder; returns the executed notebook."""
    monkeypatch.setenv("NGDGFRIC_SMOKE", "1")  # the kernel inherits the environment
    nb = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(nb, kernel_name="python3", timeout=timeout, store_widget_state=True,
                                     resources={"metadata": {"path": str(path.parent)}})
    client.execute()
    return nb


def outputs(nb):
    return [out for cell in nb.cells if cell.cell_type == "code" for out in cell.outputs]


def webgui_scenes(nb):
    """Render data of the webgui widgets displayed in the notebook's outputs, in display order."""
    state = nb.metadata["widgets"][WIDGET_STATE]["state"]
    views = [out["data"][WIDGET_VIEW]["model_id"] for out in outputs(nb) if WIDGET_VIEW in out.get("data", {})]
    return [state[view]["state"]["value"] for view in views if state[view]["state"].get("_anywidget_id") == WEBGUI]


def draw_calls(nb):
    return sum(len(re.findall(r"^Draw\(", cell.source, re.M)) for cell in nb.cells if cell.cell_type == "code")


@pytest.mark.parametrize("name", ["example_6_1", "example_6_2", "hp_adaptivity", "scenes"])
def test_notebook_runs(name, monkeypatch):
    path = NOTEBOOKS / f"{name}.ipynb"
    stored = nbformat.read(path, as_version=4)
    assert all(not cell.get("outputs") for cell in stored.cells if cell.cell_type == "code"), \
        "notebooks are committed without outputs"
    nb = run_notebook(path, monkeypatch)  # raises CellExecutionError on the first failing cell
    assert not [out for out in outputs(nb) if out.output_type == "error"]
    # the smoke switch took effect: ndf.adapt printed one line per level
    text = "".join(out.get("text", "") for out in outputs(nb) if out.output_type == "stream")
    assert len(re.findall(r"^level +\d+:", text, re.M)) == SMOKE_LEVELS[name]
    # and the run is large enough for the convergence plot to show eta_h falling
    eta_h = [float(value) for value in re.findall(r"^level +\d+:.*eta_h = (\S+),", text, re.M)]
    assert len(eta_h) == SMOKE_LEVELS[name] and eta_h[-1] < 0.5 * max(eta_h)
    # every Draw(...) displayed a webgui widget whose render data hold a triangulated surface
    scenes = webgui_scenes(nb)
    assert len(scenes) == draw_calls(nb) >= 3
    assert all(scene.get("Bezier_trig_points") for scene in scenes)
    # matplotlib: the convergence plot and the plots along Gamma_C
    figures = [out for out in outputs(nb) if "image/png" in out.get("data", {})]
    assert len(figures) >= 2

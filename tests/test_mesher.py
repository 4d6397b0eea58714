"""Netgen in a child process (ngdgfric.mesher): failures and time limits as ValueErrors, Ctrl-C at once."""

import dataclasses
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import ngdgfric as ndf


def strip(width):
    """Example 6.1's data on the rectangle (0, 1) x (0, width): valid, but thin for Netgen."""
    geometry = ndf.Polygon([(0, 0), (1, 0), (1, width), (0, width)], ("contact", "traction", "traction", "dirichlet"))
    return dataclasses.replace(ndf.example_6_1(), geometry=geometry)


def test_netgen_failure_is_a_value_error():
    with pytest.raises(ValueError, match=r"Netgen could not mesh the polygon \[\(0, 0\), .* meshing failed"):
        ndf.netgen_mesh(strip(5e-5), 1.0)


@pytest.mark.slow  # a Netgen process
def test_netgen_busy_beyond_the_time_limit_is_stopped():
    # width 1e-5: Netgen ran for more than 6 minutes of CPU (maxh = 0.1) without reacting to Ctrl-C
    start = time.perf_counter()
    with pytest.raises(ValueError, match="did not finish within 2 s"):
        ndf.netgen_mesh(strip(1e-5), 1.0, timeout=2)
    assert time.perf_counter() - start < 10


@pytest.mark.slow  # a Netgen process
def test_ctrl_c_stops_meshing_at_once():
    code = ("import sys; sys.path.insert(0, 'tests'); import test_mesher, ngdgfric as ndf\n"
            "print('meshing', flush=True)\n"
            "ndf.netgen_mesh(test_mesher.strip(1e-5), 1.0)\n")
    process = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               cwd=Path(__file__).resolve().parent.parent)
    assert process.stdout.readline() == "meshing\n"
    time.sleep(1)
    process.send_signal(signal.SIGINT)
    start = time.perf_counter()
    _, err = process.communicate(timeout=30)
    assert "KeyboardInterrupt" in err and time.perf_counter() - start < 5


def test_the_mesh_made_in_the_child_is_netgens_mesh():
    """generate() (meshed in a child process, sent back as a .vol file, read) gives the mesh Netgen makes in this
    process: same points, triangles in the same order, same boundary segments and names."""
    from netgen.geom2d import SplineGeometry

    from ngdgfric.mesher import generate, triangles_of

    geometry = ndf.example_6_1().geometry
    spline = SplineGeometry()
    points = [spline.AppendPoint(x, y) for x, y in geometry.vertices]
    for k, label in enumerate(geometry.labels):
        spline.Append(["line", points[k], points[(k + 1) % len(points)]], bc=label, leftdomain=1, rightdomain=0)
    here, there = spline.GenerateMesh(maxh=0.2), generate(geometry, 0.2, timeout=60)
    for a, b in zip(triangles_of(here), triangles_of(there), strict=True):
        assert a.shape == b.shape and (a == b).all()
    assert triangles_of(here)[1].min() == 0 and triangles_of(here)[0].shape[1] == 2
    segments = [here.Elements1D().NumPy(), there.Elements1D().NumPy()]
    assert (segments[0]["nodes"][:, :2] == segments[1]["nodes"][:, :2]).all()
    assert [here.GetBCName(k) for k in range(3)] == [there.GetBCName(k) for k in range(3)]


def test_curved_sides_and_regions_survive_the_trip_through_the_child(monkeypatch):
    """Arcs, holes and two regions: the child's mesh is the one Netgen makes here (points, triangles, region
    and boundary names); no fork of this process (which runs BLAS threads) is involved."""
    from ngdgfric.domain import Domain, Loop
    from ngdgfric.mesher import generate, triangles_of

    def no_fork():
        raise AssertionError("generate must not fork this process")

    monkeypatch.setattr("os.fork", no_fork)
    left = Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["bottom", "mid", "top", "wall"])
    right = Loop([(1, 0), (2, 0), (2, 1), (1, 1)], ["bottom", "free", "top", "mid"])
    domain = Domain({"steel": left, "rubber": right}, holes=[Loop.circle((1.5, 0.5), 0.25, "hole")])
    here, there = domain.spline_geometry().GenerateMesh(maxh=0.3), generate(domain, 0.3, timeout=60)
    for a, b in zip(triangles_of(here), triangles_of(there), strict=True):
        assert a.shape == b.shape and np.array_equal(a, b)
    assert [here.GetMaterial(k) for k in (1, 2)] == [there.GetMaterial(k) for k in (1, 2)] == ["steel", "rubber"]
    names = len(here.GetRegionNames(codim=1))
    assert [here.GetBCName(k) for k in range(names)] == [there.GetBCName(k) for k in range(names)]


@pytest.mark.slow  # a Python process, a Netgen process
def test_a_script_without_a_main_guard_can_mesh(tmp_path):
    """The child does not import the user's __main__ again (multiprocessing's forkserver and spawn children do:
    a script without ``if __name__ == "__main__":`` would start meshing again in the child)."""
    script = tmp_path / "script.py"
    script.write_text("import ngdgfric as ndf\nprint('top level', flush=True)\n"
                      "print(ndf.netgen_mesh(ndf.example_6_1(), 0.25).ne)\n")
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.count("top level") == 1 and int(out.stdout.split()[-1]) > 0


@pytest.mark.slow  # a Netgen process killed after its time limit
def test_the_mesh_server_outlives_a_killed_child_and_starts_again_after_shutdown():
    from ngdgfric import mesher

    with pytest.raises(TimeoutError):
        mesher.generate(strip(1e-5).geometry, 1.0, timeout=0.5)  # its child killed
    server = mesher._SERVER[0]
    assert server.poll() is None and len(mesher.generate(ndf.example_6_1().geometry, 0.5, 60).Elements2D()) > 0
    assert mesher._SERVER[0] is server
    mesher.shutdown()
    assert server.poll() is not None and mesher._SERVER is None
    assert len(mesher.generate(ndf.example_6_1().geometry, 0.5, 60).Elements2D()) > 0

"""Netgen in a child process (ngdgfric.mesher): failures and time limits as ValueErrors, Ctrl-C at once."""

import dataclasses
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import ngdgfric as ndf


def strip(width):
    """Example 6.1's data on the rectangle (0, 1) x (0, width): valid, but thin for Netgen."""
    geometry = ndf.Polygon([(0, 0), (1, 0), (1, width), (0, width)], ("contact", "traction", "traction", "dirichlet"))
    return dataclasses.replace(ndf.example_6_1(), geometry=geometry)


def test_netgen_failure_is_a_value_error():
    with pytest.raises(ValueError, match=r"Netgen could not mesh the polygon \[\(0, 0\), .* meshing failed"):
        ndf.netgen_mesh(strip(5e-5), 1.0)


def test_netgen_busy_beyond_the_time_limit_is_stopped():
    # width 1e-5: Netgen ran for more than 6 minutes of CPU (maxh = 0.1) without reacting to Ctrl-C
    start = time.perf_counter()
    with pytest.raises(ValueError, match="did not finish within 2 s"):
        ndf.netgen_mesh(strip(1e-5), 1.0, timeout=2)
    assert time.perf_counter() - start < 10


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

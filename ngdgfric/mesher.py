"""Netgen's 2D mesher in a child process: stoppable by Ctrl-C and by a time limit.

Netgen does not react to SIGINT while it meshes, and some valid but thin polygons keep it busy
for minutes (a 1 x 1e-5 rectangle with maxh = 1: more than 6 minutes of CPU).  The mesh is made
in a forked child and sent back as arrays; the parent waits in short polls, so Ctrl-C stops it at
once, and a child still busy after ``timeout`` seconds is killed and reported as a ValueError.
Where fork is not available the mesh is made in this process.
"""

import multiprocessing
import pickle
import time

import netgen.meshing as nm
import numpy as np
from netgen.geom2d import SplineGeometry

__all__ = ["generate", "default_timeout", "triangles_of"]


def default_timeout(elements):
    """Seconds allowed for about ``elements`` triangles: 10 + 1e-4 per element (Netgen made 5.8e5
    triangles of Example 6.1 in 31 s, 5.4e-5 s per triangle)."""
    return 10 + 1e-4 * elements


def _mesh(vertices, labels, maxh):
    spline = SplineGeometry()
    points = [spline.AppendPoint(x, y) for x, y in vertices]
    for k, label in enumerate(labels):
        spline.Append(["line", points[k], points[(k + 1) % len(points)]], bc=label, leftdomain=1, rightdomain=0)
    return spline.GenerateMesh(maxh=maxh)


def triangles_of(ngmesh):
    """(points (n, 2), triangles (m, 3) of 0-based vertex numbers) of a 2D Netgen mesh, in its element order."""
    points = np.asarray(ngmesh.Coordinates())[:, :2].copy()  # copies: the mesh may be freed
    return points, ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1


def _arrays(ngmesh):
    """The mesh as arrays: coordinates, triangles, segments with their region, region names."""
    segments = ngmesh.Elements1D().NumPy()
    names = [ngmesh.GetBCName(k) for k in range(int(segments["index"].max()))] if len(segments) else []
    return (*triangles_of(ngmesh), segments["nodes"][:, :2].copy(), segments["index"].copy(), names)


def _rebuild(points, triangles, segments, regions, names):
    """The Netgen mesh of :func:`_arrays`, numbered as the original (the geometry is not needed:
    the sides are straight)."""
    ngmesh = nm.Mesh(dim=2)
    ngmesh.AddPoints(np.column_stack([points, np.zeros(len(points))]))
    ngmesh.AddElements(dim=2, index=ngmesh.AddRegion("omega", dim=2), data=triangles.astype(np.int32), base=0)
    for name in names:
        ngmesh.AddRegion(name, dim=1)
    for (a, b), region in zip(segments, regions, strict=True):
        ngmesh.Add(nm.Element1D([nm.PointId(int(a)), nm.PointId(int(b))], index=int(region)))
    return ngmesh


def _child(connection, vertices, labels, maxh):
    try:  # arrays, not the pickled mesh: unpickling a fresh Netgen mesh with its geometry hung
        connection.send_bytes(pickle.dumps(("mesh", _arrays(_mesh(vertices, labels, maxh)))))
    except Exception as exc:  # netgen.libngpy._meshing.NgException and whatever else Netgen raises
        connection.send_bytes(pickle.dumps(("error", f"{type(exc).__name__}: {exc}")))
    finally:
        connection.close()


def generate(vertices, labels, maxh, timeout):
    """The Netgen mesh (netgen.meshing.Mesh) of the polygon ``vertices`` with side ``labels``;
    RuntimeError with Netgen's message if it fails, TimeoutError after ``timeout`` seconds."""
    try:
        context = multiprocessing.get_context("fork")
    except ValueError:  # no fork on this platform
        return _mesh(vertices, labels, maxh)
    receive, send = context.Pipe(duplex=False)
    child = context.Process(target=_child, args=(send, vertices, labels, maxh), daemon=True)
    child.start()
    send.close()
    try:
        deadline = time.monotonic() + timeout
        while not receive.poll(0.1):
            if time.monotonic() > deadline:
                raise TimeoutError(f"Netgen did not finish within {timeout:.0f} s")
            if not child.is_alive() and not receive.poll(0.1):
                raise RuntimeError(f"Netgen's process ended without a mesh (exit code {child.exitcode})")
        kind, payload = pickle.loads(receive.recv_bytes())
    finally:
        if child.is_alive():
            child.kill()
        child.join()
        receive.close()
    if kind == "error":
        raise RuntimeError(payload)
    return _rebuild(*payload)

"""Netgen's 2D mesher in a child process: stoppable by Ctrl-C and by a time limit.

Netgen does not react to SIGINT while it meshes, and some valid but thin polygons keep it busy
for minutes (a 1 x 1e-5 rectangle with maxh = 1: more than 6 minutes of CPU).  The mesh is made
in a forked child and sent back as arrays; the parent waits in short polls, so Ctrl-C stops it at
once, and a child still busy after ``timeout`` seconds is killed and reported as a ValueError.
Where fork is not available the mesh is made in this process.

The child writes the mesh to a temporary Netgen ``.vol`` file (it keeps every boundary segment's curve and
parameter, which ``mesh.Curve`` and refinement onto curved sides need; sending the pickled mesh with its
geometry hung) and sends the exact coordinates (the file keeps 16 digits); the parent reads the file, restores
the coordinates and attaches the geometry again.
"""

import multiprocessing
import os
import pickle
import tempfile
import time

import netgen.meshing as nm
import numpy as np

__all__ = ["generate", "default_timeout", "triangles_of"]


def default_timeout(elements):
    """Seconds allowed for about ``elements`` triangles: 10 + 1e-4 per element (Netgen made 5.8e5
    triangles of Example 6.1 in 31 s, 5.4e-5 s per triangle)."""
    return 10 + 1e-4 * elements


def triangles_of(ngmesh):
    """(points (n, 2), triangles (m, 3) of 0-based vertex numbers) of a 2D Netgen mesh, in its element order."""
    points = np.asarray(ngmesh.Coordinates())[:, :2].copy()  # copies: the mesh may be freed
    return points, ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1


def _child(connection, geometry, maxh, path):
    try:
        ngmesh = geometry.spline_geometry().GenerateMesh(maxh=maxh)
        ngmesh.Save(path)
        connection.send_bytes(pickle.dumps(("mesh", (path, np.array(ngmesh.Coordinates())))))
    except Exception as exc:  # netgen.libngpy._meshing.NgException and whatever else Netgen raises
        connection.send_bytes(pickle.dumps(("error", f"{type(exc).__name__}: {exc}")))
    finally:
        connection.close()


def _load(geometry, path, coordinates):
    """The mesh saved at ``path`` with the exact ``coordinates`` (the .vol file keeps 16 digits) and its geometry."""
    ngmesh = nm.Mesh(dim=2)
    ngmesh.Load(path)
    ngmesh.Coordinates()[:] = coordinates  # a writable view of the mesh's points
    ngmesh.SetGeometry(geometry.spline_geometry())
    return ngmesh


def generate(geometry, maxh, timeout):
    """The Netgen mesh (netgen.meshing.Mesh, with its geometry) of a :class:`ngdgfric.domain.Geometry`;
    RuntimeError with Netgen's message if it fails, TimeoutError after ``timeout`` seconds."""
    try:
        context = multiprocessing.get_context("fork")
    except ValueError:  # no fork on this platform
        ngmesh = geometry.spline_geometry().GenerateMesh(maxh=maxh)
        ngmesh.SetGeometry(geometry.spline_geometry())
        return ngmesh
    with tempfile.TemporaryDirectory(prefix="ngdgfric-") as folder:
        path = os.path.join(folder, "mesh.vol")
        receive, send = context.Pipe(duplex=False)
        child = context.Process(target=_child, args=(send, geometry, maxh, path), daemon=True)
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
        return _load(geometry, *payload)

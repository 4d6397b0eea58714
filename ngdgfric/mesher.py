"""Netgen's 2D mesher in a separate process: stoppable by Ctrl-C and by a time limit.

Netgen does not react to SIGINT while it meshes, and some valid but thin polygons keep it busy
for minutes (a 1 x 1e-5 rectangle with maxh = 1: more than 6 minutes of CPU).  So the mesh is made
in another process and sent back through files; this process waits in short polls, so Ctrl-C stops
it at once, and a child still busy after ``timeout`` seconds is killed and reported as a TimeoutError
(a ValueError from :func:`~ngdgfric.netgen_mesh`).

**Where the child comes from.**  The children are forked by a *mesh server* (:mod:`ngdgfric._mesh_worker`): a
fresh interpreter started once per process by ``subprocess`` (fork + exec, which inherits nothing) that imports
Netgen only (not ngsolve, not ngdgfric) with ``OPENBLAS_NUM_THREADS=1`` and so stays single-threaded, and forks one
child per mesh.  Not from this process, which by then runs OpenBLAS and NGSolve's TaskManager threads: a forked
child inherits the locks those threads may hold (deadlock risk; Python 3.12 warns about ``fork`` in a
multi-threaded process).  Not by multiprocessing's ``forkserver`` or ``spawn`` contexts either: their children
import the user's ``__main__`` again, which re-runs a script without an ``if __name__ == "__main__":`` guard
(tests/test_mesher.py).

The server is this module's one piece of process state (``_SERVER``): started at the first
``generate``, again after it died or in a forked copy of this process; it ignores Ctrl-C and ends
when this process ends (its stdin closes) or at ``shutdown``.  It is kept because a fresh interpreter
per mesh costs the interpreter's start and Netgen's import every time (the three ways timed:
:ref:`decisions-mesher`).  Without ``os.fork`` (Windows) every mesh gets its own fresh interpreter.

The child writes the mesh to a temporary Netgen ``.vol`` file (it keeps every boundary segment's curve and
parameter, which ``mesh.Curve`` and refinement onto curved sides need) and sends the exact coordinates (the
file keeps 16 digits); this process reads the file, restores the coordinates and attaches the geometry again.
"""

import atexit
import os
import pickle
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import netgen.meshing as nm
import numpy as np

__all__ = ["generate", "default_timeout", "triangles_of", "shutdown"]

WORKER = str(Path(__file__).with_name("_mesh_worker.py"))
# run the worker as a script without its folder on sys.path (whose modules could shadow others)
# the caller's working directory leaves sys.path first: a signal.py or numpy.py there must not replace the modules
LAUNCH = ("import sys; del sys.path[0]; import runpy; sys.argv = sys.argv[1:]; "
          "runpy.run_path(sys.argv[0], run_name='__main__')")
POLL = 0.02  # seconds between two looks at the child
_SERVER = None  # (the server's Popen, the process id of the process that started it)
_LOCK = threading.Lock()


def default_timeout(elements):
    """Seconds allowed for about ``elements`` triangles: 10 + 1e-4 per element (Netgen made 5.8e5
    triangles of Example 6.1 in 31 s, 5.4e-5 s per triangle)."""
    return 10 + 1e-4 * elements


def triangles_of(ngmesh):
    """(points (n, 2), triangles (m, 3) of 0-based vertex numbers) of a 2D Netgen mesh, in its element order."""
    points = np.asarray(ngmesh.Coordinates())[:, :2].copy()  # copies: the mesh may be freed
    return points, ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1


def _worker(argument, **streams):
    """The worker script in a fresh interpreter (module docstring)."""
    return subprocess.Popen([sys.executable, "-c", LAUNCH, WORKER, argument], stdout=subprocess.DEVNULL,
                            env=dict(os.environ, OPENBLAS_NUM_THREADS="1"), **streams)


def _submit(folder):
    """Have the request in ``folder`` meshed: by a child of the mesh server, or (no fork) a fresh interpreter.
    Returns the Popen of the fresh interpreter, or None."""
    global _SERVER
    if not hasattr(os, "fork"):
        with open(folder / "stderr", "wb") as stderr:
            return _worker(str(folder), stdin=subprocess.DEVNULL, stderr=stderr)
    with _LOCK:
        if _SERVER is None or _SERVER[0].poll() is not None or _SERVER[1] != os.getpid():
            if _SERVER is None:
                atexit.register(shutdown)
            _SERVER = (_worker("serve", stdin=subprocess.PIPE, stderr=subprocess.DEVNULL), os.getpid())
        server = _SERVER[0]
        server.stdin.write(f"{folder}\n".encode())
        server.stdin.flush()
    return None


def shutdown():
    """End the mesh server (module docstring); the next ``generate`` starts a new one."""
    global _SERVER
    with _LOCK:
        if _SERVER is not None and _SERVER[1] == os.getpid():
            _SERVER[0].stdin.close()
            _SERVER[0].wait()
        _SERVER = None


def _child_pid(folder):
    """The meshing child's process id, once it has written it (None before)."""
    try:
        return int((folder / "pid").read_text())
    except (FileNotFoundError, ValueError):
        return None


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # a process id reused by another user's process: ours is gone
        return False
    return True


def _ended(folder, fresh):
    """True if the child has ended (with or without a result)."""
    if fresh is not None:
        return fresh.poll() is not None
    pid = _child_pid(folder)
    server_gone = _SERVER is None or _SERVER[0].poll() is not None
    return (pid is not None and not _alive(pid)) or (pid is None and server_gone)


def _wait(folder, fresh, timeout):
    """Wait in short polls (Ctrl-C interrupts the sleep) until the child has written its result or ended;
    TimeoutError after ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    while not (folder / "result.pickle").exists() and not _ended(folder, fresh):
        if time.monotonic() > deadline:
            raise TimeoutError(f"Netgen did not finish within {timeout:.0f} s")
        time.sleep(POLL)


def _stop(folder, fresh):
    """Kill the child if it still runs (after a time-out, Ctrl-C or an error here)."""
    if fresh is not None:
        if fresh.poll() is None:
            fresh.kill()
        fresh.wait()
        return
    for _ in range(50):  # a child forked just now may not have written its process id yet
        pid = _child_pid(folder)
        if pid is not None or _SERVER is None or _SERVER[0].poll() is not None:
            break
        time.sleep(POLL)
    if pid is not None and not (folder / "result.pickle").exists():
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


def _load(geometry, path, coordinates):
    """The mesh saved at ``path`` with the exact ``coordinates`` (the .vol file keeps 16 digits) and its geometry."""
    ngmesh = nm.Mesh(dim=2)
    ngmesh.Load(str(path))
    elements = ngmesh.Elements2D().NumPy()
    ngmesh.Coordinates()[:] = geometry.unshift(  # a writable view of the mesh's points; the bodies moved back
        coordinates, elements["nodes"][:, :3].astype(np.int64) - 1, elements["index"])
    ngmesh.SetGeometry(geometry.spline_geometry())
    return ngmesh


def generate(geometry, maxh, timeout, region_maxh=None):
    """The Netgen mesh (netgen.meshing.Mesh, with its geometry) of a :class:`ngdgfric.domain.Geometry`, mesh size
    ``maxh`` and ``region_maxh`` ({region name: size}) in some regions; RuntimeError with Netgen's message if it
    fails, TimeoutError after ``timeout`` seconds."""
    with tempfile.TemporaryDirectory(prefix="ngdgfric-") as folder:
        folder = Path(folder)
        (folder / "request.pickle").write_bytes(pickle.dumps((geometry.meshing_geometry(region_maxh), maxh)))
        fresh = _submit(folder)
        try:
            _wait(folder, fresh, timeout)
        finally:
            _stop(folder, fresh)
        result = folder / "result.pickle"
        if not result.exists():
            stderr = folder / "stderr"
            last = stderr.read_text(errors="replace").strip().splitlines()[-1:] if stderr.exists() else []
            raise RuntimeError(f"Netgen's process ended without a mesh{': ' + last[0] if last else ''}")
        kind, payload = pickle.loads(result.read_bytes())
        if kind == "error":
            raise RuntimeError(payload)
        return _load(geometry, folder / "mesh.vol", payload)

"""The child side of :mod:`ngdgfric.mesher`: mesh a Netgen ``SplineGeometry`` and write the result to files.

Run as a script by a fresh interpreter (``python -c`` + ``runpy.run_path``, so neither the ngdgfric package nor
the user's ``__main__`` is imported; Netgen and numpy only, with ``OPENBLAS_NUM_THREADS=1``: a single thread).

* ``python _mesh_worker.py FOLDER``: mesh the request in FOLDER and exit.
* ``python _mesh_worker.py serve``: the mesh server.  For every line FOLDER read from stdin it forks a child that
  meshes the request in FOLDER; it never meshes itself, so it stays single-threaded and every fork is safe and
  costs milliseconds.  It ignores SIGINT (Ctrl-C is the parent's: it kills the meshing child) and ends at the end
  of stdin, i.e. when the parent closes the pipe or ends.

A request: ``request.pickle`` in FOLDER holds the pickled ``(SplineGeometry, maxh)``; the child writes its process
id to ``pid``, saves the mesh to ``mesh.vol`` and writes ``result.pickle``: ``("mesh", exact coordinates)`` or
``("error", Netgen's message)``.  Python errors of the child go to ``stderr`` in FOLDER.
"""

import os
import pickle
import signal
import sys
from pathlib import Path


def mesh(folder):
    """Mesh the request in ``folder`` (module docstring)."""
    folder = Path(folder)
    spline, maxh = pickle.loads((folder / "request.pickle").read_bytes())
    try:
        ngmesh = spline.GenerateMesh(maxh=maxh)
        ngmesh.Save(str(folder / "mesh.vol"))
        import numpy as np  # loaded by Netgen already

        result = ("mesh", np.array(ngmesh.Coordinates()))
    except Exception as exc:  # netgen.libngpy._meshing.NgException and whatever else Netgen raises
        result = ("error", f"{type(exc).__name__}: {exc}")
    (folder / "result.partial").write_bytes(pickle.dumps(result))
    os.replace(folder / "result.partial", folder / "result.pickle")


def _child(folder):
    """In a forked child of the server: record the process id, mesh, exit (never return to the server's loop)."""
    code = 1
    try:
        error = os.open(os.path.join(folder, "stderr"), os.O_WRONLY | os.O_CREAT | os.O_TRUNC)
        os.dup2(error, 2)
        with open(os.path.join(folder, "pid.partial"), "w") as pid:
            pid.write(str(os.getpid()))
        os.replace(os.path.join(folder, "pid.partial"), os.path.join(folder, "pid"))
        mesh(folder)
        code = 0
    except BaseException:  # the folder may be gone (the parent gave up): nothing to report to
        import traceback

        traceback.print_exc()
    finally:
        os._exit(code)


def serve():
    """The mesh server of the module docstring."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGCHLD, signal.SIG_IGN)  # children are reaped by the system
    import netgen.geom2d  # noqa: F401 -- loaded once here, inherited by every child
    import netgen.meshing  # noqa: F401
    import numpy  # noqa: F401

    while line := sys.stdin.readline():
        folder = line.strip()
        if folder and os.fork() == 0:
            _child(folder)


if __name__ == "__main__":
    if sys.argv[1] == "serve":
        serve()
    else:
        mesh(sys.argv[1])

r"""Solution files: a :class:`~ngdgfric.Solution` of any scene, with the problem it solves, in one file.

A solution file is an ``.npz`` (zip) archive, written atomically (:mod:`ngdgfric.files`), with the keys

* ``format`` (``"ngdgfric solution"``) and ``version`` (``VERSION``);
* ``u``, ``lam_tau``: the coefficient vectors of :math:`u_h` and of the multiplier :math:`\lambda_\tau`;
* ``orders``: the degree :math:`p_T` of every element; ``history``: the solver's convergence history;
* ``meta``: a JSON text (method, solver, iterations, timings, the mesh's curve order, a number penalty ``eta``,
  and for a reference its ``eta_h`` and description);
* ``objects``: NGSolve's own pickling (``pickle`` protocol 5) of the :class:`~ngdgfric.ContactProblem` (its
  geometry, data as numbers or CoefficientFunctions, per region and per side, contact pairs), the mesh (Netgen's
  archive: vertices, elements in their order, regions, boundary segments with their geometry parameters, the
  ``SplineGeometry`` and the curved elements), a penalty ``eta`` given as a CoefficientFunction and the solver's
  diagnostics of plain types (``info``: for contact pairs the forces at the pair points).

:func:`ngdgfric.load_solution` rebuilds the :class:`~ngdgfric.Discretization` and :class:`~ngdgfric.Contact` of that
problem on that mesh (the same spaces and numbering, the mesh curved to the same order) and puts the stored
coefficients into them, so the loaded Solution is the saved one: :func:`ngdgfric.energy_error`,
:func:`ngdgfric.estimate` and :func:`ngdgfric.force_balance` work on it.  The zip archive's CRC-32 checks refuse a
damaged file before anything is unpickled; the unpickler resolves only classes of NGSolve, Netgen and ngdgfric
and numpy's array reconstruction (``SAFE``), so a file can hold data but not call other functions.  Why NGSolve's
pickling rather than arrays, and why the stored curved elements are kept: :ref:`decisions-storage`.
"""

import io
import json
import pickle
import zipfile
import zlib
from numbers import Real
from pathlib import Path

import ngsolve as ngs
import numpy as np

from .bounds import DATA
from .contact import Contact
from .dg.discretization import Discretization
from .dg.dofs import element_dofs
from .files import atomic_path
from .solution import Solution

__all__ = ["save_solution", "load_solution", "solution_from_arrays", "read_archive", "is_solution_archive",
           "reference_meta", "check_storable_data", "FORMAT", "VERSION", "SAFE"]

FORMAT = "ngdgfric solution"
VERSION = 1
KEYS = ("format", "version", "meta", "objects", "u", "lam_tau", "orders", "history")
META = ("method", "solver", "iterations", "timings", "curve_order", "eta", "reference")
SAFE = {"numpy": {"dtype", "ndarray"}, "numpy._core.multiarray": {"scalar", "_reconstruct"},
        "numpy.core.multiarray": {"scalar", "_reconstruct"}, "numpy._core.numeric": {"_frombuffer"},
        "numpy.core.numeric": {"_frombuffer"}, "builtins": {"complex", "set", "frozenset", "slice", "range"}}
"""The functions the unpickler resolves besides classes of the packages ``PACKAGES``."""
PACKAGES = ("ngsolve", "netgen", "pyngcore", "ngdgfric")


def save_solution(sol, path, reference=None):
    r"""Store a solution, with the problem it solves, in one file.

    The file (``.npz``, written atomically; its contents: module docstring of :mod:`ngdgfric.storage`) holds the
    problem (geometry with regions, holes and arcs, data per region and per side, :math:`u_D`, symmetry sides,
    contact pairs), the mesh (curved elements to their order), the method, the element orders, :math:`u_h`, the
    multiplier and the solver's record.  :func:`ngdgfric.load_solution` reads it back in any later process.

    Parameters
    ----------
    sol : Solution
        The solution (:class:`~ngdgfric.Solution`).
    path : str or pathlib.Path
        The file to write (an existing one is replaced only once the new one is complete).
    reference : dict or None, optional
        For :func:`ngdgfric.save_reference`: ``{"eta_h": float, "description": str}``.  Default ``None``.

    Raises
    ------
    ValueError
        Naming the datum, if a datum of the problem (or the penalty ``eta``) cannot be stored: a
        CoefficientFunction that NGSolve cannot pickle, such as one made of ``specialcf.normal`` or
        ``specialcf.mesh_size``, or that does not read back.

    See Also
    --------
    ngdgfric.load_solution : Read it back.
    ngdgfric.save_reference : Store a solution as a reference, with its estimator.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> problem = ndf.example("half_disk")
    >>> sol = ndf.solve(problem, ndf.netgen_mesh(problem, 0.5), order=2)
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "half_disk.npz"
    >>> ndf.save_solution(sol, path)
    >>> loaded = ndf.load_solution(path)
    >>> loaded.ndof == sol.ndof, loaded.mesh.ne == sol.mesh.ne
    (True, True)
    """
    check_storable_data(sol.problem, sol.eta, path)
    eta = sol.eta if isinstance(sol.eta, Real) else None
    objects = dict(problem=sol.problem, mesh=sol.mesh, info=_plain(sol.info),
                   eta=sol.eta if isinstance(sol.eta, ngs.CoefficientFunction) else None)
    meta = dict(method=sol.method, solver=sol.solver, iterations=int(sol.iterations),
                timings={key: float(value) for key, value in sol.timings.items() if isinstance(value, Real)},
                curve_order=int(sol.mesh.GetCurveOrder()), eta=None if eta is None else float(eta),
                reference=reference)
    try:
        pickled = pickle.dumps(objects, protocol=5)
    except Exception as exc:  # NGSolve raises its own exception types
        raise ValueError(f"{sol.problem.name!r} cannot be stored in {path}: its geometry, mesh or solver "
                         f"diagnostics cannot be written ({type(exc).__name__}: {exc})") from None
    arrays = dict(format=np.array(FORMAT), version=np.array(VERSION), meta=np.array(json.dumps(meta)),
                  objects=np.frombuffer(pickled, dtype=np.uint8),
                  u=sol.u.vec.FV().NumPy().copy(), lam_tau=sol.lam_tau.vec.FV().NumPy().copy(),
                  orders=np.asarray(sol.orders, dtype=np.int64), history=np.asarray(sol.history, dtype=float))
    with atomic_path(path) as temporary, open(temporary, "wb") as handle:
        np.savez_compressed(handle, **arrays)


def check_storable_data(problem, eta=None, path=None):
    """ValueError naming the datum (and the file ``path`` not written) unless every datum of ``problem`` (and a
    penalty ``eta`` given as a CoefficientFunction) survives NGSolve's pickling: it is written and read back."""
    items = [(name, getattr(problem, name)) for name in DATA]
    items = [(f"{name}[{key!r}]" if isinstance(value, dict) else name, item) for name, value in items
             for key, item in (value.items() if isinstance(value, dict) else [(None, value)])]
    items += [] if not isinstance(eta, ngs.CoefficientFunction) else [("eta (the penalty)", eta)]
    where = "" if path is None else f" in {path}"
    for name, value in items:
        try:
            pickle.loads(pickle.dumps(value, protocol=5))
        except Exception as exc:  # NGSolve raises its own exception types (NgException, TypeError, ...)
            raise ValueError(f"{problem.name!r} cannot be stored{where}: its datum {name} ({type(value).__name__}) "
                             f"cannot be written and read back ({type(exc).__name__}: {exc}); give it as numbers or "
                             f"CoefficientFunctions of x and y") from None


def _plain(info):
    """The entries of a solver's ``info`` of plain types (numbers, strings, arrays and lists of them)."""
    def plain(value):
        if isinstance(value, (list, tuple)):
            return all(map(plain, value))
        return isinstance(value, (Real, str, np.ndarray)) or value is None

    return {key: value for key, value in info.items() if key != "state" and plain(value)}


class _Unpickler(pickle.Unpickler):
    """Resolves classes of ``PACKAGES`` and the functions ``SAFE`` only."""

    def find_class(self, module, name):
        if name in SAFE.get(module, ()):
            return super().find_class(module, name)
        if module.split(".")[0] in PACKAGES:
            found = super().find_class(module, name)
            if isinstance(found, type):
                return found
        raise pickle.UnpicklingError(f"{module}.{name} is not a class of {', '.join(PACKAGES)}")


def is_solution_archive(data):
    """Whether the arrays of an ``.npz`` (a dict) are a solution file's (its ``format`` key)."""
    return "format" in data and data["format"].dtype.kind == "U" and data["format"].ndim == 0 and \
        str(data["format"]) == FORMAT


def read_archive(path, kind="solution or reference file"):
    """The arrays of an ``.npz`` file as a dict; ValueError naming the file (and the ``kind`` of file expected) if it
    is no zip archive, a truncated or damaged one (CRC-32), or not an ``.npz``."""
    if not zipfile.is_zipfile(path):
        raise ValueError(f"{path}: not a {kind}: not an .npz (zip) archive, or a truncated one")
    try:
        with np.load(path, allow_pickle=False) as archive:
            return {key: archive[key] for key in archive.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, zlib.error, KeyError) as exc:
        raise ValueError(f"{path}: not a readable {kind} (.npz): {type(exc).__name__}: {exc}") from exc


def load_solution(path):
    """Read a solution file back: the :class:`~ngdgfric.Solution` that :func:`ngdgfric.save_solution` stored.

    The problem and the mesh come back as they were (the mesh curved to the same order, its elements in the same
    order); the discretisation and the contact data are rebuilt on them, and :math:`u_h` and the multiplier are the
    stored coefficients.

    Parameters
    ----------
    path : str or pathlib.Path
        A file written by :func:`ngdgfric.save_solution` (or by :func:`ngdgfric.save_reference` for a scene that is
        not one of the paper's polygons).

    Returns
    -------
    Solution
        The solution: its ``problem``, ``mesh``, ``method``, ``orders``, ``u``, ``lam_tau``, ``eta``,
        ``solver``, ``iterations``, ``history``, ``timings``, ``discretization`` and ``contact``; ``info`` holds
        the diagnostics of plain types (for contact pairs the forces and multiplier at the pair points).  The
        ``state`` of an inexact Newton solve is not stored (``None``): :func:`ngdgfric.finish` it before saving.

    Raises
    ------
    FileNotFoundError
        If there is no file at ``path``.
    ValueError
        Naming the file, if it is not a solution file (another format, a truncated or damaged archive, another
        version, missing keys, stored objects that do not read back) or its coefficients do not fit the rebuilt
        spaces.

    See Also
    --------
    ngdgfric.save_solution : Write one.
    ngdgfric.energy_error : A loaded solution serves as the reference of finer or coarser ones.
    """
    if not Path(path).exists():
        raise FileNotFoundError(f"no solution file at {path}")
    data = read_archive(path)
    if not is_solution_archive(data):
        raise ValueError(f"{path}: not a solution file (no format {FORMAT!r}: a reference file of the paper's "
                         f"polygons is read by load_reference)")
    return solution_from_arrays(path, data)


def solution_from_arrays(path, data):
    """The Solution of a solution file's arrays (``read_archive``; ``path`` for messages): ``load_solution``."""
    objects, meta = _contents(path, data)
    mesh, problem = objects["mesh"], objects["problem"]
    eta = objects["eta"] if objects["eta"] is not None else meta["eta"]
    if mesh.GetCurveOrder() != meta["curve_order"]:
        raise ValueError(f"{path}: the mesh came back curved to order {mesh.GetCurveOrder()}, stored: "
                         f"{meta['curve_order']}")
    try:  # the curved elements as stored (curving again moves them in round-off)
        disc = Discretization(problem, mesh, meta["method"], data["orders"], eta, penalty_check="ignore",
                              max_ndof=max(int(np.sum(element_dofs(data["orders"]))), 1),
                              curved=problem.geometry.curved)
    except ValueError as exc:
        raise ValueError(f"{path}: the stored problem, mesh and orders do not make a discretisation: {exc}") from exc
    contact = Contact(disc)
    u, lam_tau = ngs.GridFunction(disc.V), ngs.GridFunction(contact.Q)
    for name, gf in (("u", u), ("lam_tau", lam_tau)):
        if data[name].shape != (gf.space.ndof,) or not np.all(np.isfinite(data[name])):
            raise ValueError(f"{path}: {name} has {data[name].size} coefficients (finite: "
                             f"{bool(np.all(np.isfinite(data[name])))}) for a space of dimension {gf.space.ndof}")
        gf.vec.FV().NumPy()[:] = data[name]
    return Solution(problem=problem, mesh=disc.mesh, method=disc.method.name, max_order=disc.order, eta=disc.eta,
                    solver=meta["solver"], u=u, lam_tau=lam_tau, iterations=meta["iterations"],
                    history=data["history"].tolist(), timings=meta["timings"], discretization=disc,
                    contact=contact, info=objects["info"])


def reference_meta(path, data):
    """The ``reference`` entry (``eta_h``, ``description``) of a solution file's arrays, ValueError naming the file
    if it has none (a solution saved by ``save_solution``)."""
    meta = _meta(path, data)
    if not isinstance(meta["reference"], dict):
        raise ValueError(f"{path}: a solution file without a reference's eta_h: store it with save_reference")
    return meta["reference"]


def _contents(path, data):
    """(objects, meta) of a solution file's arrays; ValueError naming the file if keys are missing, the version
    is another, or the objects do not read back."""
    missing = [key for key in KEYS if key not in data]
    if missing:
        raise ValueError(f"{path}: not a solution file of this version: no {', '.join(missing)}")
    if data["version"].shape != () or int(data["version"]) != VERSION:
        raise ValueError(f"{path}: a solution file of version {data['version']}, this ngdgfric reads {VERSION}")
    orders = data["orders"]
    if orders.ndim != 1 or orders.dtype.kind not in "iu" or orders.size == 0:
        raise ValueError(f"{path}: orders has shape {orders.shape} and type {orders.dtype}, not one integer per "
                         f"element")
    meta = _meta(path, data)
    try:
        objects = _Unpickler(io.BytesIO(data["objects"].tobytes())).load()
    except Exception as exc:  # pickle and NGSolve's archives raise many types
        raise ValueError(f"{path}: the stored objects do not read back: {type(exc).__name__}: {exc}") from exc
    if not isinstance(objects, dict) or any(key not in objects for key in ("problem", "mesh", "info", "eta")):
        raise ValueError(f"{path}: not a solution file of this version: its stored objects lack entries")
    return objects, meta


def _meta(path, data):
    """The JSON entries ``meta`` of a solution file's arrays, ValueError naming the file if they are not there."""
    try:
        meta = json.loads(str(data["meta"]))
    except (KeyError, ValueError) as exc:
        raise ValueError(f"{path}: not a solution file: its meta is not JSON ({exc})") from exc
    if not isinstance(meta, dict) or any(key not in meta for key in META):
        raise ValueError(f"{path}: not a solution file of this version: its meta lacks entries")
    return meta

r"""Reference solutions: a very accurate :math:`u_h` stored in a small file, and true errors against it.

A reference is one ``.npz`` file: the mesh (vertices, triangles, labelled boundary segments),
the order of every element, the coefficient vector of :math:`u_h`, its estimator :math:`\eta_h`, and a
fingerprint of its problem (``fingerprint``) that :func:`ngdgfric.load_reference` checks; a scene these arrays cannot
hold (regions, holes, arcs, data per region or per side, :math:`u_D \ne 0`, symmetry sides, contact pairs) is stored
as a solution file (:mod:`ngdgfric.storage`), whose stored problem is its fingerprint.  The error
of another solution :math:`u_h` (on any mesh of the same domain) is

.. math::

    \|u_{ref} - u_h\|_h^2 = \sum_T \int_T C \epsilon(u_{ref} - u_h) : \epsilon(u_{ref} - u_h) \, dx
                            + \sum_{e \in \mathcal{E}_h^o} h_e^{-1} \|[u_h]\|_e^2,

the volume part by a Gauss rule of degree :math:`2 p + 4` on :math:`u_h`'s elements, with :math:`u_{ref}`
evaluated at those points by point search in its mesh; the jump part is exact for the exact solution :math:`u`
(it is continuous and zero on :math:`\Gamma_D`, so :math:`[u - u_h] = -[u_h]`) and so uses :math:`u_h` alone.
The DG energy norm :math:`\|\cdot\|_h` of Section 3 itself (:func:`ngdgfric.energy_norm`, :mod:`ngdgfric.energy`)
measures errors against exact solutions given as CoefficientFunctions (manufactured solutions).
"""

from dataclasses import dataclass
from pathlib import Path

import ngsolve as ngs
import numpy as np

from .bounds import DATA as BOUNDED
from .checks import check_solution
from .dg.discretization import MAX_DEGREE, dg_space
from .dg.forms import has_dirichlet_data
from .energy import EXACT_ORDER, difference, energy_matrix, energy_norm, energy_norm_squared_parts, problem_of
from .files import atomic_path
from .meshes import mesh_arrays, mesh_from_arrays
from .problem import Polygon, coefficient, is_number, pattern, strain
from .storage import is_solution_archive, read_archive, reference_meta, save_solution, solution_from_arrays
from .transfer import discontinuous

__all__ = ["Reference", "save_reference", "load_reference", "energy_error", "reference_errors", "fingerprint",
           "energy_norm", "energy_norm_squared_parts", "energy_matrix", "difference", "gridfunction_errors",
           "locate", "check_same_problem", "sample_points", "EXACT_ORDER"]


@dataclass
class Reference:
    r"""A stored reference solution, as :func:`ngdgfric.load_reference` returns it.

    A very accurate :math:`u_h` to measure the true errors of other solutions against
    (:func:`ngdgfric.energy_error`).

    Parameters
    ----------
    problem : ContactProblem
        The problem it solves.
    mesh : ngsolve.Mesh
        Its mesh, rebuilt from the stored arrays (or read back from a solution file, :mod:`ngdgfric.storage`).
    u : ngsolve.GridFunction
        The displacement, DG coefficients of each element's degree on ``mesh`` (from a solution file: the stored
        :math:`u_h` on its own space).
    orders : numpy.ndarray
        The polynomial degree of every element.
    eta_h : float
        Its estimator value :math:`\eta_h`.
    description : str
        How it was made (free text).

    See Also
    --------
    ngdgfric.save_reference : Store a solution as a reference.
    """

    problem: object
    mesh: object
    u: object
    orders: np.ndarray
    eta_h: float
    description: str


def save_reference(sol, path, eta_h, description=""):
    r"""Store a solution as a reference solution file.

    The file (``.npz``, written atomically) holds the mesh, the element orders, the displacement, ``eta_h`` and a
    fingerprint of the problem (``fingerprint``) that :func:`ngdgfric.load_reference` checks.  The displacement is
    stored as the DG coefficients of each element's degree, also for the conforming baseline (its :math:`u_h`
    copied exactly into :math:`L^2`: ``discontinuous`` of :mod:`ngdgfric.transfer`), so a reference of any method
    loads alike.

    Parameters
    ----------
    sol : Solution
        The solution (:class:`~ngdgfric.Solution`).
    path : str or pathlib.Path
        The file to write.
    eta_h : float
        The solution's estimator value :math:`\eta_h` (:func:`ngdgfric.estimate`).
    description : str, optional
        How it was made (free text).  Default ``""``.

    Raises
    ------
    ValueError
        Naming the datum, if a datum of the problem cannot be stored (:func:`ngdgfric.save_solution`).

    Notes
    -----
    A problem of the paper's kind (one polygon, one value per datum, :math:`u_D = 0`, no symmetry sides) is stored
    as the arrays above.  Any other scene (regions, holes, arcs, data per region or per side, :math:`u_D \ne 0`,
    symmetry sides, contact pairs, curved elements) is stored as a solution file (:func:`ngdgfric.save_solution`,
    :mod:`ngdgfric.storage`) with ``eta_h`` and ``description``: the problem itself is its fingerprint.
    """
    if array_reasons(sol.problem):
        save_solution(sol, path, reference=dict(eta_h=float(eta_h), description=str(description)))
        return
    u, orders = discontinuous(sol)
    points, triangles, segments, labels = mesh_arrays(sol.mesh)
    with atomic_path(path) as temporary:
        with open(temporary, "wb") as handle:
            np.savez_compressed(handle, points=points, triangles=triangles, segments=segments, labels=labels,
                                orders=orders, u=u.vec.FV().NumPy(), eta_h=eta_h,
                                method=sol.method, description=description,
                                **fingerprint(sol.problem, sol.mesh, points, triangles, segments))


# the data whose values at sample points of the reference's mesh identify the problem (8 columns)
DATA = ("E", "f", "g", "g_a", "c_n", "c_tau")
SAMPLES = 500  # sample triangles and boundary edges (each at most)


def fingerprint(problem, mesh, points, triangles, segments):
    """Arrays that identify ``problem``: its geometry, boundary names and numbers, and its data at
    the centroids of up to SAMPLES triangles and the midpoints of up to SAMPLES boundary edges of
    ``mesh`` (given by its :func:`mesh_arrays`)."""
    where = sample_points(points, triangles, segments)
    varying_nu = {} if is_number(problem.nu) else dict(fp_nu=_values_at(problem.nu, mesh, where))
    return dict(fp_vertices=np.asarray(problem.geometry.vertices), fp_labels=np.asarray(problem.geometry.labels),
                fp_names=np.asarray(problem.boundary_names()), fp_numbers=_numbers(problem),
                fp_points=where, fp_data=_data_at(problem, mesh, where), **varying_nu)


def sample_points(points, triangles, segments=None):
    """The centroids of up to SAMPLES triangles and the midpoints of up to SAMPLES boundary ``segments`` (None: none)
    of a mesh given by its :func:`ngdgfric.meshes.mesh_arrays`, evenly spread over their numbers, as a (k, 2)
    array."""
    def sample(cells):
        return points[cells[np.unique(np.linspace(0, len(cells) - 1, min(len(cells), SAMPLES)).astype(int))]].mean(1)

    centres = sample(triangles)
    return centres if segments is None else np.concatenate([centres, sample(segments)])


def array_reasons(problem):
    """Why a reference of ``problem`` cannot be stored as arrays and identified by ``fingerprint`` (an empty list if it
    can): the mesh is stored as arrays (straight triangles, one region) and the fingerprint holds a polygon, one value
    per datum and u_D = 0; other scenes are stored as solution files (:mod:`ngdgfric.storage`)."""
    return [reason for reason, found in (
        ("its domain is not a polygon (curved sides, holes or regions need the geometry to rebuild the mesh)",
         not isinstance(problem.geometry, Polygon)),
        ("it has data per region or per side", problem.per_part),
        ("it prescribes a displacement u_D != 0", has_dirichlet_data(problem)),
        ("it has symmetry sides", bool(problem.sides("symmetry"))),
        ("it has contact pairs", bool(problem.pairs))) if found]


def check_storable(problem):
    """ValueError naming the reasons of ``array_reasons``, if there are any."""
    reasons = array_reasons(problem)
    if reasons:
        raise ValueError(f"references are stored for problems on one polygon with the paper's boundary conditions; "
                         f"{problem.name!r} cannot be: {'; '.join(reasons)}")


def _numbers(problem):
    """(nu, m_n, m_t), nu as NaN where it varies (then its values are the key ``fp_nu``)."""
    return np.array([float(problem.nu) if is_number(problem.nu) else np.nan, problem.m_n, problem.m_t])


def _values_at(datum, mesh, where):
    """The values (k, components) of a datum at the points ``where`` (k, 2) of ``mesh``."""
    return np.asarray(coefficient(datum)(mesh(where[:, 0], where[:, 1]))).reshape(len(where), -1)


def _data_at(problem, mesh, where):
    """(k, 8) values of E, f, g, g_a, c_n, c_tau at the points ``where`` (k, 2) of ``mesh``."""
    return np.hstack([_values_at(getattr(problem, name), mesh, where) for name in DATA])


def load_reference(path, problem):
    """The reference solution stored in a file for a problem.

    Parameters
    ----------
    path : str or pathlib.Path
        A file written by :func:`ngdgfric.save_reference`: the arrays of a problem of the paper's kind, or a solution
        file (:func:`ngdgfric.save_solution`) with the reference's ``eta_h`` for any other scene.
    problem : ContactProblem
        The problem the reference must solve.

    Returns
    -------
    Reference
        The reference (:class:`~ngdgfric.Reference`).

    Raises
    ------
    FileNotFoundError
        If there is no file at ``path`` (``scripts/reference.py`` makes the references of the paper's examples).
    ValueError
        Naming the file and the defect, if the file is not a reference (unreadable, keys missing, arrays of wrong
        shape or type, indices out of range, non-finite values) or was made for another problem (its fingerprint:
        geometry, names, numbers, data at sample points; for a solution file the stored problem, compared as
        ``check_same_problem`` compares two solutions', and its contact pairs).
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"no reference solution at {path}: run scripts/reference.py to make it")
    data = _read(path)
    if is_solution_archive(data):
        return _scene_reference(path, data, problem)
    _check_arrays(path, data)
    _check_fingerprint(path, data, problem)
    try:
        mesh = mesh_from_arrays(problem, data["points"], data["triangles"], data["segments"], data["labels"])
    except ValueError as exc:
        raise ValueError(f"{path}: not a mesh of this problem: {exc}") from exc
    names = [f"{n}{s}" for n in DATA for s in (("[0]", "[1]") if n in ("f", "g") else ("",))]
    stored, found = [data["fp_data"]], [_data_at(problem, mesh, data["fp_points"])]
    if "fp_nu" in data:
        stored.append(data["fp_nu"].reshape(-1, 1))
        found.append(_values_at(problem.nu, mesh, data["fp_points"]))
        names.append("nu")
    stored, found = np.hstack(stored), np.hstack(found)
    differ = np.abs(found - stored) > 1e-10 * (np.abs(stored) + np.abs(stored).max(0))
    if np.any(differ):
        row, column = map(int, np.argwhere(differ)[0])
        x, y = data["fp_points"][row]
        raise ValueError(f"{path}: made for another problem: {names[column]} = {stored[row, column]:.10g} there, "
                         f"{found[row, column]:.10g} here at ({x:.6g}, {y:.6g})")
    u = ngs.GridFunction(dg_space(mesh, data["orders"]))
    if u.space.ndof != data["u"].size:
        raise ValueError(f"{path}: {data['u'].size} coefficients for a space of dimension {u.space.ndof}")
    u.vec.FV().NumPy()[:] = data["u"]
    return Reference(problem, mesh, u, data["orders"], float(data["eta_h"]), str(data["description"]))



KEYS = ("points", "triangles", "segments", "labels", "orders", "u", "eta_h", "description", "fp_vertices", "fp_labels",
        "fp_names", "fp_numbers", "fp_points", "fp_data")


def _read(path):
    """The arrays of an .npz file (``read_archive``), ValueError naming the file if it cannot be read or is no
    reference."""
    data = read_archive(path, "reference file")
    if is_solution_archive(data):
        return data
    missing = [key for key in KEYS if key not in data]
    if missing:
        raise ValueError(f"{path}: not a reference file of this version: no {', '.join(missing)} (regenerate it "
                         f"with scripts/reference.py or save_reference)")
    return data


def _scene_reference(path, data, problem):
    """The Reference of a solution file's arrays with a reference entry; ValueError naming the file if its stored
    problem is not ``problem``."""
    meta = reference_meta(path, data)
    sol = solution_from_arrays(path, data)
    try:
        check_same_problem(sol, _Approximation(problem, sol.mesh, sol.u))
    except ValueError as exc:
        raise ValueError(f"{path}: made for another problem: {exc}") from None
    if sol.problem.pairs != problem.pairs:
        raise ValueError(f"{path}: made for another problem: its contact pairs are {sol.problem.pairs}, here "
                         f"{problem.pairs}")
    return Reference(problem, sol.mesh, sol.u, sol.orders, float(meta["eta_h"]), str(meta["description"]))


def _check_arrays(path, data):
    """ValueError naming the file and the array unless shapes, types, index ranges and values are sane."""
    def fail(message):
        raise ValueError(f"{path}: {message}")

    def need(key, ndim, columns=None, kind="f", finite=True):
        array = data[key]
        if array.ndim != ndim or (columns is not None and array.shape[-1] != columns) or array.dtype.kind not in kind:
            fail(f"{key} has shape {array.shape} and type {array.dtype}, not as a reference stores it")
        if kind == "f" and finite and not np.all(np.isfinite(array)):
            fail(f"{key} holds non-finite values")
        return array

    points = need("points", 2, 2)
    for key in ("triangles", "segments"):
        cells = need(key, 2, 3 if key == "triangles" else 2, kind="iu")
        if cells.size and (cells.min() < 0 or cells.max() >= len(points)):
            fail(f"{key} refer to vertices outside 0..{len(points) - 1} (range {cells.min()}..{cells.max()})")
    if need("labels", 1, kind="U").shape[0] != len(data["segments"]):
        fail(f"{len(data['labels'])} labels for {len(data['segments'])} boundary segments")
    orders = need("orders", 1, kind="iu")
    if orders.shape[0] != len(data["triangles"]) or (orders.size and not 1 <= orders.min() <= orders.max()
                                                      <= MAX_DEGREE):
        fail(f"orders: {orders.shape[0]} orders in {orders.min(initial=0)}..{orders.max(initial=0)} for "
             f"{len(data['triangles'])} triangles (need one in 1..{MAX_DEGREE} each)")
    need("u", 1)
    if need("eta_h", 0).item() < 0:
        fail(f"eta_h = {data['eta_h'].item()} is negative")
    need("fp_points", 2, 2)
    if need("fp_data", 2, 8).shape[0] != len(data["fp_points"]):
        fail("fp_data does not match fp_points")
    need("fp_vertices", 2, 2)
    if not np.all(np.isfinite(need("fp_numbers", 1, finite=False)[1:])):
        fail("fp_numbers holds non-finite values")
    if "fp_nu" in data and need("fp_nu", 2, 1).shape[0] != len(data["fp_points"]):
        fail("fp_nu does not match fp_points")
    need("fp_labels", 1, kind="U")
    need("fp_names", 1, kind="U")


def _check_fingerprint(path, data, problem):
    """ValueError unless the reference was made for a problem with ``problem``'s geometry, names and numbers."""
    check_storable(problem)
    geometry = problem.geometry
    stored = data["fp_vertices"]
    if stored.shape != (len(geometry.vertices), 2) or not np.allclose(stored, geometry.vertices, rtol=0,
                                                                        atol=1e-12 * np.ptp(stored)):
        raise ValueError(f"{path}: made for another problem: its polygon is {stored.tolist()}, this problem's "
                         f"{list(geometry.vertices)}")
    if data["fp_labels"].tolist() != list(geometry.labels) or data["fp_names"].tolist() != list(
            problem.boundary_names()):
        raise ValueError(f"{path}: made for another problem: side labels {data['fp_labels'].tolist()} and names "
                         f"{data['fp_names'].tolist()}, here {list(geometry.labels)} and "
                         f"{list(problem.boundary_names())}")
    numbers = _numbers(problem)
    if data["fp_numbers"].shape != (3,) or not np.allclose(data["fp_numbers"], numbers, rtol=1e-12, atol=0,
                                                           equal_nan=True):
        raise ValueError(f"{path}: made for another problem: (nu, m_n, m_t) = {tuple(data['fp_numbers'].tolist())} "
                         f"there, {tuple(numbers.tolist())} here (nan: nu varies)")


def energy_error(sol, reference):
    r"""The true error :math:`\|u_{ref} - u_h\|_h` of a solution against a reference solution.

    The norm and how it is computed: module docstring of :mod:`ngdgfric.reference` (the function
    ``reference_errors`` there also returns its parts, the relative error and the :math:`H^1` and :math:`L^2`
    errors).

    Parameters
    ----------
    sol : Solution
        The solution :math:`u_h` (or a :class:`~ngdgfric.Reference`: anything with ``problem``, ``mesh`` and
        ``u``).
    reference : Reference or Solution
        A :class:`~ngdgfric.Reference`, or a finer Solution of the same problem (also one read back by
        :func:`ngdgfric.load_solution`).

    Returns
    -------
    float
        :math:`\|u_{ref} - u_h\|_h`.

    Raises
    ------
    ValueError
        If ``sol`` or ``reference`` is not a Solution or Reference, ``reference`` is a Solution of another problem
        (its geometry, the part of a side, the material or other data differ), or the meshes are of different
        domains.

    See Also
    --------
    ngdgfric.energy_norm : The error against an exact solution given as a CoefficientFunction.
    """
    return reference_errors(sol, reference)["energy"]


def reference_errors(sol, reference):
    """Norms of u_ref - u_h for a Solution against a reference solution (module docstring).

    ``reference``: a :class:`Reference` (checked against its problem when loaded), or any Solution of the same
    problem (a finer one, or one read back by :func:`ngdgfric.load_solution`); ValueError if its geometry, numbers
    or data differ from ``sol``'s.  Returns a dict:
    ``energy`` = |||u_ref - u_h|||_h with its parts ``energy_volume`` and ``energy_jumps`` (the jumps [u_h] of
    u_h's edges, u_h - u_D on Gamma_D: those of the exact solution vanish), ``relative`` = energy / (int C
    eps(u_ref) : eps(u_ref))^(1/2), ``h1`` (broken H1 seminorm), ``l2``; all volume integrals by the same Gauss
    rule on u_h's elements (degree 2 p + 4; exact when u_ref is a polynomial of degree <= p + 3 there, else a
    quadrature of a function as smooth as u_ref is on u_h's elements); ``moved_points``: the number of those
    points that lie outside the reference's mesh (two meshes of a curved side differ by their chords or curved
    elements), where u_ref is evaluated a little inside (:func:`locate`).
    """
    check_solution(sol, "sol", reference=True)
    check_solution(reference, "reference", reference=True)
    mesh, problem = sol.mesh, problem_of(sol)
    if not isinstance(reference, Reference):
        check_same_problem(sol, reference)
    rule = ngs.IntegrationRule(ngs.TRIG, 2 * sol.u.space.globalorder + 4)
    points = mesh.MapToAllElements({ngs.TRIG: rule}, ngs.VOL)
    xy = np.asarray(ngs.CF((ngs.x, ngs.y))(points)).reshape(-1, 2)
    centres = np.repeat(xy.reshape(mesh.ne, -1, 2).mean(axis=1), len(rule.weights), axis=0)
    foreign, moved = locate(reference.mesh, xy, centres)
    area = ngs.Integrate(ngs.CF(1) * ngs.dx, mesh, element_wise=True).NumPy()
    weights = 2 * np.outer(area, np.asarray(rule.weights)).ravel()

    def values(cf, at, size):
        return np.asarray(cf(at)).reshape(len(xy), size)

    mu, lam = (values(coefficient(datum), points, 1)[:, 0] for datum in (problem.mu, problem.lam))

    def energy_density(e):  # C e : e for a symmetric e (rows of 4), written out: lam tr(e)^2 + 2 mu e : e
        return lam * (e[:, 0] + e[:, 3]) ** 2 + 2 * mu * np.sum(e**2, axis=1)

    strain_ref = values(strain(reference.u), foreign, 4)
    difference = strain_ref - values(strain(sol.u), points, 4)
    gradient = values(ngs.Grad(reference.u), foreign, 4) - values(ngs.Grad(sol.u), points, 4)
    displacement = values(reference.u, foreign, 2) - values(sol.u, points, 2)
    volume = float(np.sum(weights * energy_density(difference)))
    shift = coefficient(problem.u_D) if has_dirichlet_data(problem) else None  # the exact u has u = u_D there
    _, jumps = energy_norm_squared_parts(problem, mesh, sol.u, dirichlet_value=shift)
    energy = float(np.sqrt(volume + jumps))
    return dict(energy=energy, energy_volume=float(np.sqrt(volume)), energy_jumps=float(np.sqrt(jumps)),
                relative=energy / float(np.sqrt(np.sum(weights * energy_density(strain_ref)))),
                h1=float(np.sqrt(np.sum(weights * np.sum(gradient**2, axis=1)))),
                l2=float(np.sqrt(np.sum(weights * np.sum(displacement**2, axis=1)))), moved_points=moved)


def locate(mesh, xy, centres):
    """(MeshPoints of ``mesh`` at the points ``xy`` (k, 2), the number of points moved): a point outside ``mesh`` is
    moved towards its ``centres`` row (the centre of the element it belongs to on the other mesh) by the smallest of
    1e-6, 1e-5, ..., 1 times the way that brings it inside.  Two meshes of a curved side differ near it (chords at
    p = 1, curved elements of different sizes): points of one lie up to the distance of the two boundaries outside
    the other.  ValueError if a point is not found even at its centre (meshes of different domains)."""
    found = mesh(xy[:, 0], xy[:, 1])
    missing = np.flatnonzero(found["nr"] < 0)
    moved = missing.size
    for fraction in 10.0 ** np.arange(-6, 1):
        if not missing.size:
            break
        shifted = xy[missing] + fraction * (centres[missing] - xy[missing])
        again = mesh(shifted[:, 0], shifted[:, 1])
        inside = again["nr"] >= 0
        found[missing[inside]] = again[inside]
        missing = missing[~inside]
    if missing.size:
        x, y = xy[missing[0]]
        raise ValueError(f"{missing.size} points of u_h's mesh, e.g. ({x:.6g}, {y:.6g}), lie outside the reference's "
                         f"mesh and so do their elements' centres: meshes of different domains?")
    return found, moved


def check_same_problem(sol, other):
    """ValueError unless the solution ``other`` (anything with ``problem``) is of ``sol``'s problem: the same geometry,
    every side of it in the same boundary part (Dirichlet, traction, contact, symmetry), and every datum of
    :data:`ngdgfric.bounds.DATA` the same on every region and side where it enters (:meth:`ContactProblem.value_on`):
    the material and body force at the centroids of ``sol``'s elements of the region, the boundary data at the Gauss
    points of its edges of the side (:data:`SIDE_RULE`), to 1e-10; the exponents exactly."""
    mine, theirs = sol.problem, other.problem
    if mine is theirs:
        return
    if mine.geometry != theirs.geometry:
        raise ValueError(f"the reference solves another problem: its geometry differs from u_h's ({theirs.name!r} "
                         f"against {mine.name!r})")
    roles, their_roles = mine.roles(), theirs.roles()
    for side, part in roles.items():
        if their_roles[side] != part:
            raise ValueError(f"the reference solves another problem: side {side!r} is a {their_roles[side]} side "
                             f"there, a {part} side for u_h")
    for name, datum in BOUNDED.items():
        parts = mine.geometry.region_names if datum.part == "region" else [side for side, part in roles.items()
                                                                            if part == datum.part]
        for part in parts:
            a, b = (problem.value_on(name, part) for problem in (mine, theirs))
            if datum.kind == "number":
                if a != b:
                    raise ValueError(f"the reference solves another problem: {name} is {b!r} there, {a!r} for u_h "
                                     f"on {part!r}")
                continue
            _check_values(sol.mesh, name, part, datum.part == "region", a, b)


SIDE_RULE = ngs.IntegrationRule(ngs.SEGM, 5)  # where check_same_problem compares the data of a side


def _check_values(mesh, name, part, region, a, b):
    """ValueError naming datum ``name`` and a point unless the data ``a`` (u_h's) and ``b`` (the reference's) agree
    to 1e-10 on ``part`` of ``mesh`` (a ``region``, else a side)."""
    where = mesh.Materials(pattern([part])) if region else mesh.Boundaries(pattern([part]))
    rule = ngs.IntegrationRule([(1 / 3, 1 / 3)], [0.5]) if region else SIDE_RULE
    points = mesh.MapToAllElements({ngs.TRIG if region else ngs.SEGM: rule}, where)
    a, b = (np.asarray(coefficient(value)(points)).reshape(len(points), -1) for value in (a, b))
    differ = np.abs(b - a) > 1e-10 * (np.abs(a) + np.abs(a).max())
    if np.any(differ):
        row, column = map(int, np.argwhere(differ)[0])
        x, y = float(ngs.x(points[row])), float(ngs.y(points[row]))
        raise ValueError(f"the reference solves another problem: {name} on {part!r} is {b[row, column]:.10g} there, "
                         f"{a[row, column]:.10g} for u_h at ({x:.6g}, {y:.6g})")


@dataclass(frozen=True)
class _Approximation:
    problem: object
    mesh: object
    u: object


def gridfunction_errors(problem, mesh, u, reference):
    """:func:`reference_errors` of a displacement GridFunction ``u`` of any H1 or DG vector space on ``mesh``
    (for example a conforming u_h of another code) against a :class:`Reference`: the same norms as for a
    Solution; for a continuous u_h with u_h = 0 on Gamma_D the jump part is zero."""
    return reference_errors(_Approximation(problem, mesh, u), reference)

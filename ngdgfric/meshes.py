r"""Meshes of a problem's domain with named sides and regions.

The boundary names of a mesh are the problem's side names (:math:`\Gamma_D`, :math:`\Gamma_F`, :math:`\Gamma_C`,
symmetry), its materials the names of the regions.  The mesh generators estimate the number of elements before
meshing and refuse above ``max_elements`` (default ``MAX_ELEMENTS``, :math:`10^6`), with the estimate in the
message: :math:`h = 10^{-5}` on the unit square asked for 74 GiB, and Netgen with ``maxh = 1e-9`` grew past
2 GB without reacting to Ctrl-C.
"""

import math

import netgen.meshing as nm
import ngsolve as ngs
import numpy as np

from .dg.dofs import element_dofs
from .domain import INTERFACE
from .mesher import default_timeout, generate, triangles_of

__all__ = ["uniform_mesh", "grid_mesh", "grid_counts", "netgen_mesh", "refine", "refined", "grid_arrays",
           "mesh_from_arrays", "mesh_arrays", "check_mesh", "facet_indicator", "element_diameters",
           "smallest_angles", "minimum_angle", "triangle_corners", "estimated_elements", "snapshot", "same_mesh",
           "nested", "curve", "MAX_ELEMENTS"]

DIAGONALS = ("sw-ne", "nw-se")
MAX_ELEMENTS = 10**6
FIT = 1e-8  # a mesh fits the polygon when its boundary lies on it within FIT x diameter and the areas agree to FIT


def estimated_elements(problem, h=None, maxh=None):
    """Number of triangles of ``uniform_mesh(problem, h)`` (exact) or ``netgen_mesh(problem, maxh)``
    (2.31 area / maxh^2 + perimeter / maxh: equilateral triangles of side maxh and one layer along
    the boundary; on Example 6.1 1.50, 1.18, 1.07, 1.03 times Netgen's count for maxh = 0.2, 0.1,
    0.05, 0.02)."""
    geometry = problem.geometry
    with np.errstate(over="ignore"):  # a float, inf when it overflows (h = 1e-300)
        if h is not None:
            x0, y0, x1, y1 = geometry.bounds
            return 2 * np.ceil(np.float64(x1 - x0) / h) * np.ceil(np.float64(y1 - y0) / h)
        return float(np.ceil(4 / math.sqrt(3) * geometry.area / np.float64(maxh) ** 2 + geometry.perimeter / maxh))


def _is_size(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and value > 0


def _check_elements(problem, max_elements, **size):
    (name, value), = size.items()
    estimate = estimated_elements(problem, **size)
    if max_elements is not None and estimate > max_elements:
        raise ValueError(f"{name} = {value:g} would make about {estimate:.3g} elements "
                         f"({element_dofs(1) * estimate:.3g} DOFs at P1), more than max_elements = {max_elements:.3g}; "
                         f"pass a larger max_elements to allow it")


def uniform_mesh(problem, h, diagonal="sw-ne", max_elements=MAX_ELEMENTS):
    r"""Structured mesh of the problem's rectangle: squares of side ``h``, each cut by one diagonal.

    This is the kind of mesh behind the paper's :math:`h = 2^{-k}` (Section 6).  Meshes for :math:`h` and
    :math:`h/2` are nested.

    Parameters
    ----------
    problem : ContactProblem
        A problem whose geometry is an axis-parallel rectangle (:class:`~ngdgfric.Polygon`).
    h : float
        The side of the squares; the side lengths of the rectangle must be integer multiples of it.
    diagonal : str, optional
        ``"sw-ne"`` (from the lower-left to the upper-right corner of each square) or ``"nw-se"``.
        Default ``"sw-ne"``.
    max_elements : int or None, optional
        The most triangles allowed; None: no limit.  Default ``MAX_ELEMENTS`` (:math:`10^6`).

    Returns
    -------
    ngsolve.Mesh
        The mesh, its boundaries named by the rectangle's side labels.

    Raises
    ------
    ValueError
        If the geometry is not a rectangle, ``h`` does not divide its sides, ``diagonal`` is unknown, or the
        mesh would have more than ``max_elements`` triangles.

    See Also
    --------
    ngdgfric.netgen_mesh : Unstructured meshes of any domain.

    Notes
    -----
    Not ``ngsolve.meshes.MakeStructured2DMesh``: it numbers the two triangles of each square together, cuts only
    along one diagonal and names the sides bottom/right/top/left, and its vertices differ from these in the last
    bit (1.1e-16 at :math:`h = 1/20`); every stored result would move in round-off.

    Examples
    --------
    >>> problem = ndf.example("6.1")
    >>> mesh = ndf.uniform_mesh(problem, 0.25)
    >>> mesh.ne, sorted(mesh.GetBoundaries())
    (32, ['contact', 'dirichlet', 'traction'])
    """
    geometry = problem.geometry
    if not geometry.is_rectangle:
        raise ValueError("uniform_mesh needs a rectangle geometry; use netgen_mesh for a general polygon")
    if diagonal not in DIAGONALS:
        raise ValueError(f"diagonal must be one of {DIAGONALS}, got {diagonal!r}")
    if not (_is_size(h)):
        raise ValueError(f"h must be a positive number, got {h!r}")
    _check_elements(problem, max_elements, h=h)
    x0, y0, x1, y1 = geometry.bounds
    for length in (x1 - x0, y1 - y0):
        n = length / h
        if abs(n - round(n)) > 1e-9 * max(1.0, n) or round(n) < 1:
            raise ValueError(f"h = {h} does not divide the side length {length} of the rectangle")
    return grid_mesh(problem, h, diagonal=diagonal, max_elements=None)  # its cells: squares of side h


def grid_mesh(problem, h, refinements=0, diagonal="sw-ne", max_elements=MAX_ELEMENTS):
    """Structured mesh of the problem's rectangle with cells of sides at most ``h``: ceil(width / h) x
    ceil(height / h) rectangles, each then cut into 2^``refinements`` x 2^``refinements`` (so the meshes of
    refinements 0, 1, 2 ... are nested) and every cell by one ``diagonal``.  :func:`uniform_mesh` with
    h / 2^refinements itself wherever ``h`` divides both sides (the paper's meshes); the default meshes of
    rectangles of any size (1.3 x 0.7, or 0.01 x 0.01 in metres), which ``uniform_mesh`` refuses."""
    if not problem.geometry.is_rectangle:
        raise ValueError("grid_mesh needs a rectangle geometry; use netgen_mesh for a general polygon")
    if not (_is_size(h)):
        raise ValueError(f"h must be a positive number, got {h!r}")
    if not (isinstance(refinements, int) and 0 <= refinements <= 60):
        raise ValueError(f"refinements must be an integer in 0..60, got {refinements!r}")
    if diagonal not in DIAGONALS:
        raise ValueError(f"diagonal must be one of {DIAGONALS}, got {diagonal!r}")
    nx, ny = grid_counts(problem, h, refinements)
    if max_elements is not None and 2 * nx * ny > max_elements:
        raise ValueError(f"h = {h:g} with {refinements} refinements would make {2 * nx * ny:.3g} elements "
                         f"({element_dofs(1) * 2 * nx * ny:.3g} DOFs at P1), more than max_elements = "
                         f"{max_elements:.3g}; pass a larger max_elements to allow it")
    points, triangles, segments, sides = grid_arrays(problem.geometry.bounds, nx, ny, diagonal)
    return mesh_from_arrays(problem, points, triangles, segments, np.asarray(problem.geometry.labels)[sides])


def grid_counts(problem, h, refinements=0):
    """(nx, ny): the cells of :func:`grid_mesh` along the width and the height of the problem's rectangle
    (2 nx ny triangles), computed before meshing."""
    x0, y0, x1, y1 = problem.geometry.bounds
    return tuple(max(1, math.ceil(n - 1e-9 * max(1.0, n))) * 2**refinements for n in ((x1 - x0) / h, (y1 - y0) / h))


def grid_arrays(bounds, nx, ny, diagonal="sw-ne"):
    """(points, triangles, segments, sides) of the rectangle ``bounds`` = (x0, y0, x1, y1) cut into nx x ny
    rectangles, each cut by one diagonal (``"sw-ne"`` or ``"nw-se"``), for :func:`mesh_from_arrays`: the segments
    oriented with the rectangle on their left, ``sides`` the number of the side each lies on (0 bottom, 1 right,
    2 top, 3 left: the order of :meth:`ngdgfric.problem.Polygon.rectangle`'s labels)."""
    x0, y0, x1, y1 = bounds
    xs, ys = np.meshgrid(np.linspace(x0, x1, nx + 1), np.linspace(y0, y1, ny + 1))
    j, i = np.meshgrid(np.arange(nx), np.arange(ny))
    sw = (i * (nx + 1) + j).ravel()
    se, nw = sw + 1, sw + nx + 1
    ne = nw + 1
    if diagonal == "sw-ne":
        triangles = np.concatenate([np.column_stack([sw, se, ne]), np.column_stack([sw, ne, nw])])
    else:
        triangles = np.concatenate([np.column_stack([sw, se, nw]), np.column_stack([se, ne, nw])])
    bottom = np.arange(nx)
    right = np.arange(ny) * (nx + 1) + nx
    top = ny * (nx + 1) + np.arange(nx, 0, -1)
    left = np.arange(ny, 0, -1) * (nx + 1)
    segments = [np.column_stack([bottom, bottom + 1]), np.column_stack([right, right + nx + 1]),
                np.column_stack([top, top - 1]), np.column_stack([left, left - (nx + 1)])]
    sides = np.concatenate([np.full(len(side), k) for k, side in enumerate(segments)])
    return np.column_stack([xs.ravel(), ys.ravel()]), triangles, np.concatenate(segments), sides


def mesh_from_arrays(problem, points, triangles, segments, labels):
    """Mesh from vertex coordinates (n, 2), triangles (m, 3) and boundary segments (k, 2) (0-based
    vertex numbers, segments with Omega on their left) with one boundary name per segment.

    Elements are numbered in the order given, so DG coefficient vectors saved with
    :func:`mesh_arrays` fit the rebuilt mesh.
    """
    ngmesh = nm.Mesh(dim=2)
    ngmesh.AddPoints(np.column_stack([np.asarray(points, dtype=float), np.zeros(len(points))]))
    domain = ngmesh.AddRegion("omega", dim=2)
    ngmesh.AddElements(dim=2, index=domain, data=np.asarray(triangles, dtype=np.int32), base=0)
    labels = np.asarray(labels)
    for label in dict.fromkeys(labels.tolist()):
        region = ngmesh.AddRegion(label, dim=1)
        ngmesh.AddElements(dim=1, index=region, data=np.asarray(segments, dtype=np.int32)[labels == label], base=0)
    mesh = ngs.Mesh(ngmesh)
    check_mesh(problem, mesh)
    return mesh


def mesh_arrays(mesh):
    """(points, triangles, segments, labels) of a 2D mesh, for :func:`mesh_from_arrays`."""
    ngmesh = mesh.ngmesh
    points, triangles = triangles_of(ngmesh)
    edges = ngmesh.Elements1D().NumPy()
    segments = edges["nodes"][:, :2].astype(np.int64) - 1
    names = mesh.GetBoundaries()
    labels = np.array([names[i - 1] for i in edges["index"]])
    return points, triangles, segments, labels


def netgen_mesh(problem, maxh, max_elements=MAX_ELEMENTS, timeout=None):
    """Unstructured Netgen triangulation of the problem's domain with mesh size ``maxh``.

    The mesh follows the interfaces of the domain's regions and has its geometry attached, so that it can be
    curved (``curve``, done by :class:`~ngdgfric.Discretization` for curved sides) and refined onto curved sides.
    Netgen runs in a child process, so Ctrl-C stops it (:mod:`ngdgfric.mesher`).  The polygon itself is checked
    by :class:`~ngdgfric.Polygon`.

    Parameters
    ----------
    problem : ContactProblem
        The problem whose domain is meshed.
    maxh : float or dict
        The largest element size, or a dict ``{region name: size}`` (regions left out: the largest size given):
        regions of different sizes, e.g. two bodies whose meshes do not match where they touch.
    max_elements : int or None, optional
        The most triangles allowed, by an estimate before meshing (``estimated_elements``); None: no limit.
        Default ``MAX_ELEMENTS`` (:math:`10^6`).
    timeout : float or None, optional
        Seconds Netgen may take.  Default ``None``: ``default_timeout`` of :mod:`ngdgfric.mesher` for the
        estimated number of elements.

    Returns
    -------
    ngsolve.Mesh
        The mesh, boundaries named by the side labels, materials by the region names.

    Raises
    ------
    ValueError
        Above about ``max_elements`` triangles, when Netgen fails or makes no elements, or when it has not
        finished after ``timeout`` seconds.

    Examples
    --------
    >>> problem = ndf.example("half_disk")
    >>> mesh = ndf.netgen_mesh(problem, 0.3)
    >>> mesh.ne > 0
    True
    """
    geometry = problem.geometry
    sizes = dict(maxh) if isinstance(maxh, dict) else {}
    for region, size in sizes.items():
        if region not in geometry.region_names:
            raise ValueError(f"maxh: {region!r} is not a region; known: {list(geometry.region_names)}")
        if not _is_size(size):
            raise ValueError(f"maxh[{region!r}] must be a positive number, got {size!r}")
    if sizes:
        maxh = max(sizes.values())
    if not _is_size(maxh):
        raise ValueError(f"maxh must be a positive number or a dict of them per region, got {maxh!r}")
    smallest = min(sizes.values(), default=maxh)
    _check_elements(problem, max_elements, maxh=smallest)
    if timeout is None:
        timeout = default_timeout(estimated_elements(problem, maxh=smallest))
    try:
        ngmesh = generate(geometry, maxh, timeout, sizes)
    except (RuntimeError, TimeoutError) as exc:
        raise ValueError(f"Netgen could not mesh the {geometry.kind} {_shown(geometry)} with maxh = {maxh:g}: "
                         f"{exc}") from None
    mesh = ngs.Mesh(ngmesh)
    if mesh.ne == 0:
        raise ValueError(f"Netgen made no elements for the {geometry.kind} {_shown(geometry)} with maxh = {maxh:g}")
    check_mesh(problem, mesh)
    return mesh


def _shown(geometry, count=6):
    """The first vertices of the domain's loops for a message."""
    vertices = [f"({x:.10g}, {y:.10g})" for _, loop in geometry.region_loops for x, y in loop.vertices]
    more = f", ... ({len(vertices)} vertices)" if len(vertices) > count else ""
    return "[" + ", ".join(vertices[:count]) + more + "]"


def check_mesh(problem, mesh):
    """Check that ``mesh`` is a mesh of the problem's domain.

    Its boundary names must be the problem's (and the interfaces between regions), its regions the domain's,
    every boundary edge must lie on a side of the domain with its name, and the mesh must have the domain's
    area and side lengths (to ``FIT`` = 1e-8 relative; on curved sides the circular segments cut off by the
    chords are added exactly, ``Geometry.chord_correction`` of :mod:`ngdgfric.domain`).

    Parameters
    ----------
    problem : ContactProblem
        The problem.
    mesh : ngsolve.Mesh
        A 2D mesh, for example of :func:`ngdgfric.uniform_mesh` or :func:`ngdgfric.netgen_mesh`, or one made
        elsewhere with the problem's boundary names.

    Raises
    ------
    ValueError
        If the mesh does not fit the problem; the message says where.
    """
    if not isinstance(mesh, ngs.Mesh) or mesh.dim != 2:
        raise ValueError(f"mesh must be a 2D NGSolve Mesh, got {mesh!r}")
    geometry = problem.geometry
    found = set(mesh.GetBoundaries())
    required = {name for part in ("dirichlet", "contact") for name in problem.sides(part)
                if name in geometry.side_names}
    required |= set(geometry.side_names)
    missing = sorted(required - found)
    if missing:
        raise ValueError(f"mesh has no boundary named {', '.join(map(repr, missing))}; "
                         f"its boundaries are {sorted(found)}")
    unknown = sorted(found - set(problem.boundary_names()) - {INTERFACE})
    if unknown:
        raise ValueError(f"mesh boundary {', '.join(map(repr, unknown))} is not one of the problem's "
                         f"names {problem.boundary_names()}")
    regions = set(mesh.GetMaterials())
    if len(geometry.region_names) > 1 and regions != set(geometry.region_names):
        raise ValueError(f"the mesh's regions {sorted(regions)} are not the domain's {sorted(geometry.region_names)}")
    _check_fit(geometry, *mesh_arrays(mesh))


def _check_fit(geometry, points, triangles, segments, labels):
    """ValueError unless the mesh (arrays of :func:`mesh_arrays`) fills ``geometry``."""
    gap = FIT * geometry.diameter()
    kind = geometry.kind
    correction = 0.0
    for label in map(str, np.unique(labels)):
        ends = points[segments[labels == label]]
        distance = geometry.side_distances(label, ends.reshape(-1, 2))
        if distance.max() > gap:
            k = int(np.argmax(distance))
            point = ends.reshape(-1, 2)[k]
            raise ValueError(f"the mesh does not fit the problem's {kind}: its boundary point "
                             f"({point[0]:.6g}, {point[1]:.6g}) labelled {label!r} is {distance[k]:.3g} away from "
                             f"the {kind}'s sides labelled {label!r}")
        if label == INTERFACE:
            continue
        chords = np.sum(np.linalg.norm(np.diff(ends, axis=1), axis=2))
        expected = geometry.side_length(label)
        if chords > expected * (1 + FIT) or (not geometry.curved and chords < expected * (1 - FIT)):
            raise ValueError(f"the mesh does not fit the problem's {kind}: its boundary {label!r} has length "
                             f"{chords:.10g}, the {kind}'s sides labelled {label!r} {expected:.10g}")
        correction += geometry.chord_correction(label, ends)
    a, b = (points[triangles[:, k]] - points[triangles[:, 0]] for k in (1, 2))
    area = 0.5 * np.sum(np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])) + correction
    if abs(area - geometry.area) > FIT * geometry.area:
        raise ValueError(f"the mesh does not fit the problem's {kind}: its area is {area:.10g}, the {kind}'s "
                         f"{geometry.area:.10g}")


def curve(problem, mesh, order):
    """Curve ``mesh`` to polynomial degree ``order`` where the domain has curved sides (``mesh.Curve``: every
    geometric quantity - normals, edge Jacobians, Gauss points, areas - then comes from the element mapping);
    nothing on a straight domain.  ValueError if the mesh has no geometry to curve from (a mesh rebuilt from
    arrays)."""
    if not problem.geometry.curved:
        return
    from netgen.geom2d import SplineGeometry

    if not isinstance(mesh.ngmesh.GetGeometry(), SplineGeometry):
        raise ValueError("the domain has curved sides but the mesh carries no geometry to curve it: make it with "
                         "ndf.netgen_mesh (or refine such a mesh)")
    mesh.Curve(int(order))
def facet_indicator(mesh, boundary):
    """Order-0 facet GridFunction: 1 on the edges of the named boundary, 0 elsewhere."""
    space = ngs.FacetFESpace(mesh, order=0)
    indicator = ngs.GridFunction(space)
    indicator.vec.FV().NumPy()[:] = list(space.GetDofs(mesh.Boundaries(boundary)))
    return indicator


def boundary_elements(mesh, indicators):
    """Boolean per element: True where one of its edges carries a 1 in one of the facet ``indicators``
    (:func:`facet_indicator`)."""
    edges = np.zeros(mesh.nedge, dtype=bool)
    for indicator in indicators:
        edges |= indicator.vec.FV().NumPy() > 0
    marked = np.zeros(mesh.ne, dtype=bool)
    for edge in np.flatnonzero(edges):
        for element in mesh.edges[int(edge)].elements:
            marked[element.nr] = True
    return marked


def triangle_corners(mesh):
    """(ne, 3, 2) corner coordinates of every triangle, in element order."""
    points, triangles = triangles_of(mesh.ngmesh)
    return points[triangles]


def smallest_angles(mesh):
    """The smallest interior angle of every triangle, in radians (numpy array in element order)."""
    corners = triangle_corners(mesh)
    smallest = np.full(len(corners), np.pi)
    for i in range(3):
        a = corners[:, (i + 1) % 3] - corners[:, i]
        b = corners[:, (i + 2) % 3] - corners[:, i]
        cos = np.sum(a * b, axis=1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
        smallest = np.minimum(smallest, np.arccos(np.clip(cos, -1.0, 1.0)))
    return smallest


def minimum_angle(mesh):
    """The smallest interior angle of the mesh's triangles, in degrees."""
    return float(np.degrees(smallest_angles(mesh).min()))


def element_diameters(mesh):
    """h_T: the longest edge of every triangle (numpy array in element order)."""
    corners = triangle_corners(mesh)
    lengths = np.linalg.norm(corners[:, [1, 2, 0]] - corners, axis=2)
    return lengths.max(axis=1)


def refine(mesh, marked, bisections=1):
    """Bisect the marked elements of ``mesh`` in place, ``bisections`` (1 or 2) times, plus the closure.

    Netgen's bisection is newest vertex bisection: on the first refinement every triangle's
    refinement edge is its longest edge (edges are numbered by length, ties broken consistently),
    a bisected triangle's children get the edge opposite the new vertex as their refinement edge,
    and neighbours are bisected until the mesh is conforming again (netgen ``bisect.cpp``:
    ``BTSortEdges``, ``BTDefineMarkedTri``, ``BTBisectTri``).  One bisection is the paper's h
    refinement (``Refine(onlyonce=True)``); two (``Refine()``) give each marked triangle four
    grandchildren similar to it with h/2, what the hp decision predicts for (:mod:`ngdgfric.hp`).
    """
    marked = np.asarray(marked, dtype=bool)
    if marked.shape != (mesh.ne,):
        raise ValueError(f"marked has {marked.size} entries, the mesh has {mesh.ne} elements")
    if bisections not in (1, 2):
        raise ValueError(f"bisections must be 1 or 2, got {bisections!r}")
    mesh.SetRefinementFlags(list(marked))
    mesh.Refine(onlyonce=bisections == 1)


def refined(mesh, marked, bisections=1):
    r"""A refined copy of ``mesh``: the marked elements bisected, plus the closure.

    Newest vertex bisection (``refine`` on a ``snapshot`` of the mesh); ``mesh`` itself is left as it is.  The
    step REFINE of a hand-written loop SOLVE :math:`\to` ESTIMATE :math:`\to` MARK :math:`\to` REFINE:
    ``mesh = ndf.refined(mesh, ndf.dorfler_mark(est.eta_T_squared, 0.3))``.

    Parameters
    ----------
    mesh : ngsolve.Mesh
        The mesh.
    marked : array_like of bool
        One flag per element of ``mesh``.
    bisections : int, optional
        1 (the paper's h refinement) or 2 (each marked triangle four grandchildren similar to it).
        Default ``1``.

    Returns
    -------
    ngsolve.Mesh
        The refined copy.

    Raises
    ------
    ValueError
        If ``marked`` has not one entry per element or ``bisections`` is not 1 or 2.

    See Also
    --------
    ngdgfric.dorfler_mark : The marking step.
    ngdgfric.adapt : The whole adaptive loop.
    """
    copy = snapshot(mesh)
    refine(copy, marked, bisections)
    return copy


def snapshot(mesh):
    """A copy of ``mesh`` with the same vertices and elements in the same order (Netgen's ``Copy``, which
    keeps the refinement data: the copy refines as the mesh would).  A solution (:func:`ngdgfric.solve`) lives
    on its own snapshot, so that refining the mesh it was given (which updates the spaces still alive on that
    mesh, and renumbers its elements) leaves it valid: 0.08 s for 1.3e5 triangles.  Anything but an NGSolve
    mesh is returned as it is (for :func:`check_mesh` to name)."""
    return ngs.Mesh(mesh.ngmesh.Copy()) if isinstance(mesh, ngs.Mesh) else mesh


def nested(coarse, fine):
    """Whether every triangle of ``fine`` lies in one triangle of ``coarse`` (fine refines coarse, or both are the
    same mesh): the coarse element that holds its centroid (point search) holds its three corners too (their
    barycentric coordinates in its straight triangle >= -1e-9).  False on curved domains once a refinement put
    vertices on a curved side, outside the coarse mesh's elements."""
    if same_mesh(coarse, fine):
        return True
    corners = triangle_corners(fine)  # (ne, 3, 2)
    centroids = corners.mean(axis=1)
    found = coarse(centroids[:, 0], centroids[:, 1])["nr"]
    if np.any(found < 0):
        return False
    a, b, c = np.moveaxis(triangle_corners(coarse)[found], 1, 0)  # (ne, 2) each
    basis = np.stack([b - a, c - a], axis=-1)  # (ne, 2, 2): x = a + basis (l1, l2)
    local = np.linalg.solve(basis[:, None], (corners - a[:, None])[..., None])[..., 0]  # (ne, 3, 2)
    barycentric = np.concatenate([1 - local.sum(-1, keepdims=True), local], axis=-1)
    return bool(np.all(barycentric >= -1e-9))


def same_mesh(a, b):
    """Whether the meshes ``a`` and ``b`` have the same vertices and elements in the same order (the
    same object, or snapshots of one mesh in one state): then coefficient vectors carry over."""
    if a is b:
        return True
    if a.ne != b.ne or a.nv != b.nv:
        return False
    return all(np.array_equal(x, y) for x, y in zip(triangles_of(a.ngmesh), triangles_of(b.ngmesh), strict=True))

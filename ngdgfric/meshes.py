"""Meshes of a problem's polygon with boundary labels Gamma_D, Gamma_F, Gamma_C."""

import netgen.meshing as nm
import ngsolve as ngs
import numpy as np
from netgen.geom2d import SplineGeometry

__all__ = ["uniform_mesh", "netgen_mesh", "mesh_from_arrays", "mesh_arrays", "check_mesh", "facet_indicator",
           "element_diameters"]

DIAGONALS = ("sw-ne", "nw-se")


def uniform_mesh(problem, h, diagonal="sw-ne"):
    """Structured mesh of the problem's rectangle: squares of side ``h``, each cut by one diagonal.

    This is the kind of mesh behind the paper's h = 2^-k (Section 6).  ``diagonal`` is
    ``"sw-ne"`` (from the lower-left to the upper-right corner of each square) or ``"nw-se"``.
    Meshes for h and h/2 are nested.  Side lengths must be integer multiples of ``h``.
    """
    geometry = problem.geometry
    if not geometry.is_rectangle:
        raise ValueError("uniform_mesh needs a rectangle geometry; use netgen_mesh for a general polygon")
    if diagonal not in DIAGONALS:
        raise ValueError(f"diagonal must be one of {DIAGONALS}, got {diagonal!r}")
    if not (isinstance(h, (int, float)) and h > 0):
        raise ValueError(f"h must be a positive number, got {h!r}")
    x0, y0, x1, y1 = geometry.bounds
    counts = []
    for length in (x1 - x0, y1 - y0):
        n = length / h
        if abs(n - round(n)) > 1e-9 * max(1.0, n) or round(n) < 1:
            raise ValueError(f"h = {h} does not divide the side length {length} of the rectangle")
        counts.append(int(round(n)))
    nx, ny = counts

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
    sides = [  # segments oriented with Omega on their left
        np.column_stack([bottom, bottom + 1]),
        np.column_stack([right, right + nx + 1]),
        np.column_stack([top, top - 1]),
        np.column_stack([left, left - (nx + 1)]),
    ]
    labels = np.concatenate([np.full(len(side), k) for k, side in enumerate(sides)])
    return mesh_from_arrays(problem, np.column_stack([xs.ravel(), ys.ravel()]), triangles, np.concatenate(sides),
                            np.asarray(geometry.labels)[labels])


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
    points = np.asarray(ngmesh.Coordinates())[:, :2].copy()
    triangles = ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1
    edges = ngmesh.Elements1D().NumPy()
    segments = edges["nodes"][:, :2].astype(np.int64) - 1
    names = mesh.GetBoundaries()
    labels = np.array([names[i - 1] for i in edges["index"]])
    return points, triangles, segments, labels


def netgen_mesh(problem, maxh):
    """Unstructured Netgen triangulation of the problem's polygon with mesh size ``maxh``."""
    if not (isinstance(maxh, (int, float)) and maxh > 0):
        raise ValueError(f"maxh must be a positive number, got {maxh!r}")
    geometry = problem.geometry
    spline = SplineGeometry()
    points = [spline.AppendPoint(x, y) for x, y in geometry.vertices]
    for k, label in enumerate(geometry.labels):
        spline.Append(["line", points[k], points[(k + 1) % len(points)]], bc=label, leftdomain=1, rightdomain=0)
    mesh = ngs.Mesh(spline.GenerateMesh(maxh=maxh))
    check_mesh(problem, mesh)
    return mesh


def check_mesh(problem, mesh):
    """Raise ValueError unless the mesh's boundary names are the problem's (Gamma_D, Gamma_F, Gamma_C)."""
    found = set(mesh.GetBoundaries())
    required = {problem.dirichlet, problem.contact}
    if problem.traction in problem.geometry.labels:
        required.add(problem.traction)
    missing = sorted(required - found)
    if missing:
        raise ValueError(f"mesh has no boundary named {', '.join(map(repr, missing))}; "
                         f"its boundaries are {sorted(found)}")
    unknown = sorted(found - set(problem.boundary_names()))
    if unknown:
        raise ValueError(f"mesh boundary {', '.join(map(repr, unknown))} is not one of the problem's "
                         f"names {problem.boundary_names()}")


def facet_indicator(mesh, boundary):
    """Order-0 facet GridFunction: 1 on the edges of the named boundary, 0 elsewhere."""
    space = ngs.FacetFESpace(mesh, order=0)
    indicator = ngs.GridFunction(space)
    indicator.vec.FV().NumPy()[:] = list(space.GetDofs(mesh.Boundaries(boundary)))
    return indicator


def element_diameters(mesh):
    """h_T: the longest edge of every triangle (numpy array in element order)."""
    points = np.asarray(mesh.ngmesh.Coordinates())
    nodes = mesh.ngmesh.Elements2D().NumPy()["nodes"].astype(np.int64) - 1
    corners = points[nodes]
    lengths = np.linalg.norm(corners[:, [1, 2, 0]] - corners, axis=2)
    return lengths.max(axis=1)

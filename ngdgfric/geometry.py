"""Plane geometry of the problem's polygon: is it simple, and does a mesh fill it.

Netgen is given only polygons that pass ``check_polygon`` (a NaN vertex or a duplicate one
crashed it with a segmentation fault, a self-intersecting one made it loop for minutes without
reacting to Ctrl-C, and vertices closer than about 1e-8 of the polygon's size made meshing fail).
"""

import numpy as np

__all__ = ["check_polygon", "RESOLUTION", "COORDINATE_LIMIT", "distances_to_sides", "crossings"]

# vertices (and a vertex and a side) closer than RESOLUTION times the polygon's diameter are refused:
# Netgen meshed a gap of 1e-7 of the size and failed at 1e-8
RESOLUTION = 1e-6
# coordinates within +-COORDINATE_LIMIT and a size above its inverse: areas and squared lengths stay finite and
# nonzero in floating point (a square of side 1e300 overflowed)
COORDINATE_LIMIT = 1e100


def check_polygon(vertices):
    """ValueError naming the defect unless ``vertices`` (n, 2) are those of a simple polygon.

    Checked: finite coordinates (within +-COORDINATE_LIMIT); a size of at least RESOLUTION times
    the largest coordinate (Netgen meshed a pentagon of size 1.5 at 3e6 from the origin and failed
    at 1e7); at least 3 vertices; no vertex within RESOLUTION x diameter of another vertex or of a
    side it does not bound (this also refuses sides that overlap or turn back); no two sides crossing.
    """
    v = np.asarray(vertices, dtype=float).reshape(-1, 2)
    bad = np.flatnonzero(~np.all(np.abs(v) <= COORDINATE_LIMIT, axis=1))  # also NaN
    if bad.size:
        k = int(bad[0])
        raise ValueError(f"vertices[{k}] = {_show(v[k])}: coordinates must be finite, within +-{COORDINATE_LIMIT:g}")
    n = len(v)
    if n < 3:
        raise ValueError(f"a polygon needs at least 3 vertices, got {n}")
    diameter = float(np.max(np.ptp(v, axis=0)))
    if diameter < 1 / COORDINATE_LIMIT:
        raise ValueError(f"the polygon's vertices span only {diameter:g} (at least {1 / COORDINATE_LIMIT:g} needed)")
    if diameter < RESOLUTION * np.max(np.abs(v)):
        raise ValueError(f"the polygon (size {diameter:g}) is smaller than {RESOLUTION:g} of its distance from the "
                         f"origin ({np.max(np.abs(v)):g}): shift its coordinates towards the origin (Netgen failed "
                         f"on a pentagon of size 1.5 at 1e7)")
    gap = RESOLUTION * diameter  # the smallest distance allowed between features
    for i in range(n):
        gaps = np.linalg.norm(v[i + 1:] - v[i], axis=1)
        close = np.flatnonzero(gaps <= gap)
        if close.size:
            j = i + 1 + int(close[0])
            raise ValueError(f"vertices[{i}] = {_show(v[i])} and vertices[{j}] = {_show(v[j])} coincide "
                             f"(distance {gaps[close[0]]:.3g}, less than {RESOLUTION:g} of the polygon's size)")
    starts, ends = v, np.roll(v, -1, axis=0)
    for i in range(n):
        near = distances_to_sides(v[i:i + 1], starts, ends)[0]
        near[[i, (i - 1) % n]] = np.inf  # the two sides that end at vertex i
        j = int(np.argmin(near))
        if near[j] <= gap:
            raise ValueError(f"vertices[{i}] = {_show(v[i])} lies on side {j} (from vertices[{j}] to "
                             f"vertices[{(j + 1) % n}]): the polygon touches or crosses itself")
    for i in range(n):
        crossing = crossings(starts[i], ends[i], starts, ends)
        crossing[[(i - 1) % n, i, (i + 1) % n]] = False
        if np.any(crossing):
            j = int(np.flatnonzero(crossing)[0])
            raise ValueError(f"sides {i} and {j} of the polygon cross: it is not simple")


def distances_to_sides(points, starts, ends):
    """(m, k) distances from ``points`` (m, 2) to the segments from ``starts`` to ``ends`` (k, 2)."""
    points = np.asarray(points, dtype=float)[:, None, :]
    d = ends - starts
    length2 = np.maximum(np.sum(d * d, axis=1), np.finfo(float).tiny)
    t = np.clip(np.sum((points - starts) * d, axis=2) / length2, 0.0, 1.0)
    return np.linalg.norm(points - (starts + t[..., None] * d), axis=2)


def crossings(p, q, starts, ends, margin=0.0):
    """Which segments (starts, ends) the segment p-q crosses at a point inside both (proper crossings), with
    the ends of each farther than ``margin`` from the other's line (default 0: any proper crossing)."""
    def side(a, b, c):  # |b - a| times the signed distance of c from the line through a and b
        return (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0])

    s, t = side(p, q, starts), side(p, q, ends)
    u, v = side(starts, ends, p), side(starts, ends, q)
    if margin:
        pq, st = np.hypot(*(q - p)), np.hypot(ends[:, 0] - starts[:, 0], ends[:, 1] - starts[:, 1])
        s, t = np.where(np.abs(s) > margin * pq, s, 0), np.where(np.abs(t) > margin * pq, t, 0)
        u, v = np.where(np.abs(u) > margin * st, u, 0), np.where(np.abs(v) > margin * st, v, 0)
    return (s * t < 0) & (u * v < 0)


def _show(point):
    return f"({float(point[0])!r}, {float(point[1])!r})"

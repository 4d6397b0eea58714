"""Sides and loops of a scene: straight sides, circular arcs, and closed counter-clockwise chains of them.

A :class:`Loop` is a closed counter-clockwise chain of sides, side k from ``vertices[k]`` to ``vertices[k+1]``
(cyclic), each straight or a circular ``Arc`` given by one more point it passes through.  Netgen gets every
arc as spline segments of at most 90 degrees with the control point at the intersection of the end tangents
(``Arc.pieces``): its rational quadratic segments are exact circles then.  The functions below answer what
``ngdgfric.domain.Geometry`` asks of single sides and loops (a side's key, length, end tangents, overlap
with another side, distance to points; whether points lie inside a loop, how close two loops come and whether
they cross), exactly for arcs: not on the polylines that draw them.
"""

import math
from dataclasses import dataclass

import numpy as np

from .geometry import check_polygon, crossings, distances_to_sides

__all__ = ["Arc", "Loop", "ARC_SAMPLES", "side_key", "end_tangents", "inside", "contains", "overlap", "length_of",
           "interior_point", "signed_area", "distance_to", "closest_approach", "cross"]

ARC_SAMPLES = 64  # points per full turn when an arc is drawn or checked as a polyline


@dataclass(frozen=True)
class Arc:
    """The circular arc from ``a`` to ``b`` through ``through``: centre, radius, start angle and signed sweep
    (positive counter-clockwise around the centre)."""

    a: tuple
    b: tuple
    through: tuple

    def __post_init__(self):
        (ax, ay), (bx, by), (px, py) = self.a, self.b, self.through
        d = 2 * ((ax - px) * (by - py) - (ay - py) * (bx - px))
        size = max(math.dist(self.a, self.b), math.dist(self.a, self.through), math.dist(self.b, self.through))
        if abs(d) <= 1e-9 * size**2:
            raise ValueError(f"the arc from {self.a} to {self.b} through {self.through}: the three points are on "
                             f"a line (make it a straight side)")

    @property
    def centre(self):
        (ax, ay), (bx, by), (px, py) = self.a, self.b, self.through
        a2, b2, p2 = ax * ax + ay * ay, bx * bx + by * by, px * px + py * py
        d = 2 * (ax * (by - py) + bx * (py - ay) + px * (ay - by))
        return ((a2 * (by - py) + b2 * (py - ay) + p2 * (ay - by)) / d,
                (a2 * (px - bx) + b2 * (ax - px) + p2 * (bx - ax)) / d)

    @property
    def radius(self):
        return math.dist(self.centre, self.a)

    def _angle(self, point):
        cx, cy = self.centre
        return math.atan2(point[1] - cy, point[0] - cx)

    @property
    def start(self):
        return self._angle(self.a)

    @property
    def sweep(self):
        """Signed angle from a to b along the arc (through ``through``)."""
        full = 2 * math.pi
        to_b = (self._angle(self.b) - self.start) % full
        to_p = (self._angle(self.through) - self.start) % full
        return to_b if to_p < to_b else to_b - full

    def points(self, count):
        """``count`` + 1 points from a to b along the arc (a and b exactly)."""
        cx, cy, r = *self.centre, self.radius
        angles = self.start + self.sweep * np.linspace(0.0, 1.0, count + 1)
        xy = np.column_stack([cx + r * np.cos(angles), cy + r * np.sin(angles)])
        xy[0], xy[-1] = self.a, self.b
        return xy

    def pieces(self):
        """The arc as Netgen ``spline3`` pieces (start, control point, end) of at most 90 degrees each."""
        count = max(1, math.ceil(abs(self.sweep) / (math.pi / 2) - 1e-9))
        ends = self.points(count)
        half = self.sweep / count / 2
        cx, cy, r = *self.centre, self.radius
        pieces = []
        for k in range(count):
            middle = self.start + self.sweep * (k + 0.5) / count
            control = (cx + r / math.cos(half) * math.cos(middle), cy + r / math.cos(half) * math.sin(middle))
            pieces.append((tuple(ends[k]), control, tuple(ends[k + 1])))
        return pieces

    def distance(self, xy):
        """Distances of points xy (m, 2) to the arc."""
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        cx, cy = self.centre
        angle = (np.arctan2(xy[:, 1] - cy, xy[:, 0] - cx) - self.start) % (2 * math.pi)
        inside = angle <= self.sweep if self.sweep > 0 else angle >= 2 * math.pi + self.sweep
        radial = np.abs(np.hypot(xy[:, 0] - cx, xy[:, 1] - cy) - self.radius)
        ends = np.minimum(np.linalg.norm(xy - self.a, axis=1), np.linalg.norm(xy - self.b, axis=1))
        return np.where(inside | (self.sweep == 0), radial, ends)

    def segment_area(self):
        """Signed area between the chord a-b and the arc: positive where the arc lies to the right of the
        chord (outside a counter-clockwise loop: the arc adds this area to the loop's polygon)."""
        r, angle = self.radius, abs(self.sweep)
        return math.copysign(0.5 * r * r * (angle - math.sin(angle)), self.sweep)

    @property
    def length(self):
        return self.radius * abs(self.sweep)


def _pair(where, value):
    try:
        x, y = value
        x, y = float(x), float(y)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{where} must be a pair of numbers (x, y), got {value!r}") from None
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError(f"{where} must be finite, got {value!r}")
    return x, y


@dataclass(frozen=True)
class Loop:
    """A closed chain of named sides, counter-clockwise: straight sides and circular arcs.

    The boundary of a region or a hole of a :class:`~ngdgfric.Domain`.  Checked on construction: at least 2
    vertices (3 if all sides are straight), a simple counter-clockwise chain (``check_polygon`` of
    :mod:`ngdgfric.geometry` on the arcs drawn as polylines).  ``Loop.circle(centre, radius, label)`` makes a
    circle.

    Parameters
    ----------
    vertices : sequence of (float, float)
        The vertices, counter-clockwise; side ``k`` runs from ``vertices[k]`` to ``vertices[k+1]`` (cyclic).
    labels : sequence of str
        ``labels[k]`` names side ``k``.
    arcs : dict or sequence of (int, (float, float)), optional
        Maps a side number ``k`` to a point the side passes through: side ``k`` is the circular arc through its
        ends and that point.  Default ``()``: every side straight.

    Raises
    ------
    ValueError
        If a vertex or arc point is not a pair of numbers, the labels do not match the sides, an arc is
        degenerate, or the chain crosses itself or runs clockwise.

    Examples
    --------
    A half-disk of radius 1 on the x axis, its round side an arc through (0, 1):

    >>> half_disk = ndf.Loop([(-1, 0), (1, 0)], ["contact", "traction"], arcs={1: (0, 1)})
    >>> print(f"{half_disk.area:.4f}")
    1.5708
    """

    vertices: tuple
    labels: tuple
    arcs: tuple = ()

    def __post_init__(self):
        if isinstance(self.vertices, (str, bytes)) or not hasattr(self.vertices, "__len__"):
            raise ValueError(f"vertices must be a list of points (x, y), got {self.vertices!r}")
        vertices = tuple(_pair(f"vertices[{k}]", v) for k, v in enumerate(self.vertices))
        if isinstance(self.labels, (str, bytes)) or not hasattr(self.labels, "__len__"):
            raise ValueError(f"labels must be a list of side names, got {self.labels!r}")
        labels = tuple(self.labels)
        if len(labels) != len(vertices):
            raise ValueError(f"a loop needs one label per side: {len(vertices)} sides, {len(labels)} labels")
        arcs = dict(self.arcs)
        for k, point in arcs.items():
            if not isinstance(k, int) or isinstance(k, bool) or not 0 <= k < len(vertices):
                raise ValueError(f"arcs: side {k!r} is not a side number 0 ... {len(vertices) - 1}")
            arcs[k] = _pair(f"arcs[{k}]", point)
        object.__setattr__(self, "vertices", vertices)
        object.__setattr__(self, "labels", labels)
        object.__setattr__(self, "arcs", tuple(sorted(arcs.items())))
        if len(vertices) < (2 if arcs else 3):
            raise ValueError(f"a loop needs at least {2 if arcs else 3} vertices, got {len(vertices)}")
        for k in arcs:
            self.side(k)  # a degenerate arc is refused here
        polyline = self.polyline()
        try:
            check_polygon(polyline)
        except ValueError as exc:
            if not arcs:
                raise
            raise ValueError(f"the loop crosses or touches itself (checked with its arcs drawn as polylines of "
                             f"{ARC_SAMPLES} points per turn: {exc})") from None
        if signed_area(polyline) <= 0:
            raise ValueError("a loop's vertices must be counter-clockwise and enclose a positive area")

    @classmethod
    def circle(cls, centre, radius, label):
        """A full circle as four quarter arcs, all sides named ``label``."""
        cx, cy = _pair("centre", centre)
        if not (isinstance(radius, (int, float)) and math.isfinite(radius) and radius > 0):
            raise ValueError(f"radius must be a positive number, got {radius!r}")
        at = [(cx + radius * math.cos(a), cy + radius * math.sin(a)) for a in np.arange(4) * math.pi / 2]
        middle = [(cx + radius * math.cos(a), cy + radius * math.sin(a)) for a in (np.arange(4) + 0.5) * math.pi / 2]
        return cls(at, (label,) * 4, tuple(enumerate(middle)))

    def side(self, k):
        """Side k: an ``Arc``, or the pair of its end points."""
        a, b = self.vertices[k], self.vertices[(k + 1) % len(self.vertices)]
        through = dict(self.arcs).get(k)
        return (a, b) if through is None else Arc(a, b, through)

    def sides(self):
        return [self.side(k) for k in range(len(self.vertices))]

    def polyline(self):
        """The loop drawn with every arc as a polyline (ARC_SAMPLES points per turn, at least 4 per arc)."""
        points = []
        for side in self.sides():
            if isinstance(side, Arc):
                count = max(4, math.ceil(ARC_SAMPLES * abs(side.sweep) / (2 * math.pi)))
                points.extend(map(tuple, side.points(count)[:-1]))
            else:
                points.append(side[0])
        return np.asarray(points)

    @property
    def area(self):
        """The enclosed area (exact for arcs)."""
        return signed_area(np.asarray(self.vertices)) + sum(
            side.segment_area() for side in self.sides() if isinstance(side, Arc))


def signed_area(v):
    v = np.asarray(v, dtype=float)
    x0, y0 = v[0]
    return 0.5 * float(np.sum((np.roll(v, 1, axis=0)[:, 0] - x0) * (v[:, 1] - y0)
                              - (v[:, 0] - x0) * (np.roll(v, 1, axis=0)[:, 1] - y0)))


def end_tangents(side):
    """The unit tangents of a side (a pair of points or an ``Arc``) at its two ends (direction ignored)."""
    if not isinstance(side, Arc):
        direction = np.subtract(side[1], side[0], dtype=float)
        direction /= np.linalg.norm(direction)
        return direction, direction
    radii = [np.subtract(end, side.centre, dtype=float) / side.radius for end in (side.a, side.b)]
    return tuple(np.array([-r[1], r[0]]) for r in radii)


def side_key(side):
    """Identifies a side independently of its direction (shared sides of two regions): its end points and, for
    an arc, its midpoint (the two halves of a circle have the same ends and centre)."""
    if isinstance(side, Arc):
        ends = tuple(sorted([side.a, side.b]))
        return ends + (tuple(np.round(side.points(2)[1], 12)),)
    return tuple(sorted(side))


def contains(loop, xy):
    """Which points xy (m, 2) lie inside the loop, exactly for arcs.

    Ray casting on the polygon of the vertices (the chords of the arcs), then each arc's circular segment (the
    points of its disk on its side of the chord) toggles: the loop's curve is the chords plus, per arc, the
    closed curve arc + chord back, and crossing counts add modulo 2.
    """
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    v = np.asarray(loop.vertices, dtype=float)
    a, b = v[None, :, :], np.roll(v, -1, axis=0)[None, :, :]
    x, y = xy[:, 0:1], xy[:, 1:2]
    crossing = (a[..., 1] > y) != (b[..., 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        at = a[..., 0] + (y - a[..., 1]) * (b[..., 0] - a[..., 0]) / (b[..., 1] - a[..., 1])
    result = np.count_nonzero(crossing & (x < at), axis=1) % 2 == 1
    for side in loop.sides():
        if isinstance(side, Arc):
            chord, middle = np.subtract(side.b, side.a), side.points(2)[1] - side.a
            sign = chord[0] * middle[1] - chord[1] * middle[0]
            offside = chord[0] * (xy[:, 1] - side.a[1]) - chord[1] * (xy[:, 0] - side.a[0])
            in_disk = np.hypot(xy[:, 0] - side.centre[0], xy[:, 1] - side.centre[1]) < side.radius
            result ^= in_disk & (offside * sign > 0)
    return result


def inside(point, loop):
    """Whether ``point`` lies inside the loop (``contains``: exact for arcs)."""
    return bool(contains(loop, [point])[0])


def overlap(a, b):
    """The length along which sides a and b run together (on one line or one circle), 0 otherwise."""
    if isinstance(a, Arc) != isinstance(b, Arc):
        return 0.0
    if isinstance(a, Arc):
        scale = max(a.radius, b.radius)
        if math.dist(a.centre, b.centre) > 1e-9 * scale or abs(a.radius - b.radius) > 1e-9 * scale:
            return 0.0
        on = b.distance(a.points(64)) <= 1e-9 * scale  # a's points on b: the overlap to 1/64 of a
        return float(np.count_nonzero(on[:-1] & on[1:]) * a.length / 64)
    (p, q), (r, s) = a, b
    d = np.subtract(q, p)
    length = float(np.hypot(*d))
    normal = np.array([-d[1], d[0]]) / length
    if max(abs(np.dot(np.subtract(r, p), normal)), abs(np.dot(np.subtract(s, p), normal))) > 1e-9 * length:
        return 0.0
    t = sorted(np.dot(np.subtract(x, p), d) / length for x in (r, s))
    return max(0.0, min(length, t[1]) - max(0.0, t[0]))


def length_of(side):
    return side.length if isinstance(side, Arc) else math.dist(*side)


def interior_point(loop):
    """A point inside the loop: the centroid of its polyline if inside, else the midpoint of a short chord
    across a convex vertex."""
    v = loop.polyline()
    centre = v.mean(axis=0)
    if inside(centre, loop):
        return centre
    for k in range(len(v)):
        candidate = (v[k - 1] + v[(k + 1) % len(v)] + v[k]) / 3
        if inside(candidate, loop):
            return candidate
    return centre


def distance_to(side, xy):
    """Distances of points xy (m, 2) to a side (a pair of points or an ``Arc``), exact for arcs."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    if isinstance(side, Arc):
        return side.distance(xy)
    return distances_to_sides(xy, np.asarray([side[0]], dtype=float), np.asarray([side[1]], dtype=float))[:, 0]


def _support(side):
    """The line (point, unit direction, None) or circle (centre, None, radius) a side lies on."""
    if isinstance(side, Arc):
        return np.asarray(side.centre), None, side.radius
    p, q = np.asarray(side, dtype=float)
    return p, (q - p) / np.linalg.norm(q - p), None


def _candidates(s, t):
    """Points where sides s and t may come closest: their ends, where the lines or circles they lie on meet,
    and on each circle the two points on the normal to the other side's line or on the line through both
    centres (where a circle comes closest to a line or another circle)."""
    points = [s[0], s[1]] if not isinstance(s, Arc) else [s.a, s.b]
    points += [t[0], t[1]] if not isinstance(t, Arc) else [t.a, t.b]
    (c, d, r), (e, f, rho) = _support(s), _support(t)
    if d is not None and f is not None:  # two lines
        det = d[0] * f[1] - d[1] * f[0]
        if abs(det) > 1e-12:
            lam = ((e[0] - c[0]) * f[1] - (e[1] - c[1]) * f[0]) / det
            points.append(c + lam * d)
    elif d is None and f is None:  # two circles
        between = np.subtract(e, c)
        distance = float(np.hypot(*between))
        if distance > 0:
            u = between / distance
            points += [c + r * u, c - r * u, e + rho * u, e - rho * u]
            along = (distance**2 + r * r - rho * rho) / (2 * distance)
            if abs(along) <= r:
                across = math.sqrt(r * r - along * along)
                points += [c + along * u + across * np.array([-u[1], u[0]]),
                           c + along * u - across * np.array([-u[1], u[0]])]
    else:  # a circle (centre, radius) and a line (point, direction)
        centre, radius, point, direction = (c, r, e, f) if d is None else (e, rho, c, d)
        normal = np.array([-direction[1], direction[0]])
        points += [centre + radius * normal, centre - radius * normal]
        foot = point + np.dot(centre - point, direction) * direction
        offset = float(np.dot(centre - foot, normal))
        if abs(offset) <= radius:
            half = math.sqrt(radius * radius - offset * offset)
            points += [foot + half * direction, foot - half * direction]
    return np.asarray(points, dtype=float)


def closest_approach(a, b):
    """How close loops a and b come, exactly for arcs: (distance, a point of one of them where it is least);
    distance 0 if they meet or cross.

    For each pair of sides the least of dist(p, s) + dist(p, t) over the points p of ``_candidates``: at
    least the distance of the sides (triangle inequality), and equal to it at the candidate where they come
    closest (an end of one side, a meeting point, or the foot of the common normal of a circle).
    """
    best = (math.inf, None)
    for s in a.sides():
        for t in b.sides():
            points = _candidates(s, t)
            total = distance_to(s, points) + distance_to(t, points)
            k = int(np.argmin(total))
            if total[k] < best[0]:
                best = (float(total[k]), tuple(float(c) for c in points[k]))
    return best


def _distance_to_loop(loop, xy):
    return np.min([distance_to(side, xy) for side in loop.sides()], axis=0)


def cross(a, b, margin):
    """Whether the curves of loops a and b cross by more than ``margin``: two straight sides cross with every
    end farther than ``margin`` from the other side's line, or one loop has points (of its polyline, or where
    it may come closest to the other) inside and outside the other, both farther than ``margin`` from it.
    Curves that only touch (within ``margin``, round-off included) do not cross."""
    straight_a = [side for side in a.sides() if not isinstance(side, Arc)]
    straight_b = [side for side in b.sides() if not isinstance(side, Arc)]
    if straight_a and straight_b:
        starts, ends = np.asarray(straight_b, dtype=float)[:, 0], np.asarray(straight_b, dtype=float)[:, 1]
        for p, q in straight_a:
            if np.any(crossings(np.asarray(p, dtype=float), np.asarray(q, dtype=float), starts, ends, margin)):
                return True
    extra = np.concatenate([_candidates(s, t) for s in a.sides() for t in b.sides()])
    for first, second in ((a, b), (b, a)):
        points = np.concatenate([first.polyline(), extra[_distance_to_loop(first, extra) <= margin]])
        clear = _distance_to_loop(second, points) > margin
        within = contains(second, points)
        if np.any(clear & within) and np.any(clear & ~within):
            return True
    return False

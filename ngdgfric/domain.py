"""The geometry of a scene: named regions bounded by straight sides and circular arcs, with holes.

One small interface, :class:`Geometry`, serves every domain (the paper's rectangles, a user's
polygon, a half-disk, a block with a hole, two materials side by side):

* :meth:`Geometry.spline_geometry` - the Netgen ``SplineGeometry`` (meshing, refinement that puts new
  boundary points on the true curve, and ``mesh.Curve`` for curved elements of any order);
* ``side_names`` / ``region_names`` - the names of the sides and of the regions;
* :meth:`Geometry.check_fit` - whether a mesh (as arrays) fills the domain: every boundary vertex on a
  side of its name, and the area of the triangles plus the circular segments cut off by the chords of
  curved sides equal to the domain's area;
* ``area``, ``perimeter``, ``bounds``, :meth:`Geometry.outline` (for plots).

A :class:`Loop` is a closed counter-clockwise chain of sides, side k from ``vertices[k]`` to
``vertices[k+1]`` (cyclic), each straight or a circular arc given by one more point it passes through.
A :class:`Domain` is a set of named regions (each bounded by a loop; loops of two regions may share
sides, which become interfaces, or one region's loop may lie inside another's, an inclusion) and holes
(loops inside a region).  Netgen gets every arc as spline segments of at most 90 degrees with the
control point at the intersection of the end tangents: its rational quadratic segments are exact
circles then (boundary points of refined meshes lie on the circle to round-off).
"""

import functools
import math
from dataclasses import dataclass

import numpy as np

from .geometry import RESOLUTION, check_polygon, crossings, distances_to_sides

__all__ = ["Geometry", "Loop", "Domain", "Arc", "INTERFACE", "NAME", "check_name"]

INTERFACE = "interface"  # the boundary name Netgen gives to sides between two regions (no condition)
NAME = "a name of letters, digits and underscores, starting with a letter"
ARC_SAMPLES = 64  # points per full turn when an arc is drawn or checked as a polyline


def check_name(kind, name, interface=False):
    """``name`` as a str; ValueError unless it is a name NGSolve's region patterns can select exactly (and not
    :data:`INTERFACE` unless ``interface``)."""
    if interface and name == INTERFACE:
        return name
    if not isinstance(name, str) or not name or not (name[0].isalpha() and all(c.isalnum() or c == "_" for c in name)):
        raise ValueError(f"{kind} {name!r} must be {NAME}")
    if name == INTERFACE:
        raise ValueError(f"{kind} {name!r} is reserved for the sides between two regions")
    return name


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
    """A closed chain of sides, counter-clockwise: side k from ``vertices[k]`` to ``vertices[k+1]`` (cyclic),
    named ``labels[k]``; ``arcs`` maps a side number k to a point the side passes through (a circular arc),
    other sides are straight.  Checked: at least 2 vertices (3 if all sides are straight), a simple
    counter-clockwise chain (:func:`ngdgfric.geometry.check_polygon` on the arcs drawn as polylines)."""

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
        if _signed_area(polyline) <= 0:
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
        """Side k: an :class:`Arc`, or the pair of its end points."""
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
        return _signed_area(np.asarray(self.vertices)) + sum(
            side.segment_area() for side in self.sides() if isinstance(side, Arc))


def _signed_area(v):
    v = np.asarray(v, dtype=float)
    x0, y0 = v[0]
    return 0.5 * float(np.sum((np.roll(v, 1, axis=0)[:, 0] - x0) * (v[:, 1] - y0)
                              - (v[:, 0] - x0) * (np.roll(v, 1, axis=0)[:, 1] - y0)))


def _end_tangents(side):
    """The unit tangents of a side (a pair of points or an :class:`Arc`) at its two ends (direction ignored)."""
    if not isinstance(side, Arc):
        direction = np.subtract(side[1], side[0], dtype=float)
        direction /= np.linalg.norm(direction)
        return direction, direction
    radii = [np.subtract(end, side.centre, dtype=float) / side.radius for end in (side.a, side.b)]
    return tuple(np.array([-r[1], r[0]]) for r in radii)


def _key(side):
    """Identifies a side independently of its direction (shared sides of two regions): its end points and, for
    an arc, its midpoint (the two halves of a circle have the same ends and centre)."""
    if isinstance(side, Arc):
        ends = tuple(sorted([side.a, side.b]))
        return ends + (tuple(np.round(side.points(2)[1], 12)),)
    return tuple(sorted(side))


def _inside(point, loop):
    """Whether ``point`` lies inside the loop (ray casting on its polyline)."""
    v = loop.polyline()
    x, y = point
    a, b = v, np.roll(v, -1, axis=0)
    crossing = (a[:, 1] > y) != (b[:, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        at = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return bool(np.count_nonzero(crossing & (x < at)) % 2)


class Geometry:
    """What the rest of the package asks of a domain (module docstring).  Subclasses define
    ``region_loops`` (pairs (name, :class:`Loop`)) and ``hole_loops`` (loops)."""

    region_loops = ()
    hole_loops = ()
    kind = "domain"  # how messages name it

    @functools.cached_property
    def segments(self):
        """Netgen's view: (side, label, left region number, right region number), regions numbered from 1
        in the order of ``region_loops``, 0 outside.  A side shared by two regions is one interface segment;
        a region's loop inside another region (an inclusion) bounds that region on its outside."""
        loops = [loop for _, loop in self.region_loops]
        parent = [self._parent(loop, i) for i, loop in enumerate(loops)]
        owner = {}
        for i, loop in enumerate(loops):
            for k, side in enumerate(loop.sides()):
                owner.setdefault(_key(side), []).append((i, k))
        segments = []
        for i, loop in enumerate(loops):
            for k, side in enumerate(loop.sides()):
                users = owner[_key(side)]
                if len(users) > 2:
                    raise ValueError(f"a side of region {self.region_loops[i][0]!r} is shared by more than two regions")
                if len(users) == 2:
                    j = users[1][0] if users[0][0] == i else users[0][0]
                    if i < j:
                        segments.append((side, INTERFACE, i + 1, j + 1))
                    continue
                outside = parent[i] + 1 if parent[i] is not None else 0
                if outside == 0 and loop.labels[k] == INTERFACE:
                    raise ValueError(f"side {k} of region {self.region_loops[i][0]!r} is labelled {INTERFACE!r} but "
                                     f"no other region shares it: give it a name with a condition")
                segments.append((side, loop.labels[k] if outside == 0 else INTERFACE, i + 1, outside))
        for hole in self.hole_loops:
            region = self._parent(hole, None)
            if region is None:
                raise ValueError("a hole must lie inside a region")
            for k, side in enumerate(hole.sides()):
                segments.append((side, hole.labels[k], 0, region + 1))  # the hole on the left of its loop
        return segments

    def _parent(self, loop, own):
        """The innermost region whose loop contains ``loop`` (not sharing sides with it), or None."""
        keys = {_key(side) for side in loop.sides()}
        probe = _interior_point(loop)
        best = None
        for j, (_, other) in enumerate(self.region_loops):
            if j == own or keys & {_key(side) for side in other.sides()}:
                continue
            if _inside(probe, other) and all(_inside(v, other) for v in loop.vertices):
                if best is None or other.area < self.region_loops[best][1].area:
                    best = j
        return best

    @functools.cached_property
    def corners(self):
        """The points where the solution may be singular, an (n, 2) array: the ends of sides where the boundary
        turns (its tangent changes direction), where two sides with different conditions or regions meet, or
        where an interface meets the boundary (:func:`ngdgfric.hp.hp_refine` grades meshes towards them)."""
        meeting = {}
        for side, label, left, right in self.segments:
            ends = (side.a, side.b) if isinstance(side, Arc) else side
            for end, tangent in zip(ends, _end_tangents(side), strict=True):
                meeting.setdefault(tuple(np.round(end, 12)), []).append((label, left, right, tangent))
        points = []
        for point, sides in meeting.items():
            kinds = {(label, left, right) for label, left, right, _ in sides}
            tangents = np.array([tangent for *_, tangent in sides])
            cross = np.outer(tangents[:, 0], tangents[:, 1]) - np.outer(tangents[:, 1], tangents[:, 0])
            turns = np.abs(cross).max() > 1e-9
            if len(sides) != 2 or len(kinds) > 1 or turns:
                points.append(point)
        return np.array(points, dtype=float).reshape(-1, 2)

    @property
    def side_names(self):
        """The names of the boundary sides (not interfaces), in order of appearance."""
        return tuple(dict.fromkeys(label for _, label, _, _ in self.segments if label != INTERFACE))

    @property
    def region_names(self):
        return tuple(name for name, _ in self.region_loops)

    @property
    def curved(self):
        return any(loop.arcs for loop in self._loops())

    def _loops(self):
        return [loop for _, loop in self.region_loops] + list(self.hole_loops)

    @property
    def area(self):
        """The area of the domain (exact for arcs): the top-level regions' loops minus the holes."""
        loops = [loop for _, loop in self.region_loops]
        top = [loop for i, loop in enumerate(loops) if self._parent(loop, i) is None]
        return sum(loop.area for loop in top) - sum(hole.area for hole in self.hole_loops)

    @property
    def perimeter(self):
        return sum(_length(side) for side, label, _, _ in self.segments if label != INTERFACE)

    @property
    def bounds(self):
        """(x0, y0, x1, y1) of the bounding box."""
        points = np.concatenate([loop.polyline() for loop in self._loops()])
        return (*points.min(axis=0).tolist(), *points.max(axis=0).tolist())

    @property
    def is_rectangle(self):
        return False

    def outline(self):
        """The boundary and interface curves as a list of (k, 2) polylines (for plots)."""
        return [np.vstack([loop.polyline(), loop.polyline()[:1]]) for loop in self._loops()]

    def spline_geometry(self):
        """Netgen's ``SplineGeometry`` of the domain, with the side names as boundary conditions and the
        region names as materials."""
        from netgen.geom2d import SplineGeometry

        spline, points = SplineGeometry(), {}

        def point(xy):
            key = (float(xy[0]), float(xy[1]))
            if key not in points:
                points[key] = spline.AppendPoint(*key)
            return points[key]

        for side, label, left, right in self.segments:
            if isinstance(side, Arc):
                for a, c, b in side.pieces():
                    spline.Append(["spline3", point(a), point(c), point(b)], bc=label, leftdomain=left,
                                  rightdomain=right)
            else:
                spline.Append(["line", point(side[0]), point(side[1])], bc=label, leftdomain=left, rightdomain=right)
        for number, name in enumerate(self.region_names, start=1):
            spline.SetMaterial(number, name)
        return spline

    def side_distances(self, label, xy):
        """Distances of points xy (m, 2) to the sides named ``label`` (interfaces: INTERFACE)."""
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        distance = np.full(len(xy), np.inf)
        for side, name, _, _ in self.segments:
            if name == label:
                d = side.distance(xy) if isinstance(side, Arc) else distances_to_sides(
                    xy, np.asarray([side[0]]), np.asarray([side[1]]))[:, 0]
                distance = np.minimum(distance, d)
        return distance

    def side_length(self, label):
        return sum(_length(side) for side, name, _, _ in self.segments if name == label)

    def chord_correction(self, label, ends):
        """Sum over boundary edges (ends (m, 2, 2), oriented with the domain on their left) named ``label`` of
        the signed area between the edge and the curved side it lies on (0 on straight sides): the mesh's
        triangles plus these give the domain's area exactly."""
        total = 0.0
        for side, name, left, _ in self.segments:
            if name != label or not isinstance(side, Arc):
                continue
            outward = math.copysign(1.0, side.sweep) * (1 if left else -1)  # the arc bulges out of the domain
            on = (side.distance(ends[:, 0]) <= 1e-9 * side.radius) & (side.distance(ends[:, 1]) <= 1e-9 * side.radius)
            for a, b in ends[on]:
                chord = math.dist(a, b)
                angle = 2 * math.asin(min(1.0, chord / (2 * side.radius)))
                total += outward * 0.5 * side.radius**2 * (angle - math.sin(angle))
        return total

    def diameter(self):
        x0, y0, x1, y1 = self.bounds
        return max(x1 - x0, y1 - y0)


def _overlap(a, b):
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


def _length(side):
    return side.length if isinstance(side, Arc) else math.dist(*side)


def _interior_point(loop):
    """A point inside the loop: the centroid of its polyline if inside, else the midpoint of a short chord
    across a convex vertex."""
    v = loop.polyline()
    centre = v.mean(axis=0)
    if _inside(centre, loop):
        return centre
    for k in range(len(v)):
        candidate = (v[k - 1] + v[(k + 1) % len(v)] + v[k]) / 3
        if _inside(candidate, loop):
            return candidate
    return centre


@dataclass(frozen=True)
class Domain(Geometry):
    """Named regions and holes (module docstring).

    ``regions``: a mapping {name: :class:`Loop`} or a sequence of (name, Loop) pairs; ``holes``: loops
    inside a region, whose sides are boundary sides with their own labels.  Region names and side labels
    are checked (:data:`NAME`); every side that is not shared by two regions or inside another region needs
    a label that the problem gives a condition.
    """

    regions: tuple
    holes: tuple = ()

    def __post_init__(self):
        regions = self.regions.items() if isinstance(self.regions, dict) else self.regions
        try:
            regions = tuple((name, loop) for name, loop in regions)
        except (TypeError, ValueError):
            raise ValueError(f"regions must map region names to loops, got {self.regions!r}") from None
        if not regions:
            raise ValueError("a domain needs at least one region")
        for name, loop in regions:
            check_name("region", name)
            if not isinstance(loop, Loop):
                raise ValueError(f"region {name!r} must be a Loop, got {loop!r}")
        if len({name for name, _ in regions}) != len(regions):
            raise ValueError(f"region names must be distinct, got {[name for name, _ in regions]}")
        holes = tuple(self.holes)
        for k, hole in enumerate(holes):
            if not isinstance(hole, Loop):
                raise ValueError(f"holes[{k}] must be a Loop, got {hole!r}")
        object.__setattr__(self, "regions", regions)
        object.__setattr__(self, "holes", holes)
        for loop in self._loops():
            for label in loop.labels:
                check_name("side label", label, interface=True)
        self._check_layout()
        segments = self.segments
        if self.area <= 0:
            raise ValueError("the holes cover the whole domain")
        if not any(label != INTERFACE for _, label, _, _ in segments):
            raise ValueError("the domain has no boundary side")

    def _named_loops(self):
        return [(f"region {name!r}", loop) for name, loop in self.regions] + \
            [(f"holes[{k}]", hole) for k, hole in enumerate(self.holes)]

    def _check_layout(self):
        """ValueError unless the loops fit together: no two cross, no side runs along part of another's (shared
        sides must have the same ends), no region or hole inside a hole, no hole overlapping another."""
        loops = self._named_loops()
        gap = RESOLUTION * max(np.ptp(np.concatenate([loop.polyline() for _, loop in loops]), axis=0))
        for i, (name, loop) in enumerate(loops):
            line = loop.polyline()
            starts, ends = line, np.roll(line, -1, axis=0)
            for other_name, other in loops[i + 1:]:
                other_line = other.polyline()
                other_starts, other_ends = other_line, np.roll(other_line, -1, axis=0)
                if any(np.any(crossings(p, q, other_starts, other_ends)) for p, q in zip(starts, ends, strict=True)):
                    raise ValueError(f"the sides of {name} and {other_name} cross")
                for a, b in ((loop, other), (other, loop)):
                    for side in a.sides():
                        for other_side in b.sides():
                            if _key(side) != _key(other_side) and _overlap(side, other_side) > gap:
                                raise ValueError(f"a side of {name} runs along part of a side of {other_name}: "
                                                 f"shared sides must have the same end points (split the longer)")
        for k, hole in enumerate(self.holes):
            for name, loop in loops:
                if loop is not hole and all(_inside(point, hole) for point in loop.polyline()):
                    raise ValueError(f"{name} lies inside holes[{k}]")

    @property
    def region_loops(self):
        return self.regions

    @property
    def hole_loops(self):
        return self.holes

"""The geometry of a scene: named regions bounded by straight sides and circular arcs, with holes.

One small interface, ``Geometry``, serves every domain (the paper's rectangles, a user's
polygon, a half-disk, a block with a hole, two materials side by side):

* ``spline_geometry()`` - the Netgen ``SplineGeometry`` (meshing, refinement that puts new
  boundary points on the true curve, and ``mesh.Curve`` for curved elements of any order);
* ``side_names`` / ``region_names`` - the names of the sides and of the regions;
* ``side_distances()``, ``side_length()`` and ``chord_correction()`` - whether a mesh (as arrays) fills the
  domain (:func:`ngdgfric.check_mesh`): every boundary vertex on a side of its name, and the area of the triangles
  plus the circular segments cut off by the chords of curved sides equal to the domain's area;
* ``area``, ``perimeter``, ``bounds``, ``outline()`` (for plots).

A :class:`~ngdgfric.Domain` is a set of named regions (each bounded by a :class:`~ngdgfric.Loop` of straight
sides and circular arcs, :mod:`ngdgfric.loops`; loops of two regions may share sides, which become interfaces,
or one region's loop may lie inside another's, an inclusion) and holes (loops inside a region, at a positive
distance from every other loop of that body: ``CLEARANCE``).  A region inside a hole is a body of its own (a shaft
in a bore): its loop may run along the hole's or keep a gap.  Boundary points of refined meshes lie on the circles
to round-off (``Arc.pieces`` of :mod:`ngdgfric.loops`).
"""

import functools
import math
from dataclasses import dataclass

import numpy as np

from .geometry import RESOLUTION, crossings
from .loops import (
    Arc,
    Loop,
    closest_approach,
    cross,
    distance_to,
    end_tangents,
    inside,
    interior_point,
    length_of,
    overlap,
    side_key,
)

__all__ = ["Geometry", "Loop", "Domain", "Arc", "INTERFACE", "NAME", "CLEARANCE", "check_name"]

INTERFACE = "interface"  # the boundary name Netgen gives to sides between two regions (no condition)
NAME = "a name of letters, digits and underscores, starting with a letter"
# a hole (or a region sharing no vertex with another) must stay farther than CLEARANCE times the domain's size from
# every other loop.  Netgen on a unit square (the same at sizes 0.01 and 100), mesh sizes 1 to 0.02: a circular hole
# tangent to a side failed at the coarse mesh sizes and came out pinched at the fine ones; 1e-5 and 2e-5 away it
# failed at 7 and 5 of 9 mesh sizes, from 3e-5 on at none; a triangular hole's vertex failed at 8 of 9 at 3e-5, at 4
# of 8 at 1e-4 and at none at 1e-3.  1e-4 refuses what touches and most of what Netgen cannot mesh, and accepts gaps
# of 1e-3 of the size, which mesh and solve (tests/test_domain.py)
CLEARANCE = 1e-4


def check_name(kind, name, interface=False):
    """``name`` as a str; ValueError unless it is a name NGSolve's region patterns can select exactly (and not
    ``INTERFACE`` unless ``interface``)."""
    if interface and name == INTERFACE:
        return name
    if not isinstance(name, str) or not name or not (name[0].isalpha() and all(c.isalnum() or c == "_" for c in name)):
        raise ValueError(f"{kind} {name!r} must be {NAME}")
    if name == INTERFACE:
        raise ValueError(f"{kind} {name!r} is reserved for the sides between two regions")
    return name


class Geometry:
    """What the rest of the package asks of a domain (module docstring).  Subclasses define
    ``region_loops`` (pairs (name, :class:`~ngdgfric.Loop`)) and ``hole_loops`` (loops)."""

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
        owner = self._owners
        segments = []
        for i, loop in enumerate(loops):
            for k, side in enumerate(loop.sides()):
                users = owner[side_key(side)]
                if len(users) > 2:
                    raise ValueError(f"a side of region {self.region_loops[i][0]!r} is shared by more than two regions")
                if len(users) == 2 and not self._touching_side(users):
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

    @functools.cached_property
    def _owners(self):
        """{``side_key`` of a side: [(region number, side index), ...]}: which regions' loops have each side."""
        owner = {}
        for i, (_, loop) in enumerate(self.region_loops):
            for k, side in enumerate(loop.sides()):
                owner.setdefault(side_key(side), []).append((i, k))
        return owner

    def _touching_side(self, users):
        """Whether a side that two regions share (``users``: (region, side index) twice) is a *touching* side: both
        regions label it, with different names (not ``INTERFACE``), so that each keeps it as a boundary side of its
        own (the two sides of a contact pair) instead of an interface that glues them."""
        labels = [self.region_loops[i][1].labels[k] for i, k in users]
        return INTERFACE not in labels and labels[0] != labels[1]

    @functools.cached_property
    def bodies(self):
        """The bodies: tuples of region numbers (0-based, in the order of ``region_loops``) joined by interfaces or
        inclusions, ordered by their first region (a region in a hole is no inclusion: a body of its own).  Two
        bodies may touch (along sides with names of their own, a hole's sides and the sides of a body in it, or at
        points); each is meshed on its own (``meshing_geometry``), so their meshes need not match where they
        touch."""
        root = list(range(len(self.region_loops)))

        def find(i):
            while root[i] != i:
                root[i] = root[root[i]]
                i = root[i]
            return i

        joined = [tuple(user[0] for user in users) for users in self._owners.values()
                  if len(users) == 2 and not self._touching_side(users)]
        joined += [(i, parent) for i, (_, loop) in enumerate(self.region_loops)
                   if (parent := self._parent(loop, i)) is not None]
        for i, j in joined:  # an interface or an inclusion
            a, b = find(i), find(j)
            root[max(a, b)] = min(a, b)
        groups = {}
        for i in range(len(self.region_loops)):
            groups.setdefault(find(i), []).append(i)
        return tuple(tuple(group) for group in groups.values())

    @functools.cached_property
    def region_body(self):
        """The body (its number in ``bodies``) of every region, in the order of ``region_loops``: a tuple."""
        body = [0] * len(self.region_loops)
        for k, regions in enumerate(self.bodies):
            for i in regions:
                body[i] = k
        return tuple(body)

    @functools.cached_property
    def touching(self):
        """The pairs of side labels of two bodies that run together (along a line or a circle; the sides of a hole
        belong to the body around it): a set of sorted label pairs.  :class:`~ngdgfric.ContactProblem` requires
        each to be a contact pair."""
        body, loops = self._loop_bodies(), self._loops()
        gap = RESOLUTION * self.diameter()
        found = set()
        for i, loop in enumerate(loops):
            for j in range(i + 1, len(loops)):
                if body[i] == body[j] or None in (body[i], body[j]):
                    continue
                for a, label_a in zip(loop.sides(), loop.labels, strict=True):
                    for b, label_b in zip(loops[j].sides(), loops[j].labels, strict=True):
                        if overlap(a, b) > gap:
                            found.add(tuple(sorted((label_a, label_b))))
        return found

    def _loop_bodies(self):
        """The body of every loop of ``_loops()``: a region's, and for a hole that of the region it lies in (None if
        none)."""
        holes = [self._parent(hole, None) for hole in self.hole_loops]
        return [*self.region_body, *(None if region is None else self.region_body[region] for region in holes)]

    def body_of_side(self, label):
        """The number of the body (in ``bodies``) whose boundary has the side ``label``."""
        region = next(left or right for _, name, left, right in self.segments if name == label)
        return self.region_body[region - 1]

    def body_regions(self, number):
        """The region names of body ``number``."""
        return tuple(self.region_names[i] for i in self.bodies[number])

    def _parent(self, loop, own):
        """The innermost region whose loop contains ``loop`` (not sharing sides with it), or None: also None if a
        hole inside that region contains ``loop`` (a body in a hole of another: the shaft in the bore)."""
        keys = {side_key(side) for side in loop.sides()}
        probe = interior_point(loop)
        best = None
        for j, (_, other) in enumerate(self.region_loops):
            if j == own or keys & {side_key(side) for side in other.sides()}:
                continue
            if inside(probe, other) and all(inside(v, other) for v in loop.vertices):
                if best is None or other.area < self.region_loops[best][1].area:
                    best = j
        if best is not None and any(hole is not loop and self._in_hole(loop, probe, hole)
                                    and hole.area < self.region_loops[best][1].area * (1 - 1e-9)
                                    for hole in self.hole_loops):
            return None
        return best

    @staticmethod
    def _in_hole(loop, probe, hole):
        """Whether ``loop`` (with ``probe`` = ``interior_point(loop)``) lies in ``hole``: the probe inside it and an
        area no larger (loops do not cross, ``Domain._check_layout``), so a loop on the hole's curve lies in it."""
        return inside(probe, hole) and loop.area <= hole.area * (1 + 1e-9)

    @functools.cached_property
    def corners(self):
        """The points where the solution may be singular, an (n, 2) array: the ends of sides where the boundary
        turns (its tangent changes direction), where two sides with different conditions or regions meet, or
        where an interface meets the boundary (:func:`ngdgfric.hp_refine` grades meshes towards them)."""
        meeting = {}
        for side, label, left, right in self.segments:
            ends = (side.a, side.b) if isinstance(side, Arc) else side
            for end, tangent in zip(ends, end_tangents(side), strict=True):
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
        """The area of the domain, exact for arcs.

        The top-level regions' loops minus the holes.
        """
        loops = [loop for _, loop in self.region_loops]
        top = [loop for i, loop in enumerate(loops) if self._parent(loop, i) is None]
        return sum(loop.area for loop in top) - sum(hole.area for hole in self.hole_loops)

    @property
    def perimeter(self):
        return sum(length_of(side) for side, label, _, _ in self.segments if label != INTERFACE)

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

    def spline_geometry(self, shifts=None):
        """Netgen's ``SplineGeometry`` of the domain, with the side names as boundary conditions and the
        region names as materials; ``shifts``: one (dx, dy) per body that moves it (``meshing_geometry``)."""
        from netgen.geom2d import SplineGeometry

        spline, points = SplineGeometry(), {}
        shifts = np.zeros((len(self.bodies), 2)) if shifts is None else np.asarray(shifts, dtype=float)
        region_shift = np.vstack([[0.0, 0.0], shifts[list(self.region_body)]])  # region numbers from 1

        def point(xy, region):
            key = (float(xy[0] + region_shift[region][0]), float(xy[1] + region_shift[region][1]))
            if key not in points:
                points[key] = spline.AppendPoint(*key)
            return points[key]

        for side, label, left, right in self.segments:
            region = left or right
            if isinstance(side, Arc):
                for a, c, b in side.pieces():
                    spline.Append(["spline3", point(a, region), point(c, region), point(b, region)], bc=label,
                                  leftdomain=left, rightdomain=right)
            else:
                spline.Append(["line", point(side[0], region), point(side[1], region)], bc=label, leftdomain=left,
                              rightdomain=right)
        for number, name in enumerate(self.region_names, start=1):
            spline.SetMaterial(number, name)
        return spline

    def body_shifts(self):
        """The shift of every body that ``meshing_geometry`` applies: none for one body, else the bodies side by
        side along x, three diameters apart, so that Netgen meshes each on its own (it would merge the points of
        two bodies that touch, and glue them)."""
        step = 3.0 * max(self.diameter(), 1.0)
        return [(k * step if len(self.bodies) > 1 else 0.0, 0.0) for k in range(len(self.bodies))]

    def meshing_geometry(self, region_maxh=None):
        """The ``SplineGeometry`` Netgen meshes: the bodies moved apart (``body_shifts``), with the mesh sizes
        ``region_maxh`` ({region name: size}) in some regions.  A mesh of it is moved
        back point by point (``unshift``) and gets the true ``spline_geometry()``: the curves and their parameters
        are the same, so curving and refinement put new points on the true sides."""
        spline = self.spline_geometry(self.body_shifts())
        for name, size in (region_maxh or {}).items():
            spline.SetDomainMaxH(self.region_names.index(name) + 1, float(size))
        return spline

    def unshift(self, coordinates, element_points, element_regions):
        """The coordinates (n, 2 or 3) of a mesh of ``meshing_geometry`` moved back to the domain: each point by the
        shift of the body of the elements it belongs to (``element_points``: (m, 3) 0-based vertices,
        ``element_regions``: 1-based region of each element)."""
        shifts = np.asarray(self.body_shifts())
        body_of_region = np.array([0, *self.region_body], dtype=np.int64)  # region numbers from 1
        moved = np.array(coordinates, dtype=float)
        point_body = np.zeros(len(moved), dtype=np.int64)
        point_body[np.asarray(element_points).ravel()] = np.repeat(body_of_region[element_regions],
                                                                   np.shape(element_points)[1])
        moved[:, :2] -= shifts[point_body]
        return moved

    def side_distances(self, label, xy):
        """Distances of points xy (m, 2) to the sides named ``label`` (interfaces: INTERFACE)."""
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        distance = np.full(len(xy), np.inf)
        for side, name, _, _ in self.segments:
            if name == label:
                distance = np.minimum(distance, distance_to(side, xy))
        return distance

    def side_length(self, label):
        return sum(length_of(side) for side, name, _, _ in self.segments if name == label)

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


@dataclass(frozen=True)
class Domain(Geometry):
    """A domain of named regions and holes, bounded by straight sides and circular arcs.

    Loops of two regions may share sides, which become interfaces (Netgen's boundary name ``"interface"``), or
    one region's loop may lie inside another's (an inclusion); holes are loops inside a region, and a region
    inside a hole is a body of its own, whose loop may run along the hole's (a shaft in a bore: the two sides are
    then a :class:`~ngdgfric.ContactPair`) or keep a gap (module docstring of :mod:`ngdgfric.domain`).  Every side
    that is not shared by two regions or inside another region needs a label that the problem gives a condition.

    Parameters
    ----------
    regions : dict or sequence of (str, Loop)
        The regions: a mapping ``{name: Loop}`` or a sequence of ``(name, Loop)`` pairs; stored as a tuple of
        pairs.  Region names (and side labels) are letters, digits and underscores, starting with a letter.
    holes : sequence of Loop, optional
        Loops inside a region, whose sides are boundary sides with their own labels.  Default ``()``: none.

    Raises
    ------
    ValueError
        If a name or label is not valid, two loops cross (two bodies may touch, not overlap), a side runs along
        part of another, a hole lies inside a hole with no region between, a hole touches the boundary of its
        body or another hole (comes within ``CLEARANCE`` times the domain's size of it; so does a region that
        shares no vertex with a loop of its body), or the domain has no boundary side.

    See Also
    --------
    ngdgfric.Polygon : One region with straight sides.

    Examples
    --------
    A square with a circular hole:

    >>> square = ndf.Loop([(0, 0), (1, 0), (1, 1), (0, 1)], ["contact", "dirichlet", "traction", "traction"])
    >>> hole = ndf.Loop.circle((0.5, 0.5), 0.2, "hole")
    >>> domain = ndf.Domain({"omega": square}, holes=[hole])
    >>> domain.side_names
    ('contact', 'dirichlet', 'traction', 'hole')
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
        sides must have the same ends), no hole inside a hole unless a region lies between them, no hole
        overlapping another, and a hole (or a region sharing no vertex with another loop) touches no other loop of
        its body and no hole: it stays farther than CLEARANCE times the domain's size from it (exactly, arcs as
        circles).  A region and a loop of another body (a region, or a hole of it) may touch, not cross."""
        loops = self._named_loops()
        size = max(np.ptp(np.concatenate([loop.polyline() for _, loop in loops]), axis=0))
        gap, clearance = RESOLUTION * size, CLEARANCE * size
        body = self._loop_bodies()
        for i, (name, loop) in enumerate(loops):
            line = loop.polyline()
            starts, ends = line, np.roll(line, -1, axis=0)
            for j, (other_name, other) in enumerate(loops[i + 1:], start=i + 1):
                # a region and a region or hole of another body may touch: each body is meshed on its own
                two_bodies = i < len(self.regions) and body[j] is not None and body[i] != body[j]
                apart = (j >= len(self.regions) and not two_bodies) or not set(loop.vertices) & set(other.vertices)
                if apart:  # must keep a distance: only crossings farther than round-off count as crossings
                    distance, point = closest_approach(loop, other)
                    if distance > clearance:
                        continue
                    crossing = cross(loop, other, clearance)
                elif two_bodies:
                    crossing = cross(loop, other, gap)
                else:
                    other_line = other.polyline()
                    other_starts, other_ends = other_line, np.roll(other_line, -1, axis=0)
                    crossing = any(np.any(crossings(p, q, other_starts, other_ends))
                                   for p, q in zip(starts, ends, strict=True))
                if crossing:
                    raise ValueError(f"the sides of {name} and {other_name} cross" + (
                        " (two bodies may touch, not overlap)" if two_bodies else ""))
                if two_bodies:
                    continue
                for a, b in ((loop, other), (other, loop)) if j < len(self.regions) else ():  # two regions
                    for side in a.sides():
                        for other_side in b.sides():
                            if side_key(side) != side_key(other_side) and overlap(side, other_side) > gap:
                                raise ValueError(f"a side of {name} runs along part of a side of {other_name}: "
                                                 f"shared sides must have the same end points (split the longer)")
                if apart:
                    raise ValueError(self._touching(name, other_name, i, j, point, distance, size))
        for k, hole in enumerate(self.holes):  # a region in a hole is a body of its own; a hole needs a region around
            for name, loop in loops[len(self.regions):]:
                if loop is not hole and self._parent(loop, None) is None and all(inside(point, hole)
                                                                                 for point in loop.polyline()):
                    raise ValueError(f"{name} lies inside holes[{k}]")

    def _touching(self, name, other_name, i, j, point, distance, size):
        """The message for loop j (of ``_named_loops``, a hole or a region) named ``other_name`` touching loop
        i < j named ``name`` at ``point`` (round-off of the domain's ``size`` shown as 0)."""
        x, y, distance = np.round(np.array([*point, distance]) / size, 12) * size + 0.0
        where = f"the boundary of {name}" if i < len(self.regions) else name
        if j >= len(self.regions):
            rule = "a hole must keep a positive distance from the boundary and from the other holes"
        else:
            rule = "a region that shares no vertex with another must keep a positive distance from it"
        return (f"{other_name} touches {where} at about ({x:.6g}, {y:.6g}) (distance {distance:.2g}): {rule}, "
                f"more than {CLEARANCE:g} of the domain's size ({CLEARANCE * size:.3g} here); move it or make it "
                f"smaller")

    @property
    def region_loops(self):
        """The regions as (name, :class:`~ngdgfric.Loop`) pairs, in the order of ``regions``."""
        return self.regions

    @property
    def hole_loops(self):
        """The holes, a tuple of :class:`~ngdgfric.Loop` (``holes``)."""
        return self.holes

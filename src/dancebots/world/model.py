"""The world: the room, polygon obstacles, spectators and the robots with their types and
start poses, and the start-pose rules (:func:`start_conflicts`).

Lengths in m, angles in rad, speeds in m/s and rad/s; the room's and obstacles' coordinates
are in the *world frame*. World files are read by :mod:`dancebots.world.loader`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
import shapely
from numpy.typing import NDArray

from dancebots.geometry import Pose, footprint_corners

__all__ = [
    "BUILTIN_ROBOT_TYPES",
    "CONTACT_MARGIN",
    "CROWD_KINDS",
    "DEFAULT_ROBOT_TYPE",
    "THESIS_ROOM_SIZE",
    "ConflictKind",
    "Crowd",
    "CrowdKind",
    "CrowdKindDefaults",
    "Obstacle",
    "RobotType",
    "Spectator",
    "StartConflict",
    "World",
    "WorldRobot",
    "spectator_route",
    "square_room",
    "start_conflicts",
]

THESIS_ROOM_SIZE = 10.673
"""Side of the thesis simulator's square room, m (thesis ch. 7.1)."""


@dataclass(frozen=True, slots=True)
class RobotType:
    """A kind of robot: rectangular footprint (length along x, width along y, m) and limits."""

    name: str
    length: float
    width: float
    max_speed: float
    max_angular_speed: float


BUILTIN_ROBOT_TYPES: Mapping[str, RobotType] = {
    # thesis ch. 2: HUSKY 99 x 67 cm, 1 m/s; TRADR 73 x 60 cm, 0.5 m/s; both > 180 deg/s.
    "HUSKY": RobotType("HUSKY", 0.99, 0.67, 1.0, math.pi),
    "TRADR": RobotType("TRADR", 0.73, 0.60, 0.5, math.pi),
    # thesis ch. 3: the 2D simulator's robot is 1.2 x 0.6 m.
    "SIM": RobotType("SIM", 1.2, 0.6, 0.5, math.pi),
    # the second seed's queues: TurtleBot3 Burger, 138 x 178 mm, 0.22 m/s, 2.84 rad/s.
    "TURTLEBOT3": RobotType("TURTLEBOT3", 0.138, 0.178, 0.22, 2.84),
}
DEFAULT_ROBOT_TYPE = BUILTIN_ROBOT_TYPES["SIM"]


@dataclass(frozen=True, slots=True, eq=False)
class Obstacle:
    """A polygon obstacle; ``polygon`` (N, 2) in m, world frame; ``height`` in m."""

    name: str
    polygon: NDArray[np.float64]
    height: float
    line: int


@dataclass(frozen=True, slots=True)
class WorldRobot:
    """A robot of the world: its role, type and start pose in the world frame."""

    name: str
    type: RobotType
    start: Pose
    line: int


@dataclass(frozen=True, slots=True, eq=False)
class Spectator:
    """A visitor: a disc of ``radius`` m and ``height`` m walking ``waypoints`` (K, 2) (world
    frame, m) at ``speed`` m/s, standing ``pauses`` (K,) s at each waypoint, starting after
    ``start`` s; with ``loop`` it walks back to the first waypoint and around again."""

    name: str
    radius: float
    height: float
    speed: float
    waypoints: NDArray[np.float64]
    pauses: NDArray[np.float64]
    loop: bool
    start: float
    line: int


CrowdKind = Literal["adult", "child"]
"""Who a crowd is: adults, or children (smaller, faster, unpredictable: ``sim.crowd``)."""


@dataclass(frozen=True, slots=True)
class CrowdKindDefaults:
    """A kind's defaults: preferred walking speed, mean and standard deviation (m/s), disc
    radius (m) and height (m)."""

    speed: float
    speed_sd: float
    radius: float
    height: float


CROWD_KINDS: Mapping[str, CrowdKindDefaults] = {
    # walking adults: about 1.3 m/s free walking (Helbing and Molnar 1995 take 1.34 m/s,
    # s.d. 0.26); visitors at a show stroll slower
    "adult": CrowdKindDefaults(1.0, 0.25, 0.25, 1.7),
    # children: smaller, faster, less predictable
    "child": CrowdKindDefaults(1.3, 0.4, 0.18, 1.1),
}


@dataclass(frozen=True, slots=True, eq=False)
class Crowd:
    """Random visitors: ``count`` pedestrians of ``kind`` who start at random places in
    ``area`` (a polygon (N, 2), world frame, m) and walk to random goals in it (some near a
    robot, to watch it) with the social force model (``sim.crowd``). Preferred speeds are
    drawn from a normal distribution (``speed`` mean, ``speed_sd`` standard deviation, m/s,
    clipped to [0.3, 2.5]); discs of ``radius`` m, ``height`` m tall. ``seed`` and the run's
    seed together pick everything, so a run is repeatable and every run seed a new crowd."""

    name: str
    count: int
    area: NDArray[np.float64]
    kind: CrowdKind
    speed: float
    speed_sd: float
    radius: float
    height: float
    seed: int
    line: int


@dataclass(frozen=True, slots=True, eq=False)
class World:
    """The room (polygon (N, 2), world frame), its wall height, obstacles, robots,
    spectators (scripted walks) and crowds (random, reacting pedestrians)."""

    path: str
    room: NDArray[np.float64]
    wall_height: float
    obstacles: tuple[Obstacle, ...]
    robots: tuple[WorldRobot, ...]
    spectators: tuple[Spectator, ...] = ()
    crowds: tuple[Crowd, ...] = ()

    def robot(self, name: str) -> WorldRobot | None:
        return next((r for r in self.robots if r.name == name), None)

    def largest_footprint(self) -> tuple[float, float] | None:
        """The largest length and the largest width (m) of the world's robots (not
        necessarily of one robot); None without robots."""
        if not self.robots:
            return None
        return (max(r.type.length for r in self.robots), max(r.type.width for r in self.robots))

    def slowest_speed(self) -> float | None:
        """The smallest max speed of the world's robots, m/s: the default vmax (thesis 4.1:
        the user gives the speed of the slowest robot); None without robots."""
        return min((r.type.max_speed for r in self.robots), default=None)


def square_room(size: float) -> NDArray[np.float64]:
    """The square room [0, size] x [0, size] as a counter-clockwise polygon (4, 2)."""
    return np.array([[0.0, 0.0], [size, 0.0], [size, size], [0.0, size]])


CONTACT_MARGIN = 1e-6
"""m: the rounding allowance of the start-pose tests. Robots may touch each other (the
thesis's rows touch end to end; the simulator counts a zero gap as no overlap) and may reach
into each other by up to this much; a wall, an obstacle or a visitor they must keep clear of
by at least this much (the simulator counts touching an obstacle as a contact, and a wall
touched at an angle turns into one by rounding)."""


ConflictKind = Literal["room", "robot", "obstacle", "spectator"]
"""What a robot cannot start in or against (:class:`StartConflict`)."""


@dataclass(frozen=True, slots=True)
class StartConflict:
    """Why robot ``robot`` (an index into the start poses) cannot start where it stands:
    ``kind`` "room" (its footprint is not inside the room, clear of the walls), "robot" (it
    overlaps robot ``other``), "obstacle" or "spectator" (it touches or overlaps obstacle or
    spectator ``other``); ``other`` is -1 for "room"."""

    robot: int
    kind: ConflictKind
    other: int


def start_conflicts(types: Sequence[RobotType], starts: NDArray[np.float64],
                    room: NDArray[np.float64] | None, obstacles: Sequence[Obstacle] = (),
                    spectators: Sequence[Spectator] = ()) -> list[StartConflict]:
    """Every reason the robots cannot start at ``starts`` (R, 3) (x, y, yaw in the world frame,
    m and rad): a footprint not inside ``room`` (N, 2; None: no walls) clear of its walls, a
    footprint that overlaps another robot's, or one that touches an obstacle or a spectator's
    disc at its first waypoint (within :data:`CONTACT_MARGIN`). The simulator would hold such
    a robot where it stands. Sorted by robot; a pair of robots comes once (robot < other)."""
    if len(types) == 0:
        return []
    lengths = np.array([t.length for t in types])
    widths = np.array([t.width for t in types])
    shapes = shapely.polygons(footprint_corners(starts[:, 0], starts[:, 1], starts[:, 2],
                                                lengths, widths))
    found: list[StartConflict] = []
    if room is not None:
        grown = shapely.buffer(shapes, CONTACT_MARGIN, join_style="mitre")
        outside = ~shapely.contains(shapely.Polygon(room), grown)
        found.extend(StartConflict(i, "room", -1) for i in np.flatnonzero(outside).tolist())
    # robots: the footprints less the margin all round (the centre of one smaller than that)
    cores = shapely.buffer(shapes, -CONTACT_MARGIN, join_style="mitre")
    cores = np.where(shapely.is_empty(cores), shapely.centroid(shapes), cores)
    near = shapely.STRtree(cores).query(cores, predicate="intersects")  # (2, P) index pairs
    near = near[:, near[0] < near[1]]
    near = near[:, np.lexsort((near[1], near[0]))]
    found.extend(StartConflict(a, "robot", b)
                 for a, b in zip(near[0].tolist(), near[1].tolist(), strict=True))
    tree = shapely.STRtree(shapes)
    for k, obstacle in enumerate(obstacles):
        hit = tree.query(shapely.Polygon(obstacle.polygon), predicate="dwithin",
                         distance=CONTACT_MARGIN)
        found.extend(StartConflict(int(i), "obstacle", k) for i in np.sort(hit).tolist())
    for k, spectator in enumerate(spectators):
        hit = tree.query(shapely.Point(spectator.waypoints[0]), predicate="dwithin",
                         distance=spectator.radius + CONTACT_MARGIN)
        found.extend(StartConflict(int(i), "spectator", k) for i in np.sort(hit).tolist())
    return sorted(found, key=lambda c: c.robot)


def spectator_route(spectator: Spectator) -> shapely.Geometry:
    """The line (or point) a spectator's centre walks, world frame, m: its waypoints, and
    back to the first one when it loops."""
    points = spectator.waypoints
    if spectator.loop and len(points) > 1:
        points = np.concatenate([points, points[:1]])
    if len(points) == 1 or np.all(points == points[0]):
        return shapely.Point(points[0])
    return shapely.LineString(points)

"""A plan placed in its world: the one object for "this show, in this room, with these robots".

:func:`place_show` samples the plan's desired poses once (every ``period`` s and at every
formation change), finds each robot's type, the pose of the show frame in the world frame and
each robot's start pose, and every reason the show cannot be simulated there (errors) or may
go wrong (warnings). ``check`` reports over a :class:`PlacedShow`; the simulator's setup
(``sim/setup.py``) builds its arena and start poses from the same object, so a show that
checks without errors always sets up. Pure: no I/O, no clocks.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
import shapely
from numpy.typing import NDArray

from dancebots.diagnostics import Diagnostic, Severity
from dancebots.geometry import (
    Pose,
    compose_poses,
    footprint_corners,
    points_to_world,
    wrap_angle,
    wrap_angles,
)
from dancebots.plan.planner import Plan, PlannedFormation
from dancebots.world import DEFAULT_ROBOT_TYPE, Obstacle, RobotType, World, start_conflicts

__all__ = [
    "MAX_ROBOT_SAMPLES",
    "MAX_SIMULATED_ROBOT_SECONDS",
    "MAX_START_OVERLAPS",
    "PlacedShow",
    "Places",
    "ShowSamples",
    "WorldViolation",
    "instruction_position",
    "place_show",
    "places_followed",
    "robot_types",
    "sample_show",
    "show_transform",
    "true_runs",
]

FloatArray = NDArray[np.float64]


def robot_types(plan: Plan, world: World | None,
                default: RobotType = DEFAULT_ROBOT_TYPE) -> list[RobotType]:
    """Each robot's type: from the world, else ``default`` (whose max speed is the plan's
    vmax when there is no world: vmax is then the user's statement of the robots' speed)."""
    types = []
    for robot in plan.robots:
        found = world.robot(robot) if world is not None else None
        if found is not None:
            types.append(found.type)
        elif world is None:
            types.append(RobotType(default.name, default.length, default.width,
                                   plan.parameters.vmax, default.max_angular_speed))
        else:
            types.append(default)
    return types


MAX_ROBOT_SAMPLES = 2_000_000
"""Most desired poses (robots x sample times) that one placement holds (48 MB of poses and
16 MB of formation indices; ``run`` lets them go once the show is set up)."""



def _sample_period(plan: Plan, period: float, diagnostics: list[Diagnostic]) -> float:
    """The sample period (s): ``period``, or longer when the show's robots x samples would
    pass :data:`MAX_ROBOT_SAMPLES` (then with a warning at the scenario's robots line)."""
    samples = len(plan.robots) * (plan.duration / period + 1.0 + len(plan.formations))
    if samples <= MAX_ROBOT_SAMPLES:
        return period
    coarse = float(f"{period * samples / MAX_ROBOT_SAMPLES:.2g}") * 1.5
    where = plan.scenario.robots_span
    diagnostics.append(Diagnostic(
        plan.scenario.path, where.line, where.col, Severity.WARNING,
        f"{len(plan.robots)} robots over {plan.duration:.0f} s: check samples their places "
        f"every {coarse:g} s instead of every {period:g} s",
        "a brief contact between samples may go unreported: shorten the show or check parts "
        "of it with fewer robots", where.end_col))
    return coarse


def _sample_times(plan: Plan, period: float, end: float | None = None) -> FloatArray:
    """Every ``period`` s from 0 to ``end`` (default the plan's duration), and every
    formation's start."""
    end = plan.duration if end is None else end
    grid = np.arange(0.0, end + 0.5 * period, period)
    starts = [f.start for f in plan.formations]
    return np.unique(np.concatenate([grid, starts, [plan.duration, end]]))


@dataclass(frozen=True, slots=True, eq=False)
class ShowSamples:
    """The plan's desired poses, sampled once for everything that judges the show.

    times (T,): show time in s, every ``period`` s and at every formation change;
    poses (R, T, 3): each robot's desired pose (x, y in m, yaw in rad) in the show frame, in
    the plan's robot order; formations (R, T): the index in ``plan.formations`` of the
    formation each robot belongs to at each time; diagnostics: the warning when the show is
    so large that the period had to be longer than asked.
    """

    period: float
    times: FloatArray
    poses: FloatArray
    formations: NDArray[np.int64]
    diagnostics: tuple[Diagnostic, ...] = ()

    @property
    def first_slots(self) -> FloatArray:
        """(R, 3): the desired poses at t = 0 (the first sample), the first formation's slots."""
        slots: FloatArray = self.poses[:, 0]
        return slots


Places = Literal["rigid", "path"]
"""Which poses a placement samples: the rigid slots (the ``tracking`` follower's), or the
places on the leaders' paths that the ``path`` and ``thesis`` followers drive to
(``plan.places.path_places``)."""


def places_followed(follower: str) -> Places:
    """The poses ``follower`` drives its robot to: the rigid slots for ``tracking``, the
    places on the leaders' paths for ``path`` and ``thesis``."""
    return "rigid" if follower == "tracking" else "path"


def sample_show(plan: Plan, period: float = 0.1, places: Places = "rigid") -> ShowSamples:
    """Sample every robot's desired pose (``places``: its rigid slot, or its place on its
    leader's path, then on its way to its rigid slot after its leader's end until
    ``places_end``) every ``period`` s (longer for very large shows: at most
    :data:`MAX_ROBOT_SAMPLES` poses) and at every formation change."""
    diagnostics: list[Diagnostic] = []
    chosen = _sample_period(plan, period, diagnostics)
    if places == "path":
        from dancebots.plan.places import path_places, places_end  # places imports the planner

        times = _sample_times(plan, chosen, places_end(plan))  # and their way to the slots

        def placed(robot: str) -> FloatArray:
            points, heading, _, _ = path_places(plan, robot, times)
            return np.column_stack([points, wrap_angles(heading)])

        poses = np.stack([placed(r) for r in plan.robots])  # (R, T, 3)
    else:
        times = _sample_times(plan, chosen)
        poses = np.stack([plan.desired_poses(r, times) for r in plan.robots])  # (R, T, 3)
    which = np.stack([plan.formation_indices(r, times) for r in plan.robots])  # (R, T)
    return ShowSamples(chosen, times, poses, which, tuple(diagnostics))


def instruction_position(formation: PlannedFormation, time: float) -> tuple[int, int]:
    """The scenario position of what the formation's leader is doing at ``time``."""
    for timing in formation.timings:
        if timing.start <= time < timing.end:
            return timing.span.line, timing.span.col
    return formation.span.line, formation.span.col


def true_runs(mask: NDArray[np.bool_]) -> Iterator[tuple[int, int]]:
    """Index ranges [a, b) of the true runs of a 1-D boolean array."""
    padded = np.concatenate([[False], mask, [False]])
    edges = np.flatnonzero(np.diff(padded.astype(np.int8)))
    yield from zip(edges[::2].tolist(), edges[1::2].tolist(), strict=True)



def show_transform(plan: Plan, world: World, samples: ShowSamples,
                   diagnostics: list[Diagnostic], start_tolerance: float = 0.25) -> Pose | None:
    """The show frame's pose in the world frame (None, with an error in ``diagnostics``, when
    it cannot be found).

    With start poses for every robot: the rigid transform that best puts each robot's first
    slot on its start pose (heading: circular mean; position: mean residual), and a warning for
    robots that start far from their slot. With none: the show's extent (its robots' desired
    positions) is centred in the room. Robots of the scenario that a world with robots lacks
    are errors.
    """
    named = {r.name: r for r in world.robots}
    present = [r for r in plan.robots if r in named]
    missing = [r for r in plan.robots if r not in named]
    path = plan.scenario.path
    if present and missing:
        where = plan.scenario.robots_span
        diagnostics.append(Diagnostic(
            path, where.line, where.col, Severity.ERROR,
            f"the world places {' '.join(present)} but not {' '.join(missing)} "
            f"({world.path}:{world.robots[0].line})",
            f"give every robot of the scenario a [[robots]] entry in {world.path}, or none to "
            "let the show be centred in the room"))
        return None
    if not present:
        points = samples.poses[..., :2]
        low, high = points.min(axis=(0, 1)), points.max(axis=(0, 1))
        room_centre = 0.5 * (world.room.min(axis=0) + world.room.max(axis=0))
        show_centre = 0.5 * (low + high)
        shift = room_centre - show_centre
        return Pose(float(shift[0]), float(shift[1]), 0.0)
    slots = {r: samples.first_slots[i] for i, r in enumerate(plan.robots)}
    heading = math.atan2(sum(math.sin(named[r].start.theta - slots[r][2]) for r in present),
                         sum(math.cos(named[r].start.theta - slots[r][2]) for r in present))
    turned = points_to_world(np.array([slots[r][:2] for r in present]),
                             Pose(0.0, 0.0, heading))  # (P, 2): the slots, rotated
    starts = np.array([[named[r].start.x, named[r].start.y] for r in present])
    shift = (starts - turned).mean(axis=0)
    transform = Pose(float(shift[0]), float(shift[1]), heading)
    first = plan.formations[0].span
    for robot in present:
        x, y = transform.to_world(float(slots[robot][0]), float(slots[robot][1]))
        start = named[robot].start
        off = math.hypot(start.x - x, start.y - y)
        turn = abs(wrap_angle(start.theta - (heading + slots[robot][2])))
        if off > start_tolerance or turn > math.radians(15.0):
            diagnostics.append(Diagnostic(
                path, first.line, first.col, Severity.WARNING,
                f"{robot} starts {off:.2f} m and {math.degrees(turn):.0f} deg away from its "
                f"place in the first formation ({world.path}:{named[robot].line})",
                "place the robots on their slots of the first formation"))
    return transform


@dataclass(frozen=True, slots=True, eq=False)
class PlacedShow:
    """A plan placed in a world (or, without one, in an open arena around it).

    types (R,): each robot's type, in the plan's robot order; samples: the desired poses,
    sampled once; transform: the show frame's pose in the world frame (the identity without a
    world); starts (R, 3): each robot's start pose (x, y in m, yaw in rad) in the world frame;
    both None when the show cannot be placed at all. diagnostics: errors for everything the
    simulator refuses or would be stuck on, warnings for the rest (the sampling's own warning
    is in ``samples.diagnostics``).
    """

    plan: Plan
    world: World | None
    types: tuple[RobotType, ...]
    samples: ShowSamples
    transform: Pose | None
    starts: FloatArray | None
    diagnostics: tuple[Diagnostic, ...]

    @property
    def errors(self) -> tuple[Diagnostic, ...]:
        """The diagnostics that keep the show from being simulated."""
        return tuple(d for d in self.diagnostics if d.is_error)

    def footprint_extent(self) -> tuple[FloatArray, FloatArray]:
        """The lowest and highest corner, (2,) each in m in the show frame, of everything
        the robots' desired footprints cover at the sample times."""
        low, high = np.full(2, np.inf), np.full(2, -np.inf)
        poses = self.samples.poses
        for i, kind in enumerate(self.types):  # one robot at a time: memory O(samples)
            corners = footprint_corners(poses[i, :, 0], poses[i, :, 1], poses[i, :, 2],
                                        kind.length, kind.width).reshape(-1, 2)
            low = np.minimum(low, corners.min(axis=0))
            high = np.maximum(high, corners.max(axis=0))
        return low, high


def place_show(plan: Plan, world: World | None = None,
               default_type: RobotType = DEFAULT_ROBOT_TYPE, *, period: float = 0.1,
               start_tolerance: float = 0.25, places: Places = "rigid") -> PlacedShow:
    """Place a plan in a world (or in an open arena without one) and find what makes the
    show impossible to simulate: the one function that ``check`` and the simulator's setup
    both use. default_type: robots the world does not define (:func:`robot_types`); desired
    poses (``places``: :func:`sample_show`) are sampled every ``period`` s; a robot starting
    further than ``start_tolerance`` m from its first slot is a warning."""
    types = tuple(robot_types(plan, world, default_type))
    samples = sample_show(plan, period, places)
    diagnostics: list[Diagnostic] = []
    size = len(plan.robots) * plan.duration
    if size > MAX_SIMULATED_ROBOT_SECONDS:
        where = plan.scenario.robots_span
        diagnostics.append(Diagnostic(
            plan.scenario.path, where.line, where.col, Severity.ERROR,
            f"the show is too large to simulate: {len(plan.robots)} robots for "
            f"{plan.duration:.0f} s is {size:,.0f} robot-seconds (at most "
            f"{MAX_SIMULATED_ROBOT_SECONDS:,}; the simulator keeps about 6 kB per "
            "robot-second)", "simulate fewer robots or a shorter part of the show"))
    if world is None:
        transform = Pose(0.0, 0.0, 0.0)
        starts = _slot_starts(samples, transform)
        _check_starts(plan, None, types, starts, diagnostics)
        return PlacedShow(plan, None, types, samples, transform, starts, tuple(diagnostics))
    placed = show_transform(plan, world, samples, diagnostics, start_tolerance)
    for extra in (r for r in world.robots if r.name not in plan.robots):
        diagnostics.append(Diagnostic(
            world.path, extra.line, 1, Severity.WARNING,
            f"the world's robot {extra.name} is not in the scenario: it is left out of the show",
            "remove its [[robots]] entry, or add it to the scenario's robots line"))
    if placed is None:
        return PlacedShow(plan, world, types, samples, None, None, tuple(diagnostics))
    if any(r.name in plan.robots for r in world.robots):  # then all have one (else None)
        poses = {r.name: r.start for r in world.robots}
        starts = np.array([[poses[n].x, poses[n].y, poses[n].theta] for n in plan.robots])
    else:
        starts = _slot_starts(samples, placed)
    at_start = _check_starts(plan, world, types, starts, diagnostics)
    _check_world(plan, world, placed, types, samples, diagnostics, at_start)
    return PlacedShow(plan, world, types, samples, placed, starts, tuple(diagnostics))


def _slot_starts(samples: ShowSamples, transform: Pose) -> FloatArray:
    """Each robot's slot of the first formation (R, 3), placed in the world by ``transform``
    (its heading is not wrapped: the start pose keeps the plan's heading plus the turn)."""
    slots = samples.first_slots
    return np.column_stack([points_to_world(slots[:, :2], transform),
                            slots[:, 2] + transform.theta])


MAX_SIMULATED_ROBOT_SECONDS = 200_000
"""Robots times show duration (s) that the simulator takes on (about 1.4 GB: 6.5 kB per
robot-second above a 210 MB base, ``benchmarks/bench_memory.py``): 100 robots for
33 minutes, 1,000 robots for 3 minutes. Larger shows are errors of ``check`` and refused by
``run`` before anything is simulated."""

MAX_START_OVERLAPS = 20
"""Pairs of robots overlapping at their start poses that are named one by one; the rest are
counted in one more error (a pile of 1,000 robots has 499,500 pairs)."""


def _check_starts(plan: Plan, world: World | None, types: Sequence[RobotType], starts: FloatArray,
                  diagnostics: list[Diagnostic]) -> frozenset[tuple[str, str | None]]:
    """Errors for robots that cannot start where they stand (:func:`start_conflicts`); returns
    (robot, None) for those that start outside the room and (robot, obstacle label) for those
    that start in an obstacle. Start poses from the world are reported at their [[robots]]
    entry, slots of the first formation at that formation."""
    robots = plan.robots
    from_world = world is not None and any(world.robot(r) is not None for r in robots)
    first = plan.formations[0].span
    reported: set[tuple[str, str | None]] = set()

    def error(robot: int, message: str, hint: str) -> None:
        if world is not None and from_world:
            entry = world.robot(robots[robot])
            line = entry.line if entry is not None else 0
            diagnostics.append(Diagnostic(world.path, line, 1 if line else 0, Severity.ERROR,
                                          message, hint))
        else:
            diagnostics.append(Diagnostic(plan.scenario.path, first.line, first.col,
                                          Severity.ERROR, message, hint))

    room = world.room if world is not None else None
    obstacles = world.obstacles if world is not None else ()
    spectators = world.spectators if world is not None else ()
    world_path = world.path if world is not None else ""
    source = f" ({world_path}:{{}})"
    conflicts = start_conflicts(types, starts, room, obstacles, spectators)
    overlaps = [c for c in conflicts if c.kind == "robot"]
    if len(overlaps) > MAX_START_OVERLAPS:  # a pile of robots: name a few, count the rest
        shown = overlaps[MAX_START_OVERLAPS - 1]
        conflicts = [c for c in conflicts if c.kind != "robot"] + overlaps[:MAX_START_OVERLAPS]
        error(shown.other, f"... and {len(overlaps) - MAX_START_OVERLAPS} more pairs of robots "
              "overlap at their start poses", "place the robots further apart (in the first "
              "formation or the world)")
    for conflict in conflicts:
        name = robots[conflict.robot]
        if conflict.kind == "room":
            reported.add((name, None))
            error(conflict.robot, f"{name} starts outside the room of {world_path} or "
                  "against its wall", "its footprint must lie inside the room, clear of the "
                  "walls, at the start: move the start poses or use a bigger room")
        elif conflict.kind == "robot":
            error(conflict.other, f"{name} and {robots[conflict.other]} overlap at their "
                  "start poses", "place them further apart (in the first formation or "
                  "the world): the simulator would hold both where they stand")
        elif conflict.kind == "obstacle":
            obstacle = obstacles[conflict.other]
            reported.add((name, _label(world_path, obstacle)))
            error(conflict.robot, f"{name} starts in or against obstacle '{obstacle.name}'"
                  + source.format(obstacle.line), "move its start off the obstacle (the "
                  "world's start poses, or the show's first formation)")
        elif conflict.kind == "spectator":
            spectator = spectators[conflict.other]
            error(conflict.robot, f"{name} starts where spectator '{spectator.name}' stands"
                  + source.format(spectator.line), "move the show's start or the spectator's "
                  "first waypoint")
    return frozenset(reported)


def _label(world_path: str, obstacle: Obstacle) -> str:
    """How messages name an obstacle: its name and where the world file defines it."""
    return f"{obstacle.name} ({world_path}:{obstacle.line})"


@dataclass(frozen=True, slots=True)
class WorldViolation:
    """A robot's desired footprint outside the room (``obstacle`` None) or in an obstacle,
    from ``start`` to ``end`` s of show time, during the instruction at ``line``:``col``."""

    robot: str
    obstacle: str | None
    start: float
    end: float
    line: int
    col: int


def _check_world(plan: Plan, world: World, transform: Pose, types: Sequence[RobotType],
                 samples: ShowSamples, diagnostics: list[Diagnostic],
                 at_start: frozenset[tuple[str, str | None]] = frozenset()) -> None:
    """Leaving the room is an error (the simulator refuses the show); entering an obstacle
    is a warning. ``at_start``: (robot, None or obstacle label) already reported at the start
    (:func:`_check_starts`), whose violation from the first sample on is not repeated."""
    for v in _world_violations(plan, world, transform, types, samples):
        if (v.robot, v.obstacle) in at_start and v.start == float(samples.times[0]):
            continue
        if v.obstacle is None:
            diagnostics.append(Diagnostic(
                plan.scenario.path, v.line, v.col, Severity.ERROR,
                f"{v.robot} leaves the room from t = {v.start:.1f} s to {v.end:.1f} s",
                "move the show's start poses, use a bigger room, or shorten the moves"))
        else:
            diagnostics.append(Diagnostic(
                plan.scenario.path, v.line, v.col, Severity.WARNING,
                f"{v.robot} enters {v.obstacle} from t = {v.start:.1f} s to {v.end:.1f} s",
                "steer the formation around the obstacle"))


def _world_violations(plan: Plan, world: World, transform: Pose, types: Sequence[RobotType],
                      samples: ShowSamples) -> list[WorldViolation]:
    """Where each robot's desired footprint leaves the room or enters an obstacle."""
    found: list[WorldViolation] = []
    times, which = samples.times, samples.formations
    placed = compose_poses(np.array([transform.x, transform.y, transform.theta]),
                           samples.poses)  # (R, T, 3) in the world frame
    x, y, theta = placed[..., 0], placed[..., 1], placed[..., 2]
    room = shapely.Polygon(world.room)
    shapely.prepare(room)
    obstacles = [(o, shapely.Polygon(o.polygon)) for o in world.obstacles]

    def add(robot: int, name: str | None, mask: NDArray[np.bool_]) -> None:
        for a, b in true_runs(mask):
            line, col = instruction_position(plan.formations[int(which[robot, a])],
                                             float(times[a]))
            found.append(WorldViolation(plan.robots[robot], name, float(times[a]),
                                        float(times[b - 1]), line, col))

    for i in range(len(plan.robots)):
        kind = types[i]
        reach = math.hypot(kind.length, kind.width) / 2
        near_wall = shapely.distance(room.exterior, shapely.points(x[i], y[i])) < reach
        inside = shapely.contains_xy(room, x[i], y[i])
        outside = ~inside
        check = np.flatnonzero(near_wall & inside)
        if check.size:
            corners = footprint_corners(x[i, check], y[i, check], theta[i, check], kind.length,
                                        kind.width)
            outside[check] = ~shapely.contains(room, shapely.polygons(corners))
        add(i, None, outside)
        for obstacle, shape in obstacles:
            distance = shapely.distance(shape, shapely.points(x[i], y[i]))
            check = np.flatnonzero(distance < reach)
            hit = np.zeros(len(times), dtype=bool)
            if check.size:
                corners = footprint_corners(x[i, check], y[i, check], theta[i, check],
                                            kind.length, kind.width)
                hit[check] = shapely.intersects(shape, shapely.polygons(corners))
            add(i, _label(world.path, obstacle), hit)
    return sorted(found, key=lambda v: (v.start, v.robot))

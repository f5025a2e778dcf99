"""``check_scenario`` (thesis ch. 6) as a pure function: a plan in, a report out.

The report holds the show's summary and warnings that point at the scenario line concerned:
footprints closer than a clearance, circles tighter than the formation is wide, desired speeds
above a robot's maximum, and (with a world) robots leaving the room or entering obstacles.
All geometry is evaluated on the *desired* poses of the plan, sampled every
``CheckOptions.sample_period`` seconds and at every formation change.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely
from numpy.typing import NDArray

from dancebots.diagnostics import Diagnostic, Severity
from dancebots.geometry import Pose, footprint_corners, wrap_angle
from dancebots.perception.obstacles import DetectorParams
from dancebots.plan.planner import Plan, PlannedFormation, PlanParameters, build_plan
from dancebots.scenario.model import Circle, Scenario
from dancebots.scenario.parser import parse_scenario
from dancebots.world import DEFAULT_ROBOT_TYPE, Obstacle, RobotType, World, start_conflicts

__all__ = [
    "CheckOptions",
    "CheckReport",
    "RobotSummary",
    "ShowPlacement",
    "WorldViolation",
    "check_plan",
    "compile_scenario",
    "place_plan_in_world",
    "place_show",
    "robot_types",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class CheckOptions:
    """What ``check`` looks for.

    clearance: smallest allowed gap between two robots' footprints, m.
    sample_period: desired poses are checked at this period, s.
    robot_type: footprint and limits of robots that the world does not define (or all robots
        without a world); its max_speed is replaced by vmax when there is no world.
    start_tolerance: a robot starting further than this from its first slot is reported, m.
    detection: the robots' obstacle detection: rows nearer than its stop distance behind each
        other are reported (their LIDAR would hold the rear robots).
    """

    clearance: float = 0.2
    sample_period: float = 0.1
    robot_type: RobotType = DEFAULT_ROBOT_TYPE
    start_tolerance: float = 0.25
    detection: DetectorParams = field(default_factory=DetectorParams)


@dataclass(frozen=True, slots=True)
class RobotSummary:
    """One robot over the whole show: length of its desired path (m), its largest desired
    linear (m/s) and angular (rad/s) speeds, and its type's limits."""

    name: str
    robot_type: RobotType
    path_length: float
    max_speed: float
    max_angular_speed: float


@dataclass(frozen=True, slots=True)
class CheckReport:
    """The result of checking one plan."""

    path: str
    robots: tuple[str, ...]
    groups: tuple[tuple[str, tuple[str, ...]], ...]
    duration: float
    summaries: tuple[RobotSummary, ...]
    min_clearance: float | None
    world_transform: Pose | None
    diagnostics: tuple[Diagnostic, ...] = field(default=())
    placement: ShowPlacement | None = None
    """Where the show stands (:func:`place_show`'s answer), for the simulator's setup."""

    def to_json(self) -> dict[str, object]:
        return {
            "path": self.path,
            "robots": list(self.robots),
            "groups": {name: list(members) for name, members in self.groups},
            "duration_s": round(self.duration, 3),
            "min_clearance_m": None if self.min_clearance is None else round(
                self.min_clearance, 3),
            "world_transform": None if self.world_transform is None else {
                "x": self.world_transform.x, "y": self.world_transform.y,
                "yaw": self.world_transform.theta},
            "per_robot": {
                s.name: {
                    "type": s.robot_type.name,
                    "path_length_m": round(s.path_length, 3),
                    "max_speed_mps": round(s.max_speed, 3),
                    "max_angular_speed_radps": round(s.max_angular_speed, 3),
                    "speed_limit_mps": s.robot_type.max_speed,
                } for s in self.summaries
            },
        }


def compile_scenario(
    text: str, path: str, parameters: PlanParameters | None = None
) -> tuple[Scenario | None, Plan | None, list[Diagnostic]]:
    """Parse and plan; returns whatever could be built and every diagnostic so far."""
    scenario, diagnostics = parse_scenario(text, path)
    if scenario is None:
        return None, None, diagnostics
    plan, plan_diagnostics = build_plan(scenario, parameters)
    return scenario, plan, diagnostics + plan_diagnostics


def check_plan(plan: Plan, world: World | None = None,
               options: CheckOptions | None = None) -> CheckReport:
    """Check a plan (and its placement in a world); pure, deterministic."""
    options = options or CheckOptions()
    scenario = plan.scenario
    diagnostics: list[Diagnostic] = []
    types = robot_types(plan, world, options.robot_type)
    period = _sample_period(plan, options.sample_period, diagnostics)
    times = _sample_times(plan, period)
    poses = np.stack([plan.desired_poses(r, times) for r in plan.robots])  # (R, T, 3)
    which = np.stack([plan.formation_indices(r, times) for r in plan.robots])  # (R, T)
    summaries = _summaries(plan, types, diagnostics)
    min_gap = _check_clearance(plan, types, times, poses, which, options, diagnostics)
    _check_circles(plan, diagnostics)
    placed = _place_show(plan, world, types, (times, poses, which), options.start_tolerance)
    diagnostics.extend(placed.diagnostics)
    transform = placed.transform if world is not None else None
    return CheckReport(scenario.path, scenario.robots, scenario.groups, plan.duration,
                       tuple(summaries), min_gap, transform, tuple(diagnostics), placed)


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
"""Most desired poses (robots x sample times) that one check holds (48 MB per array)."""


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


def _sample_times(plan: Plan, period: float) -> FloatArray:
    grid = np.arange(0.0, plan.duration + 0.5 * period, period)
    starts = [f.start for f in plan.formations]
    return np.unique(np.concatenate([grid, starts, [plan.duration]]))


def _line_at(formation: PlannedFormation, time: float) -> tuple[int, int]:
    """The scenario position of what the formation's leader is doing at ``time``."""
    for timing in formation.timings:
        if timing.start <= time < timing.end:
            return timing.span.line, timing.span.col
    return formation.span.line, formation.span.col


def _runs(mask: NDArray[np.bool_]) -> Iterator[tuple[int, int]]:
    """Index ranges [a, b) of the true runs of a 1-D boolean array."""
    padded = np.concatenate([[False], mask, [False]])
    edges = np.flatnonzero(np.diff(padded.astype(np.int8)))
    yield from zip(edges[::2].tolist(), edges[1::2].tolist(), strict=True)


def _warn(plan: Plan, position: tuple[int, int], message: str, hint: str | None,
          diagnostics: list[Diagnostic]) -> None:
    diagnostics.append(Diagnostic(plan.scenario.path, position[0], position[1],
                                  Severity.WARNING, message, hint))


# --- speeds ----------------------------------------------------------------------------------

_SPEED_CHUNK = 1_000_000
"""Robot speeds (robots x leader steps) computed at once by the summaries (8 MB)."""


def _summaries(plan: Plan, types: Sequence[RobotType],
               diagnostics: list[Diagnostic]) -> list[RobotSummary]:
    """Path lengths and peak speeds from the leaders' exact commands; speed warnings.

    A robot at lateral offset oy of a leader moving with (v, w) drives the leader's path
    shifted sideways by oy, at the along-track speed |v - w oy|. The longitudinal part w ox
    is not required: the formation may stretch and shrink lengthwise in turns and keeps only
    its lateral distances (thesis ch. 4.1), so it does not count as desired speed.
    """
    index = {r: k for k, r in enumerate(plan.robots)}
    length = np.zeros(len(plan.robots))
    peak = np.zeros(len(plan.robots))
    peak_turn = np.zeros(len(plan.robots))
    for formation in plan.formations:
        leader = formation.leader
        v, w = leader.commands[:, 0], leader.commands[:, 1]
        dt = np.diff(leader.times, append=leader.times[-1])
        members = list(formation.robots)
        offsets = np.array([formation.offsets[r] for r in members])  # (M, 2)
        turn = float(np.abs(w).max())
        windows = [(timing, int(a), int(b)) for timing in formation.timings
                   for a, b in [np.searchsorted(leader.times, [timing.start, timing.end])]
                   if b > a]
        robot_max = np.zeros((len(windows), len(members)))  # per window and robot, m/s
        time_max = [np.zeros(b - a) for _, a, b in windows]  # per window and step, m/s
        rows = max(1, _SPEED_CHUNK // len(v))  # robots per block: bounded memory
        for first in range(0, len(members), rows):
            block = slice(first, first + rows)
            speeds = np.abs(v[None, :] - w[None, :] * offsets[block, 1:2])  # (rows, N)
            for k, robot in enumerate(members[block]):
                i = index[robot]
                length[i] += float(speeds[k] @ dt)
                peak[i] = max(peak[i], float(speeds[k].max()))
                peak_turn[i] = max(peak_turn[i], turn)
            for n, (_, a, b) in enumerate(windows):
                window = speeds[:, a:b]
                robot_max[n, block] = window.max(axis=1)
                np.maximum(time_max[n], window.max(axis=0), out=time_max[n])
        limits = np.array([types[index[r]].max_speed for r in members])
        for n, (timing, a, _) in enumerate(windows):
            over = robot_max[n] > limits + 1e-9
            if not over.any():
                continue
            worst = [f"{members[k]} {robot_max[n, k]:.2f} m/s (max {limits[k]:g})"
                     for k in np.flatnonzero(over)]
            when = float(leader.times[a + int(np.argmax(time_max[n]))])
            _warn(plan, (timing.span.line, timing.span.col),
                  f"desired speed above the robot's maximum: {', '.join(worst)}, "
                  f"around t = {when:.1f} s",
                  "the formation turns faster than its outer robots can drive: turn by a "
                  "smaller angle or along a circle of larger radius, or lower --vmax",
                  diagnostics)
    return [RobotSummary(r, types[i], float(length[i]), float(peak[i]), float(peak_turn[i]))
            for i, r in enumerate(plan.robots)]


# --- clearance -------------------------------------------------------------------------------

def _footprints(corners: FloatArray) -> NDArray[np.object_]:
    """Shapely polygons from corners (..., 4, 2)."""
    polygons: NDArray[np.object_] = shapely.polygons(corners)
    return polygons


def _gap_in_corridor(first: FloatArray, second: FloatArray, first_size: FloatArray,
                     second_size: FloatArray, detection: DetectorParams) -> float | None:
    """The gap (m) between two robots one behind the other in a formation, when the rear one's
    stop corridor (its width plus the margin on each side) reaches the front one; offsets
    (2,) in the leader's frame, sizes (2,) length and width. None when they are side by side."""
    back, front = (first, second) if first[0] < second[0] else (second, first)
    back_size, front_size = (first_size, second_size) if first[0] < second[0] else (
        second_size, first_size)
    lateral = abs(front[1] - back[1]) - 0.5 * front_size[1]
    if lateral > 0.5 * back_size[1] + detection.corridor_margin:
        return None
    gap = (front[0] - back[0]) - 0.5 * (front_size[0] + back_size[0])
    return float(gap) if gap >= 0 else None


def _check_clearance(plan: Plan, types: Sequence[RobotType], times: FloatArray,
                     poses: FloatArray, which: NDArray[np.int64], options: CheckOptions,
                     diagnostics: list[Diagnostic]) -> float | None:
    """Footprint gaps: once per formation for robots of the same formation (their relative
    pose is fixed), at every sample for robots that follow different leaders.

    Both find near pairs first (a spatial index, shapely's STRtree, in a formation; a sort and
    sweep per sample across formations), so the cost grows with the robots and their near
    neighbours, not with the robots squared.
    """
    gaps: list[float] = []
    robots = plan.robots
    index = {r: k for k, r in enumerate(robots)}
    checked: dict[int, set[str]] = {}  # formation line -> robots whose pairs were checked
    reach = max(options.clearance,
                options.detection.stop_distance + options.detection.corridor_margin)
    for formation in plan.formations:
        members = formation.robots
        if len(members) < 2:
            continue
        done = checked.setdefault(formation.span.line, set())
        if done.issuperset(members):  # what remains of a split formation keeps its offsets
            continue
        done.update(members)
        offsets = np.array([formation.offsets[r] for r in members])
        sizes = np.array([(types[index[r]].length, types[index[r]].width) for r in members])
        shapes = _footprints(footprint_corners(offsets[:, 0], offsets[:, 1],
                                               np.zeros(len(offsets)), sizes[:, 0],
                                               sizes[:, 1]))
        if len(members) * (len(members) - 1) // 2 <= _PAIR_LOOP_LIMIT:
            first, second = np.array(list(itertools.combinations(range(len(members)), 2))).T
            pair_gaps = shapely.distance(shapes[first], shapes[second])
            gaps.append(float(pair_gaps.min()))
        else:
            tree = shapely.STRtree(shapes)
            first, second, pair_gaps = _pairs_within(tree, shapes, reach)
            if len(first):  # every pair further apart than these is further than ``reach``
                gaps.append(float(pair_gaps.min()))
            else:
                _, nearest = tree.query_nearest(shapes, exclusive=True, return_distance=True)
                gaps.append(float(nearest.min()))
        n_close = n_behind = 0
        for a, b, gap in zip(first.tolist(), second.tolist(), pair_gaps.tolist(), strict=True):
            if gap < options.clearance:
                n_close += 1
                if n_close <= _PAIR_WARNINGS:
                    _warn(plan, (formation.span.line, formation.span.col),
                          f"{members[a]} and {members[b]} are {gap:.2f} m apart in this "
                          f"formation (clearance {options.clearance:g} m)",
                          "increase the spacing or the row distance", diagnostics)
                continue
            behind = _gap_in_corridor(offsets[a], offsets[b], sizes[a], sizes[b],
                                      options.detection)
            if behind is not None and behind < options.detection.stop_distance:
                n_behind += 1
                if n_behind > _PAIR_WARNINGS:
                    continue
                front, back = (a, b) if offsets[a][0] > offsets[b][0] else (b, a)
                _warn(plan, (formation.span.line, formation.span.col),
                      f"{members[back]} follows {members[front]} at {behind:.2f} m, nearer "
                      f"than the {options.detection.stop_distance:g} m stop distance: its "
                      "LIDAR will hold it whenever the formation closes up",
                      "increase the row distance", diagnostics)
        if n_close > _PAIR_WARNINGS or n_behind > _PAIR_WARNINGS:
            _warn(plan, (formation.span.line, formation.span.col),
                  f"in all, {n_close} pairs of robots of this formation are closer than the "
                  f"clearance and {n_behind} follow each other nearer than the stop "
                  f"distance (the first {_PAIR_WARNINGS} of each are listed)",
                  "increase the spacing or the row distance", diagnostics)
    radius = np.array([math.hypot(t.length, t.width) / 2 for t in types])
    margin = max(options.clearance, 1.0)
    table, complete = _apart_candidates(poses, which, radius, margin)  # (n, 3): i, j, sample
    if not complete:
        where = plan.scenario.robots_span
        _warn(plan, (where.line, where.col),
              "so many robots are piled on each other that check compared only some of the "
              "robots of different formations",
              "spread the robots out: give the formations spacings and row distances",
              diagnostics)
    if not len(table):
        return min(gaps) if gaps else None
    i, j, k = table.T
    size = np.array([(t.length, t.width) for t in types])
    shape_i = _footprints(footprint_corners(poses[i, k, 0], poses[i, k, 1], poses[i, k, 2],
                                            size[i, 0], size[i, 1]))
    shape_j = _footprints(footprint_corners(poses[j, k, 0], poses[j, k, 1], poses[j, k, 2],
                                            size[j, 0], size[j, 1]))
    distance = shapely.distance(shape_i, shape_j)
    gaps.append(float(distance.min()))
    close = np.flatnonzero(distance < options.clearance)
    # runs: close rows of one pair at consecutive samples (rows are sorted by pair, then time)
    i, j, k, distance = i[close], j[close], k[close], distance[close]
    new = np.ones(len(close), dtype=bool)
    new[1:] = (i[1:] != i[:-1]) | (j[1:] != j[:-1]) | (k[1:] != k[:-1] + 1)
    starts = np.flatnonzero(new)
    if not len(starts):
        return min(gaps)
    ends = np.append(starts[1:], len(close))
    nearest = np.minimum.reduceat(distance, starts)
    for n, (a, b) in enumerate(zip(starts.tolist(), ends.tolist(), strict=True)):
        if n == _CROSS_WARNINGS:
            _warn(plan, (plan.scenario.robots_span.line, plan.scenario.robots_span.col),
                  f"in all, robots of different formations come closer than the clearance "
                  f"{len(starts)} times (the first {_CROSS_WARNINGS} are listed)",
                  "their paths cross: move the formations further apart or let one wait",
                  diagnostics)
            break
        first, last = int(k[a]), int(k[b - 1])
        formation = plan.formations[int(which[i[a], first])]
        _warn(plan, _line_at(formation, float(times[first])),
              f"{robots[i[a]]} and {robots[j[a]]} come within {nearest[n]:.2f} m of each "
              f"other (clearance {options.clearance:g} m) from t = {times[first]:.1f} s to "
              f"{times[last]:.1f} s",
              "their paths cross: move the formations further apart or let one wait",
              diagnostics)
    return min(gaps) if gaps else None


def _pairs_within(tree: shapely.STRtree, shapes: NDArray[np.object_], distance: float,
                  ) -> tuple[NDArray[np.int64], NDArray[np.int64], FloatArray]:
    """Index pairs (a < b), in lexicographic order, of the shapes (indexed by ``tree``) that
    are at most ``distance`` (m) apart, and their distances (m): the tree pairs the shapes
    whose bounding boxes, grown by ``distance``, overlap; one exact distance each decides."""
    low = shapely.bounds(shapes)
    boxes = shapely.box(low[:, 0] - distance, low[:, 1] - distance, low[:, 2] + distance,
                        low[:, 3] + distance)
    a, b = tree.query(boxes)
    keep = a < b
    a, b = a[keep], b[keep]
    order = np.lexsort((b, a))
    a, b = a[order].astype(np.int64), b[order].astype(np.int64)
    gaps = shapely.distance(shapes[a], shapes[b])
    near = gaps <= distance
    return a[near], b[near], gaps[near]


_PAIR_WARNINGS = 20
"""At most this many pairs of one formation are reported by name for each kind of problem."""
_MAX_CANDIDATES = 250_000
"""At most this many (pair, sample) candidates of robots of different formations are kept."""
_MAX_SWEEP = 20_000_000
"""At most this many position comparisons are made to find them (robots piled on each other
would otherwise cost robots squared times samples)."""
_CROSS_WARNINGS = 100
"""At most this many close passes of robots of different formations are reported by name."""
_PAIR_LOOP_LIMIT = 2000
"""Up to this many pairs of robots (of a formation, or that ever follow different leaders),
every pair is compared; above it, near pairs are found first (an STRtree in a formation, a
sweep along each sample's sorted positions across formations)."""


def _apart_candidates(poses: FloatArray, which: NDArray[np.int64], radius: FloatArray,
                      margin: float) -> tuple[NDArray[np.int64], bool]:
    """Rows (i, j, k), sorted: robots i < j follow different leaders at sample k and their
    centres are nearer than their radii (m) plus ``margin``; poses (R, T, 3), which (R, T).
    And whether they are all there (false when robots piled on each other made the search
    stop at :data:`_MAX_CANDIDATES` rows or :data:`_MAX_SWEEP` comparisons)."""
    count = which.shape[0]
    histories: dict[bytes, int] = {}  # robots with the same formation at every sample
    group = np.array([histories.setdefault(row.tobytes(), len(histories)) for row in which])
    sizes = np.bincount(group)
    cross = (count * count - int((sizes * sizes).sum())) // 2
    found = [np.zeros((0, 3), dtype=np.int64)]
    if cross == 0:
        return found[0], True
    if cross <= _PAIR_LOOP_LIMIT:
        for i, j in itertools.combinations(range(count), 2):
            if group[i] == group[j]:
                continue
            apart = which[i] != which[j]
            centre = np.hypot(poses[i, :, 0] - poses[j, :, 0], poses[i, :, 1] - poses[j, :, 1])
            candidates = np.flatnonzero(apart & (centre < radius[i] + radius[j] + margin))
            found.append(np.stack([np.full(candidates.size, i), np.full(candidates.size, j),
                                   candidates], axis=1).astype(np.int64))
        return np.concatenate(found), True
    reach = 2.0 * float(radius.max()) + margin
    x, y = poses[:, :, 0].T, poses[:, :, 1].T  # (T, R)
    # sweep and prune: per sample, robots sorted along the axis on which they spread most;
    # robots d places apart in that order are compared while any of them are within reach
    spread_x = x.max(axis=1) - x.min(axis=1)
    spread_y = y.max(axis=1) - y.min(axis=1)
    u = np.where((spread_x >= spread_y)[:, None], x, y)
    order = np.argsort(u, axis=1, kind="stable")
    u = np.take_along_axis(u, order, axis=1)
    complete, work = True, 0
    for d in range(1, count):
        work += u.shape[0] * (count - d)
        if work > _MAX_SWEEP:
            complete = False
            break
        k, at = np.nonzero(u[:, d:] - u[:, :-d] < reach)
        if not k.size:
            break
        a, b = order[k, at], order[k, at + d]
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        keep = which[lo, k] != which[hi, k]
        lo, hi, k = lo[keep], hi[keep], k[keep]
        keep = np.hypot(x[k, lo] - x[k, hi], y[k, lo] - y[k, hi]) < radius[lo] + radius[hi] + margin
        found.append(np.stack([lo[keep], hi[keep], k[keep]], axis=1).astype(np.int64))
        if sum(len(rows) for rows in found) > _MAX_CANDIDATES:
            complete = False
            break
    table = np.concatenate(found)
    return table[np.lexsort((table[:, 2], table[:, 1], table[:, 0]))], complete


def _check_circles(plan: Plan, diagnostics: list[Diagnostic]) -> None:
    """Thesis ch. 6: the radius must exceed every robot's lateral offset from the leader."""
    for formation in plan.formations:
        widest = max(formation.robots, key=lambda r: abs(formation.offsets[r][1]))
        lateral = abs(formation.offsets[widest][1])
        for timing in formation.timings:
            circle = timing.instruction
            if isinstance(circle, Circle) and abs(circle.radius) < lateral:
                _warn(plan, (circle.span.line, circle.span.col),
                      f"the circle's radius {abs(circle.radius):g} m is smaller than {widest}'s "
                      f"lateral offset {lateral:g} m from the virtual leader: the inner robots "
                      "would have to reverse",
                      f"use a radius larger than {lateral:g} m or a narrower formation",
                      diagnostics)


# --- world -----------------------------------------------------------------------------------

def place_plan_in_world(plan: Plan, world: World, diagnostics: list[Diagnostic],
                        start_tolerance: float = 0.25) -> Pose | None:
    """The show frame's pose in the world frame.

    With start poses for every robot: the rigid transform that best puts each robot's first
    slot on its start pose (heading: circular mean; position: mean residual), and a warning for
    robots that start far from their slot. With none: the show's extent is centred in the room.
    Robots of the scenario that a world with robots lacks are errors.
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
        times = _sample_times(plan, 1.0)
        low, high = np.full(2, np.inf), np.full(2, -np.inf)
        for robot in plan.robots:  # one robot at a time: memory O(samples)
            points = plan.desired_poses(robot, times)[:, :2]
            low, high = np.minimum(low, points.min(axis=0)), np.maximum(high, points.max(axis=0))
        room_centre = 0.5 * (world.room.min(axis=0) + world.room.max(axis=0))
        show_centre = 0.5 * (low + high)
        shift = room_centre - show_centre
        return Pose(float(shift[0]), float(shift[1]), 0.0)
    slots = {r: plan.desired_poses(r, np.zeros(1))[0] for r in plan.robots}
    heading = math.atan2(sum(math.sin(named[r].start.theta - slots[r][2]) for r in present),
                         sum(math.cos(named[r].start.theta - slots[r][2]) for r in present))
    c, s = math.cos(heading), math.sin(heading)
    residual = np.array([[named[r].start.x - (c * slots[r][0] - s * slots[r][1]),
                          named[r].start.y - (s * slots[r][0] + c * slots[r][1])]
                         for r in present])
    shift = residual.mean(axis=0)
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
class ShowPlacement:
    """Where a show stands, and every reason it cannot be simulated there.

    transform: the show frame's pose in the world frame (the identity without a world);
    starts (R, 3): each robot's start pose (x, y in m, yaw in rad) in the world frame, in the
    plan's robot order; both None when the show cannot be placed at all. diagnostics: errors
    for everything the simulator refuses or would be stuck on, warnings for the rest.
    """

    transform: Pose | None
    starts: FloatArray | None
    diagnostics: tuple[Diagnostic, ...]

    @property
    def errors(self) -> tuple[Diagnostic, ...]:
        return tuple(d for d in self.diagnostics if d.is_error)


Samples = tuple[FloatArray, FloatArray, NDArray[np.int64]]
"""Sample times (T,), desired poses (R, T, 3) in the show frame, formation indices (R, T)."""


def place_show(plan: Plan, world: World | None, types: Sequence[RobotType],
               period: float = 0.1, start_tolerance: float = 0.25) -> ShowPlacement:
    """Place a plan in a world (or in an open arena without one) and find what makes the
    show impossible to simulate: the one function that ``check`` and the simulator's setup
    both use. Desired poses are sampled every ``period`` s; ``start_tolerance`` (m) as in
    :class:`CheckOptions`."""
    return _place_show(plan, world, types, None, start_tolerance, period)


def _place_show(plan: Plan, world: World | None, types: Sequence[RobotType],
                samples: Samples | None, start_tolerance: float,
                period: float = 0.1) -> ShowPlacement:
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
        starts = _slot_starts(plan, transform)
        _check_starts(plan, None, types, starts, diagnostics)
        return ShowPlacement(transform, starts, tuple(diagnostics))
    placed = place_plan_in_world(plan, world, diagnostics, start_tolerance)
    for extra in (r for r in world.robots if r.name not in plan.robots):
        diagnostics.append(Diagnostic(
            world.path, extra.line, 1, Severity.WARNING,
            f"the world's robot {extra.name} is not in the scenario: it is left out of the show",
            "remove its [[robots]] entry, or add it to the scenario's robots line"))
    if placed is None:
        return ShowPlacement(None, None, tuple(diagnostics))
    if any(r.name in plan.robots for r in world.robots):  # then all have one (else None)
        poses = {r.name: r.start for r in world.robots}
        starts = np.array([[poses[n].x, poses[n].y, poses[n].theta] for n in plan.robots])
    else:
        starts = _slot_starts(plan, placed)
    at_start = _check_starts(plan, world, types, starts, diagnostics)
    if samples is None:  # sampled as check_plan samples (coarser for very long shows)
        times = _sample_times(plan, _sample_period(plan, period, []))
        samples = (times, np.stack([plan.desired_poses(r, times) for r in plan.robots]),
                   np.stack([plan.formation_indices(r, times) for r in plan.robots]))
    _check_world(plan, world, placed, types, *samples, diagnostics, at_start)
    return ShowPlacement(placed, starts, tuple(diagnostics))


def _slot_starts(plan: Plan, transform: Pose) -> FloatArray:
    """Each robot's slot of the first formation (R, 3), placed in the world by ``transform``."""
    slots = np.stack([plan.desired_poses(r, np.zeros(1))[0] for r in plan.robots])
    c, s = math.cos(transform.theta), math.sin(transform.theta)
    return np.stack([transform.x + c * slots[:, 0] - s * slots[:, 1],
                     transform.y + s * slots[:, 0] + c * slots[:, 1],
                     slots[:, 2] + transform.theta], axis=1)


MAX_SIMULATED_ROBOT_SECONDS = 200_000
"""Robots times show duration (s) that the simulator takes on (about 1.4 GB: 6.4 kB per
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
                 times: FloatArray, poses: FloatArray, which: NDArray[np.int64],
                 diagnostics: list[Diagnostic],
                 at_start: frozenset[tuple[str, str | None]] = frozenset()) -> None:
    """Leaving the room is an error (the simulator refuses the show); entering an obstacle
    is a warning. ``at_start``: (robot, None or obstacle label) already reported at the start
    (:func:`_check_starts`), whose violation from the first sample on is not repeated."""
    for v in _world_violations(plan, world, transform, types, times, poses, which):
        if (v.robot, v.obstacle) in at_start and v.start == float(times[0]):
            continue
        if v.obstacle is None:
            diagnostics.append(Diagnostic(
                plan.scenario.path, v.line, v.col, Severity.ERROR,
                f"{v.robot} leaves the room from t = {v.start:.1f} s to {v.end:.1f} s",
                "move the show's start poses, use a bigger room, or shorten the moves"))
        else:
            _warn(plan, (v.line, v.col), f"{v.robot} enters {v.obstacle} from t = "
                  f"{v.start:.1f} s to {v.end:.1f} s", "steer the formation around the obstacle",
                  diagnostics)


def _world_violations(plan: Plan, world: World, transform: Pose, types: Sequence[RobotType],
                      times: FloatArray, poses: FloatArray,
                      which: NDArray[np.int64]) -> list[WorldViolation]:
    found: list[WorldViolation] = []
    c, s = math.cos(transform.theta), math.sin(transform.theta)
    x = transform.x + c * poses[..., 0] - s * poses[..., 1]
    y = transform.y + s * poses[..., 0] + c * poses[..., 1]
    theta = poses[..., 2] + transform.theta
    room = shapely.Polygon(world.room)
    shapely.prepare(room)
    obstacles = [(o, shapely.Polygon(o.polygon)) for o in world.obstacles]

    def add(robot: int, name: str | None, mask: NDArray[np.bool_]) -> None:
        for a, b in _runs(mask):
            line, col = _line_at(plan.formations[int(which[robot, a])], float(times[a]))
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

"""``check_scenario`` (thesis ch. 6) as a pure function: a placed show in, a report out.

The report holds the show's summary and warnings that point at the scenario line concerned:
footprints closer than a clearance, circles tighter than the formation is wide, desired speeds
above a robot's maximum, and the placement's findings (robots starting on each other, leaving
the room, entering obstacles: :mod:`dancebots.plan.placement`). All geometry is evaluated on
the *desired* poses of the plan, sampled once by the placement every
``CheckOptions.sample_period`` seconds and at every formation change.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import shapely
from numpy.typing import NDArray

from dancebots.diagnostics import Diagnostic, Severity
from dancebots.geometry import Pose, footprint_corners
from dancebots.perception.obstacles import DetectorParams
from dancebots.plan.formation import formation_offsets
from dancebots.plan.placement import (
    PlacedShow,
    Places,
    ShowSamples,
    instruction_position,
    place_show,
)
from dancebots.plan.planner import DEPARTURE_DELAYS, Plan, build_plan
from dancebots.scenario.model import Circle, Formation
from dancebots.world import DEFAULT_ROBOT_TYPE, RobotType, World

__all__ = [
    "ROOM_FACTORS",
    "CheckOptions",
    "CheckReport",
    "RobotSummary",
    "Widening",
    "check_plan",
    "check_show",
    "widening_that_keeps_apart",
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
    places: which desired poses the clearance, speed and room checks judge: ``rigid`` (the
        rigid slots, the ``tracking`` follower's) or ``path`` (the places on the leaders'
        paths that the ``path`` and ``thesis`` followers drive to).
    """

    clearance: float = 0.2
    sample_period: float = 0.1
    robot_type: RobotType = DEFAULT_ROBOT_TYPE
    start_tolerance: float = 0.25
    detection: DetectorParams = field(default_factory=DetectorParams)
    places: Places = "rigid"


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
    placement: PlacedShow | None = None
    """The placed show that was checked, for the simulator's setup."""

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


def check_plan(plan: Plan, world: World | None = None,
               options: CheckOptions | None = None) -> CheckReport:
    """Place a plan in a world (:func:`~dancebots.plan.placement.place_show`, as the options
    say) and check it; pure, deterministic."""
    options = options or CheckOptions()
    return check_show(place_show(plan, world, options.robot_type,
                                 period=options.sample_period,
                                 start_tolerance=options.start_tolerance,
                                 places=options.places), options)


def check_show(show: PlacedShow, options: CheckOptions | None = None) -> CheckReport:
    """Check a placed show: its summary, then diagnostics in this order: sampling, speeds,
    clearance, circles, slowdowns (notes), the ways at formation changes, placement. Only
    ``options.clearance`` and
    ``options.detection`` matter here; the rest were the placement's."""
    options = options or CheckOptions()
    plan, samples, types = show.plan, show.samples, show.types
    scenario = plan.scenario
    diagnostics: list[Diagnostic] = list(samples.diagnostics)
    summaries = _summaries(plan, types, diagnostics)
    min_gap = _check_clearance(plan, types, samples.times, samples.poses, samples.formations,
                               options, diagnostics)
    _check_circles(plan, diagnostics)
    _note_slowdowns(plan, diagnostics)
    _note_departures(plan, diagnostics)
    if options.places == "path":
        _note_waits(plan, diagnostics)
    _check_transitions(plan, types, samples, diagnostics)
    diagnostics.extend(show.diagnostics)
    transform = show.transform if show.world is not None else None
    return CheckReport(scenario.path, scenario.robots, scenario.groups, plan.duration,
                       tuple(summaries), min_gap, transform, tuple(diagnostics), show)



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
                  "smaller angle or along a circle of larger radius, or let the leader slow where "
                  "it must (--timing feasible)",
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
    widenings = _Widenings()
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
        pair = (robots[i[a]], robots[j[a]])
        stuck = pair in plan.apart_by_no_delay or pair[::-1] in plan.apart_by_no_delay
        place = instruction_position(formation, float(times[first]))
        _warn(plan, place,
              f"{pair[0]} and {pair[1]} come within {nearest[n]:.2f} m of each "
              f"other (clearance {options.clearance:g} m) from t = {times[first]:.1f} s to "
              f"{times[last]:.1f} s",
              "no departure delay keeps them apart (the feasible timing tried "
              f"{_delays_text()} s for either formation): "
              + _room_text(plan, pair, place[0], widenings) if stuck else
              "their paths cross: move the formations further apart or let one wait",
              diagnostics)
    return min(gaps) if gaps else None


ROOM_FACTORS = (1.25, 1.5, 2.0)
"""How much wider check tries the formation two robots last shared, when no departure delay
keeps them apart at a later formation change (:func:`widening_that_keeps_apart`)."""


@dataclass(frozen=True, slots=True)
class Widening:
    """A formation two robots shared (``line``), widened by ``factor`` (every spacing and row
    distance), after which the feasible timing keeps them apart: their distance there
    before and after, m."""

    line: int
    factor: float
    before: float
    after: float


def widening_that_keeps_apart(plan: Plan, pair: tuple[str, str],
                              line: int) -> Widening | None:
    """The least of :data:`ROOM_FACTORS` by which widening the last formation instruction
    before ``line`` that holds both robots of ``pair`` (every spacing and row distance of it)
    lets the plan's ordered departures keep them apart (the pair is no longer among
    ``Plan.apart_by_no_delay``), the plan rebuilt with its own parameters for each; None
    when there is no such formation or none of the factors is enough."""
    index = _last_shared(plan, pair, line)
    return None if index is None else _widening(plan, pair, index)


def _last_shared(plan: Plan, pair: tuple[str, str], line: int) -> int | None:
    """The index in the scenario's instructions of the last formation before ``line`` that
    holds both robots of ``pair``, or None."""
    shared = [index for index, instruction in enumerate(plan.scenario.instructions)
              if isinstance(instruction, Formation) and instruction.span.line < line
              and all(any(robot in row for row in instruction.rows) for robot in pair)]
    return shared[-1] if shared else None


def _widening(plan: Plan, pair: tuple[str, str], index: int,
              trials: dict[tuple[int, float], tuple[tuple[str, str], ...] | None] | None = None,
              ) -> Widening | None:
    """:func:`widening_that_keeps_apart` of the formation instruction at ``index``;
    ``trials`` keeps each rebuilt plan's ``apart_by_no_delay`` (None: it did not build) by
    (index, factor), so that one rebuild answers for every pair of that formation."""
    scenario = plan.scenario
    formation = scenario.instructions[index]
    assert isinstance(formation, Formation)
    trials = {} if trials is None else trials

    def apart(shape: Formation) -> float:
        offsets = formation_offsets(shape)
        (x1, y1), (x2, y2) = offsets[pair[0]], offsets[pair[1]]
        return math.hypot(x1 - x2, y1 - y2)

    for factor in ROOM_FACTORS:
        wider = replace(formation,
                        row_distances=tuple(d * factor for d in formation.row_distances),
                        spacings=tuple(tuple(g * factor for g in row)
                                       for row in formation.spacings))
        if (index, factor) not in trials:
            instructions = (*scenario.instructions[:index], wider,
                            *scenario.instructions[index + 1:])
            trial, _ = build_plan(replace(scenario, instructions=instructions),
                                  plan.parameters)
            trials[index, factor] = None if trial is None else trial.apart_by_no_delay
        stuck = trials[index, factor]
        if stuck is not None and pair not in stuck and pair[::-1] not in stuck:
            return Widening(formation.span.line, factor, apart(formation), apart(wider))
    return None


WIDENING_SEARCHES = 4
"""At most this many formations check widens per show for its hints (each costs up to
``len(ROOM_FACTORS)`` plans); the meetings after them get the general hint."""


@dataclass
class _Widenings:
    """What the hints' widening searches found in one check: per (pair, formation index)
    the widening, the rebuilt plans' meetings by (index, factor)."""

    found: dict[tuple[tuple[str, str], int], Widening | None] = field(default_factory=dict)
    trials: dict[tuple[int, float], tuple[tuple[str, str], ...] | None] = field(
        default_factory=dict)
    searched: set[int] = field(default_factory=set)


def _room_text(plan: Plan, pair: tuple[str, str], line: int, widenings: _Widenings) -> str:
    """The hint for two robots that no departure delay keeps apart: how much wider the
    formation they last shared must be (:func:`widening_that_keeps_apart`, once per pair and
    formation, for at most :data:`WIDENING_SEARCHES` formations), or to give them more
    room."""
    index = _last_shared(plan, pair, line)
    key = (pair, -1 if index is None else index)
    if key not in widenings.found:
        widening = None
        if index is not None and (index in widenings.searched
                                  or len(widenings.searched) < WIDENING_SEARCHES):
            widenings.searched.add(index)
            widening = _widening(plan, pair, index, widenings.trials)
        widenings.found[key] = widening
    widening = widenings.found[key]
    if widening is None:
        return "give the robots more room (a wider row or spacing) or change one's path"
    return (f"make the formation at line {widening.line} {widening.factor:g} times as wide "
            f"({pair[0]} and {pair[1]} {widening.after:.2f} m apart there instead of "
            f"{widening.before:.2f} m: every spacing and row distance times "
            f"{widening.factor:g}) and the timing keeps them apart, or change one's path")


def _delays_text() -> str:
    """The ordered departures' delays as a reader reads them: '1, 3 and 8'."""
    words = [f"{delay:g}" for delay in DEPARTURE_DELAYS]
    return ", ".join(words[:-1]) + " and " + words[-1] if len(words) > 1 else words[0]


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


def _note_slowdowns(plan: Plan, diagnostics: list[Diagnostic]) -> None:
    """Notes at the instructions where the ``feasible`` timing slowed the leader, and by how
    much (``InstructionTiming.speed_fraction``)."""
    if plan.parameters.timing != "feasible":
        return
    limit = plan.parameters.slot_speed_fraction * plan.parameters.vmax
    for formation in plan.formations:
        for timing in formation.timings:
            if timing.speed_fraction < 0.995:
                diagnostics.append(Diagnostic(
                    plan.scenario.path, timing.span.line, timing.span.col, Severity.NOTE,
                    f"the virtual leader slows to {100 * timing.speed_fraction:.0f} % of its "
                    f"speed here, so that no robot's slot or place on the path moves faster "
                    f"than {limit:.2f} m/s "
                    "(--timing feasible)", None, timing.span.end_col))


def _note_departures(plan: Plan, diagnostics: list[Diagnostic]) -> None:
    """Notes at the formations whose departure the ``feasible`` timing delayed so that their
    robots do not meet others on the way (``PlannedFormation.departure_delay``)."""
    for formation in plan.formations:
        if formation.departure_delay > 0.0:
            diagnostics.append(Diagnostic(
                plan.scenario.path, formation.span.line, formation.span.col, Severity.NOTE,
                f"{' '.join(formation.robots)} "
                f"{'waits' if len(formation.robots) == 1 else 'wait'} "
                f"{formation.departure_delay:g} s here before "
                f"{'it leaves' if len(formation.robots) == 1 else 'they leave'}, so that "
                f"{'it does' if len(formation.robots) == 1 else 'they do'} not meet "
                f"{' '.join(formation.waits_for)} on the way (--timing feasible)", None,
                formation.span.end_col))


WAIT_NOTE = 1.0
"""m of the leader's path: a place that waits further than this behind where its formation
puts it (``plan.places.place_waits``) is noted at the instruction."""
WAIT_GROWTH = 0.1
"""m: a wait is noted at an instruction where it grows by more than this (where it only goes
on, it was the instruction before's)."""


def _note_waits(plan: Plan, diagnostics: list[Diagnostic]) -> None:
    """Notes at the instructions where a robot's place on the path waits behind the robots
    ahead (a turn tighter than the formation is wide): the formation loses its shape there,
    and a circle wide enough keeps it."""
    from dancebots.plan.places import place_waits  # places imports the planner

    for index, formation in enumerate(plan.formations):
        times = formation.leader.times
        steps = np.diff(times, append=times[-1])  # (N,) s from each sample to the next
        waits = place_waits(plan, index)
        found: list[tuple[tuple[int, int], str]] = []  # per instruction, the robots' waits
        for timing in formation.timings:
            during = (times >= timing.start) & (times < timing.end)
            if not during.any():
                continue
            first = int(np.argmax(during))
            # where a place falls further back: a wait that only goes on from the
            # instruction before is that one's
            listed = [f"{robot} up to {float(wait[during].max()):.1f} m for "
                      f"{float(steps[during & (wait > WAIT_NOTE)].sum()):.0f} s"
                      for robot, wait in waits.items()
                      if float(wait[during].max()) > max(WAIT_NOTE, wait[first] + WAIT_GROWTH)]
            if listed:
                found.append(((timing.span.line, timing.span.col), ", ".join(listed)))
        half_width, depth = formation.half_width, formation.depth
        # on a circle of radius r a place |oy| inside waits about depth |oy| / (r - |oy|)
        radius = math.ceil(10.0 * half_width * (1.0 + depth / WAIT_NOTE) - 1e-6) / 10.0
        for (line, col), waiting in found:
            diagnostics.append(Diagnostic(
                plan.scenario.path, line, col, Severity.NOTE,
                f"the leader turns here too tightly for the formation's width and depth: "
                f"places on its path wait behind the robots ahead and the formation loses its "
                f"shape "
                f"(along the leader's path: {waiting})",
                f"turn on a circle of radius {radius:.1f} m or more to keep the shape (on a "
                f"circle of radius r the inner places wait about {depth:g} m x {half_width:g}"
                f" m / (r - {half_width:g} m))" if half_width > 0.0 else
                "a column folds onto itself where its leader turns round within the column's "
                "length: turn on a circle instead of on the spot"))


# --- transitions -----------------------------------------------------------------------------

_MAX_WAY_PAIRS = 20_000
"""Candidate pairs of ways that one formation change examines (a pile of 1,000 robots on one
spot has 500,000): the first ones in index order; more meet anyway."""
_MAX_ASSIGNED = 300
"""Robots of one formation up to which check computes the assignment it suggests (the
Hungarian method takes cubic time)."""


def _meeting_ways(starts: FloatArray, ends: FloatArray,
                  reach: FloatArray) -> list[tuple[int, int]]:
    """Pairs (i < j) of robots whose straight ways starts[i] -> ends[i] (points (M, 2), m)
    bring them nearer than reach[i] + reach[j] (m) when both cover the same fraction of
    their ways at the same time (at a standing slot the robots approach it at a speed
    proportional to the distance left, ``TrackingParams.arrival_gain``, so they do):
    crossing, or running through each other; robots that slide along side by side do not
    meet. Candidates are the pairs whose ways as fixed segments come that near (a shapely
    STRtree; at most :data:`_MAX_WAY_PAIRS` of them are examined)."""
    moving = np.hypot(*(ends - starts).T) > 1e-9
    ways = np.where(moving, shapely.linestrings(np.stack([starts, ends], axis=1)),
                    shapely.points(starts))
    tree = shapely.STRtree(ways)
    first, second = tree.query(ways, predicate="dwithin", distance=2.0 * float(reach.max()))
    keep = first < second
    first, second = first[keep][:_MAX_WAY_PAIRS], second[keep][:_MAX_WAY_PAIRS]
    # the second robot seen from the first: from starts[j] - starts[i] to ends[j] - ends[i]
    begin = starts[second] - starts[first]
    change = (ends[second] - ends[first]) - begin
    length = (change ** 2).sum(axis=1)
    fraction = np.clip(-(begin * change).sum(axis=1) / np.where(length > 0.0, length, 1.0),
                       0.0, 1.0)
    nearest = np.hypot(*(begin + fraction[:, None] * change).T)
    near = nearest < reach[first] + reach[second]
    return sorted(zip(first[near].tolist(), second[near].tolist(), strict=True))


def _check_transitions(plan: Plan, types: Sequence[RobotType], samples: ShowSamples,
                       diagnostics: list[Diagnostic]) -> None:
    """Formation changes in which robots' ways to their new slots meet, and a slot assignment
    in which fewer do.

    A robot's way is taken as the straight line from its slot at the sample before the change
    to its slot in the new formation at the change (the samples include every formation's
    start); two ways meet when the robots, each at the same fraction of its way, come nearer
    than their half widths together (:func:`_meeting_ways`). The assignment that minimises
    the sum of the squared lengths of the ways (SciPy's
    ``linear_sum_assignment``, the Hungarian method) has no crossing ways (exchanging the ends
    of two crossing segments shortens that sum); it is suggested when fewer ways meet in it.
    """
    width = {r: types[k].width for k, r in enumerate(plan.robots)}
    row = {r: k for k, r in enumerate(plan.robots)}
    for formation in plan.formations:
        if formation.start <= 0.0 or len(formation.robots) < 2:
            continue
        robots = list(formation.robots)
        rows = [row[r] for r in robots]
        at = min(int(np.searchsorted(samples.times, formation.start)), len(samples.times) - 1)
        starts = samples.poses[rows, max(at - 1, 0), :2]
        ends = samples.poses[rows, at, :2]
        reach = 0.5 * np.array([width[r] for r in robots])
        meeting = _meeting_ways(starts, ends, reach)
        if not meeting:
            continue
        more = "at least " if len(meeting) >= _MAX_WAY_PAIRS else ""
        shown = ", ".join(f"{robots[i]} and {robots[j]}" for i, j in meeting[:5]) + (
            f" and {more}{len(meeting) - 5} more pairs" if len(meeting) > 5 else "")
        hint = "let one group move first (a move of the others before this line), or " \
               "change the slots so that the ways stay apart"
        if len(robots) > _MAX_ASSIGNED:
            _warn(plan, (formation.span.line, formation.span.col),
                  f"the ways of {shown} to their new slots meet at this formation change",
                  hint, diagnostics)
            continue
        from scipy.optimize import linear_sum_assignment  # only here: check starts fast

        cost = ((starts[:, None, :] - ends[None, :, :]) ** 2).sum(axis=2)  # robot i -> slot j
        _, slot_of = linear_sum_assignment(cost)
        better = len(_meeting_ways(starts, ends[slot_of], reach)) < len(meeting)
        moves = [(robots[i], robots[int(j)]) for i, j in enumerate(slot_of) if int(j) != i]
        if better and moves:
            swaps = [(a, b) for a, b in moves if (b, a) in moves and a < b]
            if len(swaps) * 2 == len(moves):
                advice = "; ".join(f"swap {a} and {b}" for a, b in swaps)
            else:
                advice = ", ".join(f"put {a} in {b}'s slot" for a, b in moves)
            hint = f"{advice} in this line: their ways then stay apart (the shortest assignment)"
        _warn(plan, (formation.span.line, formation.span.col),
              f"the ways of {shown} to their new slots meet at this formation change", hint,
              diagnostics)

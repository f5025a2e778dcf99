"""Scenario -> Plan: where every virtual leader and every robot should be at any show time.

The plan is a pure function of the scenario and :class:`PlanParameters` (thesis ch. 4.2: every
robot computes the same virtual leader from the same scenario). The virtual leader is integrated
with a fixed step by exact unicycle arcs, in Python floats, in file order, so every robot that
runs the same code on the same scenario computes bit-identical numbers.

Show time ``t`` is in s from the agreed start. Poses are (x, y, theta) in the *show frame*: the
frame of the first virtual leader at t = 0 (x forward, y left).
"""

from __future__ import annotations

import bisect
import dataclasses
import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal, get_args

import numpy as np
import shapely
from numpy.typing import NDArray

from dancebots.diagnostics import Diagnostic, Severity
from dancebots.geometry import (
    Pose,
    compose_points,
    footprint_corners,
    integrate_unicycle,
    wrap_angle,
    wrap_angles,
)
from dancebots.plan.formation import DEFAULT_LEAD, formation_offsets
from dancebots.plan.leader import (
    MIN_LINEAR,
    arc_angular_speed,
    arc_command,
    leader_speed,
    waypoint_command,
)
from dancebots.scenario.model import Cue, Formation, Motion, Move, Scenario, Span, Wait

__all__ = [
    "TIMINGS",
    "InstructionTiming",
    "LeaderTrajectory",
    "Meeting",
    "Plan",
    "PlanParameters",
    "PlannedFormation",
    "RobotTrack",
    "TimelineEntry",
    "Timing",
    "build_plan",
    "desired_pose",
    "instruction_timeline",
    "meetings",
    "nominal_duration",
    "path_speed_scale",
    "slot_speed_scale",
    "slot_velocities",
    "step_budget",
    "virtual_leader_pose",
]

FloatArray = NDArray[np.float64]

ARC_CARROT_LENGTH = 0.5
"""Arc recovery aims this far (m, along the arc) ahead of the leader's own angle on the arc."""
ARC_REVERSED = 0.75 * math.pi
"""A leader on the arc whose heading is further than this (rad) from the arc's direction of
travel faces back along it (after `move 0 180`): it recovers by eq. 4.1 like one off the arc."""


@dataclass(frozen=True, slots=True)
class PlanParameters:
    """Parameters of the plan. Defaults follow the thesis where it gives values.

    vmax: maximal speed of the slowest robot, m/s; the leader moves at 0.7 vmax (ch. 4.1).
    step: fixed integration step of the virtual leader, s.
    waypoint_tolerance: a move's waypoint counts as reached within this distance, m.
    lead: the virtual leader's distance ahead of the first row, m (ch. 6).
    new_vl_hold: after newVL the robots stop and the new leader waits this long, s.
    max_duration: longest show that is planned, s. Checked in closed form before the leader
        is integrated and again while it is, so that planning costs at most
        ``max_duration / step`` leader steps per formation whatever the numbers of the show
        (times ``PACE_FITS`` + 2 for a show with cues, whose instructions run again to fit
        their pace).
    arc_recovery_distance: on a circle, a leader further than this from the arc (m) steers
        back to it by eq. 4.1 instead of eq. 4.3 (see ``_run_leader``).
    timing: ``feasible`` (an addition): wherever a slot of the formation would move
        faster than ``slot_speed_fraction`` vmax (the outer robots of a turn: a slot at offset
        (ox, oy) of a leader moving with (v, w) moves at |(v - w oy, w ox)|), the leader slows
        down, v and w scaled together so that its path stays the same; ``thesis`` (default):
        the leader's speeds of eq. 4.1-4.3 and 6.1 as written.
    slot_speed_fraction: the fastest a slot may move under ``feasible`` timing, as a fraction
        of vmax (the rest is left to the robots to close gaps, as the thesis leaves 30 %).
    footprint: the largest robot's length and width, m (the world's; default the SIM type's),
        with which the ``feasible`` timing's ordered departures (:func:`first_meeting`) judge
        whether two robots of different formations would meet.
    """

    vmax: float = 0.5
    step: float = 0.05
    waypoint_tolerance: float = 0.1
    lead: float = DEFAULT_LEAD
    new_vl_hold: float = 1.0
    max_duration: float = 3600.0
    arc_recovery_distance: float = 0.3
    timing: Timing = "thesis"
    slot_speed_fraction: float = 0.8
    footprint: tuple[float, float] = (1.2, 0.6)

    def __post_init__(self) -> None:
        if self.timing not in TIMINGS:  # a node parameter or a caller's string
            raise ValueError(f"unknown timing {self.timing!r}; use one of {', '.join(TIMINGS)}")


Timing = Literal["feasible", "thesis"]
"""How fast the virtual leader moves (:class:`PlanParameters`)."""
TIMINGS: tuple[Timing, ...] = get_args(Timing)


@dataclass(frozen=True, slots=True)
class InstructionTiming:
    """When a formation's virtual leader executed one instruction: [start, end) in show time;
    speed_fraction: the smallest factor by which the ``feasible`` timing scaled the leader's
    speeds during it (1.0: never slowed); pace: the factor by which a cue scaled them (the
    instruction's own or a later one's: below 1 slower, above 1 faster; 1.0: none)."""

    instruction: Motion
    start: float
    end: float
    speed_fraction: float = 1.0
    pace: float = 1.0

    @property
    def span(self) -> Span:
        return self.instruction.span


@dataclass(frozen=True, slots=True, eq=False, weakref_slot=True)
class LeaderTrajectory:
    """A virtual leader's motion sampled at the plan step.

    times: (N,) s, increasing. poses: (N, 3) x, y, theta in the show frame. commands: (N, 2)
    linear m/s and angular rad/s, held from times[k] to times[k + 1]; the last row is zero and
    the leader stands still after the last sample.
    """

    times: FloatArray
    poses: FloatArray
    commands: FloatArray

    def poses_at(self, t: FloatArray) -> FloatArray:
        """Poses (T, 3) at show times t (T,): exact unicycle motion from the previous sample.

        Before the first sample the leader is at its first pose. Theta in (-pi, pi].
        """
        t = np.asarray(t, dtype=float)
        k = np.clip(np.searchsorted(self.times, t, side="right") - 1, 0, len(self.times) - 1)
        dt = np.maximum(t - self.times[k], 0.0)
        x, y, theta = integrate_unicycle(self.poses[k, 0], self.poses[k, 1], self.poses[k, 2],
                                         self.commands[k, 0], self.commands[k, 1], dt)
        return np.stack([x, y, wrap_angles(theta)], axis=-1)

    def commands_at(self, t: FloatArray) -> FloatArray:
        """Commands (T, 2) in effect at show times t (T,); zero outside the trajectory."""
        k = np.searchsorted(self.times, np.asarray(t, dtype=float), side="right") - 1
        inside = (k >= 0) & (k < len(self.times) - 1)
        result = np.zeros((len(k), 2))
        result[inside] = self.commands[k[inside]]
        return result


@dataclass(frozen=True, slots=True, eq=False)
class PlannedFormation:
    """One formation over time: its robots, their offsets and its virtual leader.

    Robots follow it from ``start``; its leader runs its instructions until ``end`` and then
    stands still. ``offsets`` are (x, y) in m in the leader's frame. ``waypoints`` (M, 3) are
    the ideal poses of the scenario path (thesis fig. 6.1 left), for drawing.
    departure_delay: how long (s) the ``feasible`` timing's ordered departures hold its
    leader at its start, after any newVL hold, so that its robots' places on the path keep
    apart from those of ``waits_for`` (robots of other formations).
    """

    index: int
    robots: tuple[str, ...]
    group: str | None
    offsets: Mapping[str, tuple[float, float]]
    start: float
    end: float
    leader: LeaderTrajectory
    waypoints: FloatArray
    timings: tuple[InstructionTiming, ...]
    span: Span
    new_vl: bool
    departure_delay: float = 0.0
    waits_for: tuple[str, ...] = ()

    @property
    def depth(self) -> float:
        """m: from its front row to its back row (the spread of the offsets' x)."""
        xs = [ox for ox, _ in self.offsets.values()]
        return max(xs) - min(xs) if xs else 0.0

    @property
    def half_width(self) -> float:
        """m: the largest lateral offset |oy| from its leader."""
        return max((abs(oy) for _, oy in self.offsets.values()), default=0.0)


@dataclass(frozen=True, slots=True, eq=False, weakref_slot=True)
class Plan:
    """The compiled choreography: formations over time and each robot's assignments.

    ``assignments[robot]`` lists (from show time, formation index), in time order.
    ``apart_by_no_delay``: pairs of robots (scenario order) of different formations that
    would meet on their leaders' paths and that no departure delay of the ``feasible``
    timing keeps apart (:func:`meetings`; empty under the thesis's timing).
    """

    scenario: Scenario
    parameters: PlanParameters
    formations: tuple[PlannedFormation, ...]
    assignments: Mapping[str, tuple[tuple[float, int], ...]]
    duration: float
    apart_by_no_delay: tuple[tuple[str, str], ...] = ()

    @property
    def robots(self) -> tuple[str, ...]:
        return self.scenario.robots

    def formation_of(self, robot: str, show_time: float) -> PlannedFormation:
        """The formation ``robot`` follows at ``show_time``."""
        entries = self.assignments[robot]
        k = bisect.bisect_right([start for start, _ in entries], show_time) - 1
        return self.formations[entries[max(k, 0)][1]]

    def formation_indices(self, robot: str, times: FloatArray) -> NDArray[np.int64]:
        """Index of the formation ``robot`` follows at each of the times (T,)."""
        entries = self.assignments[robot]
        starts = np.array([start for start, _ in entries])
        indices = np.array([index for _, index in entries])
        k = np.clip(np.searchsorted(starts, times, side="right") - 1, 0, len(entries) - 1)
        return indices[k]

    def desired_poses(self, robot: str, times: FloatArray) -> FloatArray:
        """Desired poses (T, 3) of ``robot`` at show times (T,): its leader's pose composed
        with its offset, heading that of the leader (thesis ch. 4.2)."""
        return self.track(robot, times).desired

    def track(self, robot: str, times: FloatArray) -> RobotTrack:
        """Everything ``robot`` needs from the plan at show times (T,), sorted ascending."""
        times = np.asarray(times, dtype=float)
        count = len(times)
        leader = np.empty((count, 3))
        desired = np.empty((count, 3))
        offsets = np.empty((count, 2))
        commands = np.empty((count, 2))
        which = self.formation_indices(robot, times)
        # runs of equal formation index (contiguous when times are sorted)
        bounds = np.concatenate([[0], np.flatnonzero(np.diff(which)) + 1, [count]])
        for a, b in zip(bounds[:-1].tolist(), bounds[1:].tolist(), strict=True):
            if a == b:
                continue
            formation = self.formations[int(which[a])]
            leader[a:b] = formation.leader.poses_at(times[a:b])
            commands[a:b] = formation.leader.commands_at(times[a:b])
            offsets[a:b] = formation.offsets[robot]
        desired[:, :2] = compose_points(leader, offsets)
        desired[:, 2] = leader[:, 2]
        # the leader shifted by the lateral offset only (x + c * 0.0 is x: no leader position
        # is -0.0, as every one is a sum starting from +0.0)
        lateral = compose_points(leader, np.column_stack([np.zeros(count), offsets[:, 1]]))
        return RobotTrack(times, leader, desired, lateral, offsets,
                          np.hypot(offsets[:, 0], offsets[:, 1]), commands, which)


@dataclass(frozen=True, slots=True, eq=False)
class RobotTrack:
    """One robot's view of the plan at show times (T,), show frame.

    leader, desired: (T, 3) poses of its virtual leader and of itself. lateral: (T, 2) the
    leader's position shifted sideways by the robot's lateral offset: the path the robot
    drives when the formation keeps its lateral distances (thesis ch. 4.1). offsets: (T, 2)
    the robot's offset in the leader's frame. required_distance: (T,) |offset|, the desired
    distance to the leader, m (thesis eq. 4.4a d_req).
    leader_commands: (T, 2) the leader's (v, w). formation: (T,) formation indices.
    """

    times: FloatArray
    leader: FloatArray
    desired: FloatArray
    lateral: FloatArray
    offsets: FloatArray
    required_distance: FloatArray
    leader_commands: FloatArray
    formation: NDArray[np.int64]

    @property
    def slot_speed(self) -> FloatArray:
        """(T,) the slot's speed along the leader's heading, m/s (:func:`slot_velocities`)."""
        speed: FloatArray = slot_velocities(self.leader_commands, self.offsets)[:, 0]
        return speed


@dataclass(frozen=True, slots=True)
class TimelineEntry:
    """One instruction as the plan runs it: its ``line`` and ``col`` in the scenario, its
    ``kind`` ("formation", "move", "circle" or "wait"), the index of the formation whose
    leader runs it, and when: [start, end) in show time, s (a formation instruction: from its
    formation's start to its leader's first move: the newVL hold and any ordered departure;
    the leader does not wait for its robots to reach their new slots); ``speed_fraction``
    and ``pace``: :class:`InstructionTiming`'s (1.0 for a formation); ``start_beat`` and
    ``end_beat``: the beats then (1 the first; None without a tempo); ``cue``: the
    instruction's cue as written (``at 12.5``, ``by beat 32``; None: none),
    ``cue_missed_by``: how late (s) the cued start or end is (0.0 when it is met, None
    without a cue) and ``cue_time`` its time (s)."""

    line: int
    col: int
    kind: str
    formation: int
    start: float
    end: float
    speed_fraction: float = 1.0
    pace: float = 1.0
    start_beat: float | None = None
    end_beat: float | None = None
    cue: str | None = None
    cue_missed_by: float | None = None
    cue_time: float | None = None


CUE_TOLERANCE = 0.1
"""s: a cue counts as met when its instruction starts (or ends) at most this late: the
plan's steps are 0.05 s, and the leader stands at most a step before a cue."""


def instruction_timeline(plan: Plan) -> tuple[TimelineEntry, ...]:
    """Every formation, move, circle and wait instruction of ``plan`` with the show times its
    formation's leader runs it (:class:`TimelineEntry`), by start time, then line; a
    formation instruction once, where it first applies."""
    tempo = plan.scenario.tempo

    def beat(time: float) -> float | None:
        return None if tempo is None else tempo.beat_at(time)

    entries = []
    listed: set[int] = set()  # robots a later formation did not name keep its line
    for index, formation in enumerate(plan.formations):
        first = formation.timings[0].start if formation.timings else formation.start
        if formation.span.line not in listed:
            listed.add(formation.span.line)
            end = max(first, formation.start)
            entries.append(TimelineEntry(formation.span.line, formation.span.col, "formation",
                                         index, formation.start, end, 1.0, 1.0,
                                         beat(formation.start), beat(end)))
        for timing in formation.timings:
            cue = timing.instruction.cue
            written, late, when = None, None, None
            if cue is not None:
                when = cue.time
                value = f"beat {cue.beat:g}" if cue.beat is not None else f"{cue.time:g}"
                written = f"{cue.kind} {value}"
                late = max(0.0, (timing.start if cue.kind == "at" else timing.end) - cue.time)
                late = 0.0 if late <= CUE_TOLERANCE else late
            entries.append(TimelineEntry(
                timing.span.line, timing.span.col, type(timing.instruction).__name__.lower(),
                index, timing.start, timing.end, timing.speed_fraction, timing.pace,
                beat(timing.start), beat(timing.end), written, late, when))
    return tuple(sorted(entries, key=lambda entry: (entry.start, entry.line)))


def virtual_leader_pose(plan: Plan, robot_or_group: str, show_time: float) -> Pose:
    """The pose of the virtual leader that a robot (or all robots of a group) follows."""
    if robot_or_group in plan.assignments:
        robot = robot_or_group
    else:
        members = plan.scenario.group_robots(robot_or_group)
        robot = members[0]
        indices = {plan.formation_of(r, show_time).index for r in members}
        if len(indices) > 1:
            raise ValueError(f"the robots of group {robot_or_group!r} follow different virtual "
                             f"leaders at t = {show_time:g} s")
    formation = plan.formation_of(robot, show_time)
    x, y, theta = formation.leader.poses_at(np.array([show_time]))[0]
    return Pose(float(x), float(y), float(theta))


def desired_pose(plan: Plan, robot: str, show_time: float) -> Pose:
    """The desired pose of ``robot`` at ``show_time`` in the show frame."""
    x, y, theta = plan.desired_poses(robot, np.array([show_time]))[0]
    return Pose(float(x), float(y), float(theta))


# --- building --------------------------------------------------------------------------------

@dataclass
class _LeaderState:
    pose: Pose  # where the leader is
    ideal: Pose  # where the scenario says it should be (the last waypoint)


@dataclass
class _Record:
    """A formation being assembled from the instruction stream (mutable, private)."""

    robots: frozenset[str]
    offsets: dict[str, tuple[float, float]]
    sources: list[int]
    spec: Formation | None  # None for what remains of a split formation
    inherit: int | None  # the record whose leader it continues (None: initial or newVL)
    span: Span
    program: list[Motion] = field(default_factory=list)


class _PlanError(Exception):
    def __init__(self, diagnostic: Diagnostic) -> None:
        self.diagnostic = diagnostic


def build_plan(
    scenario: Scenario, parameters: PlanParameters | None = None
) -> tuple[Plan | None, list[Diagnostic]]:
    """Compile a scenario into a :class:`Plan`; returns (plan or None, diagnostics)."""
    params = parameters or PlanParameters()
    records, assignment_order = _records(scenario, params)
    try:
        runs: dict[tuple[int, float, float, Pose, Pose], _LeaderRun] = {}
        plan, diagnostics = _simulate(scenario, params, records, assignment_order, runs=runs)
        if params.timing != "feasible":
            return plan, diagnostics
        delays: dict[int, tuple[float, tuple[str, ...]]] = {}
        given_up: set[tuple[str, str]] = set()
        trials = 0
        found = meetings(plan)
        while found and trials < DEPARTURE_ROUNDS:  # ordered departures (see meetings())
            meeting = found[0]
            # the later formation first, then the other, each with the delays in turn
            for index, wait in itertools.product(meeting.formations, DEPARTURE_DELAYS):
                if trials >= DEPARTURE_ROUNDS:
                    break
                trials += 1
                before, others = delays.get(index, (0.0, ()))
                others += tuple(r for r in meeting.robots
                                if r not in plan.formations[index].robots)
                trial = {**delays, index: (before + wait, tuple(dict.fromkeys(others)))}
                attempt = _simulate(scenario, params, records, assignment_order, trial, runs)
                after = [m for m in meetings(attempt[0]) if m.robots not in given_up]
                if len(after) < len(found) and all(m.robots != meeting.robots for m in after):
                    delays, (plan, diagnostics), found = trial, attempt, after
                    break
            else:
                given_up.add(meeting.robots)  # no wait removes it: check reports it
                found = found[1:]
        order = {robot: k for k, robot in enumerate(scenario.robots)}
        unresolved = tuple(sorted(given_up, key=lambda pair: (order[pair[0]], order[pair[1]])))
        return dataclasses.replace(plan, apart_by_no_delay=unresolved), diagnostics
    except _PlanError as exc:
        return None, [exc.diagnostic]


DEPARTURE_DELAYS = (1.0, 3.0, 8.0)
"""s: the delays the ``feasible`` timing tries for a formation's departure, in this order
(for the formation that started later, then for the other); a meeting that none removes is
left to ``check``'s simulation pass to report."""
DEPARTURE_ROUNDS = 6
"""At most this many delays are tried for one show (each plans the show again, a few ms)."""
CLEARANCE = 0.3
"""m: two robots of different formations meet when the gap between their footprints on
their places falls below this and :data:`MEETING_MARGIN` below the gap they had when they
parted."""
MEETING_MARGIN = 0.05
"""m: see :data:`CLEARANCE`."""
MEETING_STEP = 0.2
"""s: the time step at which ordered departures compare the robots' places."""


@dataclass(frozen=True, slots=True)
class Meeting:
    """Two robots of different formations that would meet on their leaders' paths: at
    ``tick`` (of :data:`MEETING_STEP`), ``robots`` (in the scenario's order), and the indices
    of their two formations, the one that should wait first (that started later, or is later
    in the file) first."""

    tick: int
    robots: tuple[str, str]
    formations: tuple[int, int]


def meetings(plan: Plan) -> list[Meeting]:
    """Every pair of robots of different formations that would meet on their leaders' paths
    (``places.path_places``, footprints of ``PlanParameters.footprint`` along the path's
    heading, sampled every :data:`MEETING_STEP` s), at its first meeting, in time order: the
    gap between the footprints falls below :data:`CLEARANCE` and :data:`MEETING_MARGIN` below
    the gap they had when they started to follow different formations.

    The ``feasible`` timing's ordered departures (``build_plan``) follow the prioritized
    planning of Erdmann and Lozano-Perez ("On multiple moving objects", Algorithmica 1987):
    the formations keep their paths, and one of two that would meet gets a time offset (its
    leader waits at its start) when that removes the meeting without adding another."""
    from dancebots.plan.places import path_places  # places uses this module's Plan

    robots = plan.robots
    if len(robots) < 2:
        return []
    times = np.arange(0.0, plan.duration + MEETING_STEP, MEETING_STEP)
    length, width = plan.parameters.footprint
    reach = math.hypot(length, width) + CLEARANCE
    placed = [path_places(plan, robot, times) for robot in robots]
    poses = np.stack([np.column_stack([p[0], p[1]]) for p in placed])  # (R, T, 3)
    which = np.stack([plan.formation_indices(robot, times) for robot in robots])  # (R, T)
    found: list[Meeting] = []
    for i, j in itertools.combinations(range(len(robots)), 2):
        apart = which[i] != which[j]
        centre = np.hypot(*(poses[i, :, :2] - poses[j, :, :2]).T)
        near = np.flatnonzero(apart & (centre < reach))
        if not len(near):
            continue
        parted = apart & ~np.concatenate([[False], apart[:-1]])
        run = np.maximum(np.cumsum(parted) - 1, 0)  # which run of ``apart`` each tick is in
        firsts = np.flatnonzero(parted)
        check = np.unique(np.concatenate([near, firsts]))
        ends = [footprint_corners(poses[k, check, 0], poses[k, check, 1], poses[k, check, 2],
                                  length, width) for k in (i, j)]
        gaps = np.full(len(times), np.inf)
        gaps[check] = shapely.distance(shapely.polygons(ends[0]), shapely.polygons(ends[1]))
        limit = np.minimum(CLEARANCE, gaps[firsts][run]) - MEETING_MARGIN
        meets = near[gaps[near] < limit[near]]
        if len(meets):
            tick = int(meets[0])
            pair = sorted((plan.formations[int(which[i, tick])],
                           plan.formations[int(which[j, tick])]),
                          key=lambda f: (f.start, f.index), reverse=True)
            found.append(Meeting(tick, (robots[i], robots[j]),
                                 (pair[0].index, pair[1].index)))
    return sorted(found, key=lambda m: m.tick)


def _records(scenario: Scenario, params: PlanParameters) -> tuple[list[_Record], list[list[int]]]:
    """Split the instruction stream into formations and their per-formation programs."""
    records: list[_Record] = []
    current: dict[str, int] = {}
    joined: list[list[int]] = [[] for _ in scenario.robots]  # per robot: record indices
    robot_index = {r: i for i, r in enumerate(scenario.robots)}

    def add(record: _Record) -> int:
        records.append(record)
        for robot in record.robots:
            current[robot] = len(records) - 1
            joined[robot_index[robot]].append(len(records) - 1)
        return len(records) - 1

    for instruction in scenario.instructions:
        if isinstance(instruction, Formation):
            robots = frozenset(instruction.robots)
            touched = list(dict.fromkeys(current[r] for r in instruction.robots if r in current))
            for source in touched:
                rest = records[source].robots - robots
                if rest:
                    add(_Record(rest, {r: records[source].offsets[r] for r in rest}, [source],
                                None, source, records[source].span))
            add(_Record(robots, formation_offsets(instruction, params.lead), touched,
                        instruction, None if instruction.new_vl or not touched
                        else current[instruction.robots[0]], instruction.span))
        else:
            records[current[instruction.robots[0]]].program.append(instruction)
    return records, joined


_LeaderRun = tuple[LeaderTrajectory, tuple[InstructionTiming, ...], FloatArray, _LeaderState,
                   tuple[Diagnostic, ...]]


def _simulate(scenario: Scenario, params: PlanParameters, records: list[_Record],
              joined: list[list[int]],
              delays: Mapping[int, tuple[float, tuple[str, ...]]] | None = None,
              runs: dict[tuple[int, float, float, Pose, Pose], _LeaderRun] | None = None,
              ) -> tuple[Plan, list[Diagnostic]]:
    """Plan every formation's leader in turn. ``runs`` keeps the leaders already integrated
    (by formation, start, hold and starting state) across the ordered departures' trials,
    which change only the formations that wait and those after them."""
    delays = delays or {}
    runs = {} if runs is None else runs
    diagnostics: list[Diagnostic] = []
    finals: list[_LeaderState] = []
    ends: list[float] = []
    formations: list[PlannedFormation] = []
    group_of = {frozenset(members): name for name, members in scenario.groups}
    for index, record in enumerate(records):
        start = max((ends[s] for s in record.sources), default=0.0)
        hold = 0.0
        if record.spec is not None and record.spec.new_vl and record.sources:
            state = _new_leader_state(record, records, finals, params)
            hold = params.new_vl_hold
        elif record.inherit is not None:
            inherited = finals[record.inherit]
            state = _LeaderState(inherited.pose, inherited.ideal)
            if record.spec is not None and len(record.sources) > 1:
                diagnostics.extend(_join_warnings(scenario, record, records, finals))
        else:
            state = _LeaderState(Pose(0.0, 0.0, 0.0), Pose(0.0, 0.0, 0.0))
        new_vl = hold > 0.0
        delay, waits_for = delays.get(index, (0.0, ()))
        hold += delay
        _check_nominal_duration(scenario.path, state.ideal, record.program, start + hold,
                                params)
        key = (index, start, hold, state.pose, state.ideal)
        if key not in runs:
            runs[key] = _run_leader(scenario.path, state, record.program, start, hold, params,
                                    tuple(record.offsets.values()))
        trajectory, timings, waypoints, final, cue_problems = runs[key]
        diagnostics.extend(cue_problems)
        end = float(trajectory.times[-1])
        finals.append(final)
        ends.append(end)
        ordered = tuple(r for r in scenario.robots if r in record.robots)
        formations.append(PlannedFormation(
            index=index, robots=ordered, group=group_of.get(record.robots),
            offsets=dict(record.offsets), start=start, end=end, leader=trajectory,
            waypoints=waypoints, timings=timings, span=record.span, new_vl=new_vl,
            departure_delay=delay, waits_for=waits_for))
    assignments = {
        robot: tuple((formations[i].start, i) for i in joined[k])
        for k, robot in enumerate(scenario.robots)
    }
    duration = max(ends)
    plan = Plan(scenario, params, tuple(formations), assignments, duration)
    return plan, diagnostics


def nominal_duration(ideal: Pose, instruction: Motion,
                     params: PlanParameters) -> tuple[float, Pose]:
    """Closed-form duration (s) of one instruction from the ideal pose ``ideal``, and the
    ideal pose after it.

    A move: its length (m) at the leader's top speed 0.7 vmax (thesis ch. 4.1), less the
    waypoint tolerance at each end, a lower bound of what eq. 4.1 takes. A circle: its central
    angle (rad) over the angular speed that eq. 6.1's halving rule leaves. A wait: its
    duration (a cue's pace is not counted: it only slows what is already bounded).
    """
    if isinstance(instruction, Wait):
        return instruction.duration, ideal
    if isinstance(instruction, Move):
        goal = ideal.compose(Pose(0.0, 0.0, instruction.angle)).compose(
            Pose(instruction.distance, 0.0, 0.0))
        length = max(0.0, instruction.distance - 2.0 * params.waypoint_tolerance)
        return length / leader_speed(params.vmax), goal
    sign = 1.0 if instruction.radius > 0 else -1.0
    cx, cy = ideal.to_world(0.0, instruction.radius)
    end = Pose(cx, cy, ideal.theta).compose(Pose(0.0, 0.0, sign * instruction.angle)).compose(
        Pose(0.0, -instruction.radius, 0.0))
    omega = arc_angular_speed(instruction.radius, instruction.omega, params.vmax)
    return instruction.angle / omega, end


def _check_nominal_duration(path: str, ideal: Pose, program: Sequence[Motion],
                            start: float, params: PlanParameters) -> None:
    """Raise the "longer than" error at the first instruction whose closed-form end time
    (s, :func:`nominal_duration`) passes ``max_duration``: before anything is integrated."""
    now = start
    for instruction in program:
        duration, ideal = nominal_duration(ideal, instruction, params)
        if not now + duration <= params.max_duration:
            raise _PlanError(_too_long(path, instruction, now, duration, params))
        now += duration


def _too_long(path: str, instruction: Motion, begin: float, duration: float,
              params: PlanParameters) -> Diagnostic:
    """The show passes ``max_duration`` during ``instruction`` (begun at ``begin`` s)."""
    takes = f"takes at least {duration:.4g} s" if math.isfinite(duration) else "never ends"
    if isinstance(instruction, Wait):
        hint = f"this wait {takes.replace(' at least', '')}: shorten the waits"
    elif isinstance(instruction, Move):
        hint = (f"a move of {instruction.distance:g} m {takes} at the leader's speed of "
                f"{leader_speed(params.vmax):g} m/s: shorten the moves")
    else:
        hint = (f"this arc {takes.replace(' at least', '')}: use a smaller angle or a larger "
                "angular speed")
    return Diagnostic(path, instruction.span.line, instruction.span.col, Severity.ERROR,
                      f"the show would last longer than {params.max_duration / 3600:g} h: "
                      f"this instruction starts at {begin:.0f} s", hint,
                      instruction.span.end_col)


def _new_leader_state(record: _Record, records: Sequence[_Record],
                      finals: Sequence[_LeaderState], params: PlanParameters) -> _LeaderState:
    """newVL (thesis ch. 6): a new leader placed from the robots' *desired* positions.

    Heading: the circular mean of the source leaders' headings, weighted by how many robots
    each source gives. Position: ``lead`` ahead of the mean of the first row's desired positions
    along that heading, and laterally in the middle of the formation's desired positions.
    """
    assert record.spec is not None
    desired: dict[str, tuple[float, float]] = {}
    sum_c = sum_s = 0.0
    for source in record.sources:
        leader = finals[source].pose
        for robot in record.robots & records[source].robots:
            desired[robot] = leader.to_world(*records[source].offsets[robot])
            sum_c += math.cos(leader.theta)
            sum_s += math.sin(leader.theta)
    heading = math.atan2(sum_s, sum_c)
    frame = Pose(0.0, 0.0, heading)
    along = {r: frame.to_local(*p) for r, p in desired.items()}
    first_row = record.spec.rows[0]
    forward = sum(along[r][0] for r in first_row) / len(first_row) + params.lead
    lateral = [along[r][1] for r in record.robots]
    x, y = frame.to_world(forward, 0.5 * (min(lateral) + max(lateral)))
    pose = Pose(x, y, heading)
    return _LeaderState(pose, pose)


def _join_warnings(scenario: Scenario, record: _Record, records: Sequence[_Record],
                   finals: Sequence[_LeaderState]) -> list[Diagnostic]:
    """A join without newVL keeps one leader; say so when the joined leaders disagree."""
    assert record.inherit is not None
    kept = finals[record.inherit].pose
    messages = []
    for source in record.sources:
        other = finals[source].pose
        gap = math.hypot(other.x - kept.x, other.y - kept.y)
        turn = abs(wrap_angle(other.theta - kept.theta))
        if gap > 0.01 or turn > math.radians(1.0):
            names = " ".join(r for r in scenario.robots if r in records[source].robots)
            messages.append(f"{names} ({gap:.2f} m, {math.degrees(turn):.0f} deg away)")
    if not messages:
        return []
    kept_names = " ".join(r for r in scenario.robots if r in records[record.inherit].robots)
    return [Diagnostic(
        scenario.path, record.span.line, record.span.col, Severity.WARNING,
        f"this formation joins robots that follow different virtual leaders; it keeps the "
        f"leader of {kept_names} and drops that of {', '.join(messages)}",
        "add `newVL` on the next line to place one leader from the robots' desired positions",
        record.span.end_col)]


PACE_RANGE = (0.1, 1.0 / 0.7)
"""The factors by which a cue may scale the virtual leader's speeds (``_run_leader``): down
to a tenth (what is left of the time the formation stands before the cued instruction), up
to the leader at vmax instead of 0.7 vmax (thesis ch. 4.1), the ``feasible`` timing's caps on
the robots' places still applying."""
PACE_FITS = 12
"""At most this many runs of the instructions before a cue fit their pace to it."""


def _run_leader(
    path: str, state: _LeaderState, program: Sequence[Motion], start: float,
    hold: float, params: PlanParameters, offsets: Sequence[tuple[float, float]] = (),
) -> tuple[LeaderTrajectory, tuple[InstructionTiming, ...], FloatArray, _LeaderState,
           tuple[Diagnostic, ...]]:
    """Integrate the leader through its instructions with the fixed step (thesis eq. 4.1-4.3).

    Moves: eq. 4.1 towards the waypoint until it is within the tolerance. Circles: eq. 4.3
    until the leader has swept the central angle around the centre. Eq. 4.3 assumes the leader
    starts near the arc with the arc's heading (thesis ch. 4.2); after `move 0 90` or a sharp
    corner it may not, and its saturated turn rate then spins the leader in place for ever. So
    while the leader is more than ``arc_recovery_distance`` (or half the radius) off the arc,
    or faces back along it (more than ``ARC_REVERSED`` from its direction), it steers by
    eq. 4.1 towards the point ``ARC_CARROT_LENGTH`` (at most 1 rad) ahead on the arc (an
    addition to the thesis). With ``feasible`` timing every step's (v, w) is scaled down by
    :func:`slot_speed_scale` of the formation's ``offsets`` (ox, oy), m. Waits: the leader
    stands (an addition).

    Cues (an addition): an instruction cued ``at`` T starts at show time T, one cued ``by`` T
    ends at T: the instructions since the last cue (or the program's start), the cued one
    too for ``by``, run again with their speeds scaled by one factor (the pace, within
    :data:`PACE_RANGE`; the waits keep their durations) fitted so that they end at most two
    steps before T (the leader stands the rest). A cue that cannot be met (the time has
    passed, or even the fastest pace arrives more than :data:`CUE_TOLERANCE` later) is a
    warning at the cue; the leader then runs at the fastest pace. The returned diagnostics are those
    warnings. Each cue runs its instructions again at most :data:`PACE_FITS` + 1 times.
    """
    dt = params.step
    slots = np.array(offsets, dtype=float).reshape(-1, 2)
    slot_rows = slots.tolist()  # Python floats: the per-step speed scales loop over them
    slot_limit = params.slot_speed_fraction * params.vmax if params.timing == "feasible" \
        else math.inf
    times: list[float] = []
    rows: list[tuple[float, float, float, float, float]] = []
    x, y, theta = state.pose.x, state.pose.y, state.pose.theta
    ideal = state.ideal
    waypoints = [(ideal.x, ideal.y, ideal.theta)]
    timings: list[InstructionTiming] = []
    problems: list[Diagnostic] = []
    step_count = 0  # t = start + step_count * dt keeps times exact multiples of the step

    def now() -> float:
        return start + step_count * dt

    speed_fraction = 1.0  # the smallest speed factor of the current instruction
    pace = 1.0  # a cue's scale of the leader's speeds

    arcs: list[float] = []  # the path length (m) the leader had driven at each step's start
    curvatures: list[float] = []  # and the curvature (1/m) it drove that step with
    driven = 0.0

    def advance(v: float, w: float) -> None:
        nonlocal x, y, theta, step_count, speed_fraction, driven
        arcs.append(driven)
        curvatures.append(w / v if v > 0.0 else 0.0)
        if pace != 1.0:
            v, w = v * pace, w * pace
        if v != 0.0 and len(slots) and slot_limit < math.inf:
            scale = min(slot_speed_scale(v, w, slot_rows, slot_limit),
                        path_speed_scale(v, slot_rows, arcs, curvatures, slot_limit))
            v, w = v * scale, w * scale
            speed_fraction = min(speed_fraction, scale)
        driven += v * dt
        times.append(now())
        rows.append((x, y, theta, v, w))
        half = 0.5 * w * dt
        chord = v * dt * (math.sin(half) / half if half != 0.0 else 1.0)
        x += chord * math.cos(theta + half)
        y += chord * math.sin(theta + half)
        theta = wrap_angle(theta + w * dt)
        step_count += 1

    last_step = int((params.max_duration - start) / dt)  # no step after max_duration

    def run(instruction: Motion) -> None:
        """Integrate one instruction at the current pace."""
        nonlocal ideal, speed_fraction
        begin = now()
        left = max(0, last_step - step_count)
        if isinstance(instruction, Wait):
            for _ in range(min(round(instruction.duration / dt), left)):
                advance(0.0, 0.0)
        elif isinstance(instruction, Move):
            goal = ideal.compose(Pose(0.0, 0.0, instruction.angle))
            goal = goal.compose(Pose(instruction.distance, 0.0, 0.0))
            slowest = min(MIN_LINEAR, leader_speed(params.vmax))  # eq. 4.1a's lowest speed
            budget = step_budget(math.hypot(goal.x - x, goal.y - y) / slowest / min(pace, 1.0),
                                 dt, left)
            for _ in range(budget):
                here = Pose(x, y, theta)
                gx, gy = here.to_local(goal.x, goal.y)
                if math.hypot(gx, gy) < params.waypoint_tolerance:
                    break
                advance(*waypoint_command(gx, gy, params.vmax))  # thesis eq. 4.1
            else:
                raise _PlanError(_unreached(path, instruction, "waypoint of this move")
                                 if budget < left else
                                 _too_long(path, instruction, begin, now() - begin, params))
            ideal = goal
            waypoints.append((goal.x, goal.y, goal.theta))
        else:
            sign = 1.0 if instruction.radius > 0 else -1.0
            cx, cy = ideal.to_world(0.0, instruction.radius)  # centre on the y axis (ch. 6)
            omega = arc_angular_speed(instruction.radius, instruction.omega, params.vmax)
            phi_start = math.atan2(ideal.y - cy, ideal.x - cx)
            phi = math.atan2(y - cy, x - cx)
            progress = sign * wrap_angle(phi - phi_start)
            budget = step_budget(instruction.angle / omega / min(pace, 1.0), dt, left)
            radius = abs(instruction.radius)
            for _ in range(budget):
                if progress >= instruction.angle:
                    break
                off_arc = abs(math.hypot(x - cx, y - cy) - radius)
                backwards = abs(wrap_angle(theta - (phi + sign * 0.5 * math.pi))) > ARC_REVERSED
                if off_arc <= min(params.arc_recovery_distance, 0.5 * radius) \
                        and not backwards:
                    advance(*arc_command(instruction.radius, omega, math.hypot(x - cx, y - cy)))
                else:  # far off the arc (eq. 4.3 would spin) or facing back along it (eq. 4.3
                    # would drive it round the wrong way): eq. 4.1 towards a point on the arc
                    ahead = min(progress + min(ARC_CARROT_LENGTH / radius, 1.0),
                                instruction.angle)  # at most 1 rad ahead on a tight arc
                    carrot = phi_start + sign * ahead
                    gx, gy = Pose(x, y, theta).to_local(cx + radius * math.cos(carrot),
                                                        cy + radius * math.sin(carrot))
                    advance(*waypoint_command(gx, gy, params.vmax))
                new_phi = math.atan2(y - cy, x - cx)
                progress += sign * wrap_angle(new_phi - phi)
                phi = new_phi
            else:
                raise _PlanError(_unreached(path, instruction, "end of this arc")
                                 if budget < left else
                                 _too_long(path, instruction, begin, now() - begin, params))
            end_arc = Pose(cx, cy, ideal.theta).compose(
                Pose(0.0, 0.0, sign * instruction.angle)).compose(
                Pose(0.0, -instruction.radius, 0.0))
            for fraction in np.linspace(0.0, 1.0, 2 + int(math.degrees(instruction.angle) / 5)):
                arc_point = Pose(cx, cy, ideal.theta).compose(
                    Pose(0.0, 0.0, sign * instruction.angle * float(fraction))).compose(
                    Pose(0.0, -instruction.radius, 0.0))
                waypoints.append((arc_point.x, arc_point.y, arc_point.theta))
            ideal = end_arc
        timings.append(InstructionTiming(instruction, begin, now(), speed_fraction,
                                         1.0 if isinstance(instruction, Wait) else pace))
        speed_fraction = 1.0

    def snapshot() -> tuple[float, float, float, int, float, Pose, int, int]:
        return (x, y, theta, step_count, driven, ideal, len(waypoints), len(timings))

    def restore(saved: tuple[float, float, float, int, float, Pose, int, int]) -> None:
        nonlocal x, y, theta, step_count, driven, ideal
        x, y, theta, step_count, driven, ideal, kept_waypoints, kept_timings = saved
        steps = step_count - first_step
        del times[steps:], rows[steps:], arcs[steps:], curvatures[steps:]
        del waypoints[kept_waypoints:], timings[kept_timings:]

    def stand_until(target: float) -> None:
        """Stand still until the last step at or before ``target`` s."""
        for _ in range(max(0, min(math.floor((target - now()) / dt + 1e-9),
                                  last_step - step_count))):
            advance(0.0, 0.0)

    def meet(cue: Cue, anchor: tuple[float, float, float, int, float, Pose, int, int],
             segment: Sequence[Motion], cued: Motion) -> None:
        """Run ``segment`` again from ``anchor`` at the pace that ends it at the cue's time
        (at most two steps before, the leader standing the rest), or at the fastest pace and
        report the cue unmet when that is more than :data:`CUE_TOLERANCE` late."""
        target = cue.time
        begin = start + anchor[3] * dt
        waits = sum(round(m.duration / dt) * dt for m in segment if isinstance(m, Wait))
        if now() <= target + 1e-9 and not any(not isinstance(m, Wait) for m in segment):
            stand_until(target)  # only waits before it: stand the rest
            return
        if now() > target + 1e-9 and not any(not isinstance(m, Wait) for m in segment):
            problems.append(_cue_missed(path, cue, cued, now(), begin, None))
            return
        available = target - begin - waits  # s of motion that meet the cue
        natural = now() - begin - waits  # s of motion at pace 1 (already run)
        if available <= 0.0:
            problems.append(_cue_missed(path, cue, cued, now(), begin, None))
            return
        on_time_within = 0.5 * dt  # (times are whole steps)
        if available - 2.0 * dt <= natural <= available + on_time_within:
            stand_until(target)  # on time as it is
            return
        path_start = anchor[4]
        slowest, fastest = PACE_RANGE

        def run_at(trial: float) -> float:
            """Run the segment again at pace ``trial``; the s of motion it took."""
            nonlocal pace
            restore(anchor)
            pace = trial
            for motion in segment:
                run(motion)
            pace = 1.0
            return now() - begin - waits

        # the pace that is not late (within the tolerance) and least early: bracketed
        # between the fastest pace known to be late and the slowest known not to be
        late_pace: float | None = None
        on_time: float | None = None
        trial = min(max(natural / available, slowest), fastest)
        for _ in range(PACE_FITS):
            took = run_at(trial)
            if took <= available + on_time_within:
                on_time = trial if on_time is None else min(on_time, trial)
                if took >= available - 2.0 * dt or trial <= slowest:
                    break
            else:
                late_pace = trial if late_pace is None else max(late_pace, trial)
                if trial >= fastest:
                    break  # late even at the fastest pace
                if on_time is None:
                    trial = fastest  # can it be met at all?
                    continue
            low = late_pace if late_pace is not None else slowest
            high = on_time if on_time is not None else fastest
            guess = trial * took / available  # time goes about as 1 / pace
            trial = guess if low < guess < high else 0.5 * (low + high)
        if on_time is None:  # late even at the fastest pace: run at it, and say so
            took = run_at(fastest) if pace_of_last_run(anchor) != fastest else took
            if took > available + CUE_TOLERANCE:  # (a little late counts as met)
                problems.append(_cue_missed(path, cue, cued, now(), begin,
                                            (driven - path_start, took, available)))
            return
        if pace_of_last_run(anchor) != on_time:
            run_at(on_time)
        stand_until(target)

    def pace_of_last_run(anchor: tuple[float, float, float, int, float, Pose, int, int],
                         ) -> float | None:
        """The pace the segment after ``anchor`` last ran at (from the timings of its
        motions; waits have none)."""
        paces = [t.pace for t in timings[anchor[7]:] if not isinstance(t.instruction, Wait)]
        return paces[0] if paces else None

    first_step = step_count
    for _ in range(round(hold / dt)):
        advance(0.0, 0.0)
    anchor = snapshot()
    segment: list[Motion] = []
    for instruction in program:
        cue = instruction.cue
        if cue is not None and cue.kind == "at":
            if segment:
                meet(cue, anchor, segment, instruction)
            elif now() <= cue.time + 1e-9:
                stand_until(cue.time)
            else:
                problems.append(_cue_missed(path, cue, instruction, now(), now(), None))
            anchor, segment = snapshot(), []
        segment.append(instruction)
        run(instruction)
        if cue is not None and cue.kind == "by":
            meet(cue, anchor, segment, instruction)
            anchor, segment = snapshot(), []
    times.append(now())
    rows.append((x, y, theta, 0.0, 0.0))
    table = np.array(rows, dtype=float)
    trajectory = LeaderTrajectory(np.array(times), table[:, :3].copy(), table[:, 3:].copy())
    final = _LeaderState(Pose(x, y, theta), ideal)
    return trajectory, tuple(timings), np.array(waypoints), final, tuple(problems)


def _cue_missed(path: str, cue: Cue, cued: Motion, arrives: float, begin: float,
                motion: tuple[float, float, float] | None) -> Diagnostic:
    """The warning for a cue the leader cannot meet: it arrives at ``arrives`` s (the cued
    instruction's start for ``at``, its end for ``by``); the instructions since the last
    cue began at ``begin`` s; ``motion``: (m driven, s they took at the fastest pace, s
    there were), or None when the time had passed before they began."""
    when = _clock(cue.time) + (f" (beat {cue.beat:g})" if cue.beat is not None else "")
    what = "starts" if cue.kind == "at" else "ends"
    late = arrives - cue.time
    message = (f"the cue `{cue.kind} {when}` cannot be met: this instruction {what} at "
               f"{_clock(arrives)}, {late:.1f} s late")
    if motion is None:
        hint = (f"its formation's leader gets here at {_clock(begin)} at the earliest: cue a "
                "later time, or cue the instructions before it earlier")
    else:
        length, took, available = motion
        needed = length / available if available > 0 else math.inf
        fastest = length / took if took > 0 else math.inf
        hint = (f"the instructions since {_clock(begin)} drive {length:.1f} m in {took:.1f} s "
                f"even at the fastest the robots allow ({fastest:.2f} m/s on average); the "
                f"cue leaves {available:.1f} s, {needed:.2f} m/s: cue a later time, or drive "
                "less before it")
    return Diagnostic(path, cue.span.line, cue.span.col, Severity.WARNING, message, hint,
                      cue.span.end_col)


def _clock(seconds: float) -> str:
    """A show time as the language writes it, to the hundredth: ``1:02.5`` (minutes:seconds),
    ``12.35`` below a minute."""
    if seconds < 60.0:
        return f"{seconds:.2f}".rstrip("0").rstrip(".") if seconds % 1 else f"{seconds:.1f}"
    minutes, rest = divmod(round(seconds, 2), 60.0)
    text = f"{rest:05.2f}".rstrip("0").rstrip(".")
    return f"{int(minutes)}:{text if len(text) >= 2 else '0' + text}"


def slot_velocities(leader_commands: FloatArray, offsets: FloatArray) -> FloatArray:
    """How slots move: a slot at offset (ox, oy) (m, in the leader's frame) of a leader moving
    with (v m/s, w rad/s) moves with (v - w oy, w ox) in the leader's frame. Shapes (..., 2)
    broadcast; returns (..., 2): along the leader's heading (negative: the slot moves
    backwards, the inner slot of a turn tighter than its lateral offset) and across it."""
    v, w = leader_commands[..., 0], leader_commands[..., 1]
    result: FloatArray = np.stack([v - w * offsets[..., 1], w * offsets[..., 0]], axis=-1)
    return result


def slot_speed_scale(v: float, w: float, offsets: FloatArray | Sequence[Sequence[float]],
                     limit: float) -> float:
    """The factor (0, 1] by which a leader moving with (v m/s, w rad/s) slows so that no slot
    at ``offsets`` (K, 2) (ox, oy in the leader's frame, m) moves faster than ``limit`` m/s
    (:func:`slot_velocities`; in Python floats: the planner calls it every step)."""
    rows = offsets.tolist() if isinstance(offsets, np.ndarray) else offsets
    fastest = max((math.hypot(v - w * oy, w * ox) for ox, oy in rows), default=0.0)
    return 1.0 if fastest <= limit else limit / fastest


def path_speed_scale(v: float, offsets: FloatArray | Sequence[Sequence[float]],
                     arcs: Sequence[float],
                     curvatures: Sequence[float], limit: float) -> float:
    """The factor (0, 1] by which a leader moving at v m/s slows so that no robot's place on
    its path (``control.tracking.path_references``: -ox m of path behind the leader, shifted
    by oy) moves faster than ``limit`` m/s. offsets (K, 2) (ox, oy), m; arcs (N,) the path
    length the leader had driven at the start of each step so far, ascending, m, the last
    one the current step's; curvatures (N,) the curvature of each of those steps, 1/m. A
    place at curvature kappa moves at v |1 - kappa oy|; one behind the leader's first pose
    (less than -ox driven) at v."""
    fastest = 0.0
    here = arcs[-1]
    for ox, oy in offsets.tolist() if isinstance(offsets, np.ndarray) else offsets:
        target = here + min(ox, 0.0)
        kappa = curvatures[bisect.bisect_right(arcs, target) - 1] if target >= 0.0 else 0.0
        fastest = max(fastest, abs(v * (1.0 - kappa * oy)))
    return 1.0 if fastest <= limit else limit / fastest


def step_budget(nominal_duration: float, dt: float, left: int) -> int:
    """Steps allowed for one instruction: twice its nominal duration (s) plus two minutes, at
    most ``left``, the steps before the show's longest duration (any float, even inf or nan,
    gives a finite count)."""
    steps = (2.0 * nominal_duration + 120.0) / dt
    return int(steps) + 1 if steps < left else left


def _unreached(path: str, instruction: Motion, what: str) -> Diagnostic:
    return Diagnostic(path, instruction.span.line, instruction.span.col, Severity.ERROR,
                      f"the virtual leader does not reach the {what}",
                      "report this scenario as a bug: the leader's controller should converge",
                      instruction.span.end_col)

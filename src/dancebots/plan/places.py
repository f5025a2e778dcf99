"""Where each robot should be on its leader's path (thesis ch. 4.1: a robot drives the
leader's path shifted sideways by its lateral offset oy, its along offset ox behind).

``path_places`` is the path follower's reference (``control.tracking.path_references``) and
what the ``feasible`` timing's ordered departures check (``planner.build_plan``). Show frame,
times in s of show time.

Two additions make the places drivable where the leader turns more tightly than the
formation is wide:

* **Distance kept behind the robots ahead** (:func:`path_places`). On the inner side of a
  turn the shifted path is shorter than the leader's (it loops back where the turn is
  tighter than |oy|), so a place ``L`` m of the leader's path behind another one comes
  nearer than ``L`` to it (2 |oy| tan(turn / 2) nearer at a sharp corner: 1 m at the
  open-day square's 90 deg corner, which put the rear robot on the front one). A robot keeps
  at least ``min(D, diagonal + FILE_MARGIN)`` straight distance from the place of every
  robot of its formation ahead of it (ox larger; ``D`` their rigid distance, ``diagonal``
  the world's largest robot's): its place waits on the path (it falls back and catches up
  no faster than :func:`catch_up_speed`). Robots side by side (a row) keep the leader's
  timing, so the row stays abeam (the inner robot backs up round the loop: loops are not
  cut).
* **A smooth way to the rigid slot at the end.** Where the path behind the leader is curved
  when it stops (a show that ends on an arc), a place ``-ox`` m behind on the path is not
  the rigid slot; the place goes there on a cubic Hermite curve.
"""

from __future__ import annotations

import itertools
import weakref
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from dancebots.geometry import compose_points
from dancebots.plan.planner import LeaderTrajectory

if TYPE_CHECKING:
    from dancebots.plan.planner import Plan, PlannedFormation

__all__ = ["FILE_MARGIN", "OffsetPath", "catch_up_speed", "offset_path", "path_places",
           "place_waits", "places_end"]

FloatArray = NDArray[np.float64]

FILE_MARGIN = 0.3
"""m added to the largest robot's diagonal: the least straight distance a robot keeps from
the places of the robots ahead of it in its formation (unless their rigid distance is
smaller); the planner's CLEARANCE."""
FILE_ITERATIONS = 40
"""Most steps back along the path that bring a robot the straight distance behind the robots
in front of it (secant steps on the distance still missing)."""
FILE_SECANT_FLOOR = 0.5
RATE_PASSES = 2
"""Rounds of the places' speed limit (each with the stretch where the last one left them)."""
"""The least distance gained per metre gone back that the secant step counts with."""


@dataclass(frozen=True, slots=True, eq=False)
class OffsetPath:
    """A leader's path shifted sideways by oy (m, left positive).

    Per leader sample (N,): driven, the leader's path length, m (non-decreasing); points
    (N, 2), the shifted path's point, show frame, m; heading (N,), the leader's heading, rad,
    unwrapped; stretch (N,), how fast the shifted point moves per metre the leader drives
    over the step from the sample (1 - kappa oy, kappa the leader's curvature; negative
    where it loops back). Each step's change of driven, points and heading (N - 1,) is kept
    too (the look-ups use it: the same differences, once).
    """

    driven: FloatArray
    points: FloatArray
    heading: FloatArray
    stretch: FloatArray
    _step: FloatArray = field(init=False, repr=False)
    _point_step: FloatArray = field(init=False, repr=False)
    _heading_step: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_step", self.driven[1:] - self.driven[:-1])
        object.__setattr__(self, "_point_step", self.points[1:] - self.points[:-1])
        object.__setattr__(self, "_heading_step", self.heading[1:] - self.heading[:-1])

    def _between(self, driven: FloatArray) -> tuple[NDArray[np.int64], FloatArray]:
        """For path lengths ``driven`` (T,), the sample j (T,) each lies after and the
        fraction (T,) of the step to the next one (clipped to [0, 1]; 0 on a step that
        does not move); needs two samples or more."""
        j = np.clip(np.searchsorted(self.driven, driven, side="right") - 1, 0,
                    len(self.driven) - 2)
        step = self._step[j]
        moves = step > 0.0
        fraction = np.clip(np.where(moves, (driven - self.driven[j])
                                    / np.where(moves, step, 1.0), 0.0), 0.0, 1.0)
        return j, fraction

    def at(self, driven: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Where the shifted path is when the leader has driven ``driven`` (T,) m: points
        (T, 2), heading (T,) rad and stretch (T,). Before the leader's first pose (driven <
        0) on the straight line behind it; after its last, at the end."""
        count = len(driven)
        if len(self.driven) < 2:  # a leader that never moves: its one pose
            points = np.broadcast_to(self.points[0], (count, 2)).copy()
            heading = np.full(count, self.heading[0])
            stretch = np.ones(count)
        else:
            j, fraction = self._between(driven)
            points = self.points[j] + fraction[:, None] * self._point_step[j]
            heading = self.heading[j] + fraction * self._heading_step[j]
            stretch = self.stretch[j].copy()
        behind = driven < 0.0
        if behind.any():
            back = driven[behind]
            first = self.heading[0]
            points[behind] = self._behind(back)
            heading[behind] = first
            stretch[behind] = 1.0
        return points, heading, stretch

    def points_at(self, driven: FloatArray) -> FloatArray:
        """The points (T, 2) of :meth:`at` alone."""
        if len(self.driven) < 2:
            points: FloatArray = np.broadcast_to(self.points[0], (len(driven), 2)).copy()
        else:
            j, fraction = self._between(driven)
            points = self.points[j] + fraction[:, None] * self._point_step[j]
        behind = driven < 0.0
        if behind.any():
            points[behind] = self._behind(driven[behind])
        return points

    def stretch_at(self, driven: FloatArray) -> FloatArray:
        """The stretch (T,) of :meth:`at` alone."""
        if len(self.driven) < 2:
            return np.ones(len(driven))
        j = np.clip(np.searchsorted(self.driven, driven, side="right") - 1, 0,
                    len(self.driven) - 2)
        stretch: FloatArray = self.stretch[j].copy()
        stretch[driven < 0.0] = 1.0
        return stretch

    def _behind(self, back: FloatArray) -> FloatArray:
        """Points (B, 2) ``back`` (B,) m (negative) along the straight line behind the
        leader's first pose."""
        first = self.heading[0]
        result: FloatArray = self.points[0] + back[:, None] * np.array(
            [np.cos(first), np.sin(first)])
        return result


def catch_up_speed(plan: Plan) -> float:
    """How fast (m/s) a place held back catches up, and goes to its slot after the leader's
    end: the fastest a slot moves under the ``feasible`` timing
    (``PlanParameters.slot_speed_fraction`` vmax)."""
    return plan.parameters.slot_speed_fraction * plan.parameters.vmax


def offset_path(leader: LeaderTrajectory, oy: float) -> OffsetPath:
    """The leader's path shifted by ``oy`` m to its left (thesis ch. 4.1)."""
    speed, turn = leader.commands[:, 0], leader.commands[:, 1]
    heading = np.unwrap(leader.poses[:, 2])
    points = leader.poses[:, :2] + oy * np.column_stack([-np.sin(heading), np.cos(heading)])
    driven = np.concatenate([[0.0], np.cumsum(speed[:-1] * np.diff(leader.times))])
    moving = speed > 0.0
    stretch = np.where(moving, 1.0 - oy * turn / np.where(moving, speed, 1.0), 1.0)
    return OffsetPath(driven, points, heading, stretch)


def _offset_path(formation: PlannedFormation, oy: float) -> OffsetPath:
    return _leader_offset_path(formation.leader, oy)


_OFFSET_PATHS: weakref.WeakKeyDictionary[LeaderTrajectory, dict[float, OffsetPath]] = (
    weakref.WeakKeyDictionary())
_FILE_TABLES: weakref.WeakKeyDictionary[LeaderTrajectory, dict[
    tuple[tuple[tuple[str, tuple[float, float]], ...], tuple[float, float], float],
    dict[str, FloatArray]]] = weakref.WeakKeyDictionary()
"""Caches per leader (by identity: the planner's ordered departures reuse the leaders that a
trial does not change), let go with the leader's plan."""


def _leader_offset_path(leader: LeaderTrajectory, oy: float) -> OffsetPath:
    """:func:`offset_path`, once per leader and lateral offset."""
    paths = _OFFSET_PATHS.setdefault(leader, {})
    if oy not in paths:
        paths[oy] = offset_path(leader, oy)
    return paths[oy]


def _leader_driven(leader: LeaderTrajectory, times: FloatArray) -> FloatArray:
    """How far (m) the leader has driven at show times (T,)."""
    path = _leader_offset_path(leader, 0.0)
    k = np.clip(np.searchsorted(leader.times, times, side="right") - 1, 0,
                len(leader.times) - 1)
    driven: FloatArray = path.driven[k] + leader.commands[k, 0] * np.maximum(
        times - leader.times[k], 0.0)
    return driven


def _file_table(plan: Plan, index: int) -> dict[str, FloatArray]:
    """Per robot of formation ``index``, at its leader's sample times (N,): the leader path
    length (N,) m abeam which the robot's place is (module docstring: a robot keeps its
    distance behind the robot in front of it in its file, and catches up no faster than
    :func:`catch_up_speed`)."""
    formation = plan.formations[index]
    return _leader_file_table(formation.leader, tuple(formation.offsets.items()),
                              plan.parameters.footprint, catch_up_speed(plan))


def _leader_file_table(leader: LeaderTrajectory,
                       offsets_of: tuple[tuple[str, tuple[float, float]], ...],
                       footprint: tuple[float, float], catch_up: float,
                       ) -> dict[str, FloatArray]:
    """:func:`_file_table` of a leader (by identity), the robots' offsets, the largest
    footprint (m) and the catch-up speed (m/s), once."""
    tables = _FILE_TABLES.setdefault(leader, {})
    key = (offsets_of, footprint, catch_up)
    if key not in tables:
        tables[key] = _compute_file_table(leader, offsets_of, footprint, catch_up)
    return tables[key]


def _compute_file_table(leader: LeaderTrajectory,
                        offsets_of: tuple[tuple[str, tuple[float, float]], ...],
                        footprint: tuple[float, float], catch_up: float,
                        ) -> dict[str, FloatArray]:
    """See :func:`_leader_file_table`."""
    times = leader.times
    length, width = footprint
    reach = float(np.hypot(length, width)) + FILE_MARGIN
    fastest = catch_up * np.diff(times)  # (N - 1,) m per step
    driven = _leader_driven(leader, times)
    offsets = dict(offsets_of)
    placed: dict[str, tuple[FloatArray, FloatArray]] = {}
    for robot in sorted(offsets, key=lambda name: -offsets[name][0]):
        ox, oy = offsets[robot]
        path = _leader_offset_path(leader, oy)
        abeam = driven + min(ox, 0.0)
        fronts = [(min(float(np.hypot(offsets[front][0] - ox, offsets[front][1] - oy)), reach),
                   front_place) for front, (_, front_place) in placed.items()
                  if offsets[front][0] > ox]
        if fronts and len(times) >= 2:
            # the distance first, then the speed limit, then the distance again: going back
            # round a loop can bring a place nearer, and the distance comes first
            abeam = _kept_apart(path, abeam, fronts)
            abeam = _drivable(path, abeam, fastest)
            abeam = _kept_apart(path, abeam, fronts)
        placed[robot] = (abeam, path.points_at(abeam))
    return {robot: abeam for robot, (abeam, _) in placed.items()}


def place_waits(plan: Plan, index: int) -> dict[str, FloatArray]:
    """Per robot of formation ``index``, at its leader's sample times (N,): how far (m of the
    leader's path) its place waits behind where the formation puts it, to keep its distance
    from the robots ahead (module docstring); 0 where it does not wait. ``check`` notes
    long waits: the formation loses its shape there."""
    formation = plan.formations[index]
    return {robot: np.maximum(_nominal_abeam(formation.leader, formation.offsets[robot][0])
                              - abeam, 0.0)
            for robot, abeam in _file_table(plan, index).items()}


def _nominal_abeam(leader: LeaderTrajectory, ox: float) -> FloatArray:
    """At the leader's samples (N,): the leader path length (m) abeam which a robot ``ox`` m
    along (behind: negative) has its place when it waits for no one."""
    return _leader_driven(leader, leader.times) + min(ox, 0.0)


def _kept_apart(path: OffsetPath, abeam: FloatArray,
                fronts: list[tuple[float, FloatArray]]) -> FloatArray:
    """``abeam`` (N,) (leader path length, m) moved back along ``path`` until the place is at
    least ``gap`` m straight from each ``front_place`` (N, 2) of ``fronts`` (secant steps)."""
    abeam = abeam.copy()
    count = len(abeam)
    active = np.arange(count)  # the samples still too near a robot in front
    last_short = np.full(count, np.nan)
    last_step = np.zeros(count)
    for _ in range(FILE_ITERATIONS):
        point = path.points_at(abeam[active])
        short = np.zeros(len(active))
        for gap, front_place in fronts:
            short = np.maximum(short, gap - np.hypot(*(point - front_place[active]).T))
        # the distance gained per metre gone back on the last step (1 on a straight line,
        # less round a corner): the secant step, at most 1 / FILE_SECANT_FLOOR times the
        # distance missing (a place held a little further back is safe)
        gained = np.where(last_step[active] > 0.0, (last_short[active] - short)
                          / np.where(last_step[active] > 0.0, last_step[active], 1.0), 1.0)
        step = short / np.clip(gained, FILE_SECANT_FLOOR, 1.0)
        going = short > 1e-6
        last_short[active], last_step[active] = short, step
        active = active[going]
        if not len(active):
            break
        abeam[active] -= step[going]
    return abeam


def _drivable(path: OffsetPath, abeam: FloatArray, fastest: FloatArray) -> FloatArray:
    """``abeam`` (N,) held back so that the place falls back and catches up no faster than
    ``fastest`` (N - 1,) m per step (start waiting earlier rather than jump back), as the
    place's own speed: the leader's path length per step over the stretch there
    (|1 - kappa oy|); both passes only move places further back."""
    for _ in range(RATE_PASSES):
        room = fastest / np.maximum(np.abs(path.stretch_at(abeam)[:-1]), 1.0)
        abeam = _held_back(abeam, room)
    return abeam


def _held_back(abeam: FloatArray, room: FloatArray) -> FloatArray:
    """``abeam`` (N,) after a backward pass ``v[k] = min(v[k], v[k + 1] + room[k])`` (k from
    N - 2 down) and a forward pass ``v[k] = min(v[k], v[k - 1] + room[k - 1])`` (k from 1 up),
    room (N - 1,): the same numbers as the two loops, running each only from where its
    bound binds (a sample changes only where it did with the values before the pass or its
    neighbour just changed; some 400 of 700,000 samples in a 1,000-line show)."""
    values = abeam.copy()
    with np.errstate(over="ignore", invalid="ignore"):  # (as the loops' Python floats)
        return _held_back_passes(values, room)


def _held_back_passes(values: FloatArray, room: FloatArray) -> FloatArray:
    """The two passes of :func:`_held_back` on ``values`` (changed in place, returned)."""
    for start in np.flatnonzero(values[1:] + room < values[:-1])[::-1].tolist():
        k = start
        while k >= 0 and values[k + 1] + room[k] < values[k]:  # (its chain went past: no)
            values[k] = values[k + 1] + room[k]
            k -= 1
    for start in np.flatnonzero(values[:-1] + room < values[1:]).tolist():
        k = start + 1
        while k < len(values) and values[k - 1] + room[k - 1] < values[k]:
            values[k] = values[k - 1] + room[k - 1]
            k += 1
    return values


def path_places(plan: Plan, robot: str, times: FloatArray, wait_behind: bool = True,
                ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Where ``robot``'s place on its leader's path is at show times ``times`` (T,) s,
    ascending, show frame: positions (T, 2) m; the heading the robot should have there (T,)
    rad, unwrapped (the path's, at the end the leader's final heading); the direction the
    place moves (T,) rad (the heading plus pi where the place moves backwards round a loop)
    and its speed (T,) m/s (>= 0).

    The leader's pose where the leader was ``-ox`` m of path earlier, shifted by (0, oy),
    held back to keep its distance from the robots ahead (module docstring); before the
    leader has driven that far, on the straight line behind its first pose. Computed at the
    leader's samples and interpolated between them. Once the leader stands after its last
    instruction, the place goes at :func:`catch_up_speed` on a cubic Hermite curve to the
    robot's rigid slot (the leader's final pose composed with (ox, oy)): where the path
    behind the leader is curved (a show that ends on an arc) the two differ.

    ``wait_behind=False``: the place where the formation puts the robot, without the wait
    behind the robots ahead (what the audience expects of it; the metrics' ``off_formation``)."""
    times = np.asarray(times, dtype=float)
    count = len(times)
    points = np.empty((count, 2))
    heading = np.empty(count)
    motion = np.empty(count)
    speed = np.zeros(count)
    which = plan.formation_indices(robot, times)
    bounds = np.concatenate([[0], np.flatnonzero(np.diff(which)) + 1, [count]]).tolist()
    settle = catch_up_speed(plan)
    for a, b in itertools.pairwise(bounds):
        if a == b:
            continue
        index = int(which[a])
        formation = plan.formations[index]
        ox, oy = formation.offsets[robot]
        leader = formation.leader
        now = times[a:b]
        abeam = (_file_table(plan, index)[robot] if wait_behind else
                 _nominal_abeam(leader, ox))
        path = _offset_path(formation, oy)
        place, place_heading, stretch = path.at(np.interp(now, leader.times, abeam))
        if len(leader.times) >= 2:
            k = np.clip(np.searchsorted(leader.times, now, side="right") - 1, 0,
                        len(leader.times) - 2)
            rate = np.diff(abeam) / np.diff(leader.times)  # m of the leader's path per s
            speed[a:b] = np.where((now >= leader.times[0]) & (now < leader.times[-1]),
                                  rate[k] * stretch, 0.0)  # signed, m/s
        place_motion = place_heading + np.where(speed[a:b] < 0.0, np.pi, 0.0)
        speed[a:b] = np.abs(speed[a:b])
        done = now >= leader.times[-1]  # the leader stands at its end
        if done.any():
            settling = _settle(path.at(abeam[-1:]), leader.poses[-1], (ox, oy), settle,
                               now[done] - leader.times[-1])
            place[done], place_heading[done], place_motion[done], speed[a:b][done] = settling
        points[a:b] = place
        heading[a:b] = place_heading
        motion[a:b] = place_motion
    return points, np.unwrap(heading), motion, speed


SETTLE_TANGENT = 1.0
"""The settle curve's tangents, as a multiple of the straight distance to the slot."""
SETTLE_SAMPLES = 64
"""Points of the curve by which a place goes to its rigid slot after the leader's end."""


def _settle(end: tuple[FloatArray, FloatArray, FloatArray], leader_end: FloatArray,
            offset: tuple[float, float], speed: float, after: FloatArray,
            ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """How a place goes from where its path left it at the leader's end (``end``: points
    (1, 2), heading (1,), stretch of ``OffsetPath.at``) to its rigid slot (``leader_end``
    (3,) composed with ``offset``), ``after`` (T,) s after the end: points (T, 2), heading
    (T,), direction of motion (T,), speed (T,). A cubic Hermite curve from the path's heading
    to the leader's final heading, both tangents as long as the way (forwards, or backwards
    where the slot is behind), driven at ``speed`` m/s; then it stands on the slot."""
    start, facing = end[0][0], float(end[1][0])
    slot = compose_points(leader_end, np.array(offset))
    final = float(leader_end[2])
    way = slot - start
    distance = float(np.hypot(*way))
    count = len(after)
    if distance < 1e-6:
        return (np.broadcast_to(slot, (count, 2)).copy(), np.full(count, final),
                np.full(count, final), np.zeros(count))
    sign = 1.0 if way @ np.array([np.cos(facing), np.sin(facing)]) >= 0.0 else -1.0
    tangent0 = sign * SETTLE_TANGENT * distance * np.array([np.cos(facing), np.sin(facing)])
    tangent1 = sign * SETTLE_TANGENT * distance * np.array([np.cos(final), np.sin(final)])
    tau = np.linspace(0.0, 1.0, SETTLE_SAMPLES)[:, None]
    curve = ((2 * tau**3 - 3 * tau**2 + 1) * start + (tau**3 - 2 * tau**2 + tau) * tangent0
             + (-2 * tau**3 + 3 * tau**2) * slot + (tau**3 - tau**2) * tangent1)
    lengths = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(curve, axis=0).T))])
    gone = np.minimum(after * speed, lengths[-1])
    points = np.column_stack([np.interp(gone, lengths, curve[:, 0]),
                              np.interp(gone, lengths, curve[:, 1])])
    slope = np.gradient(curve, axis=0)
    direction = np.unwrap(np.arctan2(slope[:, 1], slope[:, 0]))
    motion = np.interp(gone, lengths, direction)
    heading = motion + (np.pi if sign < 0.0 else 0.0)
    arrived = gone >= lengths[-1]
    heading[arrived] = final + 2.0 * np.pi * np.round((heading[arrived] - final) / (2 * np.pi))
    return points, heading, motion, np.where(arrived, 0.0, speed)


_PLACES_END: weakref.WeakKeyDictionary[Plan, float] = weakref.WeakKeyDictionary()
""":func:`places_end` per plan (by identity; every brain of a plan asks), let go with it."""


def places_end(plan: Plan) -> float:
    """The show time (s) by which every place has reached its rigid slot after its leader's
    last instruction (:func:`path_places`): the plan's duration plus the longest such way
    at :func:`catch_up_speed` (the straight distance times pi / 2 bounds the curve's).
    Computed once per plan."""
    if plan not in _PLACES_END:
        _PLACES_END[plan] = _compute_places_end(plan)
    return _PLACES_END[plan]


def _compute_places_end(plan: Plan) -> float:
    """See :func:`places_end`: per formation, every robot's place at the leader's end and
    its rigid slot, in one array pass."""
    longest = 0.0
    for formation in plan.formations:
        leader = formation.leader
        table = _file_table(plan, formation.index)
        if not table:
            continue
        ends = np.empty((len(table), 2))
        offsets = np.empty((len(table), 2))
        for row, (robot, abeam) in enumerate(table.items()):
            ox, oy = formation.offsets[robot]
            ends[row] = _offset_path(formation, oy).points_at(abeam[-1:])[0]
            offsets[row] = ox, oy
        slots = compose_points(leader.poses[-1], offsets)  # (R, 2)
        way = float(np.hypot(*(slots - ends).T).max())
        ready = leader.times[-1] + 0.5 * np.pi * way / catch_up_speed(plan)
        longest = max(longest, ready - plan.duration)
    return plan.duration + longest

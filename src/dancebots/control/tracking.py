"""The tracking follower: feedforward from the plan plus Kanayama's tracking law (an addition).

Every robot knows its own desired trajectory from the plan (its slot: the virtual leader's
pose composed with the robot's offset), so it need not chase a point ahead as eq. 4.4 does.
It follows the slot's motion exactly (feedforward) and corrects its error with the unicycle
tracking law of Kanayama, Kimura, Miyazaki and Noguchi, "A stable tracking control method
for an autonomous mobile robot", ICRA 1990 (eq. numbers of that paper):

    e = (ex, ey, eth): the reference pose in the robot's frame                    (Kanayama 6)
    v = vr cos(eth) + Kx ex                                                     (Kanayama 11)
    w = wr + vr Ky ey + max(|vr|, v0) Kth sin(eth)

Kanayama's w has ``vr Kth sin(eth)``, stable for vr > 0; with ``max(|vr|, v0)`` the Lyapunov
function V = (ex^2 + ey^2) / 2 + (1 - cos eth) / Ky decreases for either sign of vr:
dV/dt = -Kx ex^2 - max(|vr|, v0) (Kth / Ky) sin^2(eth) <= 0 (the cross terms in ey sin(eth)
cancel as in the paper), so a slot that moves backwards (the inner robot of a turn tighter
than its lateral offset) is tracked backwards, facing the formation, instead of the robot
turning round; and v0 keeps the heading corrected where the slot's speed passes zero.

The reference: the slot of offset (ox, oy) of a leader moving with (v, w) moves, in the
leader's frame, with velocity (v - w oy, w ox). Its heading is the direction of that velocity
folded by 180 deg so that it stays continuous (a slot whose motion reverses, the inner slot
of a turn tighter than its lateral offset, is driven in reverse instead of by turning round),
its speed that velocity's length signed by the fold, its angular speed the heading's rate of
change (``slot_references``: computed over the plan's time grid, since the fold depends on
the reference's past).

Saturation keeps the path: when |v| or |w| exceeds the robot's limits both are scaled by the
same factor, so the robot slows along the curve it was steering instead of spinning.

Frames: everything in the robot's own ``map`` frame; commands (linear m/s, angular rad/s) in
``base_link``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from dancebots.control.follower import ARRIVAL_GAIN
from dancebots.geometry import (
    Pose,
    compose_points,
    integrate_unicycle,
    wrap_angle,
    wrap_angles,
)
from dancebots.plan.places import path_places
from dancebots.plan.planner import Plan, slot_velocities

__all__ = ["BRIEF_STAND", "FACING_AWAY_COST", "FOR_GOOD", "REFERENCE_TURN", "TURN_COST",
           "SlotReference", "TrackingParams", "approach_step", "choose_folds", "fold_reference",
           "follower_places", "follower_references", "parking_step", "path_places",
           "path_references", "paused_step", "place_stand", "references_from_motion",
           "settle_step", "settling_on_slot", "shared_pose_references", "slot_reference",
           "slot_references", "stand_ends", "tracking_step", "turn_onto_slot", "turn_share",
           "turn_then_drive_step"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class TrackingParams:
    """Gains and limits of the tracking follower.

    gain_x: Kx, along-track error gain, 1/s. gain_y: Ky, cross-track error gain, 1/m^2.
    gain_theta: Kth, heading error gain, 1/m. The cross-track and heading errors then decay
    like a second-order system of natural frequency |vr| sqrt(Ky) and damping
    Kth / (2 sqrt(Ky)) (0.7 with the defaults).
    max_linear, max_angular: the robot's limits, m/s and rad/s.
    arrival_distance: at rest (the slot stands still), a robot nearer than this to its slot
        only turns to the slot's heading, m; heading_tolerance: and then stops turning, rad.
    settle_distance: nearer than this (m), it turns to the slot's heading and closes the
        distance along it, without turning towards the slot (its sideways error is left).
    arrival_gain: speed per metre of remaining distance when arriving at a standing slot, 1/s
        (the thesis follower's arrival, eq. 4.1a's form).
    turn_gain: angular speed per radian of heading error when turning on the spot at rest,
        1/s.
    reverse_distance: at rest, a slot behind the robot nearer than this is reached in
        reverse (a short step back) rather than by turning round, m.
    force_gain: angular speed per unit of the virtual force's sideways component, rad/s.
    heading_speed: v0, the least speed (m/s) the heading term counts with, so that a robot
        whose slot momentarily stands (the cusp of a tight turn) still turns to its heading.
    park_gain_alpha, park_gain_theta: k and h of the parking law at a standing slot
        (:func:`parking_step`), 1/s and 1.
    wait_speed: a robot whose law would drive it against its reference's motion while the
        reference moves at least this fast (m/s) waits for it instead (it drives backwards
        only where its reference does).
    approach_distance, approach_heading: nearer than this (m) to its final slot and facing
        less than this (rad) from its heading, the robot approaches it with
        :func:`approach_step`; turned farther, it turns and drives onto it
        (:func:`turn_then_drive_step`); the posture law brings a robot farther away within
        ``approach_distance``. approach_gain, approach_tilt: its heading's tilt
        towards the slot's side per metre of sideways error (rad/m) and the largest (rad).
    handover_turn: the turn (rad) :func:`turn_then_drive_step` rather adds than turn the
        robot within ``approach_heading`` short of its slot, where :func:`approach_step`
        takes it and leaves what it cannot close sideways (over 400 starts within
        ``approach_distance`` turned beyond ``approach_heading``, ``benchmarks/eval_parking.py``:
        0 left robots up to 0.21 m from their slots, infinity turned 14 deg more than their
        heading error at the median; docs/control.md has the table).
    face_distance: nearer than this (m) to its final slot, turned beyond
        ``approach_heading`` and not driving onto it, a robot turns to the heading where it
        stands (:func:`settle_step`) instead of turning to face the slot: on the spot a
        realistic robot's centre moves a centimetre or two, and at ``settle_distance``
        (6 cm) that moved it in and out of the region where it faced its slot, turning it
        left and right for 20 s (open-day crowd seed 212, R4: 360 deg beyond what it
        tracked).
    parking_turn_rate: the fastest (rad/s) a robot turns within ``settle_distance`` or
        ``approach_distance`` of its final slot (an addition): the corners of a SIM robot
        (1.2 x 0.6 m) swing at 0.5 m/s. At ``max_angular`` (pi rad/s, 2.1 m/s at the
        corners) a robot that drove onto its slot facing it turned 144 deg to its heading
        while a child ran at it, and under the realistic profile's lag its corner met the
        child at 0.40 m/s (open-day pillars seed 29 at 4d44341).
    """

    gain_x: float = 1.5
    gain_y: float = 10.0
    gain_theta: float = 4.4
    max_linear: float = 0.5
    max_angular: float = math.pi
    arrival_distance: float = 0.03
    settle_distance: float = 0.06
    heading_tolerance: float = math.radians(2.0)
    arrival_gain: float = ARRIVAL_GAIN
    turn_gain: float = 1.5
    reverse_distance: float = 1.0
    force_gain: float = 1.0
    heading_speed: float = 0.1
    park_gain_alpha: float = 3.0
    park_gain_theta: float = 1.5
    wait_speed: float = 0.05
    approach_distance: float = 0.3
    approach_heading: float = math.radians(45.0)
    approach_gain: float = 3.0
    approach_tilt: float = math.radians(20.0)
    handover_turn: float = math.radians(90.0)
    parking_turn_rate: float = 0.75
    face_distance: float = 0.12


@dataclass(frozen=True, slots=True)
class SlotReference:
    """Where a robot's slot is and how it moves: pose (x, y, theta) in the robot's map frame,
    signed speed along its heading, m/s, and angular speed, rad/s; final: the slot stands for
    good (the show is over), so the robot parks on it (:func:`parking_step`); paused: the
    slot stands a moment, because the formation's shared show clock stands (``sync.hold``) or
    because the plan stops it for less than :data:`BRIEF_STAND`, and moves on along its
    heading when the clock runs (:func:`tracking_step`'s paused law), backwards where
    ``backwards`` (a slot driven in reverse when the clock stood, or next)."""

    pose: tuple[float, float, float]
    speed: float
    angular_speed: float
    final: bool = False
    paused: bool = False
    backwards: bool = False

    @property
    def moving(self) -> bool:
        """True when the slot moves or turns."""
        return abs(self.speed) > 1e-9 or abs(self.angular_speed) > 1e-9


FACING_AWAY_COST = 1.0
"""Cost of one second in which a robot would face more than 90 deg away from its leader's
heading (the formation's), in the reference's fold choice (``choose_folds``)."""
TURN_COST = 1.0
"""Cost of one metre that the slot moves while its robot turns round at ``REFERENCE_TURN``,
in the fold choice: a fold change at 0.3 m/s (about 0.6 m) is worth it only if it saves the
robot over 0.6 s of facing away."""
REFERENCE_TURN = 1.5
"""rad/s: the rate at which the reference heading turns round at a fold change, and the rate
counted for the turn's cost (below the robots' pi rad/s, so that they can follow it)."""
BRIEF_STAND = 2.0
"""s: a place that stands on its path (not for good) and moves on within this is tracked with
the paused law (:func:`paused_step`), as when the shared clock stands: the robot closes on it
along its own heading and turns gently to its heading, never towards a point beside it. The
drive onto it (turning towards it first) turned the open-day show's rear robots, 0.2 m short
of a corner when the place stood 0.4 s there after turning, 55 deg past the new heading
(reversing onto the place beside them) and back when it moved on: 130 deg each, at every
run (t = 65.4 s)."""
FOR_GOOD = 2.0
""":func:`place_stand` of a place that never moves again: the robot parks on it as on its
final slot (``SlotReference.final``) before every other place has reached its own
(``plan.places.places_end``). Driven onto as a place that waits on its path, listing 7.4's
R1 (0.13 m beside it, R2 at its side) drove 0.13 m on to make room for the turn onto it,
reversed turning 40 deg away and was then swung round by the posture law (a full circle)."""


def stand_ends(grid: FloatArray) -> NDArray[np.int64]:
    """For each row of a reference grid (T, 5) (x, y, heading, speed, angular speed at ticks
    of a fixed period), the index of the first row at or after it whose place moves (T where
    none does): where a standing row's stand ends."""
    moving = (np.abs(grid[:, 3]) > 1e-9) | (np.abs(grid[:, 4]) > 1e-9)
    first = np.where(moving, np.arange(len(grid)), len(grid))
    ends: NDArray[np.int64] = np.minimum.accumulate(first[::-1])[::-1].astype(np.int64)
    return ends


def place_stand(grid: FloatArray, ends: NDArray[np.int64], row: int, show_time: float,
                period: float) -> float:
    """How the place of reference grid row ``row`` (of ``grid`` (T, 5), ``period`` s apart;
    ``ends`` from :func:`stand_ends`) stands at ``show_time`` s: :data:`FOR_GOOD` (2.0)
    where it never moves again; where it stands only briefly (it moves on within
    :data:`BRIEF_STAND` s from ``show_time``) the way it moves on, -1.0 where it is then
    driven in reverse, 1.0 otherwise; 0.0 where it moves or stands longer."""
    end = int(ends[row])
    if end >= len(grid):
        return FOR_GOOD
    if end == row or end * period - show_time >= BRIEF_STAND:
        return 0.0
    return -1.0 if grid[end, 3] < 0.0 else 1.0


def choose_folds(times: FloatArray, motion: FloatArray, leader_heading: FloatArray,
                 speed: FloatArray, compiled: bool = False) -> NDArray[np.bool_]:
    """Which way a robot faces along its slot's motion: (T,) True where it drives the slot's
    path in reverse (faces ``motion`` + pi), chosen by dynamic programming (Viterbi over the
    two folds of every row) to minimise the time it faces more than 90 deg away from its
    leader's heading (``FACING_AWAY_COST``) plus the metres its slot moves while it turns at
    every change of heading (``TURN_COST``: turning round where the slot is slow, at a cusp,
    costs little). times (T,) s ascending; motion (T,) the direction the slot moves, rad;
    leader_heading (T,) rad; speed (T,) the slot's speed, m/s (0: standing, where both folds
    are the leader's heading and cost nothing). ``compiled``: the pass as a numba kernel
    (``tracking_jit.fold_choices``, the same folds).
    """
    count = len(times)
    folds = np.zeros(count, dtype=bool)
    if count == 0:
        return folds
    last = times[-1] - times[-2] if count > 1 else 1.0  # the last row weighs one step too
    step = np.diff(times, append=times[-1] + last)
    moving = speed > 1e-9
    heading = np.stack([np.where(moving, motion, leader_heading),
                        np.where(moving, motion + np.pi, leader_heading)])  # (2, T)
    away = (np.cos(heading - leader_heading) < 0.0) & moving
    turn = np.abs(wrap_angles(heading[:, None, 1:] - heading[None, :, :-1]))  # (to, from, T-1)
    pace = np.maximum(speed[1:], speed[:-1]) * (TURN_COST / REFERENCE_TURN)
    if compiled:
        from dancebots.control.tracking_jit import fold_choices  # imports numba

        return fold_choices(FACING_AWAY_COST * away * step, turn * pace)
    row_cost = (FACING_AWAY_COST * away * step).tolist()
    turn_cost = (turn * pace).tolist()
    total = [row_cost[0][0], row_cost[1][0]]
    back = np.zeros((count, 2), dtype=np.int8)
    for k in range(1, count):
        t00, t01 = turn_cost[0][0][k - 1], turn_cost[0][1][k - 1]
        t10, t11 = turn_cost[1][0][k - 1], turn_cost[1][1][k - 1]
        a0, a1 = total[0] + t00, total[1] + t01
        b0, b1 = total[0] + t10, total[1] + t11
        back[k, 0] = 0 if a0 <= a1 else 1
        back[k, 1] = 0 if b0 <= b1 else 1
        total = [min(a0, a1) + row_cost[0][k], min(b0, b1) + row_cost[1][k]]
    state = 0 if total[0] <= total[1] else 1
    for k in range(count - 1, -1, -1):
        folds[k] = bool(state)
        state = int(back[k, state])
    return folds


def slot_references(times: FloatArray, leaders: FloatArray, offsets: FloatArray,
                    leader_commands: FloatArray, turn_rate: float = REFERENCE_TURN,
                    compiled: bool = False) -> FloatArray:
    """The reference of a rigid slot over consecutive show times ``times`` (T,) s, ascending:
    the slot at ``offsets`` (T, 2) (ox, oy, m, in the leader's frame) of leaders at poses
    ``leaders`` (T, 3) (x, y, theta) moving with ``leader_commands`` (T, 2) (v m/s, w rad/s).
    Its velocity in the leader's frame is (v - w oy, w ox). Returns (T, 5) as
    :func:`references_from_motion`."""
    times = np.asarray(times, dtype=float)
    velocity = slot_velocities(leader_commands, offsets)  # in the leader's frame
    along, across = velocity[:, 0], velocity[:, 1]
    leader_heading = np.unwrap(leaders[:, 2])
    motion = leader_heading + np.arctan2(across, along)  # the direction the slot moves
    rows = references_from_motion(times, compose_points(leaders, offsets), motion,
                                  np.hypot(along, across), leader_heading, turn_rate,
                                  compiled)
    if len(rows):
        rows[-1, 4] = leader_commands[-1, 1]  # held: the slot turns with its leader
    return rows


def path_references(plan: Plan, robot: str, times: FloatArray,
                    turn_rate: float = REFERENCE_TURN, compiled: bool = False) -> FloatArray:
    """The reference of ``robot`` at show times ``times`` (T,) s, ascending, show frame: its
    place on its leader's path (thesis ch. 4.1: a robot drives the leader's path shifted
    sideways by its lateral offset oy, its along offset ox behind): the leader's pose where
    the leader was ``-ox`` m of path earlier, shifted by (0, oy) (:func:`path_places`). So a
    column follows its leader's path round a corner instead of swinging sideways as a rigid
    body would (``ox sin(turn)``: 1.5 m for the rear of a 2.1 m column at 45 deg), and the
    robots of a row stay parallel. A robot keeps its distance from the places of the robots
    ahead of it, and after the leader's last instruction the place goes on a smooth curve to
    the rigid slot (``plan.places``). Speed: the
    leader's v times (1 - kappa oy), kappa the path's curvature there (the feasible timing
    bounds it: ``plan.planner.path_speed_scale``), less where the place is held back.
    Returns (T, 5) as :func:`references_from_motion`."""
    points, heading, motion, speed = path_places(plan, robot, times)
    return references_from_motion(np.asarray(times, dtype=float), points, motion, speed,
                                  heading, turn_rate, compiled)


def follower_places(plan: Plan, times: FloatArray, follower: str = "tracking") -> FloatArray:
    """Where every robot of the plan should be by ``follower`` at show times (T,): (R, T, 2)
    show frame, robots in the scenario's order (the rigid slots for ``tracking``, the places
    on the leaders' paths otherwise; :func:`follower_references` without the headings)."""
    if follower == "tracking":
        return np.stack([plan.track(robot, times).desired[:, :2] for robot in plan.robots])
    return np.stack([path_places(plan, robot, times)[0] for robot in plan.robots])


def follower_references(plan: Plan, robot: str, times: FloatArray,
                        follower: str = "tracking", compiled: bool = False) -> FloatArray:
    """The reference (T, 5) that ``follower`` tracks (and that the metrics judge its heading
    and direction against) at show times (T,), show frame: the rigid slot's
    (:func:`slot_references`) for ``tracking``, the place on the leader's path
    (:func:`path_references`) for ``path`` and ``thesis`` (eq. 4.4 drives the lateral path,
    thesis ch. 4.1)."""
    if follower == "tracking":
        track = plan.track(robot, times)
        return slot_references(times, track.leader, track.offsets, track.leader_commands,
                               compiled=compiled)
    return path_references(plan, robot, times, compiled=compiled)


def references_from_motion(times: FloatArray, points: FloatArray, motion: FloatArray,
                           speed: FloatArray, leader_heading: FloatArray,
                           turn_rate: float = REFERENCE_TURN, compiled: bool = False,
                           ) -> FloatArray:
    """A reference over consecutive show times ``times`` (T,) s, ascending, for a place at
    ``points`` (T, 2) that moves in the direction ``motion`` (T,) rad at ``speed`` (T,) m/s
    (0: it stands), its formation heading ``leader_heading`` (T,) rad.

    Returns (T, 5): x, y, theta (continuous, not wrapped), the signed speed along theta and
    the angular speed (a compact :class:`SlotReference` per row).

    Heading: where the place moves, the direction of its motion or that plus 180 deg (driven
    in reverse), the fold chosen over the whole sequence by :func:`choose_folds`; where it
    stands, the formation's heading (the robot turns to it). Where the chosen heading jumps
    (a fold change, a stand) it turns at most ``turn_rate`` rad/s, and the speed is the
    place's velocity along the heading (the robot slows while it turns). Angular speed: the
    heading's change to the next row over the time step (exact for commands held over the
    step, as a robot's are). ``compiled``: the two sequential passes as numba kernels
    (``tracking_jit``, the same rows).
    """
    moving = speed > 1e-9
    folds = choose_folds(times, motion, leader_heading, speed, compiled)
    target = np.where(moving, motion + np.pi * folds, leader_heading)
    heading = _rate_limited(times, target, turn_rate, compiled)
    signed = speed * np.cos(heading - motion)
    angular = np.zeros(len(times))
    step = np.diff(times)
    ahead = step > 0.0
    angular[:-1][ahead] = np.diff(heading)[ahead] / step[ahead]
    return np.column_stack([points, heading, signed, angular])


def _rate_limited(times: FloatArray, target: FloatArray, rate: float,
                  compiled: bool = False) -> FloatArray:
    """Headings (T,) that follow ``target`` (T,) rad, unwrapped, turning at most ``rate``
    rad/s between consecutive ``times`` (T,) s (the shorter way round)."""
    if compiled and len(target):
        from dancebots.control.tracking_jit import rate_limited_headings  # imports numba

        return rate_limited_headings(np.diff(times) * rate, np.ascontiguousarray(target))
    result = np.empty(len(target))
    if len(target) == 0:
        return result
    steps = (np.diff(times) * rate).tolist()
    targets = target.tolist()
    current = targets[0]
    result[0] = current
    for k in range(1, len(targets)):
        error = math.remainder(targets[k] - current, 2.0 * math.pi)
        limit = steps[k - 1]
        current += error if abs(error) <= limit else math.copysign(limit, error)
        result[k] = current
    return result


def fold_reference(row: FloatArray, heading: float) -> FloatArray:
    """A reference row (5,) of :func:`slot_references` computed alone, folded by 180 deg
    (heading turned, speed negated) when that brings its heading nearer ``heading`` rad (the
    heading of the reference sequence at the row before), so that it continues it."""
    folded = row.copy()
    if folded[3] != 0.0 and abs(wrap_angle(float(folded[2]) - heading)) > 0.5 * math.pi:
        folded[2] += math.pi
        folded[3] = -folded[3]
    return folded


def slot_reference(leader: tuple[float, float, float], offset: tuple[float, float],
                   leader_command: tuple[float, float]) -> SlotReference:
    """One slot's reference at one instant (:func:`slot_references` for a single leader
    pose: its heading folded towards the leader's, its angular speed the leader's)."""
    row = slot_references(np.zeros(1), np.array([leader], dtype=float),
                          np.array([offset], dtype=float),
                          np.array([leader_command], dtype=float))[0]
    return SlotReference((float(row[0]), float(row[1]), wrap_angle(float(row[2]))),
                         float(row[3]), float(row[4]))


def _saturate(linear: float, angular: float, params: TrackingParams,
              max_angular: float | None = None) -> tuple[float, float]:
    """Scale (v, w) by one factor so that both are within the limits (same curvature):
    ``max_linear`` m/s and ``max_angular`` rad/s (the params' unless given)."""
    top = params.max_angular if max_angular is None else max_angular
    scale = 1.0
    if abs(linear) > params.max_linear:
        scale = params.max_linear / abs(linear)
    if abs(angular) * scale > top:
        scale = top / abs(angular)
    return linear * scale, angular * scale


def settle_step(params: TrackingParams, ex: float, heading_error: float,
                ) -> tuple[float, float]:
    """(linear m/s, angular rad/s) of a robot a few centimetres (``settle_distance``) off a
    standing slot, ``ex`` m ahead of it along its heading, ``heading_error`` rad from it: it
    turns to the slot's heading (within ``heading_tolerance``) and closes the distance along
    its own while more than ``arrival_distance`` is left along it (then it stops at once, so
    that it stands still in finite time), without turning towards the slot (a
    spin for millimetres); the sideways error is left. It stops where nothing is left to do
    (else a slot 4 cm beside a robot keeps it creeping to and fro by millimetres in the
    realistic profile's noise, to the run's limit, and a creep of a centimetre towards a
    mate behind stopped R2 with the stop sentence at the open-day show's end)."""
    linear = (params.arrival_gain * ex * max(math.cos(heading_error), 0.0)
              if abs(ex) > params.arrival_distance else 0.0)
    angular = (params.turn_gain * heading_error
               if abs(heading_error) > params.heading_tolerance else 0.0)
    return linear, angular


def turn_share(params: TrackingParams, ex: float) -> float:
    """The share (0-1) of a slot's turn on the spot (about a point within
    ``arrival_distance`` of the slot: |vr| <= arrival_distance |wr|) that a robot ``ex`` m
    behind it along its own heading turns along (an addition to Kanayama's feedforward):
    all of it within
    ``arrival_distance`` (or ahead of the slot), none beyond ``settle_distance``, linearly
    between. A robot further behind closes on the turning point first (Kanayama's ``Kx ex``)
    and turns there: turning with the slot from 0.2 m short of it, the open-day show's rear
    robots ended 0.12-0.2 m beside their places, at a corner and at the final turn, and the
    drive onto them swung them 55-90 deg out and back (R4: 180 deg at the show's end)."""
    span = params.settle_distance - params.arrival_distance
    if span <= 0.0:
        return 1.0 if ex <= params.arrival_distance else 0.0
    return min(max(1.0 - (ex - params.arrival_distance) / span, 0.0), 1.0)


def parking_step(params: TrackingParams, distance: float, bearing: float,
                 heading_error: float, backwards: bool) -> tuple[float, float]:
    """(linear m/s, angular rad/s) that bring a robot onto a standing slot ``distance`` m
    away at ``bearing`` rad in ``base_link``, whose heading is ``heading_error`` rad from the
    robot's, arriving with the slot's heading: the Lyapunov-based posture law of Aicardi,
    Casalino, Bicchi and Balestrino ("Closed loop steering of unicycle-like vehicles via
    Lyapunov techniques", IEEE RAM 1995), with e = distance, alpha = bearing and theta =
    alpha - heading_error (the direction to the slot from the slot's heading):

        u = gamma e cos(alpha),  w = k alpha + gamma (cos(alpha) sin(alpha) / alpha)
                                                  (alpha + h theta)

    (gamma: ``arrival_gain``, k: ``park_gain_alpha``, h: ``park_gain_theta``), for which
    V = (lambda e^2 + alpha^2 + h theta^2) / 2 decreases (dV/dt = -lambda gamma cos^2(alpha)
    e^2 - k alpha^2), so the robot arrives with the slot's heading instead of turning to face
    a slot a few centimetres to its side and being left facing that way (listing 7.4: 154 deg
    off). ``backwards``: the same law for the robot and slot both turned by pi (it reverses
    onto the slot)."""
    alpha = wrap_angle(bearing - math.pi) if backwards else bearing
    theta = wrap_angle(alpha - heading_error)
    gain = params.arrival_gain
    ratio = math.sin(alpha) / alpha if abs(alpha) > 1e-9 else 1.0
    linear = gain * distance * math.cos(alpha)
    angular = (params.park_gain_alpha * alpha
               + gain * math.cos(alpha) * ratio * (alpha + params.park_gain_theta * theta))
    return (-linear if backwards else linear), angular


def settling_on_slot(params: TrackingParams, pose: tuple[float, float, float],
                     reference: SlotReference, settling: bool) -> bool:
    """Whether the robot at ``pose`` (x, y, theta, own map frame) settles on its final slot
    ``reference`` from this tick on, ``settling`` its value at the tick before (a
    hysteresis in space, an addition): it starts within ``settle_distance`` of a final slot
    that stands and lasts until the robot is beyond ``face_distance`` (or the slot is no
    longer final). While it lasts, :func:`tracking_step` turns a robot turned beyond
    ``approach_heading`` to the heading where it stands (:func:`settle_step`) instead of
    facing the slot again: a robot that drove onto its slot still turned away reaches
    ``settle_distance`` far off its heading, and as it turns there on the spot its centre
    moves a centimetre or two (a skid-steer robot's does) across ``settle_distance``, where
    without it it turned back to face the slot, and again (400 starts with the centre moved
    2 mm a tick, ``benchmarks/eval_parking_noise.py``: 45 runs reversed their turn twice or
    more, 5 times at most; with it 3, at most 3)."""
    if not reference.final or reference.moving:
        return False
    ex, ey = Pose(*pose).to_local(reference.pose[0], reference.pose[1])
    distance = math.sqrt(ex * ex + ey * ey)  # (as tracking_step's)
    if distance <= params.settle_distance:
        return True
    return settling and distance <= params.face_distance


def tracking_step(params: TrackingParams, pose: tuple[float, float, float],
                  reference: SlotReference,
                  force: tuple[float, float] = (0.0, 0.0),
                  settling: bool = False) -> tuple[float, float]:
    """One control tick: the robot at ``pose`` (x, y, theta, own map frame) tracks
    ``reference``; ``force`` is the virtual repulsive force (Fx, Fy) in ``base_link``.
    Returns (linear m/s, angular rad/s), within the limits.

    While the slot moves: Kanayama's law above, plus a turn away from obstacles
    (``force_gain * Fy``, in the direction of travel); where the law would drive against
    the slot's motion (the robot far ahead of a slot that moves towards it), the robot
    waits, turning to the slot's heading. While the show's clock stands, or the slot stands
    less than :data:`BRIEF_STAND` on its path (``reference.paused``): the paused law
    (:func:`paused_step`). While it stands longer on its path: drive to it (forwards, or
    backwards when it is less than ``reverse_distance`` behind). Once it stands for good
    (``reference.final``): park on it (:func:`parking_step`; within ``approach_distance``
    :func:`approach_step` or :func:`turn_then_drive_step`). Within ``settle_distance`` of
    a slot that stands so, final or not, turn to its heading and close
    the distance along it (:func:`settle_step`; driven onto, a place that stood 4 cm behind
    and beside R2 at the open-day show's end turned it 50 deg and back). Within
    ``arrival_distance``: only turn to its heading. ``settling``
    (:func:`settling_on_slot`, the brain's state): turned beyond ``approach_heading``
    within ``face_distance`` of its final slot, it settles as within ``settle_distance``.
    """
    ex, ey = Pose(*pose).to_local(reference.pose[0], reference.pose[1])
    heading_error = wrap_angle(reference.pose[2] - pose[2])
    fy = force[1]
    if reference.moving:
        vr, wr = reference.speed, reference.angular_speed
        linear = vr * math.cos(heading_error) + params.gain_x * ex
        if linear * vr < 0.0 and abs(vr) >= params.wait_speed:
            # it would drive against its reference's motion (far ahead of a place that jumped
            # behind it at a formation change, or turned round): it stands, turning to the
            # reference's heading, until the law drives it the reference's way (a heuristic
            # outside Kanayama's proof: docs/control.md)
            return _saturate(0.0, params.turn_gain * heading_error, params)
        if abs(vr) <= params.arrival_distance * abs(wr):  # a turn on the spot
            wr *= turn_share(params, ex)
        angular = (wr + vr * params.gain_y * ey
                   + max(abs(vr), params.heading_speed) * params.gain_theta
                   * math.sin(heading_error))
        direction = 1.0 if linear >= 0.0 else -1.0
        angular += direction * params.force_gain * fy
        return _saturate(linear, angular, params)
    if reference.paused and not reference.final:
        return _saturate(*paused_step(params, ex, ey, heading_error, fy, reference.backwards),
                         params)
    distance = math.sqrt(ex * ex + ey * ey)  # (not hypot: numba's rounds otherwise)
    backwards = ex < 0.0 and distance < params.reverse_distance
    push = (-1.0 if backwards else 1.0) * params.force_gain * fy  # away from what pushes
    if distance > params.settle_distance and not reference.final:
        # a slot that stands a moment (a place waiting on its path): drive to it, turning
        # towards it first (forwards, or backwards when it is less than reverse_distance
        # behind)
        bearing = math.atan2(-ey, -ex) if backwards else math.atan2(ey, ex)
        speed = min(params.arrival_gain * distance, params.max_linear) * max(
            math.cos(bearing), 0.0)
        return _saturate(-speed if backwards else speed, params.turn_gain * bearing + push,
                         params)
    # onto its final slot it turns at most parking_turn_rate (the show is over: a corner
    # swinging fast beside a person is all risk)
    top = min(params.max_angular, params.parking_turn_rate) if reference.final else (
        params.max_angular)
    if params.arrival_distance < distance <= params.settle_distance:
        return _saturate(*settle_step(params, ex, heading_error), params, top)
    if params.arrival_distance < distance <= params.approach_distance:
        if math.cos(heading_error) > math.cos(params.approach_heading):
            return _saturate(*approach_step(params, ex, ey, heading_error, fy), params, top)
        if settling and distance <= params.face_distance:
            # it came within settle_distance and its turn there moved it a little out: it
            # goes on settling rather than face the slot again (settling_on_slot)
            return _saturate(*settle_step(params, ex, heading_error), params, top)
        linear, angular = turn_then_drive_step(params, ex, ey, heading_error, fy)
        if linear == 0.0 and distance <= params.face_distance:
            # near it and not driving onto it: it settles (turns to the heading) as within
            # settle_distance, so that a turn there that moves it a centimetre out does not
            # turn it back to face a slot a few centimetres away (open-day crowd seed 212)
            linear, angular = settle_step(params, ex, heading_error)
        return _saturate(linear, angular, params, top)
    if distance > params.arrival_distance:
        linear, angular = parking_step(params, distance, math.atan2(ey, ex), heading_error,
                                       backwards)
        return _saturate(linear, angular + push, params)
    if abs(heading_error) > params.heading_tolerance:
        return _saturate(0.0, params.turn_gain * heading_error, params, top)
    return 0.0, 0.0


def approach_step(params: TrackingParams, ex: float, ey: float, heading_error: float,
                  fy: float) -> tuple[float, float]:
    """(linear m/s, angular rad/s) of a robot near its final slot (within
    ``approach_distance``, facing within ``approach_heading`` of its heading), the slot
    (ex, ey) m ahead and to the left in ``base_link``, ``heading_error`` rad from its
    heading, sideways force ``fy`` (an addition). In the slot's frame the robot stands
    ``along`` m short of the slot along the slot's heading (negative: past it) and
    ``aside`` m to the left of the slot's line. While more than ``arrival_distance`` is left
    along, it turns (``turn_gain``) to the slot's heading tilted towards the line by
    ``approach_gain`` aside, at most ``approach_tilt``, and drives that way (forwards, or
    backwards where it is past the slot) at min(arrival_gain |along|, max_linear), scaled
    from all of it with its heading on that target to none ``approach_tilt`` or more off it
    (plus the force term, steering off what it drives past): it corrects its sideways error
    as it drives, and turns before it drives where it faces away (driving turned away, it
    left this law's reach and the posture law swung it round). Then it only turns to the
    heading (within ``heading_tolerance``) and stands: measured along the slot's heading,
    turning does not bring back what is left to drive. What it cannot close on the way is
    left sideways. The posture law (:func:`parking_step`) turned robots 0.1-0.2 m beside
    their slots 90-180 deg out and back, or a full circle under the realistic profile's lag
    (to_music's R4: 330 deg); closing along the robot's own heading instead, a robot turning
    onto the heading found some distance left along it again and shuffled to and fro for 10
    s."""
    c, s = math.cos(heading_error), math.sin(heading_error)
    along = ex * c + ey * s  # the slot's position from the robot, in the slot's frame
    aside = ex * s - ey * c
    if abs(along) > params.arrival_distance:
        direction = 1.0 if along > 0.0 else -1.0
        tilt = min(max(params.approach_gain * aside, -params.approach_tilt),
                   params.approach_tilt)
        target_error = heading_error - direction * tilt
        linear = direction * min(params.arrival_gain * abs(along), params.max_linear) * max(
            1.0 - abs(target_error) / params.approach_tilt, 0.0)
        angular = params.turn_gain * target_error
        if linear != 0.0:
            angular += direction * params.force_gain * fy
        return linear, angular
    angular = (params.turn_gain * heading_error
               if abs(heading_error) > params.heading_tolerance else 0.0)
    return 0.0, angular


def turn_onto_slot(params: TrackingParams, heading_error: float, bearing: float) -> float:
    """The turn (rad, summed both ways) of a robot ``heading_error`` rad from its slot's
    heading that turns ``bearing`` rad on the spot (to face the slot, or put its back to it)
    and then to the slot's heading, plus ``handover_turn`` where the first turn takes its
    heading within ``approach_heading`` of the slot's (:func:`approach_step` takes it there,
    short of the slot, and leaves what it cannot close sideways)."""
    start, end = heading_error, heading_error - bearing  # unwrapped: the turn is continuous
    low, high = min(start, end), max(start, end)
    if any(low < k + params.approach_heading and high > k - params.approach_heading
           for k in (-2.0 * math.pi, 0.0, 2.0 * math.pi)):
        return abs(bearing) + abs(wrap_angle(end)) + params.handover_turn
    return abs(bearing) + abs(wrap_angle(end))


def turn_then_drive_step(params: TrackingParams, ex: float, ey: float, heading_error: float,
                         fy: float) -> tuple[float, float]:
    """(linear m/s, angular rad/s) of a robot within ``approach_distance`` of its final
    slot, the slot (ex, ey) m ahead and to the left in ``base_link`` and ``heading_error``
    rad from its heading, where :func:`approach_step` does not take it (turned beyond
    ``approach_heading``): an addition. It turns on the
    spot (``turn_gain``) to face the slot, or to put its back to it, whichever
    :func:`turn_onto_slot` finds the smaller turn, and drives to it (forwards or in
    reverse, at min(arrival_gain distance, max_linear)) scaled from all of it facing the
    slot to none ``approach_tilt`` or more off (plus the force term, steering off what it
    drives past), until :func:`settle_step` turns it to the heading. The posture law
    (:func:`parking_step`) here swung a robot just past its slot and turned 107 deg from
    its heading round the long way (dense crowd seed 135, R4: 256 deg of turning as an
    ideal unicycle, 176 deg off at the run's limit under the realistic profile's lag)."""
    forwards = math.atan2(ey, ex)
    backwards = wrap_angle(forwards - math.pi)
    reverse = (turn_onto_slot(params, heading_error, backwards)
               < turn_onto_slot(params, heading_error, forwards))
    bearing = backwards if reverse else forwards
    direction = -1.0 if reverse else 1.0
    distance = math.sqrt(ex * ex + ey * ey)  # (as tracking_step's)
    linear = direction * min(params.arrival_gain * distance, params.max_linear) * max(
        1.0 - abs(bearing) / params.approach_tilt, 0.0)
    angular = params.turn_gain * bearing
    if linear != 0.0:
        angular += direction * params.force_gain * fy
    return linear, angular


def paused_step(params: TrackingParams, ex: float, ey: float, heading_error: float,
                fy: float, backwards: bool = False) -> tuple[float, float]:
    """The paused law (an addition): (linear m/s, angular rad/s) of a robot whose place stands
    because the formation's shared show clock stands, the place (ex, ey) m ahead and to the
    left in ``base_link``, ``heading_error`` rad from its heading, sideways force ``fy``.
    Kanayama's law with the robot's own closing speed for the reference's: it closes the
    distance along its heading to a place ahead of it (at ``arrival_gain`` per metre; behind
    it where the slot is driven in reverse, ``backwards``; never against the slot's way: a
    robot braking past its place stands, and the place comes to it when the show runs on)
    and turns gently to the place's heading (``heading_speed``), never towards a point
    beside it. Before, the drive onto the standing point turned robots at up to 2.2 rad/s
    for places 10-20 cm to their side whenever the clock stood a tick, and back when it ran:
    open-day crowd seed 1, R1 at t = 97-99 s, left and right at 5 Hz."""
    direction = -1.0 if backwards else 1.0
    linear = direction * min(params.arrival_gain * max(direction * ex, 0.0),
                             params.max_linear) * max(math.cos(heading_error), 0.0)
    angular = (linear * params.gain_y * ey
               + max(abs(linear), params.heading_speed) * params.gain_theta
               * math.sin(heading_error))
    if linear != 0.0:  # it steers away from what it drives past, as the moving law
        angular += direction * params.force_gain * fy
    return linear, angular


def shared_pose_references(pose: FloatArray, velocity: FloatArray, ages: FloatArray,
                           relative: FloatArray) -> FloatArray:
    """What robots that share their leader robot's pose track (the ``shared-pose`` formation
    control of the network experiment, ``shows.formation``): the leader's last pose heard
    (3,) (x, y, theta, any frame) moved on along its arc by the velocity it sent (2,) (v m/s,
    w rad/s) over each robot's age of the message ``ages`` (K,) s, then each robot's slot
    ``relative`` (K, 2) (m, in the leader's frame; the slots share its heading). The slot
    moves with (v - w dy, w dx) in the leader's frame (:func:`slot_velocities`); its
    reference faces that way, driven backwards where it moves backwards. Returns (K, 5) as
    :func:`references_from_motion`: x, y, heading, signed speed, angular speed (w)."""
    count = len(ages)
    v, w = float(velocity[0]), float(velocity[1])
    x, y, theta = integrate_unicycle(np.full(count, pose[0]), np.full(count, pose[1]),
                                     np.full(count, pose[2]), np.full(count, v),
                                     np.full(count, w), ages)
    c, s = np.cos(theta), np.sin(theta)
    dx, dy = relative[:, 0], relative[:, 1]
    along, across = v - w * dy, w * dx
    speed = np.hypot(along, across)
    direction = np.where(speed > 1e-9, np.arctan2(across, along), 0.0)
    backwards = along < 0.0
    heading = theta + np.where(backwards, direction - np.pi, direction)
    return np.column_stack([x + c * dx - s * dy, y + s * dx + c * dy, heading,
                            np.where(backwards, -speed, speed), np.full(count, w)])

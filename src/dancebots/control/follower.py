"""The follower controller of thesis ch. 4.3, eq. 4.4, as a pure function.

Frames: every position is in the robot's own ``map`` frame (x, y in m); the robot's pose is
(x, y, theta) in that frame. Commands are (linear m/s, angular rad/s) in ``base_link``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal, get_args

from dancebots.geometry import Pose

__all__ = ["ARRIVAL_GAIN", "FORCE_STEERINGS", "FollowerParams", "FollowerState", "ForceSteering",
           "thesis_follower_step"]


ARRIVAL_GAIN = 1.5
"""Speed per metre of remaining distance when arriving at a standing leader, 1/s (eq. 4.1a)."""


ForceSteering = Literal["thesis", "blend"]
"""How the virtual force steers (see :class:`FollowerParams`)."""
FORCE_STEERINGS: tuple[ForceSteering, ...] = get_args(ForceSteering)

@dataclass(frozen=True, slots=True)
class FollowerParams:
    """Parameters of the thesis follower (values from thesis ch. 4.3 unless noted).

    vmax: maximal speed of the slowest robot, m/s (the leader moves at 0.7 vmax).
    max_linear, max_angular: this robot's limits, m/s and rad/s; applied keeping the sign.
    queue_period: the queue of desired positions is filled at 10 Hz, s.
    pop_distance: the queue head is popped when nearer than this, m ("30 cm").
    far_factor: the queue is cleared when the leader is further than this times the desired
        distance ("double of the desired").
    arrival_distance: an addition to the thesis: while the leader stands still (a newVL
        hold, a join, the end of the show) eq. 4.4a as written would keep driving at
        0.7 vmax |1 + 3 (d_act - d_req)| and overshoot; instead the robot then aims at its
        desired position, at most ARRIVAL_GAIN * distance fast (the form of eq. 4.1a), and
        stops within this distance, m.
    force_steering: "thesis": eq. 4.4b's second term as written, with alpha2 = atan2(Fy, Fx);
        its sgn(Fx) flips for a force from beside the robot (a neighbour in a row), so it
        steers a robot into its neighbour half of the time (scenario 7.1: 2-4 collisions).
        "blend" (default, an addition): the force is added to the unit direction to the
        target and eq. 4.4b's first term steers along the sum, as a force field does
        (thesis ch. 1: "their sum then determines the desired heading").
    """

    vmax: float = 0.5
    max_linear: float = 0.5
    max_angular: float = math.pi
    queue_period: float = 0.1
    pop_distance: float = 0.30
    far_factor: float = 2.0
    arrival_distance: float = 0.10
    force_steering: ForceSteering = "blend"


@dataclass(frozen=True, slots=True)
class FollowerState:
    """The queue of desired positions (oldest first) and when it was last filled, s."""

    queue: tuple[tuple[float, float], ...] = ()
    last_fill: float = -math.inf


def _sign(value: float) -> float:
    return 1.0 if value > 0 else -1.0 if value < 0 else 0.0


def _clip_keep_sign(value: float, limit: float) -> float:
    return math.copysign(min(abs(value), limit), value)


def thesis_follower_step(
    params: FollowerParams,
    state: FollowerState,
    now: float,
    pose: tuple[float, float, float],
    leader: tuple[float, float],
    path_point: tuple[float, float],
    desired: tuple[float, float],
    required_distance: float,
    leader_moving: bool,
    force: tuple[float, float] = (0.0, 0.0),
) -> tuple[FollowerState, tuple[float, float]]:
    """One control tick of thesis eq. 4.4. Returns the new state and (linear, angular).

    pose: the robot (x, y, theta); leader: the virtual leader's position; path_point: the
    leader's position shifted sideways by the robot's lateral offset; desired: the robot's
    desired position (leader pose + offset); all in the robot's map frame. required_distance:
    d_req, the desired distance to the leader, m. force: the virtual repulsive force (Fx, Fy)
    in ``base_link`` (zero until obstacle avoidance adds it).

        linear  = sgn(Gx) * 0.7 vmax * |1 + 3 (d_act - d_req)|            (4.4a)
        angular = 3 sgn(Gx Gy) alpha - 2 sgn(Fx) alpha2 |F|               (4.4b)

    The queue holds the leader's positions shifted by the robot's lateral offset, one every
    0.1 s: so the robot drives the leader's path at its lateral distance, and eq. 4.4a keeps
    its distance to the leader, which lets the formation stretch and shrink lengthwise in
    turns while it keeps its lateral distances (thesis ch. 4.1, 4.3). Queuing the rigid
    desired positions instead makes the rear robots of a turning formation swing sideways
    through loops. G is the target in ``base_link``: the queue head, or the current shifted
    leader position ("following the virtual leader directly") when the queue is empty or the
    leader is further than twice d_req (the queue is then cleared). alpha is the smallest
    angle between the x axis and the line to G (alpha or pi - alpha, so a target behind is
    reached by reversing); alpha2 is the direction of F, atan2(Fy, Fx): a point ahead on the
    left pushes back and to the right (alpha2 near -pi, Fx < 0), and the term turns the robot
    right.
    """
    x, y, theta = pose
    queue = state.queue
    last_fill = state.last_fill
    if now - last_fill >= params.queue_period - 1e-9:  # filled at 10 Hz
        queue = (*queue, path_point)
        last_fill = now
    d_act = math.hypot(leader[0] - x, leader[1] - y)
    speed_limit = math.inf
    if not leader_moving:  # arrival (an addition, see FollowerParams.arrival_distance)
        gap = math.hypot(desired[0] - x, desired[1] - y)
        if gap <= params.arrival_distance:
            return FollowerState((), last_fill), (0.0, 0.0)
        queue = ()
        target = desired
        speed_limit = ARRIVAL_GAIN * gap
    elif d_act > params.far_factor * required_distance:
        queue = ()
        target = path_point
    else:
        # "If the robot is closer to the queue head than 30 cm, new point is popped": popped
        # until the head is 30 cm away. One pop per tick lets a robot faster than the leader
        # close in on the head, where its angle is noise (thesis 7.2.2) and the robot spins.
        while queue and math.hypot(queue[0][0] - x, queue[0][1] - y) < params.pop_distance:
            queue = queue[1:]
        target = queue[0] if queue else path_point
    gx, gy = Pose(x, y, theta).to_local(target[0], target[1])  # the target in the robot frame
    linear = _sign(gx) * min(0.7 * params.vmax * abs(1.0 + 3.0 * (d_act - required_distance)),
                             speed_limit)
    fx, fy = force
    magnitude = math.hypot(fx, fy)
    if params.force_steering == "blend" and magnitude > 0:
        # an addition: the force bends the direction to the target, G/|G| + F, and eq. 4.4b's
        # first term steers along the result
        norm = math.hypot(gx, gy) or 1.0
        gx, gy = gx / norm + fx, gy / norm + fy
        if _sign(gx) != _sign(linear) and linear != 0.0:  # never turn a push into a reversal
            gx = math.copysign(1e-6, linear)
        magnitude = 0.0
    alpha = math.atan2(abs(gy), abs(gx))  # smallest angle to the line through G
    alpha2 = math.atan2(fy, fx) if magnitude > 0 else 0.0  # the force's direction
    angular = 3.0 * _sign(gx * gy) * alpha - 2.0 * _sign(fx) * alpha2 * magnitude
    command = (_clip_keep_sign(linear, params.max_linear),
               _clip_keep_sign(angular, params.max_angular))
    return FollowerState(queue, last_fill), command

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
leader's frame, with velocity (v - w oy, w ox). Its heading is the leader's turned by the
angle of that velocity folded to [-90, 90] deg (a slot moving backwards keeps facing
forwards and drives in reverse), its speed that velocity's length signed by the direction,
its angular speed the leader's.

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
from dancebots.geometry import Pose, compose_poses, wrap_angle
from dancebots.plan.planner import slot_velocities

__all__ = ["SlotReference", "TrackingParams", "slot_reference", "slot_references",
           "tracking_step"]

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
    arrival_gain: speed per metre of remaining distance when arriving at a standing slot, 1/s
        (the thesis follower's arrival, eq. 4.1a's form).
    turn_gain: angular speed per radian of heading error when turning on the spot at rest,
        1/s.
    reverse_distance: at rest, a slot behind the robot nearer than this is reached in
        reverse (a short step back) rather than by turning round, m.
    force_gain: angular speed per unit of the virtual force's sideways component, rad/s.
    heading_speed: v0, the least speed (m/s) the heading term counts with, so that a robot
        whose slot momentarily stands (the cusp of a tight turn) still turns to its heading.
    """

    gain_x: float = 1.5
    gain_y: float = 10.0
    gain_theta: float = 4.4
    max_linear: float = 0.5
    max_angular: float = math.pi
    arrival_distance: float = 0.03
    heading_tolerance: float = math.radians(2.0)
    arrival_gain: float = ARRIVAL_GAIN
    turn_gain: float = 1.5
    reverse_distance: float = 1.0
    force_gain: float = 1.0
    heading_speed: float = 0.1


@dataclass(frozen=True, slots=True)
class SlotReference:
    """Where a robot's slot is and how it moves: pose (x, y, theta) in the robot's map frame,
    signed speed along its heading, m/s, and angular speed, rad/s."""

    pose: tuple[float, float, float]
    speed: float
    angular_speed: float

    @property
    def moving(self) -> bool:
        """True when the slot moves or turns."""
        return abs(self.speed) > 1e-9 or abs(self.angular_speed) > 1e-9


def slot_references(leaders: FloatArray, offsets: FloatArray,
                    leader_commands: FloatArray) -> FloatArray:
    """The references of slots at ``offsets`` (T, 2) (ox, oy, m, in the leader's frame) of
    leaders at poses ``leaders`` (T, 3) (x, y, theta) moving with ``leader_commands`` (T, 2)
    (v m/s, w rad/s). Returns (T, 5): the slot's pose x, y, theta, its signed speed and its
    angular speed (a compact :class:`SlotReference` per row)."""
    velocity = slot_velocities(leader_commands, offsets)  # in the leader's frame
    along, across = velocity[:, 0], velocity[:, 1]
    w = leader_commands[:, 1]
    forwards = along >= 0.0
    turn = np.where(forwards, np.arctan2(across, along), np.arctan2(-across, -along))
    speed = np.where(along != 0.0, np.copysign(np.hypot(along, across), along),
                     np.abs(across))
    slots = compose_poses(leaders, np.column_stack([offsets, turn]))
    return np.column_stack([slots, speed, w])


def slot_reference(leader: tuple[float, float, float], offset: tuple[float, float],
                   leader_command: tuple[float, float]) -> SlotReference:
    """One slot's reference (:func:`slot_references` for a single leader pose)."""
    row = slot_references(np.array([leader], dtype=float), np.array([offset], dtype=float),
                          np.array([leader_command], dtype=float))[0]
    return SlotReference((float(row[0]), float(row[1]), float(row[2])), float(row[3]),
                         float(row[4]))


def _saturate(linear: float, angular: float, params: TrackingParams) -> tuple[float, float]:
    """Scale (v, w) by one factor so that both are within the limits (same curvature)."""
    scale = 1.0
    if abs(linear) > params.max_linear:
        scale = params.max_linear / abs(linear)
    if abs(angular) * scale > params.max_angular:
        scale = params.max_angular / abs(angular)
    return linear * scale, angular * scale


def tracking_step(params: TrackingParams, pose: tuple[float, float, float],
                  reference: SlotReference,
                  force: tuple[float, float] = (0.0, 0.0)) -> tuple[float, float]:
    """One control tick: the robot at ``pose`` (x, y, theta, own map frame) tracks
    ``reference``; ``force`` is the virtual repulsive force (Fx, Fy) in ``base_link``.
    Returns (linear m/s, angular rad/s), within the limits.

    While the slot moves: Kanayama's law above, plus a turn away from obstacles
    (``force_gain * Fy``, in the direction of travel). While it stands: drive to it (forwards,
    or backwards when it is less than ``reverse_distance`` behind), then turn to its heading.
    """
    ex, ey = Pose(*pose).to_local(reference.pose[0], reference.pose[1])
    heading_error = wrap_angle(reference.pose[2] - pose[2])
    fy = force[1]
    if reference.moving:
        vr, wr = reference.speed, reference.angular_speed
        linear = vr * math.cos(heading_error) + params.gain_x * ex
        angular = (wr + vr * params.gain_y * ey
                   + max(abs(vr), params.heading_speed) * params.gain_theta
                   * math.sin(heading_error))
        direction = 1.0 if linear >= 0.0 else -1.0
        angular += direction * params.force_gain * fy
        return _saturate(linear, angular, params)
    distance = math.hypot(ex, ey)
    if distance > params.arrival_distance:
        backwards = ex < 0.0 and distance < params.reverse_distance
        bearing = math.atan2(-ey, -ex) if backwards else math.atan2(ey, ex)
        speed = min(params.arrival_gain * distance, params.max_linear) * max(
            math.cos(bearing), 0.0)  # turn towards the slot first, then drive
        linear = -speed if backwards else speed
        angular = params.turn_gain * bearing + (-1.0 if backwards else 1.0) * (
            params.force_gain * fy)
        return _saturate(linear, angular, params)
    if abs(heading_error) > params.heading_tolerance:
        return _saturate(0.0, params.turn_gain * heading_error, params)
    return 0.0, 0.0

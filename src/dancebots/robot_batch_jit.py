"""Every robot's brain tick in one numba-compiled pass (``robot_batch.BatchBrains`` calls it).

The same decisions as :meth:`dancebots.robot.RobotBrain.step` for the ``tracking`` and
``path`` followers with the ``fixed`` or ``predicted`` stop rule and the ``compensated``
detector (the defaults), written as loops over robots on arrays of state, so that a
formation of 20 robots costs one call a tick instead of twenty brains' worth of Python.
``RobotBrain`` remains the readable reference: ``tests/test_robot_batch.py`` runs shows
through both and holds them equal. Each function names the method of ``RobotBrain`` (or the
module function) it mirrors, and keeps its arithmetic in the same order, so that the two
agree to the last bit wherever they use the same libm functions.

Shapes: R robots, M mates per robot (R - 1), K latest-cloud columns of all robots together,
H own poses of history (``robot.HISTORY_LENGTH`` + 1).
"""

from __future__ import annotations

import math
import sys

import numpy as np
from numba import njit
from numpy.typing import NDArray

from dancebots.jit_cache import drop_stale
from dancebots.perception import fast, tracks_jit
from dancebots.perception.fast import (
    far_from_all,
    kept_columns,
    perceive_columns,
    perceive_columns_split,
    to_local,
    turn_fraction_columns,
    turn_fraction_local,
    turn_shares,
)
from dancebots.perception.tracks_jit import STANDING, TRACKED, track_cloud

__all__ = ["EVENT_BEEP", "EVENT_ERROR_LIDAR", "EVENT_ERROR_POSE", "EVENT_NONE",
           "EVENT_RESUME", "EVENT_SPEECH", "brains_tick", "grid_lookups", "tick_outputs"]

FloatArray = NDArray[np.float64]

EVENT_NONE, EVENT_SPEECH, EVENT_BEEP, EVENT_RESUME, EVENT_ERROR_POSE, EVENT_ERROR_LIDAR = range(6)
"""Codes of the one event a robot may voice at a tick (``safety.monitor.safety_step``)."""

# indices of the tracking parameters (``control.tracking.TrackingParams``) in ``gains``
(GAIN_X, GAIN_Y, GAIN_THETA, ARRIVAL_DISTANCE, SETTLE_DISTANCE, HEADING_TOLERANCE,
 ARRIVAL_GAIN, TURN_GAIN, REVERSE_DISTANCE, FORCE_GAIN_STEER, HEADING_SPEED, PARK_ALPHA,
 PARK_THETA, WAIT_SPEED, APPROACH_DISTANCE, APPROACH_HEADING, TILT_GAIN,
 APPROACH_TILT, HANDOVER_TURN, PARKING_TURN_RATE, FACE_DISTANCE) = range(21)
# indices of the detection parameters (``perception.obstacles.DetectorParams``) in ``detect``
(CROP_HALF, Z_MIN, Z_MAX, STOP_DISTANCE, CORRIDOR_MARGIN, TURN_MARGIN, TURN_HORIZON,
 TURN_SHARE) = range(8)
# indices of the brain's constants (``robot`` module) in ``rules``
(FORCE_RADIUS, FORCE_GAIN, APPROACH_GAIN, MATE_GAP, OVERLAP, HOLD_LAG, SLOWED, GIVE_WAY_SPEED,
 PARKED_GAP, MAKE_ROOM_SPEED, MAKE_ROOM_FLOOR, NEAR_GAP, CORNER_SPEED, AFTER_SHOW_WAIT,
 SLOW_TURN_LAG, SENSOR_TIMEOUT, MAX_LOOKUP_FAILURES, BEEP_PERIOD, ADVANCE_MIN, LIDAR,
 PLAN_DURATION, REST_FROM, PREDICTED, SSM_REACH, PREDICTED_STOP_TIME, PACED,
 PACE_MARGIN, PACE_MIN, PAUSE_STILL, PAUSE_STILL_AFTER, FINAL_NO_ROOM,
 SSM_DECELERATION) = range(32)
# indices of the tracker's parameters (``perception.tracks.TrackParams``) in ``track_params``
(CLUSTER_GAP, MAX_WIDTH, GATE, MIN_HITS, MAX_MISSES, ACCELERATION_NOISE,
 MEASUREMENT_NOISE) = range(7)
MAKE_ROOM_SHIFTS = (0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.6)
"""``robot.MAKE_ROOM_SHIFTS`` (a test holds them equal)."""


@njit(cache=True)
def _wrap(angle: float) -> float:
    """``geometry.wrap_angle``: rad -> (-pi, pi], from the exact ``fmod`` (the IEEE remainder
    ``math.remainder`` that numba lacks, but for angles exactly an odd multiple of pi)."""
    tau = 2.0 * math.pi
    wrapped = np.fmod(angle, tau)
    if wrapped > math.pi:
        wrapped -= tau
    elif wrapped < -math.pi:
        wrapped += tau
    return math.pi if wrapped == -math.pi else wrapped


@njit(cache=True)
def _saturate(linear: float, angular: float, max_linear: float,
              max_angular: float) -> tuple[float, float]:
    """``control.tracking._saturate``."""
    scale = 1.0
    if abs(linear) > max_linear:
        scale = max_linear / abs(linear)
    if abs(angular) * scale > max_angular:
        scale = max_angular / abs(angular)
    return linear * scale, angular * scale


@njit(cache=True)
def _settle(gains: FloatArray, ex: float, heading_error: float) -> tuple[float, float]:
    """``control.tracking.settle_step``."""
    linear = (gains[ARRIVAL_GAIN] * ex * max(math.cos(heading_error), 0.0)
              if abs(ex) > gains[ARRIVAL_DISTANCE] else 0.0)
    angular = (gains[TURN_GAIN] * heading_error
               if abs(heading_error) > gains[HEADING_TOLERANCE] else 0.0)
    return linear, angular


@njit(cache=True)
def _parking(gains: FloatArray, distance: float, bearing: float, heading_error: float,
             backwards: bool) -> tuple[float, float]:
    """``control.tracking.parking_step``."""
    alpha = _wrap(bearing - math.pi) if backwards else bearing
    theta = _wrap(alpha - heading_error)
    gain = gains[ARRIVAL_GAIN]
    ratio = math.sin(alpha) / alpha if abs(alpha) > 1e-9 else 1.0
    linear = gain * distance * math.cos(alpha)
    angular = (gains[PARK_ALPHA] * alpha
               + gain * math.cos(alpha) * ratio * (alpha + gains[PARK_THETA] * theta))
    return (-linear if backwards else linear), angular


@njit(cache=True)
def _turn_onto_slot(gains: FloatArray, heading_error: float, bearing: float) -> float:
    """``control.tracking.turn_onto_slot``."""
    start, end = heading_error, heading_error - bearing
    low, high = min(start, end), max(start, end)
    turn: float = abs(bearing) + abs(_wrap(end))
    for k in (-2.0 * math.pi, 0.0, 2.0 * math.pi):
        if low < k + gains[APPROACH_HEADING] and high > k - gains[APPROACH_HEADING]:
            return turn + float(gains[HANDOVER_TURN])
    return turn


@njit(cache=True)
def _paused(gains: FloatArray, max_linear: float, ex: float, ey: float, heading_error: float,
            fy: float, backwards: bool) -> tuple[float, float]:
    """``control.tracking.paused_step`` (unsaturated)."""
    direction = -1.0 if backwards else 1.0
    linear = direction * min(gains[ARRIVAL_GAIN] * max(direction * ex, 0.0),
                             max_linear) * max(math.cos(heading_error), 0.0)
    angular = (linear * gains[GAIN_Y] * ey
               + max(abs(linear), gains[HEADING_SPEED]) * gains[GAIN_THETA]
               * math.sin(heading_error))
    if linear != 0.0:
        angular += direction * gains[FORCE_GAIN_STEER] * fy
    return linear, angular


@njit(cache=True)
def _tracking(gains: FloatArray, max_linear: float, max_angular: float, px: float, py: float,
              ptheta: float, rx: float, ry: float, rtheta: float, speed: float,
              angular_speed: float, final: bool, fy: float, paused: bool,
              backwards: bool, settling: bool) -> tuple[float, float]:
    """``control.tracking.tracking_step`` of the robot at (px, py, ptheta) tracking the
    reference (rx, ry, rtheta, speed, angular_speed, final, paused, backwards), sideways
    force ``fy``, settling on its final slot where ``settling``."""
    dx, dy = rx - px, ry - py  # ``Pose.to_local``
    c, s = math.cos(ptheta), math.sin(ptheta)
    ex, ey = c * dx + s * dy, -s * dx + c * dy
    heading_error = _wrap(rtheta - ptheta)
    if abs(speed) > 1e-9 or abs(angular_speed) > 1e-9:  # ``SlotReference.moving``
        vr, wr = speed, angular_speed
        linear = vr * math.cos(heading_error) + gains[GAIN_X] * ex
        if linear * vr < 0.0 and abs(vr) >= gains[WAIT_SPEED]:
            return _saturate(0.0, gains[TURN_GAIN] * heading_error, max_linear, max_angular)
        if abs(vr) <= gains[ARRIVAL_DISTANCE] * abs(wr):  # ``control.tracking.turn_share``
            span = gains[SETTLE_DISTANCE] - gains[ARRIVAL_DISTANCE]
            if span <= 0.0:
                wr = wr if ex <= gains[ARRIVAL_DISTANCE] else 0.0
            else:
                wr *= min(max(1.0 - (ex - gains[ARRIVAL_DISTANCE]) / span, 0.0), 1.0)
        angular = (wr + vr * gains[GAIN_Y] * ey
                   + max(abs(vr), gains[HEADING_SPEED]) * gains[GAIN_THETA]
                   * math.sin(heading_error))
        direction = 1.0 if linear >= 0.0 else -1.0
        angular += direction * gains[FORCE_GAIN_STEER] * fy
        return _saturate(linear, angular, max_linear, max_angular)
    if paused and not final:  # ``control.tracking.paused_step``
        linear, angular = _paused(gains, max_linear, ex, ey, heading_error, fy, backwards)
        return _saturate(linear, angular, max_linear, max_angular)
    distance = math.sqrt(ex * ex + ey * ey)  # (``math.hypot`` rounds otherwise in numba)
    backwards = ex < 0.0 and distance < gains[REVERSE_DISTANCE]
    push = (-1.0 if backwards else 1.0) * gains[FORCE_GAIN_STEER] * fy
    if distance > gains[SETTLE_DISTANCE] and not final:
        bearing = math.atan2(-ey, -ex) if backwards else math.atan2(ey, ex)
        drive = min(gains[ARRIVAL_GAIN] * distance, max_linear) * max(math.cos(bearing), 0.0)
        return _saturate(-drive if backwards else drive, gains[TURN_GAIN] * bearing + push,
                         max_linear, max_angular)
    # ``TrackingParams.parking_turn_rate`` onto its final slot
    top = min(max_angular, gains[PARKING_TURN_RATE]) if final else max_angular
    if gains[ARRIVAL_DISTANCE] < distance <= gains[SETTLE_DISTANCE]:
        settle_linear, settle_angular = _settle(gains, ex, heading_error)
        return _saturate(settle_linear, settle_angular, max_linear, top)
    if gains[ARRIVAL_DISTANCE] < distance <= gains[APPROACH_DISTANCE]:
        c_error, s_error = math.cos(heading_error), math.sin(heading_error)
        if c_error > math.cos(gains[APPROACH_HEADING]):
            # ``control.tracking.approach_step``
            along = ex * c_error + ey * s_error
            aside = ex * s_error - ey * c_error
            if abs(along) > gains[ARRIVAL_DISTANCE]:
                direction = 1.0 if along > 0.0 else -1.0
                tilt = min(max(gains[TILT_GAIN] * aside, -gains[APPROACH_TILT]),
                           gains[APPROACH_TILT])
                target_error = heading_error - direction * tilt
                linear = direction * min(gains[ARRIVAL_GAIN] * abs(along), max_linear) * max(
                    1.0 - abs(target_error) / gains[APPROACH_TILT], 0.0)
                angular = gains[TURN_GAIN] * target_error
                if linear != 0.0:
                    angular += direction * gains[FORCE_GAIN_STEER] * fy
                return _saturate(linear, angular, max_linear, top)
            if abs(heading_error) > gains[HEADING_TOLERANCE]:
                return _saturate(0.0, gains[TURN_GAIN] * heading_error, max_linear,
                                 top)
            return 0.0, 0.0
        if settling and distance <= gains[FACE_DISTANCE]:  # it goes on settling
            settle_linear, settle_angular = _settle(gains, ex, heading_error)
            return _saturate(settle_linear, settle_angular, max_linear, top)
        # ``control.tracking.turn_then_drive_step``
        forwards = math.atan2(ey, ex)
        back = _wrap(forwards - math.pi)
        reverse = (_turn_onto_slot(gains, heading_error, back)
                   < _turn_onto_slot(gains, heading_error, forwards))
        bearing = back if reverse else forwards
        direction = -1.0 if reverse else 1.0
        linear = direction * min(gains[ARRIVAL_GAIN] * distance, max_linear) * max(
            1.0 - abs(bearing) / gains[APPROACH_TILT], 0.0)
        angular = gains[TURN_GAIN] * bearing
        if linear != 0.0:
            angular += direction * gains[FORCE_GAIN_STEER] * fy
        if linear == 0.0 and distance <= gains[FACE_DISTANCE]:  # it settles there
            linear, angular = _settle(gains, ex, heading_error)
        return _saturate(linear, angular, max_linear, top)
    if distance > gains[ARRIVAL_DISTANCE]:
        linear, angular = _parking(gains, distance, math.atan2(ey, ex), heading_error,
                                   backwards)
        return _saturate(linear, angular + push, max_linear, max_angular)
    if abs(heading_error) > gains[HEADING_TOLERANCE]:
        return _saturate(0.0, gains[TURN_GAIN] * heading_error, max_linear, top)
    return 0.0, 0.0


@njit(cache=True)
def _settling_on_slot(gains: FloatArray, px: float, py: float, ptheta: float, rx: float,
                      ry: float, speed: float, angular_speed: float, final: bool,
                      settling: bool) -> bool:
    """``control.tracking.settling_on_slot`` of the robot at (px, py, ptheta) whose
    reference is (rx, ry, speed, angular_speed, final), ``settling`` at the tick before."""
    if not final or abs(speed) > 1e-9 or abs(angular_speed) > 1e-9:
        return False
    dx, dy = rx - px, ry - py  # ``Pose.to_local``
    c, s = math.cos(ptheta), math.sin(ptheta)
    ex, ey = c * dx + s * dy, -s * dx + c * dy
    distance = math.sqrt(ex * ex + ey * ey)
    if distance <= gains[SETTLE_DISTANCE]:
        return True
    return settling and distance <= gains[FACE_DISTANCE]


@njit(cache=True)
def _heard_in_own_frame(heard: FloatArray, robot: int, count: int, cos_sin: FloatArray,
                        own_frame: FloatArray) -> FloatArray:
    """(count, 2) where robot ``robot``'s mates said they are (``heard`` (R, 2), show frame,
    NaN: not heard; ``count`` of them heard), in its own frame (its show frame's pose
    ``own_frame`` (3,), with its cos and sin ``cos_sin`` (2,)): ``compose_points``."""
    result = np.empty((count, 2))
    c, s = cos_sin[0], cos_sin[1]
    k = 0
    for j in range(heard.shape[0]):
        if j != robot and math.isfinite(heard[j, 0]) and math.isfinite(heard[j, 1]):
            result[k, 0] = own_frame[0] + c * heard[j, 0] - s * heard[j, 1]
            result[k, 1] = own_frame[1] + s * heard[j, 0] + c * heard[j, 1]
            k += 1
    return result


@njit(cache=True)
def _mate_centres(places: FloatArray, heard: FloatArray, robot: int, count: int,
                  cos_sin: FloatArray, own_frame: FloatArray) -> FloatArray:
    """``RobotBrain._mate_centres``: (M + count, 2) where robot ``robot``'s mates should be
    (``places`` (M, 2), own frame) and where the ``count`` heard said they are
    (:func:`_heard_in_own_frame`)."""
    where = np.empty((places.shape[0] + count, 2))
    where[:places.shape[0]] = places
    if count > 0:
        where[places.shape[0]:] = _heard_in_own_frame(heard, robot, count, cos_sin, own_frame)
    return where


@njit(cache=True)
def _approach_limit(rules: FloatArray, stop: float, free: float, strangers_free: float,
                    has_strangers: bool, reference_speed: float, parked: bool) -> float:
    """``RobotBrain._approach_limit`` (``has_strangers`` False: ``strangers_free`` None)."""
    gain = float(rules[APPROACH_GAIN])
    limit = gain * max(free - stop, 0.0)
    if parked and has_strangers:
        return gain * max(min(free - float(rules[PARKED_GAP]), strangers_free - stop), 0.0)
    if not has_strangers or free <= stop + rules[MATE_GAP]:
        return limit
    cruise = reference_speed + gain * (free - stop - float(rules[MATE_GAP]))
    return max(limit, min(cruise, gain * max(strangers_free - stop, 0.0)))


@njit(cache=True)
def _turn_reach(length: float, width: float, linear: float, detect: FloatArray,
                share: float) -> float:
    """``perception.obstacles.turn_reach``."""
    half_l, half_w = 0.5 * length, 0.5 * width
    sweep = math.hypot(half_l, half_w) - min(half_l, half_w) + abs(linear) * detect[TURN_HORIZON]
    return float(detect[TURN_MARGIN] + sweep / share)


@njit(cache=True)
def _crop_points(columns: FloatArray, height_step: float, detect: FloatArray) -> FloatArray:
    """``perception.obstacles.obstacle_points_from_columns``: the obstacle points (N, 2) of
    the columns, in their frame."""
    keep = kept_columns(columns, height_step, detect[CROP_HALF], detect[Z_MIN],
                        detect[Z_MAX])
    return columns[keep, :2].copy()


@njit(cache=True)
def _points_now(columns: FloatArray, height_step: float, detect: FloatArray,
                seen_from: FloatArray, pose: FloatArray) -> FloatArray:
    """``perception.obstacles.obstacle_points_now``: the obstacle points (N, 2) of the
    columns (``base_link`` at ``seen_from``) in ``base_link`` at ``pose``."""
    points = _crop_points(columns, height_step, detect)
    if (seen_from[0] == pose[0] and seen_from[1] == pose[1]
            and seen_from[2] == pose[2]):
        return points
    c0, s0 = math.cos(seen_from[2]), math.sin(seen_from[2])
    c1, s1 = math.cos(pose[2]), math.sin(pose[2])
    for i in range(points.shape[0]):  # ``compensate_motion``
        wx = seen_from[0] + c0 * points[i, 0] - s0 * points[i, 1]
        wy = seen_from[1] + s0 * points[i, 0] + c0 * points[i, 1]
        dx, dy = wx - pose[0], wy - pose[1]
        points[i, 0] = c1 * dx + s1 * dy
        points[i, 1] = -s1 * dx + c1 * dy
    return points


@njit(cache=True)
def _make_room(columns: FloatArray, height_step: float, detect: FloatArray,
               seen_from: FloatArray, pose: FloatArray, length: float, width: float,
               angular: float, previous: float, rules: FloatArray, mates: FloatArray,
               mate_radius: float) -> float:
    """``RobotBrain._make_room`` (``mates`` (J, 2): the mates' centres, ``base_link`` at
    ``seen_from``)."""
    shares = turn_shares(_crop_points(columns, height_step, detect), mates, mate_radius,
                         detect[TURN_SHARE])  # ``RobotBrain._turn_points``
    points = _points_now(columns, height_step, detect, seen_from, pose)
    half_l = 0.5 * length
    front, rear = math.inf, math.inf  # ``clear_distances``
    for i in range(points.shape[0]):
        if abs(points[i, 1]) <= 0.5 * width + detect[CORRIDOR_MARGIN]:
            if points[i, 0] >= half_l - 1e-9:
                front = min(front, points[i, 0] - half_l)
            if points[i, 0] <= -half_l + 1e-9:
                rear = min(rear, -points[i, 0] - half_l)
    moved = np.empty_like(points)
    for attempt in range(3):
        if attempt == 0:
            if previous == 0.0:
                continue
            direction = previous
        else:
            direction = 1.0 if attempt == 1 else -1.0
        free = front if direction > 0.0 else rear
        for shift in MAKE_ROOM_SHIFTS:
            if shift + detect[STOP_DISTANCE] + rules[MATE_GAP] > free:
                break
            for i in range(points.shape[0]):
                moved[i, 0] = points[i, 0] - direction * shift
                moved[i, 1] = points[i, 1]
            if turn_fraction_local(moved, length, width, 0.0, angular, detect[TURN_MARGIN],
                                   detect[TURN_HORIZON], shares, False) > 0.0:
                return direction
    return 0.0


@njit(cache=True)
def _guard_turn(columns: FloatArray, height_step: float, detect: FloatArray,
                seen_from: FloatArray, pose: FloatArray, length: float, width: float,
                linear: float, angular: float, may_make_room: bool, making_room: float,
                rules: FloatArray, mates: FloatArray, mate_radius: float,
                ) -> tuple[float, float, float]:
    """``RobotBrain._guard_turn`` (``may_make_room`` False: ``making_room`` None; ``mates``
    (J, 2): the mates' centres, ``base_link`` at ``seen_from``)."""
    fraction = turn_fraction_columns(
        columns, height_step, detect[CROP_HALF], detect[Z_MIN], detect[Z_MAX], seen_from,
        pose, length, width, linear, angular, detect[TURN_MARGIN], detect[TURN_HORIZON],
        detect[TURN_SHARE], mates, mate_radius, False)
    if fraction == 0.0 and may_make_room and (
            abs(linear) < rules[GIVE_WAY_SPEED] or making_room != 0.0):
        room = _make_room(columns, height_step, detect, seen_from, pose, length, width,
                          angular, making_room, rules, mates, mate_radius)
        if room != 0.0:
            return room * rules[MAKE_ROOM_SPEED], 0.0, room
    if fraction == 0.0 and turn_fraction_columns(
            columns, height_step, detect[CROP_HALF], detect[Z_MIN], detect[Z_MAX], seen_from,
            pose, length, width, linear, angular, detect[TURN_MARGIN], detect[TURN_HORIZON],
            detect[TURN_SHARE], mates, mate_radius, True) == 0.0:
        linear = math.copysign(min(abs(linear), rules[GIVE_WAY_SPEED]), linear)
    return linear, fraction * angular, 0.0


@njit(cache=True)
def _pose_at(history: FloatArray, size: int, stamp: float) -> int:
    """``RobotBrain._pose_at``: the index in ``history`` (H, 4) = (t, x, y, theta), its
    first ``size`` rows in time order, of the record nearest to ``stamp`` (the earlier of two
    equally near); -1 without history."""
    if size == 0:
        return -1
    if math.isnan(stamp):
        return 0  # ``bisect_left`` compares nothing with NaN: the oldest record
    after = size  # ``bisect_left`` on the times
    for k in range(size):
        if history[k, 0] >= stamp:
            after = k
            break
    if after == size or (after > 0 and stamp - history[after - 1, 0]
                         <= history[after, 0] - stamp):
        after -= 1
    return after


@njit(cache=True)
def _any_tracked(kind: NDArray[np.int8]) -> bool:
    """Whether any point is of a tracked object (else ``_predicted_gaps`` finds none)."""
    return bool(np.any(kind == TRACKED))


@njit(cache=True)
def _predicted_gaps(points: FloatArray, velocity: FloatArray, kind: NDArray[np.int8],
                    pose: FloatArray, age: float, length: float,
                    width: float, detect: FloatArray, mates: FloatArray,
                    heard: FloatArray, use_heard: bool, robot: int,
                    frame_cos_sin: FloatArray, own_frame: FloatArray,
                    mate_radius: float, stop_time: float) -> tuple[float, float, float]:
    """``RobotBrain._predicted_gaps`` on the points (N, 2) of the latest cloud in
    ``base_link`` at ``pose`` now (the tracker's kinds (N,) and velocities (N, 2), own map
    frame; none when their counts differ: tracks of an older cloud): the tracked
    strangers' points moved on for ``age`` s and for ``age`` + ``stop_time`` s, and how far
    (m) the nearest is ahead and behind in the corridor and from the footprint (inf: none);
    strangers are more than
    ``mate_radius`` from every mate's place ``mates`` (M, 2) and, where ``use_heard``, from
    where each other robot said it is (``heard`` (R, 2) show frame, with this robot's
    frame)."""
    front, rear, nearest = math.inf, math.inf, math.inf
    if points.shape[0] != kind.shape[0] or points.shape[0] == 0:
        return front, rear, nearest  # the tracks of an older cloud
    c, s = math.cos(pose[2]), math.sin(pose[2])
    mc, ms = frame_cos_sin[0], frame_cos_sin[1]
    half_l, half_w = 0.5 * length, 0.5 * width
    for i in range(points.shape[0]):
        if kind[i] != TRACKED:
            continue
        px, py = points[i, 0], points[i, 1]
        near = False
        for j in range(mates.shape[0] + (heard.shape[0] if use_heard else 0)):
            if j < mates.shape[0]:
                wx, wy = mates[j, 0], mates[j, 1]
            else:
                k = j - mates.shape[0]
                if k == robot or not (math.isfinite(heard[k, 0])
                                      and math.isfinite(heard[k, 1])):
                    continue
                wx = own_frame[0] + mc * heard[k, 0] - ms * heard[k, 1]
                wy = own_frame[1] + ms * heard[k, 0] + mc * heard[k, 1]
            dx, dy = wx - pose[0], wy - pose[1]  # ``points_to_local``
            lx, ly = c * dx + s * dy, -s * dx + c * dy
            ex, ey = px - lx, py - ly
            if (abs(ex) > mate_radius or abs(ey) > mate_radius) and ex == ex and ey == ey:
                continue  # far on an axis: far (NaN: near)
            if not math.hypot(ex, ey) > mate_radius:
                near = True
                break
        if near:
            continue
        # ``predicted_points``: moved on at its velocity, in ``base_link``, for the data's
        # age and for that and the robot's stopping time
        vx, vy = velocity[i, 0], velocity[i, 1]
        for span in (max(age, 0.0), max(age + stop_time, 0.0)):
            x = px + (vx * c + vy * s) * span
            y = py + (vx * -s + vy * c) * span
            if abs(y) <= 0.5 * width + detect[CORRIDOR_MARGIN]:  # ``clear_distances``
                if x >= half_l - 1e-9:
                    front = min(front, x - half_l)
                if x <= -half_l + 1e-9:
                    rear = min(rear, -x - half_l)
            # ``footprint_clearance``
            nearest = min(nearest, math.hypot(max(abs(x) - half_l, 0.0),
                                              max(abs(y) - half_w, 0.0)))
    return front, rear, nearest


@njit(cache=True)
def _not_near_mates(world: FloatArray, taken: FloatArray, half: float, mates: FloatArray,
                    heard: FloatArray, use_heard: bool, robot: int, cos_sin: FloatArray,
                    own_frame: FloatArray, radius: float) -> NDArray[np.bool_]:
    """(N,) which of the points world (N, 2) (own map frame, within the square of half side
    ``half`` m around ``taken`` (3,)) lie farther than ``radius`` m from every mate: where it
    should be (mates (M, 2), own frame) and, with ``use_heard``, where each other robot said
    it stands (heard (R, 2), show frame; not finite: not heard), placed with the show
    frame's cos and sin (2,) and pose own_frame (3,) (``RobotBrain._near_mates``). A mate
    whose place is not a number is near every point. Only the mates that can reach the
    square are tested (farther than its half diagonal plus ``radius``, with a millimetre to
    spare for rounding, they are far from every point of it: the same answer), the mate the
    last point was near first."""
    c, s = cos_sin[0], cos_sin[1]
    reach = half * math.sqrt(2.0) + radius + 1e-3
    where = np.empty((mates.shape[0] + (heard.shape[0] if use_heard else 0), 2))
    near = 0
    for j in range(where.shape[0]):
        if j < mates.shape[0]:
            wx, wy = mates[j, 0], mates[j, 1]
        else:
            h = j - mates.shape[0]
            if h == robot or not (math.isfinite(heard[h, 0]) and math.isfinite(heard[h, 1])):
                continue
            wx = own_frame[0] + c * heard[h, 0] - s * heard[h, 1]
            wy = own_frame[1] + s * heard[h, 0] + c * heard[h, 1]
        if math.hypot(wx - taken[0], wy - taken[1]) > reach:  # (NaN: kept, near)
            continue
        where[near, 0], where[near, 1] = wx, wy
        near += 1
    unknown = np.ones(world.shape[0], dtype=np.bool_)  # no mate: tracked
    last = 0  # the mate the last point was near first: a scan's next point is on it too
    for i in range(world.shape[0]):
        for n in range(near):
            j = (last + n) % near
            dx, dy = world[i, 0] - where[j, 0], world[i, 1] - where[j, 1]
            if (abs(dx) > radius or abs(dy) > radius) and (
                    dx == dx and dy == dy):  # (far on an axis: far; NaN: near)
                continue
            if not math.hypot(dx, dy) > radius:
                unknown[i] = False
                last = j
                break
    return unknown


@njit(cache=True)
def _grid_index(show_time: float, period: float, grid_end: float,
                length: int) -> tuple[int, bool]:
    """``RobotBrain._grid_index`` as ``BatchBrains`` computed it with NumPy: the index of
    ``show_time`` s on a grid of ``length`` entries ``period`` s apart, the last one from
    ``grid_end`` on, and whether the time is on it (else the index is 0, unused)."""
    if show_time >= grid_end:
        return length - 1, True
    k = np.rint(show_time / period)
    if abs(k * period - show_time) < 1e-9 and k >= 0 and k < length:
        return int(k), True
    return 0, False


@njit(cache=True)
def tick_outputs(flags: NDArray[np.bool_], safety: FloatArray,
                 ) -> tuple[NDArray[np.int8], NDArray[np.bool_], NDArray[np.bool_],
                            NDArray[np.bool_]]:
    """What ``BatchBrains.step`` reports of a tick's flags (R, 4) and safety (R, 5)
    (``brains_tick``): each robot's status (R,) (0 running, 1 stopped, 2 error), whether it
    holds the show (R,) (it holds it, or its safety is in error), asks for room (R,) (it
    holds the show, stopped, no error) and waits (R,)."""
    count = flags.shape[0]
    status = np.zeros(count, dtype=np.int8)
    holding = np.empty(count, dtype=np.bool_)
    asking = np.empty(count, dtype=np.bool_)
    waiting = np.empty(count, dtype=np.bool_)
    for r in range(count):
        error = safety[r, 0] != 0.0
        stopped, holds_show = flags[r, 3], flags[r, 1]
        status[r] = 2 if error else (1 if stopped else 0)
        holding[r] = holds_show or error
        asking[r] = holds_show and stopped and not error
        waiting[r] = flags[r, 2]
    return status, holding, asking, waiting


@njit(cache=True)
def grid_lookups(grid: FloatArray, mates: FloatArray, period: float, grid_end: float,
                 lead: float, show_times: FloatArray, stand_ends: NDArray[np.int64],
                 brief: float, paced: bool, headings: FloatArray,
                 ) -> tuple[FloatArray, NDArray[np.bool_], FloatArray]:
    """What each follower tracks on the brains' grid at its show time (R,) s: the rows
    (R, 6) (x, y, heading, speed, angular speed; with ``lead`` > 0 s the speeds
    interpolated between the two grid ticks around the time ``lead`` s ahead; and how the
    place stands there, ``control.tracking.place_stand`` with the rows' ``stand_ends``
    (R, T) and ``brief`` s for ``BRIEF_STAND``), whether the
    row is the grid's or a paced time's between two of its ticks (R,) (else the brain
    computes it: ``RobotBrain._reference``), and
    where each robot's mates should be (R, M, 2) (the nearest grid tick's). grid (R, T, 5),
    mates (R, M, T', 2), both in each robot's own frame (``BatchBrains``). ``paced``: a
    time between two grid ticks (a paced clock's) is interpolated linearly between them as
    ``RobotBrain.slot_at`` does, the heading from ``headings`` (R, T), the grid's headings
    before they were wrapped (the brain's own), and the place stands as at the earlier
    tick (``RobotBrain._place_stand``)."""
    count, length = grid.shape[0], grid.shape[1]
    rows = np.empty((count, 6))
    on = np.empty(count, dtype=np.bool_)
    places = np.empty((count, mates.shape[1], 2))
    for r in range(count):
        show_time = show_times[r]
        k, found = _grid_index(show_time, period, grid_end, length)
        rows[r, :5] = grid[r, k, :]
        if not found and paced and 0.0 <= show_time < grid_end and length >= 2:
            # ``RobotBrain.slot_at``'s paced branch, operation for operation
            first = min(math.floor(show_time / period), length - 2)
            start = first * period  # (the grid's last step ends at grid_end)
            span = min((first + 1) * period, grid_end) - start
            weight = min(max((show_time - start) / span, 0.0), 1.0) if span > 0.0 else 0.0
            for d in range(5):
                a = headings[r, first] if d == 2 else grid[r, first, d]
                b = headings[r, first + 1] if d == 2 else grid[r, first + 1, d]
                rows[r, d] = (1.0 - weight) * a + weight * b
            rows[r, 2] = _wrap(rows[r, 2])
            k, found = min(math.floor(show_time / period), length - 1), True
        # ``control.tracking.place_stand``
        end = stand_ends[r, k]
        rows[r, 5] = 0.0
        if end >= length:
            rows[r, 5] = 2.0  # ``FOR_GOOD``
        elif end != k and end * period - show_time < brief:
            rows[r, 5] = -1.0 if grid[r, end, 3] < 0.0 else 1.0
        if lead > 0.0:
            steps = (show_time + lead) / period
            first = np.floor(steps)
            weight = steps - first
            before, found_before = _grid_index(first * period, period, grid_end, length)
            after, found_after = _grid_index((first + 1.0) * period, period, grid_end, length)
            for d in range(3, 5):
                rows[r, d] = (1.0 - weight) * grid[r, before, d] + weight * grid[r, after, d]
            found = found and found_before and found_after
        on[r] = found
        tick = np.rint(show_time / period)  # (NumPy's clip of it; NaN: the first)
        last = mates.shape[2] - 1
        index = 0 if not tick > 0.0 else (last if tick >= last else int(tick))
        places[r, :, :] = mates[r, :, index, :]
    return rows, on, places


@njit(cache=True, nogil=True)  # (lets a scan run on the other core: ``Stage.scan_ahead``)
def brains_tick(now: float, show_times: FloatArray, poses: FloatArray,
                pose_known: NDArray[np.bool_], arrived: NDArray[np.bool_],
                stamps: FloatArray, columns: FloatArray, offsets: NDArray[np.int64],
                height_steps: FloatArray, references: FloatArray,
                finals: NDArray[np.bool_], mates: FloatArray, heard: FloatArray,
                use_heard: bool, frame_cos_sin: FloatArray, own_frames: FloatArray,
                sizes: FloatArray, limits: FloatArray, mate_radius: FloatArray,
                mate_body: FloatArray, gains: FloatArray, detect: FloatArray, rules: FloatArray,
                history: FloatArray, history_size: NDArray[np.int64],
                seen_from: FloatArray, has_seen_from: NDArray[np.bool_],
                last_show_time: FloatArray, making_room: FloatArray,
                near_since: FloatArray, safety: FloatArray,
                lookup_failures: NDArray[np.int64], commands: FloatArray,
                flags: NDArray[np.bool_], events: NDArray[np.int64],
                event_values: FloatArray, track_params: FloatArray,
                track_states: FloatArray, track_covariances: FloatArray,
                track_hits: NDArray[np.int64], track_misses: NDArray[np.int64],
                track_count: NDArray[np.int64], track_stamp: FloatArray,
                cloud_stamp: FloatArray, point_velocity: FloatArray,
                point_kind: NDArray[np.int8], point_count: NDArray[np.int64],
                rates: FloatArray, paces: FloatArray, paused_since: FloatArray,
                settling: NDArray[np.bool_]) -> None:
    """One control tick of every robot (``RobotBrain.step``), in place.

    Per tick: now (s, the robots' clock); show_times (R,) s; poses (R, 3) own map frame,
    valid where pose_known (R,); arrived (R,) whether a cloud reached the robot, taken at
    stamps (R,) s; columns (K, 4) each robot's latest cloud (``base_link`` at its stamp),
    robot r's rows offsets[r]:offsets[r + 1], height_steps (R,) m; references (R, 6) what
    each follower tracks (x, y, heading, speed, angular speed: ``RobotBrain._reference``;
    and ``control.tracking.place_stand`` of its place: ``grid_lookups``; a place that
    never moves again is final),
    finals (R,); mates (R, M, 2) where each robot's mates should be (its own frame);
    heard (R, 2) where each robot said it stands (show frame, NaN: not heard), used where
    use_heard, with each robot's show frame in its own (own_frames (R, 3), their cos and sin
    (R, 2) as NumPy computes them).
    Per robot: sizes (R, 2) length, width; limits (R, 2) max linear, angular speed;
    mate_radius (R,), mate_body (R,) (``RobotBrain.mate_body_radius``); gains, detect, rules:
    the indexed constants above.
    State, updated: history (R, H, 4) with history_size (R,); seen_from (R, 3) where
    has_seen_from; last_show_time (R,) (NaN: none); making_room (R,); near_since (R,) (NaN);
    safety (R, 5) error (0/1), last cloud, first tick, stopped since, last beep (NaN: None)
    with lookup_failures (R,).
    Out: commands (R, 2); flags (R, 4) held, holds the show, waiting, stopped (the safety's
    stopped state); events (R,) an EVENT_ code and event_values (R,) its figure.
    The ``predicted`` stop rule (rules[PREDICTED]): its tracker's parameters track_params
    (indexed above) and, per robot, state updated: tracks (``perception.tracks_jit.
    track_cloud``) in track_states (R, K, 4), track_covariances (R, K, 4, 4), track_hits,
    track_misses (R, K), the first track_count (R,) of each valid, last tracked at
    track_stamp (R,) (NaN: never); the latest cloud's stamp cloud_stamp (R,) (NaN: none);
    the tracked velocity (R, P, 2) and kind (R, P) of the first point_count (R,) points of
    the latest tracked cloud (-1: none yet). The caller makes K hold every track plus one per
    point of the clouds that arrive, and P one per point.
    The ``paced`` hold strategy (rules[PACED]): each robot's clock ran at rates (R,) (0-1)
    since its last tick; out: paces (R,), the share of the plan's speeds each can follow
    (``robot._pace_left``; 1 without it).
    State, updated: paused_since (R,) each robot's clock at the first tick at which its show
    time had not advanced (NaN: it advances); settling (R,) whether each settles on its final
    slot (``control.tracking.settling_on_slot``).
    """
    count = poses.shape[0]
    capacity = history.shape[1]
    stop = detect[STOP_DISTANCE]
    lidar = rules[LIDAR] != 0.0
    predicted = rules[PREDICTED] != 0.0
    paced = rules[PACED] != 0.0
    ssm_detect = detect.copy()  # what the tracker watches: the SSM square
    ssm_detect[CROP_HALF] = rules[SSM_REACH]
    for r in range(count):
        show_time = show_times[r]
        pose = poses[r]
        known = pose_known[r]
        length, width = sizes[r, 0], sizes[r, 1]
        if known and lidar:  # the history the compensated detector looks up
            if history_size[r] == capacity:
                history[r, :-1] = history[r, 1:].copy()
                history_size[r] -= 1
            k = history_size[r]
            history[r, k, 0] = now
            history[r, k, 1:] = pose
            history_size[r] += 1
        if arrived[r] and lidar:
            at = _pose_at(history[r], history_size[r], stamps[r])
            if at >= 0:
                seen_from[r] = history[r, at, 1:]
            has_seen_from[r] = at >= 0
            cloud_stamp[r] = stamps[r]
        cloud = columns[offsets[r]:offsets[r + 1]]
        height_step = height_steps[r]
        if arrived[r] and lidar and predicted and (has_seen_from[r] or known):
            # the obstacles tracked in the own map frame (``RobotBrain.step``)
            taken = seen_from[r] if has_seen_from[r] else pose
            flat = _crop_points(cloud, height_step, ssm_detect)
            tc, ts = math.cos(taken[2]), math.sin(taken[2])  # ``points_to_world``
            world = np.empty_like(flat)
            for i in range(flat.shape[0]):
                world[i, 0] = taken[0] + tc * flat[i, 0] - ts * flat[i, 1]
                world[i, 1] = taken[1] + ts * flat[i, 0] + tc * flat[i, 1]
            # the mates where they should be or said they are are not tracked
            # (``RobotBrain._near_mates``)
            unknown = _not_near_mates(world, taken, rules[SSM_REACH], mates[r], heard,
                                      use_heard, r, frame_cos_sin[r], own_frames[r],
                                      mate_radius[r])
            k = track_count[r]
            n = world.shape[0]
            point_velocity[r, :n] = 0.0
            point_kind[r, :n] = STANDING
            if k > 0 or unknown.any():  # (no track and nothing to track: none after it)
                states, covariances, hits, misses, some_velocity, some_kind = track_cloud(
                    track_states[r, :k], track_covariances[r, :k], track_hits[r, :k],
                    track_misses[r, :k], track_stamp[r], world[unknown], stamps[r],
                    track_params[CLUSTER_GAP], track_params[MAX_WIDTH], track_params[GATE],
                    int(track_params[MIN_HITS]), int(track_params[MAX_MISSES]),
                    track_params[ACCELERATION_NOISE], track_params[MEASUREMENT_NOISE])
                k = states.shape[0]
                track_states[r, :k], track_covariances[r, :k] = states, covariances
                track_hits[r, :k], track_misses[r, :k] = hits, misses
                m = 0
                for i in range(n):
                    if unknown[i]:
                        point_velocity[r, i] = some_velocity[m]
                        point_kind[r, i] = some_kind[m]
                        m += 1
            track_count[r], track_stamp[r] = k, stamps[r]
            point_count[r] = n
        linear, angular = 0.0, 0.0
        pace = 1.0
        held = holds_show = waiting = False
        near_time = math.nan
        room = 0.0
        paused = (not math.isnan(last_show_time[r])
                  and show_time <= last_show_time[r] + rules[ADVANCE_MIN])
        if not paused:
            paused_since[r] = math.nan
        elif math.isnan(paused_since[r]):
            paused_since[r] = now
        stood_for = 0.0 if math.isnan(paused_since[r]) else now - paused_since[r]
        was_settling = settling[r]  # (its last tick's; none where it does not track)
        settling[r] = False
        if known and show_time >= 0.0:
            view = seen_from[r] if has_seen_from[r] else pose
            mates_now = mates[r]
            front, rear, nearest, fy = math.inf, math.inf, math.inf, 0.0
            s_front, s_rear, s_nearest = math.inf, math.inf, math.inf
            has_strangers = False
            if lidar and cloud.shape[0] > 0:  # ``RobotBrain._perceive_all``
                everything, strangers, left_out = perceive_columns_split(
                    cloud, height_step, detect[CROP_HALF], detect[Z_MIN], detect[Z_MAX],
                    view, pose, length, width, stop, detect[CORRIDOR_MARGIN],
                    rules[FORCE_RADIUS], rules[FORCE_GAIN], mates_now, mate_radius[r])
                front, rear, nearest, _, fy = everything
                if left_out:
                    has_strangers = True
                    s_front, s_rear, s_nearest, _fx, fy = strangers
            speed, angular_speed = references[r, 3], references[r, 4]
            full_speed, full_angular = speed, angular_speed
            going = paused and not finals[r]  # what the show would ask (``RobotBrain.step``)
            # (a place that stands a moment there: as if the clock stood, ``place_stand``)
            stands_briefly = ((references[r, 5] == 1.0 or references[r, 5] == -1.0)
                              and not (abs(speed) > 1e-9 or abs(angular_speed) > 1e-9))
            go_linear, go_angular = 0.0, 0.0
            if going:
                go_linear, go_angular = _tracking(
                    gains, limits[r, 0], limits[r, 1], pose[0], pose[1], pose[2],
                    references[r, 0], references[r, 1], references[r, 2], speed,
                    angular_speed, finals[r], fy, stands_briefly, references[r, 5] < 0.0,
                    was_settling)
            backwards = speed < 0.0  # (the slot's way when the clock stood)
            standing_briefly = False  # (as if the clock stood: ``RobotBrain.step``)
            if paused:
                speed, angular_speed = 0.0, 0.0
            elif stands_briefly and not finals[r]:
                standing_briefly = True
                backwards = references[r, 5] < 0.0
            elif paced and rates[r] < 1.0:  # the clock runs slow: so does the place
                speed, angular_speed = speed * rates[r], angular_speed * rates[r]
            reference_speed = abs(speed)
            behind = math.hypot(references[r, 0] - pose[0], references[r, 1] - pose[1])
            if (going and behind <= rules[PAUSE_STILL]
                    and stood_for >= rules[PAUSE_STILL_AFTER] - 1e-9
                    and not flags[r, 1] and paces[r] >= 1.0):  # (its last tick's)
                linear, angular = 0.0, 0.0  # near its place it waits where it is
            else:
                linear, angular = _tracking(
                    gains, limits[r, 0], limits[r, 1], pose[0], pose[1], pose[2],
                    references[r, 0], references[r, 1], references[r, 2], speed,
                    angular_speed, finals[r], fy, paused or standing_briefly, backwards,
                    was_settling)
            settling[r] = _settling_on_slot(gains, pose[0], pose[1], pose[2],
                                            references[r, 0], references[r, 1], speed,
                                            angular_speed, finals[r], was_settling)
            wanted_linear, wanted_angular = linear, angular
            if not going:
                go_linear, go_angular = linear, angular
            seen_front, seen_rear = front < stop, rear < stop
            # ``near``: the strangers' perception, else everything's
            n_front = s_front if has_strangers else front
            n_rear = s_rear if has_strangers else rear
            n_nearest = s_nearest if has_strangers else nearest
            heard_count = 0
            if use_heard:
                for j in range(count):
                    if j != r and math.isfinite(heard[j, 0]) and math.isfinite(heard[j, 1]):
                        heard_count += 1
            if lidar and heard_count > 0 and mates_now.shape[0] > 0 and (
                    seen_front or seen_rear or behind > rules[HOLD_LAG]
                    or n_nearest < rules[NEAR_GAP]):
                # ``RobotBrain._without_mates`` with the mates heard (``compose_points``)
                where = _mate_centres(mates_now, heard, r, heard_count, frame_cos_sin[r],
                                      own_frames[r])
                keep = far_from_all(cloud, to_local(where, view), mate_radius[r])
                if not keep.all():
                    n_front, n_rear, n_nearest, _, _ = perceive_columns(
                        cloud[keep, :], height_step, detect[CROP_HALF], detect[Z_MIN],
                        detect[Z_MAX], view, pose, length, width, stop,
                        detect[CORRIDOR_MARGIN], rules[FORCE_RADIUS], rules[FORCE_GAIN])
            near_front, near_rear = n_front < stop, n_rear < stop
            parked = show_time >= rules[REST_FROM]
            flag_front = near_front if parked else seen_front
            flag_rear = near_rear if parked else seen_rear
            stranger_near = n_nearest < rules[NEAR_GAP]
            if stranger_near and show_time >= rules[REST_FROM]:
                near_time = now if math.isnan(near_since[r]) else near_since[r]
            # ``predicted``: where the tracked strangers will be by now
            p_front, p_rear, p_nearest = math.inf, math.inf, math.inf
            if (predicted and (go_linear != 0.0 or go_angular != 0.0) and point_count[r] >= 0
                    and _any_tracked(point_kind[r, :point_count[r]])):
                p_front, p_rear, p_nearest = _predicted_gaps(
                    _points_now(cloud, height_step, ssm_detect, view, pose),
                    point_velocity[r, :point_count[r]], point_kind[r, :point_count[r]], pose,
                    now - (cloud_stamp[r] if not math.isnan(cloud_stamp[r]) else now),
                    length, width, detect, mates_now, heard, use_heard, r,
                    frame_cos_sin[r], own_frames[r], mate_radius[r], rules[PREDICTED_STOP_TIME])
            # ``RobotBrain.step``'s body_nearest: no mate's body where every mate said it is
            sweep_reach = (0.5 * math.hypot(length, width) - 0.5 * min(length, width))
            b_nearest = n_nearest
            if (lidar and nearest < sweep_reach and n_nearest > nearest and heard_count > 0
                    and heard_count == mates_now.shape[0]):
                bodies = _mate_centres(mates_now, heard, r, heard_count, frame_cos_sin[r],
                                       own_frames[r])
                keep = far_from_all(cloud, to_local(bodies, view), mate_body[r])
                beyond = nearest
                if not keep.all():
                    _, _, beyond, _, _ = perceive_columns(
                        cloud[keep, :], height_step, detect[CROP_HALF], detect[Z_MIN],
                        detect[Z_MAX], view, pose, length, width, stop,
                        detect[CORRIDOR_MARGIN], rules[FORCE_RADIUS], rules[FORCE_GAIN])
                b_nearest = min(n_nearest, beyond)
            if b_nearest <= rules[OVERLAP] or (p_nearest <= rules[OVERLAP]
                                               and b_nearest < sweep_reach):
                # (on or in its footprint, or a tracked stranger will be by now; the brain's
                # ``knows_strangers`` holds for every batched brain: ``batch_supported``)
                held = holds_show = True
                linear = angular = 0.0
            elif (not math.isnan(near_time) and now - near_time < rules[AFTER_SHOW_WAIT]
                  and (linear != 0.0 or angular != 0.0)):
                held = holds_show = waiting = True
                linear = angular = 0.0
            elif (predicted and go_linear != 0.0
                  and (p_front if go_linear > 0 else p_rear)
                  < stop + abs(go_linear) * rules[PREDICTED_STOP_TIME]
                  + go_linear * go_linear / (2.0 * rules[SSM_DECELERATION])):
                # a tracked person will be in the corridor by now (``_predicted_gaps``),
                # with the robot's own way until it stands (``robot.predicted_stop_distance``)
                held = holds_show = True
                linear = 0.0
            elif (flag_front and linear > 0) or (flag_rear and linear < 0):
                held = True
                holds_show = (near_front and linear > 0) or (near_rear and linear < 0)
                linear = 0.0
            elif going and ((near_front and go_linear > 0) or (near_rear and go_linear < 0)):
                held = holds_show = True  # a stranger in the way the show would go on
                linear = 0.0
            elif rules[APPROACH_GAIN] > 0:
                if linear > 0:
                    linear = min(linear, _approach_limit(
                        rules, stop, front, s_front, has_strangers, reference_speed, parked))
                elif linear < 0:
                    linear = max(linear, -_approach_limit(
                        rules, stop, rear, s_rear, has_strangers, reference_speed, parked))
            if stranger_near:
                top = rules[CORNER_SPEED] / (0.5 * math.hypot(length, width))
                if abs(angular) > top:  # ``RobotBrain.step``: slower along the same arc
                    linear = linear * (top / abs(angular))
                    angular = min(max(angular, -top), top)
            # ``RobotBrain._mate_centres``: turning on the spot (``robot.turns_on_the_spot``),
            # the guard leaves mates room for their own turn
            on_the_spot = angular != 0.0 and abs(linear) <= abs(angular) * 0.5 * width
            places = mates_now.shape[0] if on_the_spot else 0
            centres = _mate_centres(mates_now[:places], heard, r,
                                    heard_count if places > 0 else 0, frame_cos_sin[r],
                                    own_frames[r])
            if angular != 0.0 and nearest < _turn_reach(
                    length, width, linear, detect,
                    detect[TURN_SHARE] if centres.shape[0] > 0 else 1.0):
                may_make_room = (not held and n_nearest >= _turn_reach(
                    length, width, rules[MAKE_ROOM_SPEED], detect, 1.0)
                    and nearest >= rules[MAKE_ROOM_FLOOR]
                    and not (finals[r] and behind <= rules[FINAL_NO_ROOM]))
                linear, angular, room = _guard_turn(
                    cloud, height_step, detect, view, pose, length, width, linear, angular,
                    may_make_room, making_room[r], rules, to_local(centres, view),
                    mate_radius[r])
            if angular != 0.0 and b_nearest < sweep_reach:  # a stranger within it: no turn
                angular = 0.0
            if angular != 0.0 and held and holds_show and b_nearest < rules[NEAR_GAP]:
                angular = 0.0  # held for a stranger: no turn while one is near
            if angular != 0.0 and p_nearest < sweep_reach:  # a stranger will be within it
                angular = 0.0
            if not held and behind > rules[HOLD_LAG]:
                free = n_front if wanted_linear >= 0.0 else n_rear
                by_stranger = _approach_limit(rules, stop, free, 0.0, False, 0.0, False) < (
                    abs(wanted_linear) - rules[SLOWED])
                turn_cut = abs(angular) < abs(wanted_angular) - rules[SLOWED] and (
                    (stranger_near and behind > rules[SLOW_TURN_LAG])
                    or n_nearest < _turn_reach(length, width, linear, detect, 1.0))
                holds_show = (abs(linear) < abs(wanted_linear) - rules[SLOWED]
                              and by_stranger) or turn_cut
                if paced and holds_show:  # ``robot._pace_left``
                    share = 1.0
                    asked = full_speed if full_speed != 0.0 else wanted_linear
                    if asked != 0.0:
                        share = min(share, abs(linear) / abs(asked))
                    asked = full_angular if full_angular != 0.0 else wanted_angular
                    if asked != 0.0:
                        share = min(share, abs(angular) / abs(asked))
                    pace = rules[PACE_MARGIN] * share
                    holds_show = pace < rules[PACE_MIN] * rules[PACE_MARGIN]
                    if holds_show:
                        pace = 1.0
            # ``RobotBrain.step``: held or paced at its last tick and crept up to its standing
            # place, it keeps holding (and says so) while a stranger would cut the motion the
            # show would ask
            if (going and (flags[r, 1] or paces[r] < 1.0) and not held and not holds_show
                    and pace >= 1.0 and go_linear != 0.0):
                go_limit = _approach_limit(rules, stop, n_front if go_linear > 0.0 else n_rear,
                                           0.0, False, 0.0, False)
                if go_limit < abs(go_linear) - rules[SLOWED]:
                    held = holds_show = True
                    if paced:  # ``robot._pace_left`` of the linear speed alone
                        planned = full_speed if full_speed != 0.0 else go_linear
                        pace = rules[PACE_MARGIN] * min(1.0, go_limit / abs(planned))
                        held = holds_show = pace < rules[PACE_MIN] * rules[PACE_MARGIN]
                        if holds_show:
                            pace = 1.0
        # ``safety.monitor.safety_step``
        events[r], event_values[r] = EVENT_NONE, 0.0
        may_move = False
        if safety[r, 0] == 0.0:
            first = safety[r, 2] if not math.isnan(safety[r, 2]) else now
            last_cloud = now if (arrived[r] or not lidar) else safety[r, 1]
            failures = 0 if known else lookup_failures[r] + 1
            reference_time = last_cloud if not math.isnan(last_cloud) else first
            lookup_failures[r] = failures
            safety[r, 1], safety[r, 2] = last_cloud, first
            if failures >= rules[MAX_LOOKUP_FAILURES]:
                events[r], event_values[r] = EVENT_ERROR_POSE, failures
                safety[r, 0], safety[r, 3], safety[r, 4] = 1.0, math.nan, math.nan
            elif now - reference_time > rules[SENSOR_TIMEOUT] + 1e-6:
                events[r], event_values[r] = EVENT_ERROR_LIDAR, now - reference_time
                safety[r, 0], safety[r, 3], safety[r, 4] = 1.0, math.nan, math.nan
            else:
                may_move = True
                if held and math.isnan(safety[r, 3]):
                    safety[r, 3], safety[r, 4] = now, now
                    events[r] = EVENT_SPEECH
                elif held and not math.isnan(safety[r, 4]) and (
                        now - safety[r, 4] >= rules[BEEP_PERIOD] - 1e-9):
                    safety[r, 4] = now
                    events[r] = EVENT_BEEP
                elif not held and not math.isnan(safety[r, 3]):
                    safety[r, 3], safety[r, 4] = math.nan, math.nan
                    events[r] = EVENT_RESUME
        if not may_move:
            linear = angular = 0.0
        commands[r, 0], commands[r, 1] = linear, angular
        moves = linear != 0.0 or angular != 0.0
        making_room[r] = room if may_move and moves else 0.0
        near_since[r] = near_time
        last_show_time[r] = show_time
        flags[r, 0], flags[r, 1], flags[r, 2] = held, holds_show, waiting
        flags[r, 3] = not math.isnan(safety[r, 3])
        paces[r] = pace


drop_stale(sys.modules[__name__], (fast, tracks_jit))  # its kernels call perception.fast's

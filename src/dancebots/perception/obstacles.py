"""Obstacle detection of thesis ch. 5.2 as pure functions.

A LIDAR cloud in ``base_link`` (x forward, y left, z up, m) becomes the 2D obstacle points
around the robot: everything in the 4 m x 4 m square around it (2 m to each side of the
``base_link`` origin) between 0.10 m and 1.5 m high, flattened to z = 0. ``stop_front`` /
``stop_rear`` are set when an obstacle point is nearer than 0.55 m to the robot's front /
rear. Because the cloud lags (about 300 ms), :func:`compensate_motion` moves the points by
the robot's own motion since the cloud's stamp (an addition: thesis 7.2.2 saw a collision
caused by that lag).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from dancebots.control.force_field import repulsive_force
from dancebots.geometry import points_to_local, points_to_world

__all__ = [
    "DetectorParams",
    "Perception",
    "StopFlags",
    "clear_distances",
    "compensate_motion",
    "near_quadrants",
    "obstacle_points",
    "obstacle_points_from_columns",
    "perceive",
    "rotation_allowed",
    "stop_flags",
    "turn_fraction",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class DetectorParams:
    """crop_half: half side of the square kept around ``base_link``, m (thesis: 4 x 4 m);
    z_min, z_max: kept heights, m (thesis: above 10 cm, below 1.5 m); stop_distance: m
    (thesis: 55 cm); corridor_margin: the stop zones are as wide as the robot plus this on
    each side, m, so that neighbours beside the robot do not stop it; turn_guard: points this
    near the footprint (m) are checked before the robot turns a corner towards them
    (:func:`turn_fraction`): the turn may not bring any of them nearer than turn_margin (m)
    within turn_horizon (s)."""

    crop_half: float = 2.0
    z_min: float = 0.10
    z_max: float = 1.5
    stop_distance: float = 0.55
    corridor_margin: float = 0.10
    turn_guard: float = 0.30
    turn_margin: float = 0.05
    turn_horizon: float = 1.0


@dataclass(frozen=True, slots=True)
class StopFlags:
    front: bool
    rear: bool


def obstacle_points(points: FloatArray, params: DetectorParams = DetectorParams()) -> FloatArray:
    """Cloud (N, 3) -> obstacle points (M, 2): cropped, height-filtered, flattened, unique."""
    keep = ((np.abs(points[:, 0]) <= params.crop_half) & (np.abs(points[:, 1]) <= params.crop_half)
            & (points[:, 2] > params.z_min) & (points[:, 2] < params.z_max))
    flat: FloatArray = np.unique(np.round(points[keep, :2], 9), axis=0)
    return flat


def obstacle_points_from_columns(columns: FloatArray, height_step: float,
                                 params: DetectorParams = DetectorParams()) -> FloatArray:
    """The same points as :func:`obstacle_points` (as a set) on a cloud stored as columns
    (K, 4) = x, y, z_low, z_high of points repeated every ``height_step`` (see
    ``perception.cloud.PointCloud``)."""
    low, high = columns[:, 2], columns[:, 3]
    first = np.where(low > params.z_min, 0.0,
                     np.floor((params.z_min - low) / height_step + 1e-9) + 1.0)
    z = low + first * height_step  # the lowest level above z_min
    keep = ((z < params.z_max) & (z <= high + 1e-9)
            & (np.abs(columns[:, 0]) <= params.crop_half)
            & (np.abs(columns[:, 1]) <= params.crop_half))
    flat: FloatArray = columns[keep, :2]  # one column per ray and object: no duplicates
    return flat


def stop_flags(points: FloatArray, length: float, width: float,
               params: DetectorParams = DetectorParams()) -> StopFlags:
    """Obstacle points (M, 2) in ``base_link`` -> (stop_front, stop_rear): is a point within
    ``stop_distance`` ahead of the front edge / behind the rear edge, inside the corridor the
    robot sweeps (its width plus the margin on each side)."""
    front, rear = clear_distances(points, length, width, params)
    return StopFlags(front < params.stop_distance, rear < params.stop_distance)


def clear_distances(points: FloatArray, length: float, width: float,
                    params: DetectorParams = DetectorParams()) -> tuple[float, float]:
    """How far the robot can drive forward and backward before its front / rear edge meets
    an obstacle point (M, 2) in the corridor it sweeps, m (inf when the corridor is clear)."""
    if len(points) == 0:
        return math.inf, math.inf
    half_l = 0.5 * length
    corridor = np.abs(points[:, 1]) <= 0.5 * width + params.corridor_margin
    ahead = points[corridor & (points[:, 0] >= half_l - 1e-9), 0]
    behind = points[corridor & (points[:, 0] <= -half_l + 1e-9), 0]
    front = float(ahead.min() - half_l) if ahead.size else math.inf
    rear = float(-behind.max() - half_l) if behind.size else math.inf
    return front, rear


def near_quadrants(points: FloatArray, length: float, width: float,
                   params: DetectorParams = DetectorParams()) -> tuple[bool, bool, bool, bool]:
    """Which quadrants of ``base_link`` (front-left, front-right, rear-left, rear-right) hold
    an obstacle point (M, 2) within ``turn_guard`` m of the footprint (points on an axis
    count in none)."""
    if len(points) == 0:
        return False, False, False, False
    half = np.array([0.5 * length, 0.5 * width])
    outside = np.maximum(np.abs(points) - half, 0.0)
    near = points[np.hypot(outside[:, 0], outside[:, 1]) < params.turn_guard]
    x, y = near[:, 0], near[:, 1]
    return (bool(((x > 0) & (y > 0)).any()), bool(((x > 0) & (y < 0)).any()),
            bool(((x < 0) & (y > 0)).any()), bool(((x < 0) & (y < 0)).any()))


def rotation_allowed(points: FloatArray, length: float, width: float,
                     params: DetectorParams = DetectorParams()) -> tuple[bool, bool]:
    """(may turn left, may turn right): turning left swings the front half of the robot to
    the left and the rear half to the right, so a point within ``turn_guard`` of the
    footprint ahead-left or behind-right forbids turning left (and mirrored for right)."""
    front_left, front_right, rear_left, rear_right = near_quadrants(points, length, width,
                                                                    params)
    return not (front_left or rear_right), not (front_right or rear_left)


TURN_FRACTIONS = (1.0, 0.5, 0.25, 0.0)
"""The fractions of a commanded angular speed :func:`turn_fraction` tries, largest first."""


def turn_fraction(points: FloatArray, length: float, width: float, linear: float,
                  angular: float, params: DetectorParams = DetectorParams()) -> float:
    """The largest of :data:`TURN_FRACTIONS` of ``angular`` (rad/s) at which the robot,
    driving ``linear`` (m/s) on that arc for ``params.turn_horizon`` s (sampled every 0.1 s),
    brings no obstacle point (M, 2) in ``base_link`` (taken as standing) within
    ``params.turn_margin`` m of its footprint, nor nearer than it already is if it is nearer,
    unless driving straight would bring it as near (the stop flags are for that). 0.0 when
    only driving straight does (an addition; thesis ch. 5.2 stops the robot only ahead and
    behind, and a skid-steer robot's corners swing out as it turns: a 1.2 m robot turning
    on a 0.25 m radius sweeps its tail 0.26 m beyond its side)."""
    if len(points) == 0 or angular == 0.0:
        return 1.0
    half = np.array([0.5 * length, 0.5 * width])
    times = np.arange(0.0, params.turn_horizon + 1e-9, 0.1)  # (K,)
    fractions = np.array(TURN_FRACTIONS)  # (F,)
    w = fractions[:, None] * angular  # (F, 1)
    theta = w * times  # (F, K)
    small = np.abs(w) < 1e-9
    safe_w = np.where(small, 1.0, w)
    dx = np.where(small, linear * times, linear * np.sin(theta) / safe_w)  # (F, K)
    dy = np.where(small, 0.0, linear * (1.0 - np.cos(theta)) / safe_w)
    px = points[:, 0][None, None, :] - dx[..., None]  # (F, K, M), world frame of now
    py = points[:, 1][None, None, :] - dy[..., None]
    c, s = np.cos(theta)[..., None], np.sin(theta)[..., None]
    x, y = c * px + s * py, -s * px + c * py  # in base_link at each time
    gap = np.hypot(np.maximum(np.abs(x) - half[0], 0.0), np.maximum(np.abs(y) - half[1], 0.0))
    nearest = gap.min(axis=1)  # (F, M): the nearest each point comes on each arc
    floor = np.minimum(gap[0, 0], params.turn_margin) - 1e-9  # (M,)
    bad = (nearest < floor) & (nearest < nearest[-1] - 1e-9)  # worse than straight, too near
    for fraction, blocked in zip(TURN_FRACTIONS, bad.any(axis=1), strict=True):
        if not blocked:
            return fraction
    return 0.0


def compensate_motion(points: FloatArray, pose_at_stamp: tuple[float, float, float],
                      pose_now: tuple[float, float, float]) -> FloatArray:
    """Points (M, 2) seen in ``base_link`` at the cloud's stamp, expressed in ``base_link``
    now, from the robot's own poses (odometry, any fixed frame) then and now."""
    return points_to_local(points_to_world(points, pose_at_stamp), pose_now)


@dataclass(frozen=True, slots=True)
class Perception:
    """Everything a control tick needs from the obstacle points, computed in one pass:
    the stop flags, the free distances ahead and behind (m), whether turning left / right is
    allowed, and the virtual force (Fx, Fy) in ``base_link``."""

    flags: StopFlags
    front_free: float
    rear_free: float
    near: tuple[bool, bool, bool, bool]
    force: tuple[float, float]

    @property
    def turn_left(self) -> bool:
        """Turning left swings no corner into a point near it (front-left, rear-right)."""
        return not (self.near[0] or self.near[3])

    @property
    def turn_right(self) -> bool:
        """Turning right swings no corner into a point near it (front-right, rear-left)."""
        return not (self.near[1] or self.near[2])


CLEAR = Perception(StopFlags(False, False), math.inf, math.inf,
                   (False, False, False, False), (0.0, 0.0))


def perceive(points: FloatArray, length: float, width: float,
             params: DetectorParams = DetectorParams(), force_radius: float = 1.0,
             force_gain: float = 0.02) -> Perception:
    """Everything a control tick needs from the obstacle points (M, 2) in ``base_link``:
    :func:`clear_distances` (and the stop flags they imply), :func:`rotation_allowed` and
    ``control.force_field.repulsive_force``. ``perception.fast`` compiles the same pass."""
    if len(points) == 0:
        return CLEAR
    front, rear = clear_distances(points, length, width, params)
    near = near_quadrants(points, length, width, params)
    force = repulsive_force(points, length, width, force_radius, force_gain) if (
        force_radius > 0) else (0.0, 0.0)
    return Perception(StopFlags(front < params.stop_distance, rear < params.stop_distance),
                      front, rear, near, force)

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
    "obstacle_points",
    "obstacle_points_from_columns",
    "perceive",
    "rotation_allowed",
    "stop_flags",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class DetectorParams:
    """crop_half: half side of the square kept around ``base_link``, m (thesis: 4 x 4 m);
    z_min, z_max: kept heights, m (thesis: above 10 cm, below 1.5 m); stop_distance: m
    (thesis: 55 cm); corridor_margin: the stop zones are as wide as the robot plus this on
    each side, m, so that neighbours beside the robot do not stop it; turn_guard: points this
    near the footprint forbid turning the corner nearest to them towards them, m."""

    crop_half: float = 2.0
    z_min: float = 0.10
    z_max: float = 1.5
    stop_distance: float = 0.55
    corridor_margin: float = 0.10
    turn_guard: float = 0.30


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


def rotation_allowed(points: FloatArray, length: float, width: float,
                     params: DetectorParams = DetectorParams()) -> tuple[bool, bool]:
    """(may turn left, may turn right): turning left swings the front half of the robot to
    the left and the rear half to the right, so a point within ``turn_guard`` of the
    footprint ahead-left or behind-right forbids turning left (and mirrored for right)."""
    if len(points) == 0:
        return True, True
    half = np.array([0.5 * length, 0.5 * width])
    outside = np.maximum(np.abs(points) - half, 0.0)
    near = np.hypot(outside[:, 0], outside[:, 1]) < params.turn_guard
    quadrant = points[near, 0] * points[near, 1]
    return not bool((quadrant > 0).any()), not bool((quadrant < 0).any())


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
    turn_left: bool
    turn_right: bool
    force: tuple[float, float]


CLEAR = Perception(StopFlags(False, False), math.inf, math.inf, True, True, (0.0, 0.0))


def perceive(points: FloatArray, length: float, width: float,
             params: DetectorParams = DetectorParams(), force_radius: float = 1.0,
             force_gain: float = 0.02) -> Perception:
    """Everything a control tick needs from the obstacle points (M, 2) in ``base_link``:
    :func:`clear_distances` (and the stop flags they imply), :func:`rotation_allowed` and
    ``control.force_field.repulsive_force``. ``perception.fast`` compiles the same pass."""
    if len(points) == 0:
        return CLEAR
    front, rear = clear_distances(points, length, width, params)
    turn_left, turn_right = rotation_allowed(points, length, width, params)
    force = repulsive_force(points, length, width, force_radius, force_gain) if (
        force_radius > 0) else (0.0, 0.0)
    return Perception(StopFlags(front < params.stop_distance, rear < params.stop_distance),
                      front, rear, turn_left, turn_right, force)

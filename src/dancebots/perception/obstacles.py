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
    "footprint_clearance",
    "near_any",
    "obstacle_points",
    "obstacle_points_from_columns",
    "obstacle_points_now",
    "perceive",
    "predicted_points",
    "predicted_stop_flags",
    "stop_flags",
    "turn_floor",
    "turn_fraction",
    "turn_reach",
    "turn_samples",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class DetectorParams:
    """crop_half: half side of the square kept around ``base_link``, m (thesis: 4 x 4 m);
    z_min, z_max: kept heights, m (thesis: above 10 cm, below 1.5 m); stop_distance: m
    (thesis: 55 cm); corridor_margin: the stop zones are as wide as the robot plus this on
    each side, m, so that neighbours beside the robot do not stop it; turn_margin,
    turn_horizon: a turn may not bring any obstacle point nearer than turn_margin (m) to the
    footprint within turn_horizon (s) (:func:`turn_fraction`); turn_share: the share of a
    point's gap beyond turn_margin that a turn may close, the rest left for the point's own
    move (a mate turning on the spot beside the robot: 0.5 and two robots that both turn
    take half the gap each; 1.0 takes all of it, as if every point stood)."""

    crop_half: float = 2.0
    z_min: float = 0.10
    z_max: float = 1.5
    stop_distance: float = 0.55
    corridor_margin: float = 0.10
    turn_margin: float = 0.10
    turn_horizon: float = 1.0
    turn_share: float = 0.5

    def __post_init__(self) -> None:
        if not (self.turn_horizon >= 0.0 and self.turn_margin > 0.0):
            raise ValueError("turn_horizon must be >= 0 s and turn_margin > 0 m")
        if not 0.0 < self.turn_share <= 1.0:
            raise ValueError("turn_share must be > 0 and <= 1")


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
    # (the rounding allowance can skip a level just above z_min: take it back)
    first = np.where((first >= 1.0) & (low + (first - 1.0) * height_step > params.z_min),
                     first - 1.0, first)
    z = low + first * height_step  # the lowest level above z_min
    top = np.floor((high - low) / height_step + 1e-9)  # the highest (``PointCloud.points``)
    keep = ((z < params.z_max) & (first <= top)
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


def predicted_points(points: FloatArray, velocity: FloatArray, moving: NDArray[np.bool_],
                     heading: float, age: float) -> FloatArray:
    """Where the moving points will be (M, 2), ``base_link``: points (N, 2) in ``base_link``,
    those with ``moving`` (N,) moved on at their ``velocity`` (N, 2), m/s in the map frame
    the robot's ``heading`` (rad) is in, for ``age`` s (the data's age)."""
    c, s = math.cos(heading), math.sin(heading)
    vx, vy = velocity[moving, 0], velocity[moving, 1]  # into base_link (no BLAS: the
    span = max(age, 0.0)  # batched kernel's arithmetic to the last bit)
    return np.column_stack([points[moving, 0] + (vx * c + vy * s) * span,
                            points[moving, 1] + (vx * -s + vy * c) * span])


def predicted_stop_flags(points: FloatArray, velocity: FloatArray, moving: NDArray[np.bool_],
                         heading: float, age: float, length: float, width: float,
                         params: DetectorParams = DetectorParams()) -> StopFlags:
    """:func:`stop_flags` on where moving points will be (:func:`predicted_points`); the
    others are left out (they stand, and :func:`stop_flags` on the cloud already sees
    them). The ``predicted`` stop rule (``robot.STOP_RULES``)."""
    if not moving.any():
        return StopFlags(False, False)
    return stop_flags(predicted_points(points, velocity, moving, heading, age), length,
                      width, params)


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


def footprint_clearance(points: FloatArray, length: float, width: float) -> float:
    """The smallest distance (m) from obstacle points (M, 2) in ``base_link`` to the robot's
    footprint (0 for a point on or in it; inf without points)."""
    if len(points) == 0:
        return math.inf
    outside = np.maximum(np.abs(points) - np.array([0.5 * length, 0.5 * width]), 0.0)
    return float(np.hypot(outside[:, 0], outside[:, 1]).min())


def turn_reach(length: float, width: float, linear: float,
               params: DetectorParams = DetectorParams(), share: float = 1.0) -> float:
    """How far from the footprint (m) a point can be and still block the robot turning
    within ``params.turn_horizon`` s at ``linear`` m/s: the turn margin and the robot's
    sweep (the corners' swing beyond the sides, half diagonal less the smaller half side, a
    turn on the spot, and the way driven) over ``share``, the share of the gap beyond the
    margin that the turn may close (1.0 for a standing point, ``params.turn_share`` for one
    that may move: :func:`turn_fraction`); :func:`turn_fraction` is needed only for points
    nearer than this."""
    half_l, half_w = 0.5 * length, 0.5 * width
    sweep = math.hypot(half_l, half_w) - min(half_l, half_w) + abs(linear) * params.turn_horizon
    return params.turn_margin + sweep / share


MAX_TURN_SAMPLES = 1000
"""Where :func:`turn_samples` would need more steps than this (speeds no robot drives: a
1.2 m robot at about 50 rad/s), :func:`turn_fraction` allows no turn."""


def turn_samples(length: float, width: float, linear: float, angular: float,
                 params: DetectorParams = DetectorParams(), share: float = 1.0) -> int:
    """How many instants :func:`turn_fraction` checks, evenly over ``params.turn_horizon``:
    at most 0.1 s apart, and so close that a point within :func:`turn_reach` (of ``share``)
    moves at most half the turn margin across the robot between two of them (its speed in
    ``base_link`` is at most |v| + |w| r, r its distance from the middle), so that a point
    the samples keep the turn margin (10 cm) away is never nearer than half of it in
    between; for a ``share`` below 1, the instants of standing points (share 1) and as many
    more between each two as that needs, so that the instants of standing points are always
    among them; 0 when either would take more than :data:`MAX_TURN_SAMPLES` steps."""
    counts = []
    for each in (1.0, share):
        reach = math.hypot(0.5 * length, 0.5 * width) + turn_reach(length, width, linear,
                                                                   params, each)
        step = min(0.1, 0.5 * params.turn_margin / (abs(linear) + abs(angular) * reach))
        needed = params.turn_horizon / step if step > 0.0 else math.inf  # huge: absurd speeds
        if not needed < MAX_TURN_SAMPLES:
            return 0
        counts.append(math.ceil(needed - 1e-9) + 1)
    standing, moving = counts
    if standing <= 1 or moving <= standing:
        return standing
    # the standing points' instants and more (a multiple of their intervals), so that a
    # point that may move never makes the guard miss what it saw of a standing one
    return math.ceil((moving - 1) / (standing - 1)) * (standing - 1) + 1


TURN_FRACTIONS = (1.0, 0.5, 0.25, 0.0)
"""The fractions of a commanded angular speed :func:`turn_fraction` tries, largest first."""


def turn_fraction(points: FloatArray, length: float, width: float, linear: float,
                  angular: float, params: DetectorParams = DetectorParams(),
                  moving: NDArray[np.bool_] | None = None) -> float:
    """The largest of :data:`TURN_FRACTIONS` of ``angular`` (rad/s) at which the robot,
    driving ``linear`` (m/s) on that arc for ``params.turn_horizon`` s (at
    :func:`turn_samples` instants), brings no obstacle point (M, 2) in ``base_link`` nearer
    than its :func:`turn_floor` of the nearest it comes driving straight: within
    ``params.turn_margin`` m of its footprint, nor, for the points that may move themselves
    (``moving`` (M,); None: none, every point stands), more than ``params.turn_share`` of
    the way from that gap to the margin (the rest is the point's own, a mate beside the
    robot that turns too: two robots that both turn close the gap between them to the
    margin at most), nor nearer than driving straight if that is within the margin (the
    stop flags are for what driving straight brings near). 0.0 when only driving straight
    does, and for speeds that are not finite or too fast to sample
    (:data:`MAX_TURN_SAMPLES`) (an addition; thesis ch. 5.2 stops the robot only ahead and
    behind, and a skid-steer robot's corners swing out as it turns: a 1.2 m robot turning
    on a 0.25 m radius sweeps its tail 0.26 m beyond its side)."""
    if len(points) == 0 or angular == 0.0:
        return 1.0
    if not (math.isfinite(linear) and math.isfinite(angular)):
        return 0.0  # no turn that cannot be predicted
    shares = (np.ones(len(points)) if moving is None
              else np.where(moving, params.turn_share, 1.0))  # (M,)
    half_l, half_w = 0.5 * length, 0.5 * width
    sweep = math.hypot(half_l, half_w) - min(half_l, half_w) + abs(linear) * params.turn_horizon
    within = np.hypot(*np.maximum(np.abs(points) - [half_l, half_w], 0.0).T) < (
        params.turn_margin + sweep / shares)  # turn_reach of each point
    points, shares = points[within], shares[within]
    if len(points) == 0:
        return 1.0
    samples = turn_samples(length, width, linear, angular, params, float(shares.min()))
    if samples == 0:
        return 0.0
    half = np.array([half_l, half_w])
    times = np.linspace(0.0, params.turn_horizon, samples)  # (K,)
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
    floor = turn_floor(nearest[-1], params.turn_margin, shares) - 1e-9  # (M,)
    bad = (nearest < floor) & (nearest < nearest[-1] - 1e-9)  # worse than straight, too near
    for fraction, blocked in zip(TURN_FRACTIONS, bad.any(axis=1), strict=True):
        if not blocked:
            return fraction
    return 0.0


def turn_floor(gap: FloatArray, margin: float, share: FloatArray | float) -> FloatArray:
    """How near (m) a turn may bring points that driving straight brings ``gap`` (M,) m from
    the footprint: the gap less ``share`` (M,) or one for all of its part beyond ``margin``
    (m): the margin for a standing point (share 1), the gap itself within the margin
    (:func:`turn_fraction`)."""
    result: FloatArray = gap - share * np.maximum(gap - margin, 0.0)
    return result


def near_any(points: FloatArray, centres: FloatArray, radius: float) -> NDArray[np.bool_]:
    """(M,) whether each point (M, 2) lies within ``radius`` m of any of ``centres`` (K, 2),
    same frame (a centre that is not a number is near everything; no centre: none)."""
    gaps = np.hypot(points[:, None, 0] - centres[None, :, 0],
                    points[:, None, 1] - centres[None, :, 1])  # (M, K)
    near: NDArray[np.bool_] = np.any(~(gaps > radius), axis=1)
    return near


def compensate_motion(points: FloatArray, pose_at_stamp: tuple[float, float, float],
                      pose_now: tuple[float, float, float]) -> FloatArray:
    """Points (M, 2) seen in ``base_link`` at the cloud's stamp, expressed in ``base_link``
    now, from the robot's own poses (odometry, any fixed frame) then and now."""
    return points_to_local(points_to_world(points, pose_at_stamp), pose_now)


def obstacle_points_now(columns: FloatArray, height_step: float,
                        seen_from: tuple[float, float, float], pose: tuple[float, float, float],
                        params: DetectorParams = DetectorParams()) -> FloatArray:
    """The obstacle points (M, 2) of a cloud's columns (K, 4) taken in ``base_link`` at the
    own pose ``seen_from``, in ``base_link`` at the own pose ``pose`` now
    (:func:`obstacle_points_from_columns`, then :func:`compensate_motion` when the robot
    moved)."""
    points = obstacle_points_from_columns(columns, height_step, params)
    return points if seen_from == pose else compensate_motion(points, seen_from, pose)


@dataclass(frozen=True, slots=True)
class Perception:
    """Everything a control tick needs from the obstacle points, computed in one pass:
    the stop flags, the free distances ahead and behind (m), whether turning left / right is
    allowed, and the virtual force (Fx, Fy) in ``base_link``."""

    flags: StopFlags
    front_free: float
    rear_free: float
    nearest: float
    force: tuple[float, float]


CLEAR = Perception(StopFlags(False, False), math.inf, math.inf, math.inf, (0.0, 0.0))


def perceive(points: FloatArray, length: float, width: float,
             params: DetectorParams = DetectorParams(), force_radius: float = 1.0,
             force_gain: float = 0.02) -> Perception:
    """Everything a control tick needs from the obstacle points (M, 2) in ``base_link``:
    :func:`clear_distances` (and the stop flags they imply), :func:`rotation_allowed` and
    ``control.force_field.repulsive_force``. ``perception.fast`` compiles the same pass."""
    if len(points) == 0:
        return CLEAR
    front, rear = clear_distances(points, length, width, params)
    nearest = footprint_clearance(points, length, width)
    force = repulsive_force(points, length, width, force_radius, force_gain) if (
        force_radius > 0) else (0.0, 0.0)
    return Perception(StopFlags(front < params.stop_distance, rear < params.stop_distance),
                      front, rear, nearest, force)

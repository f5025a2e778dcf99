"""The per-tick perception of ``perception.obstacles`` compiled with numba, in one loop.

Same results as ``compensate_motion`` followed by ``perceive`` (the tests hold them equal);
the NumPy functions remain the readable reference. Called for every robot ten times a second,
where NumPy's per-call overhead on a few hundred points would dominate.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import NDArray

__all__ = ["perceive_columns", "perceive_moved"]


@njit(cache=True)
def perceive_columns(columns: NDArray[np.float64], height_step: float, crop_half: float,
                     z_min: float, z_max: float, seen_from: NDArray[np.float64],
                     pose: NDArray[np.float64], length: float, width: float,
                     stop_distance: float, corridor_margin: float, turn_guard: float,
                     force_radius: float, force_gain: float,
                     ) -> tuple[float, float, bool, bool, bool, bool, float, float]:
    """A cloud stored as columns (K, 4) (see ``PointCloud``): its obstacle points (crop and
    height filter of ``obstacle_points_from_columns``), then :func:`perceive_moved`."""
    keep = np.zeros(columns.shape[0], dtype=np.bool_)
    for i in range(columns.shape[0]):
        low, high = columns[i, 2], columns[i, 3]
        first = 0.0 if low > z_min else math.floor((z_min - low) / height_step + 1e-9) + 1.0
        z = low + first * height_step
        keep[i] = (z < z_max and z <= high + 1e-9 and abs(columns[i, 0]) <= crop_half
                   and abs(columns[i, 1]) <= crop_half)
    return perceive_moved(columns[keep, :2], seen_from, pose, length, width, stop_distance,
                          corridor_margin, turn_guard, force_radius, force_gain)


@njit(cache=True)
def perceive_moved(points: NDArray[np.float64], seen_from: NDArray[np.float64],
                   pose: NDArray[np.float64], length: float, width: float,
                   stop_distance: float, corridor_margin: float, turn_guard: float,
                   force_radius: float, force_gain: float,
                   ) -> tuple[float, float, bool, bool, bool, bool, float, float]:
    """Obstacle points (M, 2) in ``base_link`` at ``seen_from`` (x, y, theta), moved to the
    robot's ``pose`` (same frame), then: free distance ahead and behind (m), a point near
    the footprint front-left, front-right, rear-left, rear-right (``near_quadrants``), force
    (Fx, Fy). See ``perception.obstacles.perceive``."""
    c0, s0 = math.cos(seen_from[2]), math.sin(seen_from[2])
    c1, s1 = math.cos(pose[2]), math.sin(pose[2])
    half_l, half_w = 0.5 * length, 0.5 * width
    front, rear = math.inf, math.inf
    front_left, front_right, rear_left, rear_right = False, False, False, False
    fx, fy = 0.0, 0.0
    for i in range(points.shape[0]):
        wx = seen_from[0] + c0 * points[i, 0] - s0 * points[i, 1] - pose[0]
        wy = seen_from[1] + s0 * points[i, 0] + c0 * points[i, 1] - pose[1]
        x = c1 * wx + s1 * wy
        y = -s1 * wx + c1 * wy
        if abs(y) <= half_w + corridor_margin:
            if x >= half_l - 1e-9:
                front = min(front, x - half_l)
            if x <= -half_l + 1e-9:
                rear = min(rear, -x - half_l)
        nx = min(max(x, -half_l), half_l)
        ny = min(max(y, -half_w), half_w)
        ax, ay = nx - x, ny - y
        d = math.hypot(ax, ay)
        if d < turn_guard:
            if x > 0 and y > 0:
                front_left = True
            elif x > 0 and y < 0:
                front_right = True
            elif x < 0 and y > 0:
                rear_left = True
            elif x < 0 and y < 0:
                rear_right = True
        if force_radius > 0 and 1e-9 < d < force_radius:
            weight = force_gain * (1.0 - d / force_radius) ** 2 / d
            fx += ax * weight
            fy += ay * weight
    return front, rear, front_left, front_right, rear_left, rear_right, fx, fy

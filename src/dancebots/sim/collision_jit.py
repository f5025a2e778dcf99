"""The collision tests of ``sim.collision`` compiled with numba: the same separating-axis
test and segment proximity as loops (NumPy's per-call cost dominates for a few robots).
Importing this module imports numba; ``sim.collision`` imports it only when asked to."""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import NDArray

__all__ = ["footprint_gap", "near_segments", "overlapping_pairs"]

FloatArray = NDArray[np.float64]


@njit(cache=True)
def footprint_gap(dx: float, dy: float, cos: float, sin: float, half_length: float,
                  half_width: float) -> float:
    """The distance (m) from a point ``(dx, dy)`` from a robot's centre (world axes) to its
    footprint (heading's cos and sin, half sizes, m); 0 on or in it
    (``collision.footprint_gaps`` for one point, the same arithmetic)."""
    ex = max(abs(cos * dx + sin * dy) - half_length, 0.0)
    ey = max(abs(-sin * dx + cos * dy) - half_width, 0.0)
    return math.hypot(ex, ey)


@njit(cache=True)
def _separated(first: FloatArray, second: FloatArray, along: FloatArray) -> bool:
    """Do two rectangles (4, 2) lie apart along both edge directions of ``along`` (4, 2)?"""
    for axis in range(2):
        ax = along[axis + 1, 0] - along[axis, 0]
        ay = along[axis + 1, 1] - along[axis, 1]
        low_a = low_b = np.inf
        high_a = high_b = -np.inf
        for c in range(4):
            pa = ax * first[c, 0] + ay * first[c, 1]
            pb = ax * second[c, 0] + ay * second[c, 1]
            low_a, high_a = min(low_a, pa), max(high_a, pa)
            low_b, high_b = min(low_b, pb), max(high_b, pb)
        if high_a <= low_b or high_b <= low_a:
            return True
    return False


@njit(cache=True)
def overlapping_pairs(corners: FloatArray, reach: FloatArray) -> NDArray[np.int64]:
    """(P, 2) index pairs of overlapping rectangles: the separating-axis test of
    :func:`rectangles_overlap` on the pairs whose centres are nearer than their reaches."""
    count = corners.shape[0]
    result = np.empty((max(count * (count - 1) // 2, 0), 2), dtype=np.int64)
    found = 0
    for i in range(count):
        xi = 0.5 * (corners[i, 0, 0] + corners[i, 2, 0])
        yi = 0.5 * (corners[i, 0, 1] + corners[i, 2, 1])
        for j in range(i + 1, count):
            xj = 0.5 * (corners[j, 0, 0] + corners[j, 2, 0])
            yj = 0.5 * (corners[j, 0, 1] + corners[j, 2, 1])
            if math.hypot(xi - xj, yi - yj) >= reach[i] + reach[j]:
                continue
            if _separated(corners[i], corners[j], corners[i]) or _separated(
                    corners[i], corners[j], corners[j]):
                continue
            result[found, 0], result[found, 1] = i, j
            found += 1
    return result[:found]


@njit(cache=True)
def near_segments(centres: FloatArray, reach: FloatArray, start: FloatArray,
                   direction: FloatArray, length2: FloatArray) -> NDArray[np.bool_]:
    """(R, E): is each centre (R, 2) within its reach (R,) of each segment (start (E, 2),
    direction (E, 2), squared length (E,))?"""
    result = np.zeros((centres.shape[0], start.shape[0]), dtype=np.bool_)
    for r in range(centres.shape[0]):
        for e in range(start.shape[0]):
            rx, ry = centres[r, 0] - start[e, 0], centres[r, 1] - start[e, 1]
            u = min(max((rx * direction[e, 0] + ry * direction[e, 1]) / length2[e], 0.0), 1.0)
            result[r, e] = math.hypot(rx - u * direction[e, 0],
                                      ry - u * direction[e, 1]) < reach[r]
    return result

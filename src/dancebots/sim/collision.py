"""Collision tests between robot rectangles, and between robots and walls or obstacles.

Vectorised over robots: corners have shape (R, 4, 2) (see ``geometry.footprint_corners``).
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from numba import njit
from numpy.typing import NDArray

from dancebots.geometry import points_in_frames

__all__ = ["Boundaries", "disc_contacts", "overlapping_pairs", "rectangles_overlap"]

FloatArray = NDArray[np.float64]


def rectangles_overlap(first: FloatArray, second: FloatArray) -> NDArray[np.bool_]:
    """Separating-axis test for pairs of rectangles (P, 4, 2) and (P, 4, 2) -> (P,) bool.

    Touching rectangles (zero gap) do not overlap.
    """
    edges = np.concatenate([first[:, 1:3] - first[:, 0:2], second[:, 1:3] - second[:, 0:2]],
                           axis=1)  # (P, 4, 2): two edge directions of each rectangle
    proj_a = np.einsum("pkd,pcd->pkc", edges, first)  # (P, 4 axes, 4 corners)
    proj_b = np.einsum("pkd,pcd->pkc", edges, second)
    separated = (proj_a.max(axis=2) <= proj_b.min(axis=2)) | (
        proj_b.max(axis=2) <= proj_a.min(axis=2))
    result: NDArray[np.bool_] = ~separated.any(axis=1)
    return result


def overlapping_pairs(corners: FloatArray, reach: FloatArray) -> list[tuple[int, int]]:
    """All pairs (i < j) of robots whose rectangles (R, 4, 2) overlap (a zero gap is no
    overlap); ``reach`` (R,) is each robot's half diagonal, used to skip pairs whose centres
    are too far apart. Compiled loops: NumPy's per-call cost dominates for a few robots."""
    pairs = _overlapping_pairs(np.ascontiguousarray(corners, dtype=np.float64),
                               np.asarray(reach, dtype=np.float64))
    return [(int(i), int(j)) for i, j in pairs]


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
def _overlapping_pairs(corners: FloatArray, reach: FloatArray) -> NDArray[np.int64]:
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
def _near_segments(centres: FloatArray, reach: FloatArray, start: FloatArray,
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


def _centres(corners: FloatArray) -> FloatArray:
    """The centres (R, 2) of rectangles (R, 4, 2): the middle of a diagonal."""
    result: FloatArray = 0.5 * (corners[:, 0] + corners[:, 2])
    return result


class Boundaries:
    """The room and the obstacles, ready for fast per-step tests.

    room: polygon (N, 2); obstacles: polygons (M_k, 2), all in the world frame, m.
    """

    def __init__(self, room: FloatArray, obstacles: list[FloatArray]) -> None:
        self.room = shapely.Polygon(room)
        shapely.prepare(self.room)
        self.obstacles = [shapely.Polygon(o) for o in obstacles]
        for obstacle in self.obstacles:
            shapely.prepare(obstacle)
        segments = [self._segments(room)] + [self._segments(o) for o in obstacles]
        every = np.concatenate(segments)  # (E, 2, 2)
        self._owner = np.concatenate([np.full(len(s), k - 1) for k, s in enumerate(segments)])
        self._start = np.ascontiguousarray(every[:, 0])  # (E, 2)
        self._direction = every[:, 1] - self._start
        self._length2 = np.maximum((self._direction**2).sum(axis=1), 1e-12)

    @staticmethod
    def _segments(polygon: FloatArray) -> FloatArray:
        return np.stack([polygon, np.concatenate([polygon[1:], polygon[:1]])], axis=1)

    def _near(self, centres: FloatArray, reach: FloatArray) -> NDArray[np.bool_]:
        """(R, E): is each robot's centre within its reach of each boundary segment."""
        return _near_segments(np.ascontiguousarray(centres), np.asarray(reach, dtype=float),
                              self._start, self._direction, self._length2)

    def contacts(self, corners: FloatArray, reach: FloatArray) -> list[tuple[int, int]]:
        """(robot, what) for every robot touching a wall (what = -1) or inside or touching
        obstacle k (what = k); a robot entirely outside the room counts as at the wall."""
        centres = _centres(corners)
        near = self._near(centres, reach)
        inside_room = shapely.contains_xy(self.room, centres[:, 0], centres[:, 1])
        result: list[tuple[int, int]] = []
        for robot in np.flatnonzero(near.any(axis=1) | ~inside_room).tolist():
            shape = shapely.Polygon(corners[robot])
            if not inside_room[robot] or not self.room.contains(shape):
                result.append((robot, -1))
            for k, obstacle in enumerate(self.obstacles):
                if near[robot, self._owner == k].any() and obstacle.intersects(shape):
                    result.append((robot, k))
        for k, obstacle in enumerate(self.obstacles):  # a robot entirely inside an obstacle
            inside = shapely.contains_xy(obstacle, centres[:, 0], centres[:, 1])
            for robot in np.flatnonzero(inside & ~near[:, self._owner == k].any(axis=1)).tolist():
                result.append((robot, k))
        return result


def disc_contacts(poses: FloatArray, lengths: FloatArray, widths: FloatArray,
                  discs: FloatArray) -> list[tuple[int, int]]:
    """(robot, disc) pairs whose footprint (poses (R, 3)) and disc (C, 3) overlap."""
    if len(discs) == 0:
        return []
    local = points_in_frames(discs[None, :, :2], poses[:, None, :])  # (R, C, 2)
    lx, ly = local[..., 0], local[..., 1]
    ex = np.maximum(np.abs(lx) - 0.5 * lengths[:, None], 0.0)
    ey = np.maximum(np.abs(ly) - 0.5 * widths[:, None], 0.0)
    r, k = np.nonzero(np.hypot(ex, ey) < discs[None, :, 2])
    return list(zip(r.tolist(), k.tolist(), strict=True))

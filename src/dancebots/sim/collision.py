"""Collision tests between robot rectangles, and between robots and walls or obstacles.

Vectorised over robots: corners have shape (R, 4, 2) (see ``geometry.footprint_corners``).
"""

from __future__ import annotations

import numpy as np
import shapely
from numpy.typing import NDArray

__all__ = ["Boundaries", "overlapping_pairs", "rectangles_overlap"]

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
    """All pairs (i < j) of robots whose rectangles overlap; ``reach`` (R,) is each robot's
    half diagonal, used to skip pairs whose centres are too far apart."""
    centres = corners.mean(axis=1)
    count = len(centres)
    if count < 2:
        return []
    i, j = np.triu_indices(count, k=1)
    near = np.hypot(*(centres[i] - centres[j]).T) < reach[i] + reach[j]
    i, j = i[near], j[near]
    if i.size == 0:
        return []
    hit = rectangles_overlap(corners[i], corners[j])
    return list(zip(i[hit].tolist(), j[hit].tolist(), strict=True))


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
        self._segments_all = np.concatenate(segments)  # (E, 2, 2)
        self._owner = np.concatenate([np.full(len(s), k - 1) for k, s in enumerate(segments)])

    @staticmethod
    def _segments(polygon: FloatArray) -> FloatArray:
        return np.stack([polygon, np.concatenate([polygon[1:], polygon[:1]])], axis=1)

    def _near(self, centres: FloatArray, reach: FloatArray) -> NDArray[np.bool_]:
        """(R, E): is each robot's centre within its reach of each boundary segment."""
        start = self._segments_all[:, 0]  # (E, 2)
        direction = self._segments_all[:, 1] - start
        length2 = np.maximum((direction**2).sum(axis=1), 1e-12)
        rel = centres[:, None, :] - start[None, :, :]  # (R, E, 2)
        u = np.clip((rel * direction).sum(axis=2) / length2, 0.0, 1.0)
        closest = start[None] + u[..., None] * direction[None]
        distance = np.hypot(*(centres[:, None, :] - closest).transpose(2, 0, 1))
        result: NDArray[np.bool_] = distance < reach[:, None]
        return result

    def contacts(self, corners: FloatArray, reach: FloatArray) -> list[tuple[int, int]]:
        """(robot, what) for every robot touching a wall (what = -1) or inside or touching
        obstacle k (what = k); a robot entirely outside the room counts as at the wall."""
        centres = corners.mean(axis=1)
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

"""Collision tests between robot rectangles, and between robots and walls or obstacles.

Vectorised over robots: corners have shape (R, 4, 2) (see ``geometry.footprint_corners``).
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from numpy.typing import NDArray

from dancebots.geometry import points_in_frames

__all__ = ["Boundaries", "closing_speed", "disc_contacts", "footprint_gaps",
           "overlapping_pairs", "rectangles_overlap"]

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


def overlapping_pairs(corners: FloatArray, reach: FloatArray,
                      compiled: bool = True) -> list[tuple[int, int]]:
    """All pairs (i < j) of robots whose rectangles (R, 4, 2) overlap (a zero gap is no
    overlap); ``reach`` (R,) is each robot's half diagonal, used to skip pairs whose centres
    are too far apart. ``compiled``: the numba loops (``sim.collision_jit``: NumPy's
    per-call cost dominates for a few robots), else :func:`rectangles_overlap` on the pairs
    near enough (same pairs)."""
    corners = np.ascontiguousarray(corners, dtype=np.float64)
    reach = np.asarray(reach, dtype=np.float64)
    if compiled:
        from dancebots.sim.collision_jit import overlapping_pairs as compiled_pairs

        return [(int(i), int(j)) for i, j in compiled_pairs(corners, reach)]
    first, second = np.triu_indices(len(corners), k=1)
    centres = _centres(corners)
    near = np.hypot(*(centres[first] - centres[second]).T) < reach[first] + reach[second]
    first, second = first[near], second[near]
    hit = rectangles_overlap(corners[first], corners[second])
    return list(zip(first[hit].tolist(), second[hit].tolist(), strict=True))


def _centres(corners: FloatArray) -> FloatArray:
    """The centres (R, 2) of rectangles (R, 4, 2): the middle of a diagonal."""
    result: FloatArray = 0.5 * (corners[:, 0] + corners[:, 2])
    return result


class Boundaries:
    """The room and the obstacles, ready for fast per-step tests.

    room: polygon (N, 2); obstacles: polygons (M_k, 2), all in the world frame, m.
    """

    def __init__(self, room: FloatArray, obstacles: list[FloatArray],
                 compiled: bool = True) -> None:
        self.compiled = compiled
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

    def edges(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Every edge of the room and the obstacles: starts (E, 2), directions (E, 2) and
        squared lengths (E,), m."""
        return self._start, self._direction, self._length2

    @staticmethod
    def _segments(polygon: FloatArray) -> FloatArray:
        return np.stack([polygon, np.concatenate([polygon[1:], polygon[:1]])], axis=1)

    def _near(self, centres: FloatArray, reach: FloatArray) -> NDArray[np.bool_]:
        """(R, E): is each robot's centre within its reach of each boundary segment."""
        reach = np.asarray(reach, dtype=float)
        if self.compiled:
            from dancebots.sim.collision_jit import near_segments

            result: NDArray[np.bool_] = near_segments(
                np.ascontiguousarray(centres), reach, self._start, self._direction,
                self._length2)
            return result
        relative = centres[:, None, :] - self._start[None]  # (R, E, 2)
        along = np.clip((relative * self._direction[None]).sum(axis=2) / self._length2,
                        0.0, 1.0)  # (R, E)
        gap = relative - along[..., None] * self._direction[None]
        near: NDArray[np.bool_] = np.hypot(gap[..., 0], gap[..., 1]) < reach[:, None]
        return near

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


def footprint_gaps(points: FloatArray, poses: FloatArray, lengths: FloatArray | float,
                   widths: FloatArray | float) -> FloatArray:
    """The distance (m) from points (..., 2) to the footprints of robots at poses (..., 3)
    with sizes (...), all in one frame; the shapes broadcast (as
    ``geometry.points_in_frames``): 0 for a point on or in a footprint."""
    local = points_in_frames(points, poses)
    ex = np.maximum(np.abs(local[..., 0]) - 0.5 * np.asarray(lengths), 0.0)
    ey = np.maximum(np.abs(local[..., 1]) - 0.5 * np.asarray(widths), 0.0)
    result: FloatArray = np.hypot(ex, ey)
    return result


def disc_contacts(poses: FloatArray, lengths: FloatArray, widths: FloatArray,
                  discs: FloatArray) -> list[tuple[int, int]]:
    """(robot, disc) pairs whose footprint (poses (R, 3)) and disc (C, 3) overlap."""
    if len(discs) == 0:
        return []
    gaps = footprint_gaps(discs[None, :, :2], poses[:, None, :], lengths[:, None],
                          widths[:, None])  # (R, C)
    r, k = np.nonzero(gaps < discs[None, :, 2])
    return list(zip(r.tolist(), k.tolist(), strict=True))


def closing_speed(pose: FloatArray, velocity: FloatArray, length: float, width: float,
                  point: FloatArray) -> float:
    """The speed (m/s) at which a robot at ``pose`` (3,) driving at ``velocity`` (v m/s, w
    rad/s) moves the point of its footprint (``length`` x ``width`` m) nearest ``point`` (2,),
    world frame, towards it: positive driving or turning at it, negative moving away, 0
    standing still or sliding past; ISO/TS 15066's speed of the robot towards the person
    (for a point inside the footprint, along the line from the robot's centre)."""
    c, s = math.cos(float(pose[2])), math.sin(float(pose[2]))
    dx, dy = float(point[0]) - float(pose[0]), float(point[1]) - float(pose[1])
    lx, ly = c * dx + s * dy, -s * dx + c * dy  # base_link
    px = min(max(lx, -0.5 * length), 0.5 * length)
    py = min(max(ly, -0.5 * width), 0.5 * width)
    nx, ny = lx - px, ly - py
    if math.hypot(nx, ny) < 1e-9:  # inside: the way from the centre
        nx, ny = lx, ly
    norm = math.hypot(nx, ny)
    if norm < 1e-9:
        return 0.0
    v, w = float(velocity[0]), float(velocity[1])
    return ((v - w * py) * nx + w * px * ny) / norm

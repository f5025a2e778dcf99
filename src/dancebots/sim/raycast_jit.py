"""The LIDAR ray caster compiled with numba: the same geometry as ``sim.raycast``, as loops.

NumPy's per-call overhead dominates the vectorised caster for a few robots; compiled loops
over (robot, candidate segment, ray) avoid it. ``tests/sim/test_lidar.py`` holds the results
equal to the NumPy kernels. Shapes: R sensors, N rays, S segments, C discs, W wall edges.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import NDArray

__all__ = ["cast_scene"]

FloatArray = NDArray[np.float64]


@njit(cache=True)
def cast_scene(origins: FloatArray, headings: FloatArray, angles: FloatArray,
               segments: FloatArray, owner: NDArray[np.int64], heights: FloatArray,
               discs: FloatArray, disc_heights: FloatArray, walls: FloatArray,
               max_range: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Per sensor and ray: the nearest solid hit (robots' and obstacles' edges, discs), its
    height, and the distance to the room's walls.

    origins (R, 2), headings (R,), angles (N,) relative to the heading, segments (S, 2, 2)
    with owner (S,) (the robot they belong to, -1 for obstacles; a sensor skips its own) and
    heights (S,), discs (C, 3) with heights (C,), walls (W, 2, 2). Edges facing away from a
    sensor (outlines are counter-clockwise) and edges beyond max_range are skipped.
    Returns solid (R, N), solid_height (R, N), wall (R, N); inf where nothing is hit.
    """
    count, rays = origins.shape[0], angles.shape[0]
    solid = np.full((count, rays), np.inf)
    solid_height = np.zeros((count, rays))
    wall = np.full((count, rays), np.inf)
    candidates = np.empty(segments.shape[0], dtype=np.int64)
    for r in range(count):
        ox, oy = origins[r, 0], origins[r, 1]
        found = 0
        for s in range(segments.shape[0]):
            if owner[s] == r:
                continue
            px, py = segments[s, 0, 0], segments[s, 0, 1]
            ex, ey = segments[s, 1, 0] - px, segments[s, 1, 1] - py
            if (px - ox) * ey - (py - oy) * ex >= 0.0:  # back face
                continue
            length2 = ex * ex + ey * ey
            u = ((ox - px) * ex + (oy - py) * ey) / length2 if length2 > 0 else 0.0
            u = min(max(u, 0.0), 1.0)
            if math.hypot(px + u * ex - ox, py + u * ey - oy) > max_range:
                continue
            candidates[found] = s
            found += 1
        # each candidate edge only against the rays inside its angular span (rays evenly
        # spaced over the full circle from angles[0])
        step = 2.0 * math.pi / rays
        for c in range(found):
            s = candidates[c]
            px, py = segments[s, 0, 0], segments[s, 0, 1]
            ex, ey = segments[s, 1, 0] - px, segments[s, 1, 1] - py
            a0 = math.atan2(py - oy, px - ox) - headings[r] - angles[0]
            a1 = math.atan2(py + ey - oy, px + ex - ox) - headings[r] - angles[0]
            first = a0 % (2.0 * math.pi)
            span = (a1 - a0) % (2.0 * math.pi)
            if span > math.pi:
                first = a1 % (2.0 * math.pi)
                span = 2.0 * math.pi - span
            start = int(math.floor(first / step))  # noqa: RUF046 (explicit for numba)
            size = int(math.floor((first + span) / step)) - start + 2  # noqa: RUF046
            qx, qy = px - ox, py - oy
            for j in range(size):
                k = (start + j) % rays
                angle = headings[r] + angles[k]
                dx, dy = math.cos(angle), math.sin(angle)
                denominator = dx * ey - dy * ex
                if abs(denominator) <= 1e-12:
                    continue
                t = (qx * ey - qy * ex) / denominator
                u = (qx * dy - qy * dx) / denominator
                if t >= 0.0 and 0.0 <= u <= 1.0 and t < solid[r, k]:
                    solid[r, k] = t
                    solid_height[r, k] = heights[s]
        for k in range(rays):
            angle = headings[r] + angles[k]
            dx, dy = math.cos(angle), math.sin(angle)
            best, best_height = solid[r, k], solid_height[r, k]
            for c in range(discs.shape[0]):
                rx, ry = ox - discs[c, 0], oy - discs[c, 1]
                b = dx * rx + dy * ry
                cc = rx * rx + ry * ry - discs[c, 2] * discs[c, 2]
                disc = b * b - cc
                if cc > 0.0 and disc >= 0.0:
                    t = -b - math.sqrt(disc)
                    if 0.0 <= t < best:
                        best, best_height = t, disc_heights[c]
            solid[r, k], solid_height[r, k] = best, best_height
            nearest = np.inf
            for w in range(walls.shape[0]):
                px, py = walls[w, 0, 0], walls[w, 0, 1]
                ex, ey = walls[w, 1, 0] - px, walls[w, 1, 1] - py
                denominator = dx * ey - dy * ex
                if abs(denominator) <= 1e-12:
                    continue
                qx, qy = px - ox, py - oy
                t = (qx * ey - qy * ex) / denominator
                u = (qx * dy - qy * dx) / denominator
                if t >= 0.0 and 0.0 <= u <= 1.0 and t < nearest:
                    nearest = t
            wall[r, k] = nearest
    return solid, solid_height, wall


@njit(cache=True)
def build_columns(solid: FloatArray, solid_height: FloatArray, wall: FloatArray,
                  angles: FloatArray, min_range: float, max_range: float,
                  wall_height: float) -> tuple[FloatArray, NDArray[np.int64]]:
    """The thesis's height columns of every ray, robot by robot: the solid hit (0 to its
    height) and the upper half of the wall behind it, or the whole wall when nothing stands
    before it; nothing nearer than min_range or beyond max_range. Returns columns (K, 4) =
    x, y, z_low, z_high in ``base_link``, robot after robot, and each robot's count (R,)."""
    count, rays = solid.shape
    counts = np.zeros(count, dtype=np.int64)
    for r in range(count):
        for k in range(rays):
            blocked = solid[r, k] < wall[r, k]
            if blocked and min_range <= solid[r, k] <= max_range:
                counts[r] += 1
            if wall[r, k] <= max_range:
                counts[r] += 1
    columns = np.empty((counts.sum(), 4))
    i = 0
    for r in range(count):
        for k in range(rays):
            c, s = math.cos(angles[k]), math.sin(angles[k])
            blocked = solid[r, k] < wall[r, k]
            if blocked and min_range <= solid[r, k] <= max_range:
                columns[i, 0], columns[i, 1] = solid[r, k] * c, solid[r, k] * s
                columns[i, 2], columns[i, 3] = 0.0, solid_height[r, k]
                i += 1
            if wall[r, k] <= max_range:
                columns[i, 0], columns[i, 1] = wall[r, k] * c, wall[r, k] * s
                columns[i, 2] = 0.5 * wall_height if blocked else 0.0
                columns[i, 3] = wall_height
                i += 1
    return columns, counts

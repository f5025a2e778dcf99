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

__all__ = ["build_columns", "cast_scene", "ray_turns"]

FloatArray = NDArray[np.float64]


@njit(cache=True)
def _ray_span(ax: float, ay: float, bx: float, by: float, base: float,
              rays: int) -> tuple[int, int]:
    """The rays (first index, count) that can cross the segment from (ax, ay) to (bx, by),
    both relative to the sensor, for ``rays`` rays evenly spaced over the circle from the
    world angle ``base``: the segment's angular span (at most pi) with one ray of margin."""
    step = 2.0 * math.pi / rays
    a0 = math.atan2(ay, ax) - base
    a1 = math.atan2(by, bx) - base
    first = a0 % (2.0 * math.pi)
    span = (a1 - a0) % (2.0 * math.pi)
    if span > math.pi:
        first = a1 % (2.0 * math.pi)
        span = 2.0 * math.pi - span
    start = int(math.floor(first / step))  # noqa: RUF046 (explicit for numba)
    size = int(math.floor((first + span) / step)) - start + 2  # noqa: RUF046
    return start, min(size, rays)


@njit(cache=True)
def _ray_hit(dx: float, dy: float, qx: float, qy: float, ex: float, ey: float) -> float:
    """Distance along the unit ray (dx, dy) from the sensor to the segment that starts at
    (qx, qy) relative to the sensor and runs along (ex, ey); inf when it misses."""
    denominator = dx * ey - dy * ex
    if abs(denominator) <= 1e-12:
        return np.inf
    t = (qx * ey - qy * ex) / denominator
    u = (qx * dy - qy * dx) / denominator
    if t >= 0.0 and 0.0 <= u <= 1.0:
        return t
    return np.inf


@njit(cache=True, nogil=True)
def cast_scene(origins: FloatArray, headings: FloatArray, angles: FloatArray,
               corners: FloatArray, robot_height: float, segments: FloatArray,
               heights: FloatArray, discs: FloatArray, disc_heights: FloatArray,
               walls: FloatArray, max_range: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Per sensor and ray: the nearest solid hit (robots' and obstacles' edges, discs), its
    height, and the distance to the room's walls.

    origins (R, 2), headings (R,), angles (N,) relative to the heading (evenly spaced over
    the circle), corners (R, 4, 2) the robots' footprints (counter-clockwise; a sensor does
    not see its own) of height robot_height, segments (S, 2, 2) the obstacles' edges with
    heights (S,), discs (C, 3) with heights (C,), walls (W, 2, 2). Edges facing away from a
    sensor (outlines are counter-clockwise) and edges beyond max_range are skipped; every
    edge and disc is tested only against the rays inside its angular span.
    Returns solid (R, N), solid_height (R, N), wall (R, N); inf where nothing is hit.
    """
    count, rays = origins.shape[0], angles.shape[0]
    solid = np.full((count, rays), np.inf)
    solid_height = np.zeros((count, rays))
    wall = np.full((count, rays), np.inf)
    ray_x = np.empty(rays)
    ray_y = np.empty(rays)
    # each ray's direction: its angle's unit vector (once per scan) turned by the heading
    # (a rotation per robot instead of two libm calls per ray, which cost half the scan)
    angle_cos, angle_sin = np.empty(rays), np.empty(rays)
    for k in range(rays):  # (libm, as ``sim.raycast`` takes them)
        angle_cos[k], angle_sin[k] = math.cos(angles[k]), math.sin(angles[k])
    for r in range(count):
        ox, oy = origins[r, 0], origins[r, 1]
        base = headings[r] + angles[0]
        heading_cos, heading_sin = math.cos(headings[r]), math.sin(headings[r])
        for k in range(rays):
            ray_x[k] = heading_cos * angle_cos[k] - heading_sin * angle_sin[k]
            ray_y[k] = heading_sin * angle_cos[k] + heading_cos * angle_sin[k]
        for s in range(4 * count + segments.shape[0]):
            if s < 4 * count:  # the other robots' edges
                other, corner = s // 4, s % 4
                if other == r:
                    continue
                ax, ay = corners[other, corner, 0], corners[other, corner, 1]
                bx, by = corners[other, (corner + 1) % 4, 0], corners[other, (corner + 1) % 4, 1]
                height = robot_height
            else:
                e = s - 4 * count
                ax, ay, bx, by = segments[e, 0, 0], segments[e, 0, 1], segments[e, 1, 0], \
                    segments[e, 1, 1]
                height = heights[e]
            qx, qy, ex, ey = ax - ox, ay - oy, bx - ax, by - ay
            if qx * ey - qy * ex >= 0.0:  # back face
                continue
            length2 = ex * ex + ey * ey
            u = -(qx * ex + qy * ey) / length2 if length2 > 0 else 0.0
            u = min(max(u, 0.0), 1.0)
            if math.hypot(qx + u * ex, qy + u * ey) > max_range:
                continue
            start, size = _ray_span(qx, qy, qx + ex, qy + ey, base, rays)
            for j in range(size):
                k = (start + j) % rays
                t = _ray_hit(ray_x[k], ray_y[k], qx, qy, ex, ey)
                if t < solid[r, k]:
                    solid[r, k] = t
                    solid_height[r, k] = height
        for c in range(discs.shape[0]):
            rx, ry = ox - discs[c, 0], oy - discs[c, 1]
            radius = discs[c, 2]
            cc = rx * rx + ry * ry - radius * radius
            if cc <= 0.0:  # the sensor inside the disc sees nothing of it
                continue
            centre = math.atan2(-ry, -rx) - base
            half = math.asin(radius / math.sqrt(rx * rx + ry * ry))
            step = 2.0 * math.pi / rays
            start = int(math.floor(((centre - half) % (2.0 * math.pi)) / step))  # noqa: RUF046
            size = min(int(2.0 * half / step) + 2, rays)
            for j in range(size):
                k = (start + j) % rays
                b = ray_x[k] * rx + ray_y[k] * ry
                disc = b * b - cc
                if disc >= 0.0:
                    t = -b - math.sqrt(disc)
                    if 0.0 <= t < solid[r, k]:
                        solid[r, k], solid_height[r, k] = t, disc_heights[c]
        for w in range(walls.shape[0]):
            qx, qy = walls[w, 0, 0] - ox, walls[w, 0, 1] - oy
            ex, ey = walls[w, 1, 0] - walls[w, 0, 0], walls[w, 1, 1] - walls[w, 0, 1]
            start, size = _ray_span(qx, qy, qx + ex, qy + ey, base, rays)
            for j in range(size):
                k = (start + j) % rays
                t = _ray_hit(ray_x[k], ray_y[k], qx, qy, ex, ey)
                if t < wall[r, k]:
                    wall[r, k] = t
    return solid, solid_height, wall


@njit(cache=True)
def ray_turns(angles: FloatArray) -> FloatArray:
    """The cosines and sines (2, N) of ray angles (N,) for :func:`build_columns` (computed
    once per LIDAR, as the kernel computed them at every scan)."""
    turns = np.empty((2, angles.shape[0]))
    turns[0], turns[1] = np.cos(angles), np.sin(angles)
    return turns


@njit(cache=True, nogil=True)
def build_columns(solid: FloatArray, solid_height: FloatArray, wall: FloatArray,
                  turns: FloatArray, min_range: float, max_range: float,
                  wall_height: float) -> tuple[FloatArray, NDArray[np.int64]]:
    """The thesis's height columns of every ray, robot by robot: the solid hit (0 to its
    height) and the upper half of the wall behind it, or the whole wall when nothing stands
    before it; nothing beyond max_range, and a hit nearer than min_range at min_range (too
    near to measure, but there: ``sim.lidar``). Returns columns (K, 4) =
    x, y, z_low, z_high in ``base_link``, robot after robot, and each robot's count (R,).
    turns (2, N): the cosines and sines of the rays' angles (:func:`ray_turns`)."""
    count, rays = solid.shape
    counts = np.zeros(count, dtype=np.int64)
    for r in range(count):
        for k in range(rays):
            blocked = solid[r, k] < wall[r, k]
            if blocked and solid[r, k] <= max_range:
                counts[r] += 1
            if wall[r, k] <= max_range:
                counts[r] += 1
    columns = np.empty((counts.sum(), 4))
    cosines, sines = turns[0], turns[1]
    i = 0
    for r in range(count):
        for k in range(rays):
            c, s = cosines[k], sines[k]
            blocked = solid[r, k] < wall[r, k]
            if blocked and solid[r, k] <= max_range:
                near = max(solid[r, k], min_range)
                columns[i, 0], columns[i, 1] = near * c, near * s
                columns[i, 2], columns[i, 3] = 0.0, solid_height[r, k]
                i += 1
            if wall[r, k] <= max_range:
                columns[i, 0], columns[i, 1] = wall[r, k] * c, wall[r, k] * s
                columns[i, 2] = 0.5 * wall_height if blocked else 0.0
                columns[i, 3] = wall_height
                i += 1
    return columns, counts

"""One step of the stage where nothing touches, compiled with numba.

``Stage.advance`` moves the robots with NumPy calls (the 10 Hz rule, the actuation
profile, exact arcs, footprints, contact tests), some thirty of them a step: their per-call
cost, not the arithmetic, is most of a step's time for a few robots or twenty.
:func:`free_step` does the same arithmetic in one call, operation for operation as the NumPy
functions do it (the same numbers, bit for bit: tested), and tells whether the step is free
of every contact: no two footprints overlap, no robot comes within its reach of a wall or
an obstacle's edge, every centre lies inside the room and outside every obstacle. Only then
does the stage take it; a step with any contact, or near one, takes the NumPy path, which
counts and reports contacts. Importing this module imports numba.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import NDArray

from dancebots.jit_cache import drop_stale
from dancebots.sim import collision_jit
from dancebots.sim.collision_jit import footprint_gap, near_segments, overlapping_pairs

__all__ = ["compose_turned", "free_step"]

FloatArray = NDArray[np.float64]

EPS = float(np.finfo(np.float64).eps)
"""What ``np.sinc`` puts in place of a zero argument."""


@njit(cache=True)
def _wrap(angle: float) -> float:
    """``geometry.wrap_angles`` of one angle: NumPy's remainder (Python's float modulo),
    then -pi as pi."""
    wrapped = (angle + np.pi) % (2.0 * np.pi) - np.pi
    return np.pi if wrapped == -np.pi else wrapped


@njit(cache=True)
def _inside(x: float, y: float, polygon: FloatArray) -> bool:
    """Is (x, y) inside the polygon (N, 2) (crossing number)? Only asked of points farther
    than a robot's reach from every edge, where it cannot be on one."""
    inside = False
    count = polygon.shape[0]
    for k in range(count):
        x1, y1 = polygon[k, 0], polygon[k, 1]
        x2, y2 = polygon[(k + 1) % count, 0], polygon[(k + 1) % count, 1]
        if (y1 > y) != (y2 > y):
            cross = x1 + (y - y1) * (x2 - x1) / (y2 - y1)
            if x < cross:
                inside = not inside
    return inside


@njit(cache=True)
def free_step(pose: FloatArray, velocity: FloatArray, command: FloatArray,
              issued: FloatArray, now: float, timeout: float, limits: FloatArray,
              noise: FloatArray, discs: FloatArray,
              lagging: bool, lag_factor: float, acceleration: FloatArray,
              standstill: FloatArray,
              dt: float, lengths: FloatArray, widths: FloatArray, reach: FloatArray,
              room: FloatArray, obstacles: FloatArray, obstacle_offsets: NDArray[np.int64],
              start: FloatArray, direction: FloatArray, length2: FloatArray,
              noisy: bool, noise_scale: FloatArray,
              ) -> tuple[FloatArray, FloatArray, FloatArray, bool]:
    """One step of ``dt`` s of robots at pose (R, 3) with velocity (R, 2) under commands
    (R, 2) issued at ``issued`` (R,) s, at ``now`` s, as ``Stage.advance`` takes it without
    engine: the commands clipped to ``limits`` (R, 2) and zero when older than
    ``timeout`` s (``kinematics.fresh_commands``), the velocity after ``actuate`` (with
    ``lagging``, the lag's factor 1 - exp(-dt / lag); ``acceleration`` (2,) the largest
    change a step, m/s and rad/s; ``standstill`` (2,); with ``noisy``, the standard normal
    draws ``noise`` (R, 2) times ``noise_scale`` (2,) on the robots that are driven), exact
    arcs (``geometry.integrate_unicycle``, headings wrapped) and footprints
    (``geometry.footprint_corners``, sizes (R,)). People: discs (C, 3) x, y, radius; a
    footprint within a micrometre of one is a contact (``collision.disc_contacts``).

    The boundaries: the room polygon (W, 2), the obstacles' corners (K, 2), obstacle k's
    rows ``obstacle_offsets[k]:obstacle_offsets[k + 1]``, and every edge (``Boundaries``:
    start (E, 2), direction (E, 2), squared length (E,)); reach (R,) each robot's half
    diagonal.

    Returns the poses (R, 3), corners (R, 4, 2) and velocities (R, 2) after the step, and
    whether it is free of contacts (else the caller takes the step as ``Stage.advance``
    does, and these are not to be used).
    """
    count = pose.shape[0]
    proposed = np.empty((count, 3))
    moved = np.empty((count, 2))
    corners = np.empty((count, 4, 2))
    for r in range(count):  # what is not a number goes the NumPy way
        fresh = (now - issued[r]) <= timeout + 1e-9
        for d in range(3):
            if not math.isfinite(pose[r, d]) or (d < 2 and not (
                    math.isfinite(velocity[r, d])
                    and (math.isfinite(command[r, d]) or not fresh))):
                return proposed, corners, moved, False
    for r in range(count):
        fresh = (now - issued[r]) <= timeout + 1e-9
        driven = 0.0  # (``actuate``: noise only on commanded motion)
        for d in range(2):
            wanted = min(max(command[r, d], -limits[r, d]), limits[r, d]) if fresh else 0.0
            if wanted != 0.0:
                driven = 1.0
            current = velocity[r, d]
            target = current + (wanted - current) * lag_factor if lagging else wanted
            value = current + min(max(target - current, -acceleration[d]), acceleration[d])
            if standstill[d] != 0.0 and wanted == 0.0 and abs(value) < standstill[d]:
                value = 0.0
            moved[r, d] = value
        if noisy:  # ``actuate``: result + driven * noise * scale, as NumPy evaluates it
            for d in range(2):
                moved[r, d] = moved[r, d] + driven * noise[r, d] * noise_scale[d]
        v, w = moved[r, 0], moved[r, 1]
        dtheta = w * dt
        half = 0.5 * dtheta
        x = np.pi * (half / np.pi)  # ``np.sinc(half / pi)``
        y = x if x != 0.0 else EPS
        chord = v * dt * (math.sin(y) / y)
        mid = pose[r, 2] + half
        px = pose[r, 0] + chord * math.cos(mid)
        py = pose[r, 1] + chord * math.sin(mid)
        theta = _wrap(pose[r, 2] + dtheta)
        proposed[r, 0], proposed[r, 1], proposed[r, 2] = px, py, theta
        c, s = math.cos(theta), math.sin(theta)
        half_l, half_w = 0.5 * lengths[r], 0.5 * widths[r]
        along_x, along_y = c * half_l, s * half_l
        across_x, across_y = -s * half_w, c * half_w
        corners[r, 0, 0] = px + along_x + across_x
        corners[r, 0, 1] = py + along_y + across_y
        corners[r, 1, 0] = px - along_x + across_x
        corners[r, 1, 1] = py - along_y + across_y
        corners[r, 2, 0] = px - along_x - across_x
        corners[r, 2, 1] = py - along_y - across_y
        corners[r, 3, 0] = px + along_x - across_x
        corners[r, 3, 1] = py + along_y - across_y
    for r in range(count):
        for d in range(2):
            if not math.isfinite(moved[r, d]):  # (the NumPy path says what follows)
                return proposed, corners, moved, False
    if overlapping_pairs(corners, reach).shape[0] > 0:
        return proposed, corners, moved, False
    for r in range(count):  # ``disc_contacts`` (``collision.footprint_gaps``), a um to spare
        c, s = math.cos(proposed[r, 2]), math.sin(proposed[r, 2])
        half_l, half_w = 0.5 * lengths[r], 0.5 * widths[r]
        for k in range(discs.shape[0]):
            gap = footprint_gap(discs[k, 0] - proposed[r, 0], discs[k, 1] - proposed[r, 1],
                                c, s, half_l, half_w)
            if not gap >= discs[k, 2] + 1e-6:  # (NaN: the NumPy way)
                return proposed, corners, moved, False
    centres = np.empty((count, 2))
    for r in range(count):
        centres[r, 0] = 0.5 * (corners[r, 0, 0] + corners[r, 2, 0])
        centres[r, 1] = 0.5 * (corners[r, 0, 1] + corners[r, 2, 1])
    near = near_segments(centres, reach, start, direction, length2)
    for r in range(count):
        for e in range(near.shape[1]):
            if near[r, e]:
                return proposed, corners, moved, False
        if not _inside(centres[r, 0], centres[r, 1], room):
            return proposed, corners, moved, False
        for k in range(obstacle_offsets.shape[0] - 1):
            if _inside(centres[r, 0], centres[r, 1],
                       obstacles[obstacle_offsets[k]:obstacle_offsets[k + 1]]):
                return proposed, corners, moved, False
    return proposed, corners, moved, True


@njit(cache=True)
def compose_turned(frames: FloatArray, cosines: FloatArray, sines: FloatArray,
                   poses: FloatArray) -> FloatArray:
    """``geometry.compose_poses`` of frames (R, 3) and poses (R, 3) (or points (R, 2): the
    positions only) given the frames' cosines and sines (R,) (``geometry.frame_turns``):
    the same operations in one call, headings wrapped to (-pi, pi]."""
    result = np.empty_like(poses)
    for r in range(poses.shape[0]):
        c, s = cosines[r], sines[r]
        result[r, 0] = frames[r, 0] + c * poses[r, 0] - s * poses[r, 1]
        result[r, 1] = frames[r, 1] + s * poses[r, 0] + c * poses[r, 1]
        if poses.shape[1] > 2:  # ``geometry.wrap_angles``
            wrapped = (frames[r, 2] + poses[r, 2] + np.pi) % (2.0 * np.pi) - np.pi
            result[r, 2] = np.pi if wrapped == -np.pi else wrapped
    return result


drop_stale(__import__(__name__, fromlist=["_"]), (collision_jit,))

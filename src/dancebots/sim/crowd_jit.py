"""The social forces of ``sim.crowd`` compiled with numba, as loops: the same sums as
``crowd.social_acceleration`` and ``crowd._wall_distance`` (tested equal to 1e-9), in a
fraction of their time (NumPy's per-call cost dominates for a crowd of tens: the force
took a third of a certify run). Importing this module imports numba; ``sim.crowd`` imports
it only when asked to (``crowd_step(..., compiled=True)``)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import NDArray

from dancebots.jit_cache import drop_stale
from dancebots.sim import collision_jit
from dancebots.sim.collision_jit import footprint_gap

__all__ = ["pauses", "robots_standing", "social_acceleration_loops", "steps_into_robots", "walk",
           "wall_distances"]

FloatArray = NDArray[np.float64]


@njit(cache=True)
def _from_segment(px: float, py: float, sx: float, sy: float, ex: float,
                  ey: float) -> tuple[float, float]:
    """The vector from the nearest point of segment (sx, sy)-(ex, ey) to (px, py) (as
    ``crowd._nearest_on_segments``)."""
    ax, ay = ex - sx, ey - sy
    length2 = max(ax * ax + ay * ay, 1e-12)
    rx, ry = px - sx, py - sy
    t = min(max((rx * ax + ry * ay) / length2, 0.0), 1.0)
    return rx - t * ax, ry - t * ay


@njit(cache=True)
def wall_distances(points: FloatArray, walls: FloatArray) -> FloatArray:
    """The distance (P,) from each point (P, 2) to the nearest wall segment (S, 2, 2)
    (``crowd._wall_distance``; inf for no segment)."""
    result = np.full(points.shape[0], np.inf)
    for p in range(points.shape[0]):
        for s in range(walls.shape[0]):
            vx, vy = _from_segment(points[p, 0], points[p, 1], walls[s, 0, 0], walls[s, 0, 1],
                                   walls[s, 1, 0], walls[s, 1, 1])
            result[p] = min(result[p], math.hypot(vx, vy))
    return result


@njit(cache=True)
def _border_push(vx: float, vy: float, strength: float, reach: float) -> tuple[float, float]:
    """H&M eq. 6 for one border's nearest vector (``crowd._border_force``)."""
    distance = math.hypot(vx, vy)
    magnitude = strength / reach * math.exp(-distance / reach) / max(distance, 1e-9)
    return magnitude * vx, magnitude * vy


@njit(cache=True)
def social_acceleration_loops(position: FloatArray, velocity: FloatArray, goal: FloatArray,
                              walking: NDArray[np.bool_], preferred: FloatArray,
                              robot_strength: FloatArray, robot_range: FloatArray,
                              walls: FloatArray,
                              rings: NDArray[np.int64], robot_poses: FloatArray,
                              robot_lengths: FloatArray, robot_widths: FloatArray,
                              relaxation: float, pedestrian_strength: float,
                              pedestrian_range: float, border_strength: float,
                              border_range: float, step_time: float, cos_sight: float,
                              out_of_sight: float) -> FloatArray:
    """dv/dt (P, 2) of every pedestrian: ``crowd.social_acceleration`` (H&M eq. 2-6) for
    positions, velocities and goals (P, 2), walking (P,) (not pausing), preferred speeds
    (P,), each robot's push on each pedestrian, strength (a factor of U0) and range (P, R)
    (``CrowdState.robot_push``),
    walls (S, 2, 2) with the border of each (``rings`` (S,), contiguous;
    each border pushes from its nearest point), robots' poses (R, 3) and sizes (R,)."""
    count = position.shape[0]
    accel = np.empty((count, 2))
    heading = np.empty((count, 2))
    for a in range(count):  # eq. 2: towards the goal at the preferred speed
        gx, gy = goal[a, 0] - position[a, 0], goal[a, 1] - position[a, 1]
        scale = 1.0 / max(math.hypot(gx, gy), 1e-9)
        dx, dy = gx * scale, gy * scale
        wx, wy = (preferred[a] * dx, preferred[a] * dy) if walking[a] else (0.0, 0.0)
        accel[a, 0] = (wx - velocity[a, 0]) / relaxation
        accel[a, 1] = (wy - velocity[a, 1]) / relaxation
        if walking[a]:
            heading[a, 0], heading[a, 1] = dx, dy
        else:
            speed = max(math.hypot(velocity[a, 0], velocity[a, 1]), 1e-9)
            heading[a, 0], heading[a, 1] = velocity[a, 0] / speed, velocity[a, 1] / speed
    for a in range(count):  # eq. 3-5: every other pedestrian's elliptic repulsion
        fx_sum, fy_sum = 0.0, 0.0
        for b in range(count):
            if a == b:
                continue
            rx, ry = position[a, 0] - position[b, 0], position[a, 1] - position[b, 1]
            sx, sy = step_time * velocity[b, 0], step_time * velocity[b, 1]
            nx, ny = rx - sx, ry - sy
            n_r, n_next, n_step = math.hypot(rx, ry), math.hypot(nx, ny), math.hypot(sx, sy)
            half = 0.5 * math.sqrt(max((n_r + n_next) ** 2 - n_step ** 2, 1e-12))
            grow = (n_r + n_next) / (4.0 * half)
            gx = grow * (rx / max(n_r, 1e-9) + nx / max(n_next, 1e-9))
            gy = grow * (ry / max(n_r, 1e-9) + ny / max(n_next, 1e-9))
            size = pedestrian_strength / pedestrian_range * math.exp(-half / pedestrian_range)
            fx, fy = size * gx, size * gy
            seen = heading[a, 0] * -fx + heading[a, 1] * -fy >= math.hypot(fx, fy) * cos_sight
            weight = 1.0 if seen else out_of_sight
            fx_sum += weight * fx
            fy_sum += weight * fy
        accel[a, 0] += fx_sum
        accel[a, 1] += fy_sum
    for a in range(count):  # eq. 6: each border from its nearest point, then each robot
        px, py = position[a, 0], position[a, 1]
        s = 0
        while s < walls.shape[0]:
            best, bx, by = math.inf, 0.0, 0.0
            ring = rings[s]
            while s < walls.shape[0] and rings[s] == ring:
                vx, vy = _from_segment(px, py, walls[s, 0, 0], walls[s, 0, 1], walls[s, 1, 0],
                                       walls[s, 1, 1])
                distance = math.hypot(vx, vy)
                if distance < best:
                    best, bx, by = distance, vx, vy
                s += 1
            fx, fy = _border_push(bx, by, border_strength, border_range)
            accel[a, 0] += fx
            accel[a, 1] += fy
        for r in range(robot_poses.shape[0]):
            c, sn = math.cos(robot_poses[r, 2]), math.sin(robot_poses[r, 2])
            dx, dy = px - robot_poses[r, 0], py - robot_poses[r, 1]
            lx, ly = c * dx + sn * dy, -sn * dx + c * dy
            half_l, half_w = 0.5 * robot_lengths[r], 0.5 * robot_widths[r]
            ex = lx - min(max(lx, -half_l), half_l)
            ey = ly - min(max(ly, -half_w), half_w)
            if ex == 0.0 and ey == 0.0:  # inside: pushed out the way it lies
                ex, ey = lx, ly
            fx, fy = _border_push(c * ex - sn * ey, sn * ex + c * ey,
                                  border_strength * robot_strength[a, r], robot_range[a, r])
            accel[a, 0] += fx
            accel[a, 1] += fy
    return accel


@njit(cache=True)
def walk(position: FloatArray, velocity: FloatArray, goal: FloatArray,
         walking: NDArray[np.bool_], preferred: FloatArray, robot_strength: FloatArray,
         robot_range: FloatArray, radius: FloatArray, walls: FloatArray, rings: NDArray[np.int64],
         robot_poses: FloatArray, robot_lengths: FloatArray, robot_widths: FloatArray,
         relaxation: float, pedestrian_strength: float, pedestrian_range: float,
         border_strength: float, border_range: float, step_time: float, cos_sight: float,
         out_of_sight: float, max_speed_factor: float, steps: int,
         h: float) -> tuple[FloatArray, FloatArray]:
    """``crowd_step``'s ``steps`` substeps of ``h`` s in one call: the social forces
    (:func:`social_acceleration_loops`), the velocity capped at ``max_speed_factor`` times
    the preferred speed (H&M eq. 7), and no step through a wall (a disc, ``radius`` (P,)
    m, that would touch one, nearer than before, stands). The same operations in the same
    order as ``crowd_step``'s NumPy loop around the forces. Returns positions and
    velocities (P, 2); ``robot_strength`` and ``robot_range`` (P, R) as in
    :func:`social_acceleration_loops`."""
    count = position.shape[0]
    position, velocity = position.copy(), velocity.copy()
    ahead = np.empty((count, 2))
    for _ in range(steps):
        accel = social_acceleration_loops(
            position, velocity, goal, walking, preferred, robot_strength, robot_range, walls,
            rings, robot_poses, robot_lengths, robot_widths, relaxation, pedestrian_strength,
            pedestrian_range, border_strength, border_range, step_time, cos_sight,
            out_of_sight)
        before = wall_distances(position, walls)
        for a in range(count):
            vx, vy = velocity[a, 0] + h * accel[a, 0], velocity[a, 1] + h * accel[a, 1]
            factor = min(1.0, max_speed_factor * preferred[a] / max(math.hypot(vx, vy), 1e-12))
            velocity[a, 0], velocity[a, 1] = vx * factor, vy * factor
            ahead[a, 0] = position[a, 0] + h * velocity[a, 0]
            ahead[a, 1] = position[a, 1] + h * velocity[a, 1]
        if walls.shape[0] > 0:
            after = wall_distances(ahead, walls)
            for a in range(count):
                if after[a] < radius[a] and after[a] < before[a]:
                    ahead[a, 0], ahead[a, 1] = position[a, 0], position[a, 1]
                    velocity[a, 0], velocity[a, 1] = 0.0, 0.0
        position[:, :] = ahead
    return position, velocity


@njit(cache=True)
def steps_into_robots(before: FloatArray, after: FloatArray, radii: FloatArray,
                      poses: FloatArray, lengths: FloatArray,
                      widths: FloatArray) -> NDArray[np.bool_]:
    """``Stage._steps_into_robots``: (P,) the people (centres (P, 2) before and after a
    step, radii (P,) m) whose step would reach into a robot's footprint (poses (R, 3),
    sizes (R,)) from outside (``collision.footprint_gaps``, the nearest robot's)."""
    result = np.zeros(before.shape[0], dtype=np.bool_)
    for p in range(before.shape[0]):
        gap_before, gap_after = math.inf, math.inf
        for r in range(poses.shape[0]):
            c, s = math.cos(poses[r, 2]), math.sin(poses[r, 2])
            half_l, half_w = 0.5 * lengths[r], 0.5 * widths[r]
            gap_before = min(gap_before, footprint_gap(
                before[p, 0] - poses[r, 0], before[p, 1] - poses[r, 1], c, s, half_l, half_w))
            gap_after = min(gap_after, footprint_gap(
                after[p, 0] - poses[r, 0], after[p, 1] - poses[r, 1], c, s, half_l, half_w))
        result[p] = gap_after < radii[p] and gap_before >= radii[p]
    return result


@njit(cache=True)
def pauses(pause: FloatArray, goal: FloatArray, position: FloatArray, behaviour: FloatArray,
           columns: NDArray[np.int64], draws: FloatArray, change_draws: FloatArray,
           dt: float) -> tuple[NDArray[np.bool_], FloatArray, NDArray[np.bool_]]:
    """``crowd_step``'s pauses in one call, the same operations: who arrived at its goal
    (P,) (not pausing, within ``arrive`` m), the pauses (P,) s left ``dt`` s later (one who
    arrived pauses ``pause_min + (pause_max - pause_min) * draws`` s) and who picks a new
    goal (P,) (a pause that ends, or a change of mind at ``change_rate`` per s:
    ``change_draws`` below ``change_rate * dt``). The four figures are each pedestrian's
    ``behaviour`` (P, K) at ``columns`` (4,): arrive, pause_min, pause_max, change_rate (the
    matrix, not its column views: one compiled version for crowds of any size). draws,
    change_draws (P,) uniform in [0, 1)."""
    arrive, pause_min, pause_max, change_rate = columns[0], columns[1], columns[2], columns[3]
    count = pause.shape[0]
    arrived = np.empty(count, dtype=np.bool_)
    left = np.empty(count)
    rethink = np.empty(count, dtype=np.bool_)
    for p in range(count):
        arrived[p] = pause[p] <= 0.0 and math.hypot(
            goal[p, 0] - position[p, 0], goal[p, 1] - position[p, 1]) < behaviour[p, arrive]
        low, high = behaviour[p, pause_min], behaviour[p, pause_max]
        now = low + (high - low) * draws[p] if arrived[p] else pause[p]
        was_pausing = now > 0.0
        left[p] = max(now - dt, 0.0)
        rethink[p] = (was_pausing and left[p] <= 0.0) or (
            left[p] <= 0.0 and change_draws[p] < behaviour[p, change_rate] * dt)
    return arrived, left, rethink


@njit(cache=True)
def robots_standing(velocity: FloatArray, command: FloatArray, issued: FloatArray,
                    now: float, timeout: float, limits: FloatArray,
                    moving_speed: float) -> NDArray[np.bool_]:
    """``Stage._standing`` in one call (among crowds): (R,) whether each robot's velocity
    (R, 2) and its command (R, 2) issued at ``issued`` (R,) s, clipped to ``limits`` (R, 2)
    and zero when older than ``timeout`` s at ``now`` (``kinematics.fresh_commands``), stay
    within ``moving_speed`` (m/s and rad/s)."""
    count = velocity.shape[0]
    result = np.empty(count, dtype=np.bool_)
    for r in range(count):
        fresh = (now - issued[r]) <= timeout + 1e-9
        standing = True
        for d in range(2):
            given = min(max(command[r, d], -limits[r, d]), limits[r, d]) if fresh else 0.0
            if not (abs(velocity[r, d]) <= moving_speed and abs(given) <= moving_speed):
                standing = False
        result[r] = standing
    return result


drop_stale(__import__(__name__, fromlist=["_"]), (collision_jit,))  # calls footprint_gap

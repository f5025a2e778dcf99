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

__all__ = ["far_from_all", "kept_columns", "perceive_columns", "perceive_columns_split",
           "perceive_moved", "to_local", "turn_fraction_columns", "turn_fraction_local",
           "turn_shares"]


@njit(cache=True)
def kept_columns(columns: NDArray[np.float64], height_step: float, crop_half: float,
                 z_min: float, z_max: float) -> NDArray[np.bool_]:
    """Which columns (K, 4) of a cloud (see ``PointCloud``) hold an obstacle point: the crop
    and height filter of ``obstacle_points_from_columns`` (K,). The lowest point above
    ``z_min`` is worked out once for a run of columns with the same foot (most stand on the
    floor), only for those in the crop: the same answers."""
    keep = np.zeros(columns.shape[0], dtype=np.bool_)
    last_low, z, first = math.nan, math.nan, math.nan
    for i in range(columns.shape[0]):
        if not (abs(columns[i, 0]) <= crop_half and abs(columns[i, 1]) <= crop_half):
            continue
        low = columns[i, 2]
        if low != last_low:  # (NaN: each time)
            last_low = low
            first = (0.0 if low > z_min
                     else math.floor((z_min - low) / height_step + 1e-9) + 1.0)
            if first >= 1.0 and low + (first - 1.0) * height_step > z_min:
                first -= 1.0  # (the rounding allowance skipped a level just above z_min)
            z = low + first * height_step
        high = columns[i, 3]
        # up to the column's highest level (``PointCloud.points``'s rule, worked out only
        # where z is within a micrometre of the top, or where heights or the step are so
        # large that rounding could reach one: elsewhere its answer is plain)
        plain = abs(low) < 1e6 and abs(high) < 1e6 and height_step < 10.0
        keep[i] = z < z_max and ((plain and z <= high - 1e-6) or (
            (not plain or z <= high + 1e-6)
            and first <= math.floor((high - low) / height_step + 1e-9)))
    return keep


@njit(cache=True)
def _kept(columns: NDArray[np.float64], height_step: float, crop_half: float, z_min: float,
          z_max: float) -> NDArray[np.float64]:
    """The obstacle points (M, 2) of a cloud stored as columns (K, 4) (see ``PointCloud``):
    the crop and height filter of ``obstacle_points_from_columns``."""
    return columns[kept_columns(columns, height_step, crop_half, z_min, z_max), :2]


@njit(cache=True)
def perceive_columns(columns: NDArray[np.float64], height_step: float, crop_half: float,
                     z_min: float, z_max: float, seen_from: NDArray[np.float64],
                     pose: NDArray[np.float64], length: float, width: float,
                     stop_distance: float, corridor_margin: float,
                     force_radius: float, force_gain: float,
                     ) -> tuple[float, float, float, float, float]:
    """A cloud stored as columns (K, 4) (see ``PointCloud``): its obstacle points (crop and
    height filter of ``obstacle_points_from_columns``), then :func:`perceive_moved`."""
    return perceive_moved(_kept(columns, height_step, crop_half, z_min, z_max), seen_from,
                          pose, length, width, stop_distance, corridor_margin, force_radius,
                          force_gain)


@njit(cache=True)
def turn_fraction_columns(columns: NDArray[np.float64], height_step: float, crop_half: float,
                          z_min: float, z_max: float, seen_from: NDArray[np.float64],
                          pose: NDArray[np.float64], length: float, width: float,
                          linear: float, angular: float, margin: float, horizon: float,
                          share: float, mates: NDArray[np.float64], mate_radius: float,
                          leading: bool) -> float:
    """``perception.obstacles.turn_fraction`` of the obstacle points of a cloud stored as
    columns (K, 4) seen at ``seen_from``, moved to ``pose`` (as :func:`perceive_columns`);
    the points within ``mate_radius`` of a centre of ``mates`` (J, 2), ``base_link`` at
    ``seen_from`` (``perception.obstacles.near_any``), may move themselves (turn ``share``),
    the others stand; ``leading``: of the points ahead of the robot's middle in its
    direction of travel only (behind it when ``linear`` < 0)."""
    if angular == 0.0:
        return 1.0
    points = _kept(columns, height_step, crop_half, z_min, z_max)
    c0, s0 = math.cos(seen_from[2]), math.sin(seen_from[2])
    c1, s1 = math.cos(pose[2]), math.sin(pose[2])
    local = np.empty_like(points)
    shares = turn_shares(points, mates, mate_radius, share)
    for i in range(points.shape[0]):
        wx = seen_from[0] + c0 * points[i, 0] - s0 * points[i, 1] - pose[0]
        wy = seen_from[1] + s0 * points[i, 0] + c0 * points[i, 1] - pose[1]
        local[i, 0] = c1 * wx + s1 * wy
        local[i, 1] = -s1 * wx + c1 * wy
    return turn_fraction_local(local, length, width, linear, angular, margin, horizon, shares,
                               leading)


@njit(cache=True)
def turn_shares(points: NDArray[np.float64], mates: NDArray[np.float64], mate_radius: float,
                share: float) -> NDArray[np.float64]:
    """(M,) the turn share of each obstacle point (M, 2): ``share`` within ``mate_radius`` of
    a centre of ``mates`` (J, 2), same frame (``perception.obstacles.near_any``), else 1.0
    (a standing point)."""
    shares = np.empty(points.shape[0])
    for i in range(points.shape[0]):
        shares[i] = share if _near_a_mate(points[i, 0], points[i, 1], mates,
                                          mate_radius) else 1.0
    return shares


@njit(cache=True)
def turn_fraction_local(points: NDArray[np.float64], length: float, width: float,
                        linear: float, angular: float, margin: float, horizon: float,
                        shares: NDArray[np.float64], leading: bool) -> float:
    """``perception.obstacles.turn_fraction`` of obstacle points (M, 2) in ``base_link``
    (turn margin and horizon given; ``shares`` (M,): each point's turn share, 1.0 for a
    standing point); ``leading``: of the points ahead of the robot's middle in its
    direction of travel only (behind it when ``linear`` < 0)."""
    if angular == 0.0 or points.shape[0] == 0:
        return 1.0
    if not (math.isfinite(linear) and math.isfinite(angular)):
        return 0.0
    half_l, half_w = 0.5 * length, 0.5 * width
    sweep = math.hypot(half_l, half_w) - min(half_l, half_w) + abs(linear) * horizon
    # the points that may block (within their ``turn_reach``) and the least share of them
    least = math.inf
    for i in range(points.shape[0]):
        x0, y0 = points[i, 0], points[i, 1]
        if leading and x0 * (1.0 if linear >= 0.0 else -1.0) <= 0.0:
            continue
        gap0 = math.hypot(max(abs(x0) - half_l, 0.0), max(abs(y0) - half_w, 0.0))
        if gap0 < margin + sweep / shares[i]:
            least = min(least, shares[i])
    if least == math.inf:
        return 1.0
    # the instants of ``perception.obstacles.turn_samples``, evenly over the horizon: for
    # standing points (share 1) and for the least share, nested
    counts = np.empty(2, dtype=np.int64)
    for j in range(2):
        reach = margin + sweep / (1.0 if j == 0 else least)  # ``turn_reach``
        spread = math.hypot(half_l, half_w) + reach
        step = min(0.1, 0.5 * margin / (abs(linear) + abs(angular) * spread))
        needed = horizon / step if step > 0.0 else math.inf
        if not needed < 1000.0:  # perception.obstacles.MAX_TURN_SAMPLES: no turn
            return 0.0
        counts[j] = math.ceil(needed - 1e-9) + 1
    steps = counts[0]
    if counts[0] > 1 and counts[1] > counts[0]:
        steps = (-((counts[1] - 1) // -(counts[0] - 1))) * (counts[0] - 1) + 1
    spacing = horizon / (steps - 1) if steps > 1 else 0.0
    fractions = (1.0, 0.5, 0.25, 0.0)
    # the robot's pose on each arc (fraction, step): dx, dy, cos, sin
    arcs = np.empty((4, steps, 4))
    for f in range(4):
        w = fractions[f] * angular
        for k in range(steps):
            t = horizon if k == steps - 1 and steps > 1 else k * spacing  # as np.linspace
            theta = w * t
            if abs(w) < 1e-9:
                dx, dy = linear * t, 0.0
            else:
                dx, dy = linear * math.sin(theta) / w, linear * (1.0 - math.cos(theta)) / w
            arcs[f, k, 0], arcs[f, k, 1] = dx, dy
            arcs[f, k, 2], arcs[f, k, 3] = math.cos(theta), math.sin(theta)
    # a fraction is blocked by a point whose nearest gap on its arc is below both the floor
    # and its nearest gap driving straight (less 1e-9): each point's straight gap first, then
    # each arc not yet blocked only until a gap below that threshold (the same answer as
    # every gap, sooner); a point too far from the robot's middle to come that near on any
    # arc is skipped (its distance from the middle less the half diagonal bounds its gap),
    # and so are the instants at which a point cannot have come that near yet
    # (:func:`_next_instant_that_may_reach`)
    blocked = np.zeros(3, dtype=np.bool_)
    half_diagonal = math.hypot(half_l, half_w)
    travel = abs(linear) * horizon  # the farthest the middle moves, m
    for i in range(points.shape[0]):
        x0, y0 = points[i, 0], points[i, 1]
        if leading and x0 * (1.0 if linear >= 0.0 else -1.0) <= 0.0:
            continue
        gap0 = math.hypot(max(abs(x0) - half_l, 0.0), max(abs(y0) - half_w, 0.0))
        if gap0 >= margin + sweep / shares[i]:
            continue
        share = shares[i]
        # ``turn_floor`` of the gap now: no lower than that of the straight gap (<= gap0)
        bound = gap0 - share * max(gap0 - margin, 0.0) - 1e-9
        if math.hypot(x0, y0) - travel - half_diagonal - 1e-9 >= bound:
            continue
        # the straight gap: for a standing point it matters only below bound + 1e-9 (the
        # margin or gap0; else the threshold is the bound), for a point that may move it
        # sets the floor (the nearest gap: only instants that may come nearer)
        straight = math.inf
        k = 0
        while k < steps:
            px, py = x0 - arcs[3, k, 0], y0 - arcs[3, k, 1]
            c, s = arcs[3, k, 2], arcs[3, k, 3]
            x, y = c * px + s * py, -s * px + c * py
            gap = math.hypot(max(abs(x) - half_l, 0.0), max(abs(y) - half_w, 0.0))
            straight = min(straight, gap)
            k = _next_instant_that_may_reach(
                k, gap, bound + 1e-9 if share == 1.0 else straight, abs(linear), 0.0,
                math.hypot(x, y) + travel, spacing, steps)
        floor = straight - share * max(straight - margin, 0.0) - 1e-9  # ``turn_floor``
        threshold = min(floor, straight - 1e-9)
        for f in range(3):
            if blocked[f]:
                continue
            turn = abs(fractions[f] * angular)
            k = 0
            while k < steps:
                px, py = x0 - arcs[f, k, 0], y0 - arcs[f, k, 1]
                c, s = arcs[f, k, 2], arcs[f, k, 3]
                x, y = c * px + s * py, -s * px + c * py
                gap = math.hypot(max(abs(x) - half_l, 0.0), max(abs(y) - half_w, 0.0))
                if gap < threshold:
                    blocked[f] = True
                    break
                k = _next_instant_that_may_reach(k, gap, threshold, abs(linear), turn,
                                                 math.hypot(x, y) + travel, spacing, steps)
        if blocked[0] and blocked[1] and blocked[2]:
            return 0.0
    for f in range(3):
        if not blocked[f]:
            return fractions[f]
    return 0.0


@njit(cache=True)
def _next_instant_that_may_reach(k: int, gap: float, threshold: float, linear: float,
                                 angular: float, distance: float, spacing: float,
                                 steps: int) -> int:
    """The next of ``steps`` instants ``spacing`` s apart after instant ``k`` at which a
    standing point ``gap`` m from the footprint at instant ``k`` may be nearer than
    ``threshold`` m (``steps`` for none): the gap changes no faster than the point moves in
    ``base_link``, at most ``linear`` + ``angular`` * ``distance`` m/s (speeds >= 0;
    ``distance`` bounds its distance from the robot's middle meanwhile, m), with 1e-9 m
    spare for rounding."""
    slack = gap - threshold - 1e-9
    if slack <= 0.0:
        return k + 1
    speed = linear + angular * distance
    if speed <= 0.0 or spacing <= 0.0:
        return steps  # it stays where it is, beyond the threshold
    ahead = slack / speed / spacing
    return k + 1 + (int(ahead) if ahead < steps else steps)


@njit(cache=True)
def perceive_moved(points: NDArray[np.float64], seen_from: NDArray[np.float64],
                   pose: NDArray[np.float64], length: float, width: float,
                   stop_distance: float, corridor_margin: float,
                   force_radius: float, force_gain: float,
                   ) -> tuple[float, float, float, float, float]:
    """Obstacle points (M, 2) in ``base_link`` at ``seen_from`` (x, y, theta), moved to the
    robot's ``pose`` (same frame), then: free distance ahead and behind (m), the smallest
    distance of a point to the footprint (m, ``footprint_clearance``), force (Fx, Fy). See
    ``perception.obstacles.perceive``."""
    c0, s0 = math.cos(seen_from[2]), math.sin(seen_from[2])
    c1, s1 = math.cos(pose[2]), math.sin(pose[2])
    half_l, half_w = 0.5 * length, 0.5 * width
    front, rear = math.inf, math.inf
    nearest = math.inf
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
        nearest = min(nearest, d)
        if force_radius > 0 and 1e-9 < d < force_radius:
            weight = force_gain * (1.0 - d / force_radius) ** 2 / d
            fx += ax * weight
            fy += ay * weight
    return front, rear, nearest, fx, fy


@njit(cache=True)
def far_from_all(points: NDArray[np.float64], centres: NDArray[np.float64],
                 radius: float) -> NDArray[np.bool_]:
    """(K,) True where a point of ``points`` (K, >= 2) (x, y first) is more than ``radius`` m
    from every centre of ``centres`` (M, 2), same frame; all True for no centre. The mask of
    ``RobotBrain._without_mates`` (NumPy: ``hypot(points[:, None] - centres[None]).min(1) >
    radius``)."""
    keep = np.ones(points.shape[0], dtype=np.bool_)
    for i in range(points.shape[0]):
        for j in range(centres.shape[0]):
            dx, dy = points[i, 0] - centres[j, 0], points[i, 1] - centres[j, 1]
            if (abs(dx) > radius or abs(dy) > radius) and dx == dx and dy == dy:
                continue  # hypot >= either: far, cheaply (a NaN leaves it to hypot)
            distance = math.hypot(dx, dy)
            if not distance > radius:  # NaN too, as NumPy's min(...) > radius
                keep[i] = False
                break
    return keep


@njit(cache=True)
def to_local(points: NDArray[np.float64], frame: NDArray[np.float64]) -> NDArray[np.float64]:
    """Points (M, 2) of the parent frame of ``frame`` (x, y, theta) in ``frame``:
    ``geometry.points_to_local``, which a kernel cannot call."""
    c, s = math.cos(frame[2]), math.sin(frame[2])
    local = np.empty((points.shape[0], 2))
    for j in range(points.shape[0]):
        dx, dy = points[j, 0] - frame[0], points[j, 1] - frame[1]
        local[j, 0] = c * dx + s * dy
        local[j, 1] = -s * dx + c * dy
    return local


@njit(cache=True)
def _near_a_mate(x: float, y: float, mates: NDArray[np.float64], radius: float) -> bool:
    """Whether the point (x, y) is within ``radius`` of any centre of ``mates`` (M, 2), same
    frame (a centre that is not a number is near everything): :func:`far_from_all`'s test
    of one point, negated."""
    for j in range(mates.shape[0]):
        dx, dy = x - mates[j, 0], y - mates[j, 1]
        if (abs(dx) > radius or abs(dy) > radius) and dx == dx and dy == dy:
            continue
        if not math.hypot(dx, dy) > radius:
            return True
    return False


@njit(cache=True)
def perceive_columns_split(columns: NDArray[np.float64], height_step: float, crop_half: float,
                           z_min: float, z_max: float, seen_from: NDArray[np.float64],
                           pose: NDArray[np.float64], length: float, width: float,
                           stop_distance: float, corridor_margin: float,
                           force_radius: float, force_gain: float,
                           mates: NDArray[np.float64], mate_radius: float,
                           ) -> tuple[tuple[float, float, float, float, float],
                                      tuple[float, float, float, float, float], bool]:
    """:func:`perceive_columns` twice in one pass: of every obstacle point of the cloud's
    columns (K, 4), and of those more than ``mate_radius`` m from every centre of ``mates``
    (M, 2), given in the parent frame of ``seen_from`` (the robot's own map frame), as
    ``RobotBrain._without_mates`` leaves them out (any column, kept or not); third, whether
    any column was left out (else the second is the first).
    Same results as ``perceive_columns(columns)`` and ``perceive_columns(columns[
    far_from_all(columns, points_to_local(mates, seen_from), mate_radius)])``, to the last
    bit (the same points in the same order), in one loop without copies: a column outside
    the crop or the heights is tested against the mates only until one was left out."""
    local = to_local(mates, seen_from)
    # the mates a column inside the crop can be near (a mate further out on either axis
    # than the crop and the radius, with a margin for rounding, fails the first test of
    # ``_near_a_mate`` for every such column): a 20-robot block tests a third of them
    reach = crop_half + mate_radius + 1e-6
    close = np.empty_like(local)
    count = 0
    for j in range(local.shape[0]):
        if not (abs(local[j, 0]) > reach or abs(local[j, 1]) > reach):  # NaN: near all
            close[count] = local[j]
            count += 1
    close = close[:count]
    c0, s0 = math.cos(seen_from[2]), math.sin(seen_from[2])
    c1, s1 = math.cos(pose[2]), math.sin(pose[2])
    half_l, half_w = 0.5 * length, 0.5 * width
    front, rear, nearest, fx, fy = math.inf, math.inf, math.inf, 0.0, 0.0
    s_front, s_rear, s_nearest, s_fx, s_fy = math.inf, math.inf, math.inf, 0.0, 0.0
    left_out = False
    keep = kept_columns(columns, height_step, crop_half, z_min, z_max)
    for i in range(columns.shape[0]):
        kept = keep[i]
        if not kept and left_out:
            continue
        near = _near_a_mate(columns[i, 0], columns[i, 1], close if kept else local,
                            mate_radius)
        left_out = left_out or near
        if not kept:
            continue
        # ``perceive_moved`` of the point, for everything and, far from the mates, strangers
        wx = seen_from[0] + c0 * columns[i, 0] - s0 * columns[i, 1] - pose[0]
        wy = seen_from[1] + s0 * columns[i, 0] + c0 * columns[i, 1] - pose[1]
        x = c1 * wx + s1 * wy
        y = -s1 * wx + c1 * wy
        ahead = behind = math.inf
        if abs(y) <= half_w + corridor_margin:
            if x >= half_l - 1e-9:
                ahead = x - half_l
            if x <= -half_l + 1e-9:
                behind = -x - half_l
        nx = min(max(x, -half_l), half_l)
        ny = min(max(y, -half_w), half_w)
        ax, ay = nx - x, ny - y
        d = math.hypot(ax, ay)
        pushed = force_radius > 0 and 1e-9 < d < force_radius
        weight = force_gain * (1.0 - d / force_radius) ** 2 / d if pushed else 0.0
        front, rear, nearest = min(front, ahead), min(rear, behind), min(nearest, d)
        if pushed:
            fx += ax * weight
            fy += ay * weight
        if not near:
            s_front, s_rear = min(s_front, ahead), min(s_rear, behind)
            s_nearest = min(s_nearest, d)
            if pushed:
                s_fx += ax * weight
                s_fy += ay * weight
    everything = (front, rear, nearest, fx, fy)
    if not left_out:
        return everything, everything, False
    return everything, (s_front, s_rear, s_nearest, s_fx, s_fy), True

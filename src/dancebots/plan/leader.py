"""The virtual leader's controllers (thesis ch. 4.2) as pure functions of its state.

Frames: ``goal_x``, ``goal_y`` are the next waypoint in the virtual leader's own frame
(x forward, y left), in m. Returned commands are (linear m/s, angular rad/s).
"""

from __future__ import annotations

import math

__all__ = [
    "ANGULAR_LIMIT",
    "MIN_LINEAR",
    "arc_angular_speed",
    "arc_command",
    "leader_speed",
    "waypoint_command",
]

ANGULAR_LIMIT = math.pi / 2
"""Saturation of the virtual leader's angular speed, rad/s (thesis ch. 4.2: "-pi/2 and pi/2")."""
MIN_LINEAR = 0.1
"""The virtual leader never goes slower than this while it has a waypoint, m/s (eq. 4.1a)."""
LEADER_SPEED_FRACTION = 0.7
"""The virtual leader moves at 70 % of vmax (thesis ch. 4.1)."""


def leader_speed(vmax: float) -> float:
    """Largest linear speed of the virtual leader, m/s: 0.7 * vmax (thesis ch. 4.1)."""
    return LEADER_SPEED_FRACTION * vmax


def _clip(value: float, limit: float) -> float:
    return max(-limit, min(limit, value))


def waypoint_command(goal_x: float, goal_y: float, vmax: float) -> tuple[float, float]:
    """Thesis eq. 4.1: the virtual leader's command towards a waypoint.

    linear  = min(max(1.5 * Gx, 0.1), 0.7 * vmax)           (4.1a)
    angular = 2 * sgn(Gy) * alpha, saturated to +-pi/2      (4.1b)

    alpha is the unsigned angle between the leader's x axis and the waypoint. For a waypoint
    exactly behind (Gy == 0, Gx < 0), sgn(Gy) = 0 as written would drive the leader away for
    ever; the leader then turns left (sgn taken as +1), see docs/language.md.
    """
    linear = min(max(1.5 * goal_x, MIN_LINEAR), leader_speed(vmax))  # thesis eq. 4.1a
    alpha = abs(math.atan2(goal_y, goal_x))
    if goal_y > 0.0 or (goal_y == 0.0 and goal_x < 0.0):
        sign = 1.0
    elif goal_y < 0.0:
        sign = -1.0
    else:
        sign = 0.0
    angular = _clip(2.0 * sign * alpha, ANGULAR_LIMIT)  # thesis eq. 4.1b
    return linear, angular


def arc_angular_speed(radius: float, omega: float, vmax: float) -> float:
    """Thesis eq. 6.1 and the halving rule: the angular speed actually used on an arc, rad/s.

    v = omega * |r| (eq. 6.1); while v exceeds the leader's maximal speed 0.7 * vmax, omega
    (and so v) is halved.
    """
    limit = leader_speed(vmax)
    while omega * abs(radius) > limit:
        omega *= 0.5
    return omega


def arc_command(radius: float, omega: float, current_radius: float) -> tuple[float, float]:
    """Thesis eq. 4.3: the virtual leader's command on a circular arc.

    linear  = omega * |r|                                   (4.3a, from v = omega * r, 4.2)
    angular = sgn(r) * omega * (1 - 5 * (|r| - r_real))     (4.3b)

    ``radius`` r is signed (> 0: centre on the left), ``omega`` the (halved) desired angular
    speed, ``current_radius`` r_real the leader's distance to the centre. The thesis prints
    (r - r_real) in 4.3b; for r < 0 that would multiply the turn rate by 1 + 10 |r|, so r is
    read as |r| there, as in 4.3a. The result is saturated to +-pi/2 like eq. 4.1b.
    """
    sign = 1.0 if radius > 0 else -1.0
    linear = omega * abs(radius)  # thesis eq. 4.3a
    angular = sign * omega * (1.0 - 5.0 * (abs(radius) - current_radius))  # thesis eq. 4.3b
    return linear, _clip(angular, ANGULAR_LIMIT)

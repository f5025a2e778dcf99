"""Where the spectators are: each walks its waypoints with pauses (and loops), as a pure
function of how long it has walked. The simulator advances a spectator's walking time only
while its next position is free of robots: visitors do not walk into robots, so any contact
is a robot's doing.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
from numpy.typing import NDArray

from dancebots.world import Spectator

__all__ = ["spectator_discs", "spectator_position", "walk_duration"]


def spectator_position(spectator: Spectator, walked: float) -> tuple[float, float]:
    """Position (x, y) in m after ``walked`` s of the spectator's own timeline (its start
    delay included): standing at the first waypoint until ``start``, then legs between
    waypoints at ``speed`` with the pause of each waypoint on arrival."""
    points = spectator.waypoints
    if len(points) == 1 or walked <= spectator.start:
        return float(points[0, 0]), float(points[0, 1])
    order, durations = _legs(spectator)
    cycle = sum(durations)
    t = walked - spectator.start
    if spectator.loop and cycle > 0:
        t = math.fmod(t, cycle)
    elif t >= cycle:
        return float(points[order[-1], 0]), float(points[order[-1], 1])
    for leg, (a, b) in enumerate(itertools.pairwise(order)):
        travel, pause = durations[2 * leg], durations[2 * leg + 1]
        if t < travel:
            fraction = t / travel
            x, y = points[a] + fraction * (points[b] - points[a])
            return float(x), float(y)
        t -= travel
        if t < pause:
            return float(points[b, 0]), float(points[b, 1])
        t -= pause
    return float(points[order[-1], 0]), float(points[order[-1], 1])


def walk_duration(spectator: Spectator) -> float:
    """How long the spectator's walk takes, s: its start delay, legs and pauses (one round
    for a spectator that loops)."""
    return spectator.start + sum(_legs(spectator)[1])


def _legs(spectator: Spectator) -> tuple[list[int], list[float]]:
    """The waypoint order walked (back to the first for a loop) and, per leg, its walking
    time and the pause at its end, s: [walk 1, pause 1, walk 2, pause 2, ...]."""
    points = spectator.waypoints
    order = list(range(len(points))) + ([0] if spectator.loop else [])
    durations: list[float] = []
    for a, b in itertools.pairwise(order):
        durations.append(float(np.hypot(*(points[b] - points[a]))) / spectator.speed)
        durations.append(float(spectator.pauses[b]))
    return order, durations


def spectator_discs(spectators: tuple[Spectator, ...],
                    walked: NDArray[np.float64]) -> NDArray[np.float64]:
    """Discs (C, 3) = (x, y, radius) of all spectators at their walked times (C,)."""
    if not spectators:
        return np.zeros((0, 3))
    return np.array([[*spectator_position(s, float(w)), s.radius]
                     for s, w in zip(spectators, walked.tolist(), strict=True)])

"""People closing in: how fast the strangers around a robot approach it, measured between two
scans without a tracker, and whether one approaches faster than the robot can stop (an
addition: the ``closing`` stop rule, ``RobotBrain``).

The strangers' points (obstacle points that are no formation mate) of two consecutive
clouds, each moved from where it was taken to the robot's pose now (so the robot's own
motion cancels and only the people's remains), are reduced to the smallest gap to the
footprint in each of ``sectors`` bearing sectors around the robot's centre
(:func:`sector_gaps`). A sector's closing speed is how much that gap shrank per second, the
gap before taken as the smallest of the sector's and of those neighbours' whose gap grew or
emptied (a person walking round the robot into the next sector does not count as
approaching; a person standing in the next sector does not hide one who does). The data's
age counts two actuator lags more, in which a lagging robot's speed dies away (as ``ssm``
has it). For the thesis follower, which knows no mates' places, a mate is a stranger too.
A stranger approaching
at u (m/s, at least ``min_speed``, at most ``max_speed``) is too near when its gap is within
ISO/TS 15066's protective separation distance S_p (``perception.ssm.protective_distance``):
the way it closes over the data's age, the robot's reaction and its braking, plus the
robot's own reaction and braking way and the margin C. The robot then stands until the
approach ends: a standing or strolling watcher (below ``min_speed``) is left to the fixed
stop distance, so people watching from nearby do not stall the show as SSM's assumed
walking speed does (``docs/safety.md``).

``perception.closing_jit`` compiles the strangers' points of a cloud's columns and
:func:`sector_gaps` of points moved to a pose.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from dancebots.perception.ssm import protective_distance

__all__ = ["ClosingParams", "closing_speeds", "sector_gaps", "too_near"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class ClosingParams:
    """sectors: bearing sectors around the robot's centre; min_speed: slower approaches are
    left to the fixed stop distance, m/s (a visitor stepping up to watch); max_speed: a
    measured approach is capped here, m/s (a person appearing from behind another is no
    5 m/s sprinter; a child runs at 2-3 m/s); margin: C, m."""

    sectors: int = 16
    min_speed: float = 0.5
    max_speed: float = 3.0
    margin: float = 0.25

    def __post_init__(self) -> None:
        values = (self.min_speed, self.max_speed, self.margin)
        if not (isinstance(self.sectors, int) and 4 <= self.sectors <= 360) or not all(
                math.isfinite(v) and v >= 0.0 for v in values) or (
                self.max_speed < self.min_speed):
            raise ValueError("closing parameters: 4 to 360 sectors, speeds and margin finite "
                             "and 0 or more, max_speed at least min_speed")


def sector_gaps(points: FloatArray, length: float, width: float, sectors: int) -> FloatArray:
    """(S,) the smallest gap (m) between the footprint (``length`` x ``width`` m, centred on
    ``base_link``) and the points (N, 2) in ``base_link`` whose bearing from the centre falls
    in each of ``sectors`` equal sectors, the first starting at -pi; inf where none."""
    gaps = np.full(sectors, math.inf)
    points = points[np.isfinite(points).all(axis=1)]  # a point that is not a number is none
    if len(points) == 0:
        return gaps
    x, y = points[:, 0], points[:, 1]
    gap = np.hypot(np.maximum(np.abs(x) - 0.5 * length, 0.0),
                   np.maximum(np.abs(y) - 0.5 * width, 0.0))
    sector = np.minimum(((np.arctan2(y, x) + math.pi) / (2.0 * math.pi) * sectors).astype(
        np.int64), sectors - 1)
    np.minimum.at(gaps, sector, gap)
    return gaps


def closing_speeds(before: FloatArray, after: FloatArray, elapsed: float,
                   max_speed: float) -> FloatArray:
    """(S,) how fast (m/s, 0 to ``max_speed``) each sector's gap closed from ``before`` to
    ``after`` (S,) over ``elapsed`` s; the gap before is the smallest of the sector's and
    those of its two neighbours (circularly) whose gap grew or emptied since (what left a
    neighbour may have walked into this sector; a neighbour whose gap stayed, a person
    standing beside, hides nothing approaching here); 0 where either is inf or ``elapsed``
    is not positive and finite."""
    if not (elapsed > 0.0 and math.isfinite(elapsed)):
        return np.zeros(len(after))
    nearby = before.copy()
    for shift in (1, -1):
        neighbour_before, neighbour_after = np.roll(before, shift), np.roll(after, shift)
        nearby = np.minimum(nearby, np.where(neighbour_after > neighbour_before,
                                             neighbour_before, math.inf))
    with np.errstate(invalid="ignore"):
        speed = (nearby - after) / elapsed
    speed = np.where(np.isfinite(speed), speed, 0.0)
    return np.clip(speed, 0.0, max_speed)


def too_near(gaps: FloatArray, speeds: FloatArray, robot_speed: float, latency: float,
             reaction_time: float, deceleration: float, params: ClosingParams) -> bool:
    """Whether a stranger approaching at ``speeds`` (S,) m/s (``min_speed`` or more) is
    within S_p of the robot: its gap ``gaps`` (S,) m (data ``latency`` s old) against
    ``protective_distance`` of the robot at ``robot_speed`` m/s, which reacts within
    ``reaction_time`` s and brakes at ``deceleration`` m/s^2."""
    approaching = speeds >= params.min_speed
    if not approaching.any():
        return False
    needed = protective_distance(abs(robot_speed), speeds[approaching], max(latency, 0.0),
                                 reaction_time, deceleration, params.margin)
    return bool(np.any(gaps[approaching] < needed))

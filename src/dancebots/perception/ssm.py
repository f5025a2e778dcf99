"""Speed and separation monitoring (an addition; the principle of ISO/TS 15066 clause 5.5.4 and
ISO 13855 for machines near people), as pure vectorised functions.

The protective separation distance of ISO/TS 15066 (eq. 1 there, simplified to a robot whose
speed is constant until it reacts and which then brakes at a constant deceleration ``a``):

    S_p(v_r, v_h) = v_h (T_l + T_r + T_s)  +  v_r T_r  +  v_r^2 / (2 a)  +  C
                    `----- person: S_h ---'   `-robot: S_r-'  `-braking: S_s'

with T_s = v_r / a the robot's stopping time, T_r its reaction time (a control tick and the
actuator's lag), T_l the age of the LIDAR data the decision rests on (the robot compensates
its own motion over it, not the person's), v_h the speed at which the person approaches
and C a margin (intrusion distance and measurement uncertainty). ISO 13855 takes
v_h = 1.6 m/s for a walking person; a tracked object approaches at its estimated speed
towards the robot plus an uncertainty (``perception.tracks``).

The robot may drive at v_r only where every obstacle point keeps at least S_p from the area
the robot sweeps until it stands (its footprint stretched by S_r + S_s in the direction it
drives): :func:`ssm_speed_limit` gives the largest such speed. Frames: ``base_link`` (x
forward, y left, m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["SsmParams", "protective_distance", "ssm_speed_limit", "swept_gaps", "turn_allowed"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class SsmParams:
    """reaction_time: T_r, s (a 10 Hz control tick; the actuator lag is added per robot);
    deceleration: a, the braking deceleration a robot is sure of, m/s^2 (the realistic
    profile's limit); walking_speed: v_h of an object the tracker has not confirmed yet, m/s
    (ISO 13855: 1.6); speed_margin: m/s added to a tracked object's estimated approach
    speed (a standing person may step towards the robot); margin: C for people and other
    strangers, m; mate_margin: C for a formation mate where it should be or said it is, m
    (mates are robots that keep to the plan: their approach is the plan's, which the
    rigid check keeps apart); reach: SSM watches the points in the square of 2 x reach m
    around ``base_link`` (thesis 5.2's detector keeps 4 x 4 m: too near for a person walking
    at 1.6 m/s towards a robot driving at 0.5 m/s, whose S_p is about 2.4 m ahead of it)."""

    reaction_time: float = 0.1
    deceleration: float = 1.0
    walking_speed: float = 1.6
    speed_margin: float = 0.3
    margin: float = 0.25
    mate_margin: float = 0.1
    reach: float = 4.0

    def __post_init__(self) -> None:
        values = (self.reaction_time, self.deceleration, self.walking_speed,
                  self.speed_margin, self.margin, self.mate_margin, self.reach)
        if not all(math.isfinite(v) for v in values) or self.deceleration <= 0.0 or min(
                self.reaction_time, self.walking_speed, self.speed_margin, self.margin,
                self.mate_margin) < 0.0 or self.reach <= 0.0:
            raise ValueError("SSM parameters must be finite, the deceleration and reach above "
                             "0 and the others 0 or more")


def protective_distance(robot_speed: float | FloatArray, approach_speed: float | FloatArray,
                        latency: float, reaction_time: float, deceleration: float,
                        margin: float | FloatArray) -> FloatArray:
    """S_p of ISO/TS 15066 (see the module), m: the robot at ``robot_speed`` (m/s, >= 0)
    reacts after ``reaction_time`` s and brakes at ``deceleration`` m/s^2; the person
    approaches at ``approach_speed`` m/s (>= 0) from data ``latency`` s old. Broadcasts."""
    v = np.asarray(robot_speed, dtype=float)
    stopping = v / deceleration
    result: FloatArray = (np.asarray(approach_speed, dtype=float)
                          * (latency + reaction_time + stopping)
                          + v * reaction_time + 0.5 * v * stopping + margin)
    return result


def swept_gaps(points: FloatArray, length: float, width: float, reach: float,
               direction: float) -> FloatArray:
    """Distances (M,) from obstacle points (M, 2) in ``base_link`` to the area the footprint
    (``length`` x ``width``, m, centred) sweeps driving ``reach`` m straight ahead
    (``direction`` +1) or back (-1): 0 on or in it."""
    half_l, half_w = 0.5 * length, 0.5 * width
    x = points[:, 0] * (1.0 if direction >= 0.0 else -1.0)
    dx = np.maximum(np.maximum(-half_l - x, x - (half_l + reach)), 0.0)
    dy = np.maximum(np.abs(points[:, 1]) - half_w, 0.0)
    result: FloatArray = np.hypot(dx, dy)
    return result


def _predicted(points: FloatArray, velocity: FloatArray, spread: FloatArray, margins: FloatArray,
               first: float, last: float, samples: int) -> tuple[FloatArray, FloatArray]:
    """Where the points (M, 2) moving at ``velocity`` (M, 2) are at ``samples`` instants from
    ``first`` to ``last`` s after the data were taken, (K, M, 2), and the distance each must
    keep then, (K, M): its margin, its uncertainty grown at ``spread`` m/s, and half its way
    between two instants (so that the samples miss no approach)."""
    taus = np.linspace(first, last, samples)  # (K,)
    where = points[None] + taus[:, None, None] * velocity[None]
    step = (last - first) / max(samples - 1, 1)
    speed = np.hypot(velocity[:, 0], velocity[:, 1])
    need = margins[None] + spread[None] * taus[:, None] + 0.5 * step * speed[None]
    return where, need


def ssm_speed_limit(points: FloatArray, velocity: FloatArray, spread: FloatArray,
                    margins: FloatArray, length: float, width: float, direction: float,
                    top: float, latency: float, reaction_time: float, deceleration: float,
                    settle: float = 0.0, samples: int = 8, iterations: int = 20) -> float:
    """The largest speed v in [0, ``top``] (m/s) at which the robot may drive ``direction``
    (+1 forwards, -1 backwards): every obstacle point (M, 2, ``base_link``), predicted on
    along its ``velocity`` (M, 2, m/s, ``base_link`` axes, its own motion: the robot's is in
    the swept area) with an uncertainty growing at ``spread`` (M,) m/s (ISO 13855's 1.6 m/s
    for what is not tracked yet: S_h), keeps its margin (M,) (C) from the area the robot
    sweeps until it stands (:func:`swept_gaps`, reach S_r + S_s = v T_r + v^2 / 2a) at every
    instant from when the data were taken (``latency`` s ago) until the robot stands (T_r +
    v / a + ``settle`` from now; ``settle``: the time its speed takes to die away after
    braking, for an actuator that lags). For a point walking straight at the robot this is
    :func:`protective_distance`. 0.0 when even standing still is not enough (the robot
    stops: thesis 5.2's stop flag in SSM form), and for a ``top`` that is not finite and
    above 0. The condition only tightens as v grows, so bisection finds the limit (to
    top / 2^iterations)."""
    if not (math.isfinite(top) and top > 0.0):
        return 0.0  # no speed, or one that cannot be judged: stand
    if len(points) == 0:
        return float(top)

    def allowed(speed: float) -> bool:
        reach = speed * reaction_time + 0.5 * speed * speed / deceleration  # S_r + S_s
        where, need = _predicted(points, velocity, spread, margins, latency,
                                 latency + reaction_time + speed / deceleration + settle,
                                 samples)
        gaps = swept_gaps(where.reshape(-1, 2), length, width, reach, direction)
        return bool(np.all(gaps >= need.reshape(-1)))

    if allowed(top):
        return float(top)
    if not allowed(0.0):
        return 0.0
    low, high = 0.0, float(top)
    for _ in range(iterations):
        middle = 0.5 * (low + high)
        if allowed(middle):
            low = middle
        else:
            high = middle
    return low


def turn_allowed(points: FloatArray, velocity: FloatArray, spread: FloatArray,
                 margins: FloatArray, sweep_radius: float, latency: float, exposure: float,
                 samples: int = 8) -> bool:
    """Whether a robot standing still may turn on the spot: every obstacle point (M, 2,
    ``base_link``), predicted as in :func:`ssm_speed_limit`, keeps its margin outside the
    circle its footprint sweeps (``sweep_radius``, m: its half diagonal) from when the data
    were taken (``latency`` s ago) for ``exposure`` s more (the reaction and the time its turn
    takes to die away): SSM for a turn, so that a person walking up to a held robot does not
    meet a corner swinging out."""
    if len(points) == 0:
        return True
    where, need = _predicted(points, velocity, spread, margins, latency, latency + exposure,
                             samples)
    gaps = np.maximum(np.hypot(where[..., 0], where[..., 1]) - sweep_radius, 0.0)
    return bool(np.all(gaps >= need))

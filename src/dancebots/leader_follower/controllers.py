"""The second seed's controllers (MAGESys 2019, sec. 2.2) as pure functions of state.

B1 ``pid_step``, go-to-goal PID (eq. 1, 2): the distance error e_u = d - standoff, taken as
e_u cos(e_w) ("horizontal displacement", smoother for a target moving sideways), and the
heading error e_w (wrapped to (-pi, pi]); two discrete PID loops

    u[k] = Kp_u e_u[k] + Ki_u sum e_u + Kd_u (e_u[k] - e_u[k-1])          (1)
    w[k] = Kp_w e_w[k] + Ki_w sum e_w + Kd_w (e_w[k] - e_w[k-1])          (2)

with the seed's gain sets (``SEED_FIRST_GAINS``: Kp_u 1.2, Kp_w 0.5; ``SEED_TUNED_GAINS``:
Kp_u 0.6, Kp_w 0.1, Ki_w 0.01; no integral on distance, whose error never changes sign);
limits applied keeping the sign (the seed's code dropped the sign of w), and anti-windup
(the sum stops growing while the output is saturated in its direction).

B2 ``vo_step``, velocity obstacles (sec. 2.2.2; Fiorini and Shiller 1998; the reciprocal
form of van den Berg et al. 2008 as an option): candidate velocities of the point eps ahead
of the robot, in the robot frame, are tested against every object's velocity-obstacle cone
within a time horizon; the free candidate nearest to the preferred velocity (towards the
stand-off point) wins, or, when none is free, the one that best trades the time to
collision against the preference (the penalty of the RVO code the seed used). Feedback
linearisation in the robot frame (eq. 3, 4 with yaw = 0, as the README of the seeds
corrects): u = v_x, w = v_y / eps. Starts and stops are smoothed by acceleration limits
(the seed saw steps from 0 to full speed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np
from numpy.typing import NDArray

from dancebots.geometry import Pose
from dancebots.leader_follower.scan import Detection, to_robot

__all__ = ["CONTROLLERS", "SEED_FIRST_GAINS", "SEED_TUNED_GAINS", "PidGains", "PidParams",
           "PidState", "QueueController", "VoParams", "VoState", "feedback_linearization",
           "leader_robot_command", "pid_step", "time_to_collision", "vo_step"]

FloatArray = NDArray[np.float64]
QueueController = Literal["pid", "vo"]
CONTROLLERS: tuple[QueueController, ...] = get_args(QueueController)


@dataclass(frozen=True, slots=True)
class PidGains:
    kp_u: float = 0.6
    ki_u: float = 0.0
    kd_u: float = 0.0
    kp_w: float = 0.1
    ki_w: float = 0.01
    kd_w: float = 0.0


SEED_FIRST_GAINS = PidGains(kp_u=1.2, ki_u=0.0, kd_u=0.0, kp_w=0.5, ki_w=0.0, kd_w=0.0)
"""The seed's first run (sec. 3.3.1, fig. 7, 8): saturates fast."""
SEED_TUNED_GAINS = PidGains()
"""The seed's tuned controller (fig. 9, 10): Kp_u 0.6, Kp_w 0.1, Ki_w 0.01."""


@dataclass(frozen=True, slots=True)
class PidParams:
    """standoff: the distance kept to the target, m; max_linear m/s, max_angular rad/s;
    reverse: may the robot back off when too close (the seed's distance error is never
    negative, so its robots only stop); horizontal: use e_u cos(e_w)."""

    gains: PidGains = SEED_TUNED_GAINS
    standoff: float = 0.5
    max_linear: float = 0.22
    max_angular: float = 2.84
    reverse: bool = False
    horizontal: bool = True


@dataclass(frozen=True, slots=True)
class PidState:
    sum_u: float = 0.0
    sum_w: float = 0.0
    last_u: float | None = None
    last_w: float | None = None


def _limit(value: float, limit: float) -> float:
    """Clip keeping the sign."""
    return math.copysign(min(abs(value), limit), value)


def pid_step(params: PidParams, state: PidState, pose: tuple[float, float, float],
             detection: Detection | None) -> tuple[PidState, tuple[float, float]]:
    """One tick of B1: the robot at ``pose`` (odometry frame) towards the detection's target.
    No target: stop and forget the loops' memory. Returns (state, (u m/s, w rad/s))."""
    if detection is None or detection.target is None:
        return PidState(), (0.0, 0.0)
    gains = params.gains
    tx, ty = to_robot(detection.target.position, pose)
    e_w = math.atan2(ty, tx)  # wrapped to (-pi, pi] by atan2
    e_u = math.hypot(tx, ty) - params.standoff
    if params.horizontal:
        e_u *= math.cos(e_w)
    d_u = 0.0 if state.last_u is None else e_u - state.last_u
    d_w = 0.0 if state.last_w is None else e_w - state.last_w
    raw_u = gains.kp_u * e_u + gains.ki_u * state.sum_u + gains.kd_u * d_u
    raw_w = gains.kp_w * e_w + gains.ki_w * state.sum_w + gains.kd_w * d_w
    u = _limit(raw_u, params.max_linear)
    if not params.reverse:
        u = max(u, 0.0)
    w = _limit(raw_w, params.max_angular)
    # anti-windup: integrate only while the output is not saturated in the error's direction
    sum_u = state.sum_u + (e_u if abs(raw_u) < params.max_linear or e_u * raw_u < 0 else 0.0)
    sum_w = state.sum_w + (e_w if abs(raw_w) < params.max_angular or e_w * raw_w < 0 else 0.0)
    return PidState(sum_u, sum_w, e_u, e_w), (u, w)


@dataclass(frozen=True, slots=True)
class VoParams:
    """standoff m; max_linear m/s, max_angular rad/s; epsilon: the distance of the
    controlled point ahead of the centre, m (the seeds' README: about 0.1 m); radius: the
    robot's, m; horizon: how far ahead collisions count, s; gain: of the preferred velocity,
    1/s; reciprocal: RVO instead of VO; speeds, headings: the candidate grid; penalty: weight
    of 1/time-to-collision for colliding candidates, m; max_linear_acceleration m/s^2 and
    max_angular_acceleration rad/s^2: the smoothing; dt: the control period, s."""

    standoff: float = 0.5
    max_linear: float = 0.22
    max_angular: float = 2.84
    epsilon: float = 0.1
    radius: float = 0.15
    horizon: float = 2.0
    gain: float = 1.0
    reciprocal: bool = False
    speeds: int = 8
    headings: int = 36
    penalty: float = 0.2
    max_linear_acceleration: float = 0.5
    max_angular_acceleration: float = 4.0
    dt: float = 0.1


@dataclass(frozen=True, slots=True)
class VoState:
    velocity: tuple[float, float] = (0.0, 0.0)  # the last chosen (vx, vy), robot frame
    command: tuple[float, float] = (0.0, 0.0)  # the last (u, w)


def time_to_collision(relative_velocities: FloatArray, positions: FloatArray,
                      radii: FloatArray) -> FloatArray:
    """When does a point leaving the origin at relative velocities (M, 2), or (M, K, 2) one
    per disc, enter each disc (K,) at positions (K, 2) of radii (K,)? (M, K) s, inf for
    never; 0 when inside a disc and not moving out of it."""
    w = relative_velocities if relative_velocities.ndim == 3 else relative_velocities[:, None]
    p = positions[None, :, :]  # (1, K, 2)
    a = (w**2).sum(axis=2)
    b = (w * p).sum(axis=2)  # the approach rate times |p| projected
    c = (p**2).sum(axis=2) - radii[None, :] ** 2
    disc = b**2 - a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (b - np.sqrt(np.maximum(disc, 0.0))) / a
    hits = (disc >= 0.0) & (a > 1e-12) & (t >= 0.0)
    result = np.where(hits, t, np.inf)
    inside = c <= 0.0
    result = np.where(inside & (b > 0.0), 0.0, np.where(inside, np.inf, result))
    out: FloatArray = result
    return out


def feedback_linearization(velocity: tuple[float, float], epsilon: float,
                           ) -> tuple[float, float]:
    """The (u, w) that moves the point ``epsilon`` ahead of the robot at ``velocity``
    (vx, vy) in the robot frame (seed eq. 3, 4 in the robot's own frame): u = vx,
    w = vy / epsilon."""
    return velocity[0], velocity[1] / epsilon


def vo_step(params: VoParams, state: VoState, pose: tuple[float, float, float],
            detection: Detection | None) -> tuple[VoState, tuple[float, float]]:
    """One tick of B2 for the robot at ``pose`` (odometry frame). Returns (state, (u, w))."""
    target = None if detection is None else detection.target
    if target is None:
        return _smoothed(params, state, (0.0, 0.0), (0.0, 0.0))
    heading = Pose(0.0, 0.0, pose[2])

    def in_robot(vector: tuple[float, float]) -> tuple[float, float]:
        return heading.to_local(vector[0], vector[1])  # a direction: rotated, not moved

    goal = np.array(to_robot(target.position, pose)) - np.array([params.epsilon, 0.0])
    distance = float(np.hypot(*goal))
    error = math.hypot(*to_robot(target.position, pose)) - params.standoff
    speed = min(params.max_linear, params.gain * max(error, 0.0))
    preferred = goal / distance * speed if distance > 1e-9 else np.zeros(2)
    objects = [o for o in (detection.objects if detection else ()) if o != target]
    # the candidate grid: speeds x headings, and standing still
    speeds = np.linspace(0.0, params.max_linear, params.speeds + 1)[1:]
    angles = np.linspace(-math.pi, math.pi, params.headings, endpoint=False)
    grid = np.column_stack([np.outer(speeds, np.cos(angles)).ravel(),
                            np.outer(speeds, np.sin(angles)).ravel()])
    candidates = np.vstack([np.zeros((1, 2)), preferred[None], grid])
    if objects:
        positions = np.array([to_robot(o.position, pose) for o in objects]) - np.array(
            [params.epsilon, 0.0])
        velocities = np.array([in_robot(o.velocity) for o in objects])
        radii = np.array([o.radius for o in objects]) + params.radius
        own = np.array(state.velocity)
        relative = (2.0 * candidates[:, None, :] - own[None, None, :] if params.reciprocal
                    else candidates[:, None, :]) - velocities[None, :, :]  # (M, K, 2)
        ttc = time_to_collision(relative, positions, radii).min(axis=1)
    else:
        ttc = np.full(len(candidates), np.inf)
    deviation = np.hypot(*(candidates - preferred).T)
    free = ttc > params.horizon
    if free.any():
        choice = int(np.argmin(np.where(free, deviation, np.inf)))
    else:
        choice = int(np.argmin(params.penalty / np.maximum(ttc, 1e-3) + deviation))
    chosen = (float(candidates[choice, 0]), float(candidates[choice, 1]))
    return _smoothed(params, state, chosen, feedback_linearization(chosen, params.epsilon))


def _smoothed(params: VoParams, state: VoState, velocity: tuple[float, float],
              command: tuple[float, float]) -> tuple[VoState, tuple[float, float]]:
    """Limit the command's change by the accelerations (smoothed starts and stops) and its
    size by the robot's limits, keeping signs."""
    step_u = params.max_linear_acceleration * params.dt
    step_w = params.max_angular_acceleration * params.dt
    u = state.command[0] + max(-step_u, min(step_u, command[0] - state.command[0]))
    w = state.command[1] + max(-step_w, min(step_w, command[1] - state.command[1]))
    u, w = _limit(u, params.max_linear), _limit(w, params.max_angular)
    return VoState(velocity, (u, w)), (u, w)


def leader_robot_command(goal: tuple[float, float], pose: tuple[float, float, float],
                         max_linear: float, max_angular: float) -> tuple[float, float]:
    """The leader robot's (u, w) towards where the person would be now (a go-to-goal law:
    u = 1.5 d cos(e), w = 2 e, e the heading error; stops within 5 cm; limits keep signs)."""
    dx, dy = goal[0] - pose[0], goal[1] - pose[1]
    distance = math.hypot(dx, dy)
    if distance < 0.05:
        return 0.0, 0.0
    error = math.atan2(dy, dx) - pose[2]
    error = math.atan2(math.sin(error), math.cos(error))
    u = max(0.0, min(max_linear, 1.5 * distance * math.cos(error)))
    w = math.copysign(min(abs(2.0 * error), max_angular), error)
    return u, w

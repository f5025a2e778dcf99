"""Robot motion in the simulator: actuation profiles and unicycle integration, vectorised.

Arrays have shape (R,), one entry per robot; units m, rad, m/s, rad/s, s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["IDEAL", "PHYSICS", "PHYSICS_GEOMETRIC", "PROFILES", "REALISTIC", "Profile", "actuate",
           "fresh_commands"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Profile:
    """How commands become motion.

    lag: first-order actuator time constant, s (0: commands act at once).
    linear_acceleration, angular_acceleration: limits, m/s^2 and rad/s^2 (inf: none).
    linear_noise, angular_noise: standard deviation of the velocity noise added each step
        to robots that are commanded to move, m/s and rad/s, from the run's seeded generator.
    standstill: (m/s, rad/s) below which a speed commanded to zero is zero: a skid-steer
        robot's tracks need a breakaway torque to slide, so it does not creep on the lag's
        exponential tail (without it a robot told to stop at 0.1 m/s still moves at 2 mm/s a
        second later); (0, 0): no standstill.
    engine: None: the fields above move the robots (``actuate``, then the unicycle);
        "mujoco": a physics engine does (``sim.physics``: mass, inertia, wheel slip, motor
        limits) and the fields above are not used.
    drive: with an engine, how the robots' drivers turn (v, w) into wheel speeds:
        "calibrated" (the track widened by the skid-steer ICR expansion, as real drivers do)
        or "geometric" (the plain track: skid-steer robots under-turn by their slip).
    """

    name: str
    lag: float = 0.0
    linear_acceleration: float = math.inf
    angular_acceleration: float = math.inf
    linear_noise: float = 0.0
    angular_noise: float = 0.0
    standstill: tuple[float, float] = (0.0, 0.0)
    engine: str | None = None
    drive: str = "calibrated"


IDEAL = Profile("ideal")
"""Commands act at once, no noise: the thesis's 2D simulator (ch. 7.1)."""
REALISTIC = Profile("realistic", lag=0.25, linear_acceleration=1.0, angular_acceleration=4.0,
                    linear_noise=0.01, angular_noise=0.02, standstill=(0.01, 0.02))
"""Inertia, actuator lag and noise: standing in for the thesis's 3D simulation (ch. 7.2.1)."""
PHYSICS = Profile("physics", engine="mujoco")
"""Skid-steer, tracked and differential robots in MuJoCo (``sim.physics``): standing in for
the thesis's 3D simulator (Gazebo) with the robots' models, whose wheels slip in turns; their
drivers widen the track for it, as real ones do."""
PHYSICS_GEOMETRIC = Profile("physics-geometric", engine="mujoco", drive="geometric")
"""The physics profile with drivers that turn (v, w) into wheel speeds by the plain track:
skid-steer robots under-turn by their wheels' slip (a HUSKY at about 0.55 of the rate)."""
PROFILES = {profile.name: profile
            for profile in (IDEAL, REALISTIC, PHYSICS, PHYSICS_GEOMETRIC)}


def actuate(profile: Profile, velocity: FloatArray, command: FloatArray, dt: float,
            rng: np.random.Generator, noise: FloatArray | None = None) -> FloatArray:
    """The velocities (R, 2) after one step of dt s from ``velocity`` towards ``command``;
    a noisy profile's standard normal draws (R, 2) are ``noise`` when given, else drawn from
    ``rng`` here."""
    if profile.lag > 0.0:
        target = velocity + (command - velocity) * (1.0 - math.exp(-dt / profile.lag))
    else:
        target = command
    limits = np.array([profile.linear_acceleration, profile.angular_acceleration]) * dt
    result: FloatArray = velocity + np.clip(target - velocity, -limits, limits)
    if profile.standstill != (0.0, 0.0):
        result = np.where((command == 0.0) & (np.abs(result) < np.array(profile.standstill)),
                          0.0, result)
    if profile.linear_noise > 0.0 or profile.angular_noise > 0.0:
        # wheels that are told to stand still do not drift: noise only on commanded motion
        if noise is None:
            noise = rng.normal(0.0, 1.0, size=result.shape)
        driven = np.any(command != 0.0, axis=1, keepdims=True)
        result = result + driven * noise * np.array([profile.linear_noise,
                                                     profile.angular_noise])
    return result


def fresh_commands(command: FloatArray, issued: FloatArray, now: float,
                   timeout: float) -> FloatArray:
    """The robots' 10 Hz rule (thesis ch. 2): commands (R, 2) issued at ``issued`` (R,) s act
    only while they are at most ``timeout`` s old at ``now``; older ones become zero."""
    fresh = (now - issued) <= timeout + 1e-9
    result: FloatArray = np.where(fresh[:, None], command, 0.0)
    return result

"""Kinematics: the 10 Hz rule and the actuation profiles."""

from __future__ import annotations

import numpy as np

from dancebots.sim.kinematics import IDEAL, REALISTIC, Profile, actuate, fresh_commands


def test_ten_hertz_rule() -> None:
    command = np.array([[0.5, 0.1], [0.4, 0.0], [0.3, -0.2]])
    issued = np.array([1.0, 0.9, 0.85])
    assert fresh_commands(command, issued, 1.0, 0.1).tolist() == [
        [0.5, 0.1], [0.4, 0.0], [0.0, 0.0]]


def test_realistic_profile_has_lag_and_acceleration_limits() -> None:
    rng = np.random.default_rng(0)
    quiet = Profile("test", lag=0.25, linear_acceleration=1.0, angular_acceleration=4.0)
    velocity = actuate(quiet, np.zeros((1, 2)), np.array([[1.0, 3.0]]), 0.1, rng)
    # lag: 1 - exp(-0.1 / 0.25) = 0.33 of the step, then limited to 0.1 m/s and 0.4 rad/s
    np.testing.assert_allclose(velocity, [[0.1, 0.4]])
    assert actuate(IDEAL, np.zeros((1, 2)), np.array([[1.0, 3.0]]), 0.1, rng).tolist() == [
        [1.0, 3.0]]


def test_a_robot_told_to_stop_stands_once_its_speed_is_below_the_standstill() -> None:
    """The lag's exponential tail does not creep on: a speed commanded to zero is zero below
    ``standstill``; a commanded speed, however small, is not cut."""
    rng = np.random.default_rng(0)
    velocity = np.array([[0.1, 0.3]])
    steps = 0
    while np.any(velocity != 0.0):
        velocity = actuate(REALISTIC, velocity, np.zeros((1, 2)), 0.1, rng)
        steps += 1
        assert steps < 30, velocity
    # per 0.1 s step the 0.25 s lag keeps 0.67 of the speed: 0.1 m/s falls below 1 cm/s
    # after 6 steps (0.67 ** 6 = 0.09), 0.3 rad/s below 0.02 rad/s after 7 (0.67 ** 7 = 0.06)
    assert steps == 7
    creeping = actuate(REALISTIC, np.array([[0.005, 0.0]]), np.array([[0.005, 0.0]]), 0.1,
                       np.random.default_rng(1))
    assert creeping[0, 0] != 0.0
    lagging = actuate(Profile("lag only", lag=0.25), np.array([[0.005, 0.0]]),
                      np.zeros((1, 2)), 0.1, rng)
    assert lagging[0, 0] > 0.0  # without a standstill the tail goes on

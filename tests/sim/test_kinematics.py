"""Kinematics: the 10 Hz rule and the actuation profiles."""

from __future__ import annotations

import numpy as np

from dancebots.sim.kinematics import IDEAL, Profile, actuate, fresh_commands


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

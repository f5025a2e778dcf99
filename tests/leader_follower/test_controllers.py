"""Controllers B1 (PID) and B2 (velocity obstacles): properties and known cases."""

from __future__ import annotations

import itertools
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.leader_follower.controllers import (
    SEED_FIRST_GAINS,
    SEED_TUNED_GAINS,
    PidParams,
    PidState,
    VoParams,
    VoState,
    feedback_linearization,
    pid_step,
    time_to_collision,
    vo_step,
)
from dancebots.leader_follower.scan import Detection, TrackedObject

coordinates = st.floats(-5.0, 5.0, allow_nan=False)
poses = st.tuples(coordinates, coordinates, st.floats(-10.0, 10.0, allow_nan=False))
gain_sets = st.sampled_from([SEED_FIRST_GAINS, SEED_TUNED_GAINS])


def detection_at(x: float, y: float) -> Detection:
    return Detection(TrackedObject((x, y)))


@settings(max_examples=300)
@given(poses, coordinates, coordinates, gain_sets)
def test_pid_turns_towards_the_target(pose, tx, ty, gains) -> None:  # type: ignore[no-untyped-def]
    bearing = math.atan2(ty - pose[1], tx - pose[0]) - pose[2]
    heading_error = math.atan2(math.sin(bearing), math.cos(bearing))
    _, (_, w) = pid_step(PidParams(gains=gains), PidState(), pose, detection_at(tx, ty))
    ambiguous = abs(heading_error) < 1e-6 or abs(abs(heading_error) - math.pi) < 1e-6
    if not ambiguous and math.hypot(tx - pose[0], ty - pose[1]) > 1e-6:
        assert math.copysign(1.0, w) == math.copysign(1.0, heading_error)


@settings(max_examples=200)
@given(st.lists(st.tuples(coordinates, coordinates), min_size=1, max_size=30), poses,
       gain_sets)
def test_pid_never_exceeds_its_limits(targets, pose, gains) -> None:  # type: ignore[no-untyped-def]
    params = PidParams(gains=gains, max_linear=0.22, max_angular=2.84)
    state = PidState()
    for tx, ty in targets:
        state, (u, w) = pid_step(params, state, pose, detection_at(tx, ty))
        assert 0.0 <= u <= 0.22  # forward only, as the seed's robots
        assert abs(w) <= 2.84


def test_pid_integral_does_not_wind_up_while_saturated() -> None:
    params = PidParams(gains=SEED_TUNED_GAINS, max_angular=0.2)
    state = PidState()
    for _ in range(500):  # the target far to the left for 50 s: w saturated at +0.2
        state, (_, w) = pid_step(params, state, (0, 0, 0), detection_at(0.0, 1.0))
    assert w == pytest.approx(0.2)
    # the sum stopped growing at saturation: 0.01 x sum covers only what Kp leaves to 0.2
    assert params.gains.ki_w * state.sum_w < 0.2 - params.gains.kp_w * math.pi / 2 + 0.02
    turns = []
    for _ in range(20):  # the target now to the right: w turns within two seconds
        state, (_, w) = pid_step(params, state, (0, 0, 0), detection_at(1.0, -0.3))
        turns.append(w)
    assert min(turns) < 0


def test_pid_stops_when_the_target_is_lost() -> None:
    state, _ = pid_step(PidParams(), PidState(), (0, 0, 0), detection_at(2.0, 0.5))
    state, command = pid_step(PidParams(), state, (0, 0, 0), Detection(None))
    assert command == (0.0, 0.0)
    assert state == PidState()


def test_pid_keeps_the_standoff() -> None:
    _, (u, _) = pid_step(PidParams(standoff=0.5), PidState(), (0, 0, 0), detection_at(0.5, 0))
    assert u == 0.0
    _, (u, _) = pid_step(PidParams(standoff=0.5), PidState(), (0, 0, 0), detection_at(0.3, 0))
    assert u == 0.0  # too close: stops (never reverses by default)


@given(st.floats(-1.0, 1.0), st.floats(1e-3, 1.0), st.floats(0.01, 0.5))
def test_feedback_linearization_turns_towards_a_sideways_velocity(vx, vy, eps) -> None:  # type: ignore[no-untyped-def]
    u, w = feedback_linearization((vx, vy), eps)
    assert w > 0  # a velocity to the left turns left
    assert u == vx
    _, w_right = feedback_linearization((vx, -vy), eps)
    assert w_right < 0


def test_time_to_collision_known_cases() -> None:
    import numpy as np

    ttc = time_to_collision(np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]]),
                            np.array([[2.0, 0.0]]), np.array([0.5]))
    assert ttc[0, 0] == pytest.approx(1.5)  # head on: 2 m - 0.5 m at 1 m/s
    assert ttc[1, 0] == math.inf  # passing sideways
    assert ttc[2, 0] == math.inf  # moving away


def test_vo_goes_straight_to_a_free_target() -> None:
    params = VoParams(max_linear_acceleration=100.0, max_angular_acceleration=100.0)
    _, (u, w) = vo_step(params, VoState(), (0, 0, 0), detection_at(2.0, 0.0))
    assert u == pytest.approx(params.max_linear)
    assert w == pytest.approx(0.0, abs=1e-9)


def test_vo_steers_around_an_object_between_robot_and_target() -> None:
    params = VoParams(max_linear_acceleration=100.0, max_angular_acceleration=100.0)
    blocker = TrackedObject((0.7, 0.0), (0.0, 0.0), 0.2, track=7)  # reached within 2 s
    detection = Detection(TrackedObject((2.5, 0.0), track=3), (blocker,))
    state, (_u, w) = vo_step(params, VoState(), (0, 0, 0), detection)
    vx, vy = state.velocity
    assert abs(vy) > 0.02  # not straight at the blocker
    ttc = time_to_collision(__import__("numpy").array([[vx, vy]]),
                            __import__("numpy").array([[0.6, 0.0]]),
                            __import__("numpy").array([0.2 + params.radius]))
    assert ttc[0, 0] > params.horizon
    assert w != 0.0


def test_vo_starts_smoothly() -> None:
    params = VoParams(max_linear_acceleration=0.5, dt=0.1)
    state = VoState()
    speeds = []
    for _ in range(6):
        state, (u, _) = vo_step(params, state, (0, 0, 0), detection_at(3.0, 0.0))
        speeds.append(u)
    assert speeds[0] == pytest.approx(0.05)  # 0.5 m/s^2 x 0.1 s, not 0 -> full speed
    assert all(b - a <= 0.05 + 1e-9 for a, b in itertools.pairwise(speeds))

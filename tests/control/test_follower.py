"""The thesis follower (eq. 4.4) against hand-computed values, and its properties."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from dancebots.control.follower import FollowerParams, FollowerState, thesis_follower_step

PARAMS = FollowerParams(vmax=0.5, max_linear=1.0, max_angular=math.pi)


def step(pose: tuple[float, float, float], leader: tuple[float, float],
         path_point: tuple[float, float], desired: tuple[float, float] = (0.0, 0.0),
         required: float = 0.78, moving: bool = True, state: FollowerState | None = None,
         params: FollowerParams = PARAMS, now: float = 0.0,
         ) -> tuple[FollowerState, tuple[float, float]]:
    return thesis_follower_step(params, state or FollowerState(), now, pose, leader,
                                path_point, desired, required, moving)


def test_eq_4_4a_faster_when_the_gap_is_too_big() -> None:
    # target straight ahead; d_act = 1.0, d_req = 0.78:
    # linear = 0.7 * 0.5 * |1 + 3 * 0.22| = 0.35 * 1.66 = 0.581; angular = 0.
    state, (linear, angular) = step((0.0, 0.0, 0.0), (1.0, 0.0), (0.78, 0.0), (0.5, 0.0))
    assert linear == pytest.approx(0.581)
    assert angular == 0.0
    assert state.queue == ((0.78, 0.0),)


def test_eq_4_4a_slower_when_the_gap_is_too_small() -> None:
    # d_act = 0.6: linear = 0.35 * |1 - 0.54| = 0.161
    _, (linear, _) = step((0.0, 0.0, 0.0), (0.6, 0.0), (0.5, 0.0), (0.4, 0.0))
    assert linear == pytest.approx(0.161)


def test_eq_4_4b_turns_towards_the_target() -> None:
    # target (1, 1): alpha = pi/4, angular = 3 * pi/4 = 2.356
    _, (linear, angular) = step((0.0, 0.0, 0.0), (1.2, 1.2), (1.0, 1.0), (0.5, 0.5),
                                required=0.7)
    assert angular == pytest.approx(3 * math.pi / 4)
    assert linear > 0


def test_target_behind_is_reached_by_reversing() -> None:
    # target (-1, 0.5): Gx < 0 -> reverse; alpha = atan(0.5 / 1) = 0.4636,
    # angular = 3 * sgn(-0.5) * 0.4636 = -1.391 (the rear swings left, towards the target).
    _, (linear, angular) = step((0.0, 0.0, 0.0), (-1.0, 0.5), (-1.0, 0.5), (-1.0, 0.5),
                                required=1.118)
    assert linear < 0
    assert angular == pytest.approx(-3 * math.atan2(0.5, 1.0))


def test_limits_keep_the_sign() -> None:
    params = FollowerParams(vmax=0.5, max_linear=0.3, max_angular=1.0)
    _, (linear, angular) = step((0.0, 0.0, 0.0), (-3.0, -3.0), (-2.0, -2.0), (-1.0, -1.0),
                                params=params)
    assert (linear, angular) == (-0.3, 1.0)


def test_queue_head_popped_until_thirty_centimetres_away() -> None:
    queue = ((0.1, 0.0), (0.2, 0.0), (0.29, 0.0), (0.45, 0.0))
    state, _ = step((0.0, 0.0, 0.0), (1.3, 0.0), (1.0, 0.0), state=FollowerState(queue, 0.0),
                    now=0.05, required=1.3)
    assert state.queue == ((0.45, 0.0),)  # not filled: the last fill was 0.05 s ago


def test_queue_cleared_when_the_leader_is_too_far() -> None:
    queue = ((0.5, 0.0), (0.6, 0.0))
    state, (_, angular) = step((0.0, 0.0, 0.0), (2.0, 0.0), (1.6, 1.0),
                               state=FollowerState(queue, 0.0), now=0.05, required=0.78)
    assert state.queue == ()
    assert angular > 0  # steering straight at the current path point, not the old queue


def test_arrival_at_a_standing_leader() -> None:
    state, command = step((0.0, 0.0, 0.0), (0.5, 0.6), (0.5, 0.0), desired=(0.05, 0.0),
                          moving=False, state=FollowerState(((0.4, 0.0),), 0.0), now=0.05)
    assert command == (0.0, 0.0)
    assert state.queue == ()
    # further away it drives there, slowing down like eq. 4.1a: 1.5 * 0.2 = 0.3 m/s
    _, (linear, _) = step((0.0, 0.0, 0.0), (0.7, 0.6), (0.7, 0.0), desired=(0.2, 0.0),
                          moving=False)
    assert linear == pytest.approx(0.3)


coordinates = st.floats(-5, 5, allow_nan=False)


@given(coordinates, coordinates, st.floats(-math.pi, math.pi), coordinates, coordinates,
       coordinates, coordinates)
def test_output_within_limits_and_signs_match(x: float, y: float, theta: float, lx: float,
                                              ly: float, px: float, py: float) -> None:
    params = FollowerParams(vmax=0.5, max_linear=0.5, max_angular=2.0)
    _, (linear, angular) = step((x, y, theta), (lx, ly), (px, py), desired=(px, py),
                                params=params, required=1.0)
    assert abs(linear) <= 0.5
    assert abs(angular) <= 2.0
    # the commanded direction agrees with where the target lies in base_link
    gx = math.cos(theta) * (px - x) + math.sin(theta) * (py - y)
    gy = -math.sin(theta) * (px - x) + math.cos(theta) * (py - y)
    if math.hypot(px - x, py - y) >= 0.3 and abs(gx) > 1e-9 and abs(gy) > 1e-9:
        assert math.copysign(1, linear) == math.copysign(1, gx) or linear == 0
        assert math.copysign(1, angular) == math.copysign(1, gx * gy)

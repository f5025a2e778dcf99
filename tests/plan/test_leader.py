"""The virtual leader's controllers against hand-computed values (thesis eq. 4.1, 4.3, 6.1)."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from dancebots.plan.leader import arc_angular_speed, arc_command, waypoint_command


def test_eq_4_1_far_waypoint_ahead_left() -> None:
    # G = (2, 1): linear = min(max(3, 0.1), 0.35) = 0.35;
    # alpha = atan2(1, 2) = 0.4636476 rad, angular = 2 * 0.4636476 = 0.9272952.
    linear, angular = waypoint_command(2.0, 1.0, vmax=0.5)
    assert linear == pytest.approx(0.35)
    assert angular == pytest.approx(0.9272952180016122)


def test_eq_4_1_near_waypoint_slows_down() -> None:
    # G = (0.1, -0.02): linear = max(0.15, 0.1) = 0.15; angular = -2 * atan(0.2) = -0.3947911.
    linear, angular = waypoint_command(0.1, -0.02, vmax=0.5)
    assert linear == pytest.approx(0.15)
    assert angular == pytest.approx(-0.39479112)


def test_eq_4_1_minimum_speed_and_saturation() -> None:
    # G = (0, -2): linear = max(0, 0.1) = 0.1; angular = -2 * pi/2 = -pi, saturated to -pi/2.
    linear, angular = waypoint_command(0.0, -2.0, vmax=0.5)
    assert linear == pytest.approx(0.1)
    assert angular == pytest.approx(-math.pi / 2)


def test_eq_4_1_waypoint_straight_behind_turns_left() -> None:
    linear, angular = waypoint_command(-1.0, 0.0, vmax=1.0)
    assert linear == pytest.approx(0.1)
    assert angular == pytest.approx(math.pi / 2)


def test_eq_4_1_straight_ahead_no_turn() -> None:
    assert waypoint_command(0.2, 0.0, vmax=1.0) == pytest.approx((0.3, 0.0))


@given(st.floats(-50, 50), st.floats(-50, 50), st.floats(0.1, 2.0))
def test_eq_4_1_bounds(gx: float, gy: float, vmax: float) -> None:
    linear, angular = waypoint_command(gx, gy, vmax)
    assert min(0.1, 0.7 * vmax) <= linear <= 0.7 * vmax + 1e-12
    assert abs(angular) <= math.pi / 2
    turns = abs(math.atan2(gy, gx)) > 0.0  # 0 for a subnormal gy ahead (5e-324)
    if gy > 0 and turns:
        assert angular > 0
    if gy < 0 and turns:
        assert angular < 0


def test_eq_6_1_halving() -> None:
    # r = 3, omega = 0.1: v = 0.3 <= 0.35, kept.
    assert arc_angular_speed(-3.0, 0.1, vmax=0.5) == 0.1
    # r = 5, omega = 0.2: v = 1.0 -> 0.5 -> 0.25 <= 0.35 after two halvings: omega = 0.05.
    assert arc_angular_speed(5.0, 0.2, vmax=0.5) == pytest.approx(0.05)


def test_eq_4_3_on_the_arc() -> None:
    # r = 2, omega = 0.1, r_real = 2: linear = 0.2, angular = 0.1 * (1 - 0) = 0.1.
    assert arc_command(2.0, 0.1, 2.0) == pytest.approx((0.2, 0.1))


def test_eq_4_3_outside_the_arc_turns_harder_towards_centre() -> None:
    # r = 2, r_real = 2.1: angular = 0.1 * (1 - 5 * (2 - 2.1)) = 0.1 * 1.5 = 0.15.
    assert arc_command(2.0, 0.1, 2.1) == pytest.approx((0.2, 0.15))
    # r = -3 (centre on the right), r_real = 3.2: angular = -0.1 * (1 + 1.0) = -0.2.
    assert arc_command(-3.0, 0.1, 3.2) == pytest.approx((0.3, -0.2))


def test_eq_4_3_inside_the_arc_opens_up() -> None:
    # r = 2, r_real = 1.9: angular = 0.1 * (1 - 0.5) = 0.05.
    assert arc_command(2.0, 0.1, 1.9) == pytest.approx((0.2, 0.05))

"""Speed and separation monitoring (perception/ssm.py): ISO/TS 15066's protective distance and
the speed limit that keeps every point at it."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.perception.ssm import (
    SsmParams,
    protective_distance,
    ssm_speed_limit,
    swept_gaps,
)

LENGTH, WIDTH = 1.2, 0.6
REACTION, DECELERATION = 0.1, 1.0


def test_protective_distance_adds_the_person_the_robot_and_its_braking() -> None:
    # v_h (T_l + T_r + v/a) + v T_r + v^2 / 2a + C with v = 0.5, v_h = 1.6, T_l = 0.3
    expected = 1.6 * (0.3 + 0.1 + 0.5) + 0.5 * 0.1 + 0.125 + 0.25
    assert protective_distance(0.5, 1.6, 0.3, 0.1, 1.0, 0.25) == pytest.approx(expected)
    # a robot standing still before a standing object keeps only the margin
    assert protective_distance(0.0, 0.0, 0.3, 0.1, 1.0, 0.25) == pytest.approx(0.25)


def test_swept_gaps_of_points_ahead_beside_behind_and_inside() -> None:
    points = np.array([[2.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.1, 0.1], [0.9, 0.0]])
    gaps = swept_gaps(points, LENGTH, WIDTH, reach=0.3, direction=1.0)
    np.testing.assert_allclose(gaps, [2.0 - 0.9, 0.7, 0.4, 0.0, 0.0], atol=1e-12)
    backwards = swept_gaps(points, LENGTH, WIDTH, reach=0.3, direction=-1.0)
    np.testing.assert_allclose(backwards, [1.4, 0.7, 0.1, 0.0, 0.3], atol=1e-12)


def test_a_standing_point_ahead_allows_the_speed_that_stops_at_the_margin() -> None:
    # f = v T_r + v^2 / 2a + C  =>  v = a (-T_r + sqrt(T_r^2 + 2 (f - C) / a))
    free, margin = 0.8, 0.25
    point = np.array([[0.6 + free, 0.0]])
    limit = ssm_speed_limit(point, np.zeros(1), np.full(1, margin), LENGTH, WIDTH, 1.0, 1.0,
                            0.3, REACTION, DECELERATION)
    expected = DECELERATION * (-REACTION + math.sqrt(REACTION**2 + 2 * (free - margin)
                                                     / DECELERATION))
    assert limit == pytest.approx(expected, abs=1e-6)
    # the same point behind a robot driving forwards does not limit it
    assert ssm_speed_limit(-point, np.zeros(1), np.full(1, margin), LENGTH, WIDTH, 1.0, 1.0,
                           0.3, REACTION, DECELERATION) == 1.0


def test_an_approaching_person_stops_the_robot_before_it_is_near() -> None:
    # a person 1 m beside the robot walking towards it at 1.6 m/s: S_p(0) = 1.6 x 0.4 + 0.25
    beside = np.array([[0.0, 0.3 + 0.8]])
    assert ssm_speed_limit(beside, np.array([1.6]), np.array([0.25]), LENGTH, WIDTH, 1.0, 0.5,
                           0.3, REACTION, DECELERATION) == 0.0
    # standing there, the person does not stop it
    assert ssm_speed_limit(beside, np.array([0.0]), np.array([0.25]), LENGTH, WIDTH, 1.0, 0.5,
                           0.3, REACTION, DECELERATION) == 0.5


@pytest.mark.parametrize("top", [0.0, -1.0, math.nan, math.inf, 1e-300])
def test_hostile_top_speeds_give_a_finite_limit(top: float) -> None:
    limit = ssm_speed_limit(np.array([[3.0, 0.0]]), np.zeros(1), np.full(1, 0.25), LENGTH,
                            WIDTH, 1.0, top, 0.3, REACTION, DECELERATION)
    # no speed, or one that cannot be judged, stands; a tiny one is kept (nothing is near)
    assert limit == (1e-300 if top == 1e-300 else 0.0)


def test_no_points_leave_the_speed_as_it_is() -> None:
    assert ssm_speed_limit(np.zeros((0, 2)), np.zeros(0), np.zeros(0), LENGTH, WIDTH, 1.0,
                           0.4, 0.3, REACTION, DECELERATION) == 0.4


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.floats(-4, 4), st.floats(-4, 4), st.floats(0, 2.5)),
                min_size=1, max_size=12),
       st.floats(0.01, 1.5), st.sampled_from([1.0, -1.0]), st.floats(0.0, 0.5))
def test_the_limit_is_the_largest_speed_that_keeps_every_distance(
        rows: list[tuple[float, float, float]], top: float, direction: float,
        latency: float) -> None:
    points = np.array([r[:2] for r in rows])
    approach = np.array([r[2] for r in rows])
    margins = np.full(len(rows), 0.25)

    def keeps(speed: float) -> bool:
        # every point's distance along and beside the way: swept gap + the robot's S_r + S_s
        reach = speed * REACTION + 0.5 * speed**2 / DECELERATION
        need = protective_distance(speed, approach, latency, REACTION, DECELERATION, margins)
        return bool(np.all(swept_gaps(points, LENGTH, WIDTH, reach, direction) + reach
                           >= need - 1e-12))

    limit = ssm_speed_limit(points, approach, margins, LENGTH, WIDTH, direction, top, latency,
                            REACTION, DECELERATION)
    assert 0.0 <= limit <= top
    if limit > 0.0:
        assert keeps(limit)  # the robot may drive at the limit
    if limit < top:
        assert not keeps(limit + 1e-6)  # nor faster
    else:
        assert keeps(top)


def test_parameters_are_checked() -> None:
    with pytest.raises(ValueError, match="deceleration and reach above 0"):
        SsmParams(deceleration=0.0)
    with pytest.raises(ValueError, match="finite"):
        SsmParams(margin=math.nan)

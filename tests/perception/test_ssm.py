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
    turn_allowed,
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


def _limit(points: np.ndarray, velocity: np.ndarray | None = None,
           spread: np.ndarray | None = None, margin: float = 0.25, direction: float = 1.0,
           top: float = 1.0, latency: float = 0.3) -> float:
    count = len(points)
    return ssm_speed_limit(points, np.zeros((count, 2)) if velocity is None else velocity,
                           np.zeros(count) if spread is None else spread,
                           np.full(count, margin), LENGTH, WIDTH, direction, top, latency,
                           REACTION, DECELERATION)


def test_a_standing_point_ahead_allows_the_speed_that_stops_at_the_margin() -> None:
    # f = v T_r + v^2 / 2a + C  =>  v = a (-T_r + sqrt(T_r^2 + 2 (f - C) / a))
    free, margin = 0.8, 0.25
    point = np.array([[0.6 + free, 0.0]])
    expected = DECELERATION * (-REACTION + math.sqrt(REACTION**2 + 2 * (free - margin)
                                                     / DECELERATION))
    assert _limit(point, margin=margin) == pytest.approx(expected, abs=1e-5)
    # the same point behind a robot driving forwards does not limit it
    assert _limit(-point, margin=margin) == 1.0


def test_a_person_walking_straight_at_the_robot_needs_the_protective_distance() -> None:
    """Walking at 1.6 m/s straight at the robot's front, the limit is the speed whose S_p of
    ISO/TS 15066 is the distance (the samples add half a step's way: within 1.6 x step / 2)."""
    free = 3.0
    point, velocity = np.array([[0.6 + free, 0.0]]), np.array([[-1.6, 0.0]])
    limit = _limit(point, velocity, margin=0.25, latency=0.3)
    distance = float(protective_distance(limit, 1.6, 0.3, REACTION, DECELERATION, 0.25))
    step = (REACTION + limit / DECELERATION) / 7
    assert free - 0.5 * 1.6 * step - 0.02 <= distance <= free + 1e-6


def test_an_approaching_person_stops_the_robot_and_a_passer_by_does_not() -> None:
    beside = np.array([[0.0, 0.3 + 0.8]])  # 0.8 m beside the robot's side
    # walking at the robot's side at 1.6 m/s: it stops (it cannot be still in time)
    assert _limit(beside, np.array([[0.0, -1.6]]), top=0.5) == 0.0
    # standing there (tracked, no uncertainty), or walking past it along its side: no stop
    assert _limit(beside, top=0.5) == 0.5
    assert _limit(beside, np.array([[1.2, 0.0]]), top=0.5) == 0.5
    # not tracked yet (ISO 13855: it may walk towards the robot at 1.6 m/s): it stops
    assert _limit(beside, spread=np.array([1.6]), top=0.5) == 0.0


@pytest.mark.parametrize("top", [0.0, -1.0, math.nan, math.inf, 1e-300])
def test_hostile_top_speeds_give_a_finite_limit(top: float) -> None:
    limit = _limit(np.array([[3.0, 0.0]]), top=top)
    # no speed, or one that cannot be judged, stands; a tiny one is kept (nothing is near)
    assert limit == (1e-300 if top == 1e-300 else 0.0)


def test_no_points_leave_the_speed_as_it_is() -> None:
    assert _limit(np.zeros((0, 2)), top=0.4) == 0.4


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.floats(-4, 4), st.floats(-4, 4), st.floats(-2, 2),
                          st.floats(-2, 2), st.floats(0, 1.6)), min_size=1, max_size=12),
       st.floats(0.01, 1.5), st.sampled_from([1.0, -1.0]), st.floats(0.0, 0.5))
def test_the_limit_is_the_largest_speed_that_keeps_every_margin(
        rows: list[tuple[float, float, float, float, float]], top: float, direction: float,
        latency: float) -> None:
    points = np.array([r[:2] for r in rows])
    velocity = np.array([r[2:4] for r in rows])
    spread = np.array([r[4] for r in rows])
    margins = np.full(len(rows), 0.25)

    def keeps(speed: float) -> bool:
        reach = speed * REACTION + 0.5 * speed**2 / DECELERATION
        last = latency + REACTION + speed / DECELERATION
        taus = np.linspace(latency, last, 8)
        step = (last - latency) / 7
        for tau in taus:
            where = points + tau * velocity
            need = margins + spread * tau + 0.5 * step * np.hypot(*velocity.T)
            if np.any(swept_gaps(where, LENGTH, WIDTH, reach, direction) < need - 1e-12):
                return False
        return True

    limit = ssm_speed_limit(points, velocity, spread, margins, LENGTH, WIDTH, direction, top,
                            latency, REACTION, DECELERATION)
    assert 0.0 <= limit <= top
    if limit > 0.0:
        assert keeps(limit)  # the robot may drive at the limit
    if 0.0 < limit < top:
        assert not keeps(min(limit + 2.0 * top / 2**20, top))  # nor faster
    if limit == 0.0:
        assert not keeps(0.0) or not keeps(top / 2**20)
    else:
        assert limit < top or keeps(top)


def test_a_standing_robot_turns_only_when_no_one_can_reach_its_sweep() -> None:
    radius = 0.5 * math.hypot(LENGTH, WIDTH)
    point = np.array([[radius + 0.6, 0.0]])
    assert turn_allowed(point, np.zeros((1, 2)), np.zeros(1), np.full(1, 0.25), radius, 0.3,
                        0.6)
    assert not turn_allowed(point, np.array([[-1.0, 0.0]]), np.zeros(1), np.full(1, 0.25),
                            radius, 0.3, 0.6)
    assert turn_allowed(np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0), np.zeros(0), radius,
                        0.3, 0.6)


def test_parameters_are_checked() -> None:
    with pytest.raises(ValueError, match="deceleration and reach above 0"):
        SsmParams(deceleration=0.0)
    with pytest.raises(ValueError, match="finite"):
        SsmParams(margin=math.nan)

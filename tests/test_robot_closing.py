"""The ``closing`` stop rule in the brain (``RobotBrain``, ``perception.closing``): a robot
stands while a person runs at it, long before the fixed 0.55 m, and a cloud it cannot use
(a repeated or not-a-number stamp) does not release it; the NumPy path decides as the
compiled one."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dancebots.perception.cloud import PointCloud
from dancebots.robot import BrainOptions, BrainState, Command, RobotBrain, brain_for
from dancebots.world import DEFAULT_ROBOT_TYPE
from tests_support import plan_of

SHOW = "robots R1\nrow R1 0 0\nmove 6 0\n"
RUNNER_SPEED = 2.0  # m/s, head-on, from 4 m ahead of the robot's centre


def _brain(rule: str = "closing", compiled: bool = True) -> RobotBrain:
    return brain_for(plan_of(SHOW), "R1", DEFAULT_ROBOT_TYPE, BrainOptions(
        follower="path", stop_rule=rule, compiled=compiled))  # type: ignore[arg-type]


def _runner(t: float) -> PointCloud:
    """A person (a 0.3 m wide column of hits) running head-on at the robot standing at the
    origin, seen at show time ``t``; base_link."""
    x = 4.0 - RUNNER_SPEED * (t - 1.0)
    columns = np.array([[x, y, 0.0, 1.5] for y in (-0.15, 0.0, 0.15)])
    return PointCloud(t, columns)


def _drive(brain: RobotBrain, ticks: int) -> list[tuple[float, Command, BrainState]]:
    """``ticks`` ticks of 0.1 s from show time 1.0, the robot at the origin, a cloud each
    tick: (gap of the runner to the footprint's front, command, state)."""
    state = brain.initial_state()
    out = []
    for k in range(ticks):
        t = 1.0 + 0.1 * k
        cloud = _runner(t)
        state, command, _ = brain.step(state, t, (0.0, 0.0, 0.0), cloud, clock=t)
        gap = float(cloud.columns[:, 0].min()) - 0.5 * brain.sensing.length
        out.append((gap, command, state))
    return out


def test_a_robot_stands_for_a_runner_long_before_the_fixed_stop_distance() -> None:
    ticks = _drive(_brain(), 15)
    first = next(i for i, (_, command, state) in enumerate(ticks) if state.held)
    gap, command, state = ticks[first]
    assert command == Command(0.0, 0.0)
    assert state.holds_show
    assert gap > 1.5  # S_p of 2 m/s: about 2 m; the fixed rule waits for 0.55 m
    assert all(state.held for _, _, state in ticks[first:])  # while the runner comes on
    fixed = _drive(_brain("fixed"), 15)
    assert not any(state.held for gap, _, state in fixed if gap > 0.6)


@pytest.mark.parametrize("stamp", [math.nan, "repeated"])
def test_a_cloud_it_cannot_use_does_not_release_a_robot_a_runner_approaches(
        stamp: float | str) -> None:
    brain = _brain()
    ticks = _drive(brain, 12)
    _, _, state = ticks[-1]
    assert state.held
    assert state.closing is not None
    t = 2.2
    bad = PointCloud(state.closing[0] if stamp == "repeated" else float(stamp),
                     _runner(t).columns)
    after, command, _ = brain.step(state, t, (0.0, 0.0, 0.0), bad, clock=t)
    assert after.held
    assert command == Command(0.0, 0.0)
    assert after.strangers_seen is state.strangers_seen
    assert after.closing is state.closing


def test_the_numpy_path_decides_as_the_compiled_one() -> None:
    compiled, reference = _drive(_brain(), 15), _drive(_brain(compiled=False), 15)
    for (_, fast, fast_state), (_, slow, slow_state) in zip(compiled, reference, strict=True):
        assert fast == slow
        assert fast_state.held == slow_state.held
        if fast_state.closing is not None:
            assert slow_state.closing is not None
            np.testing.assert_allclose(fast_state.closing[1], slow_state.closing[1])
            np.testing.assert_allclose(fast_state.closing[2], slow_state.closing[2])

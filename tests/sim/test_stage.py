"""The stage's compiled step free of contacts (sim/stage_jit.py) moves the robots exactly as
its NumPy steps do, and leaves every step with a contact, or near one, to them."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.geometry import Pose
from dancebots.sim.kinematics import IDEAL, Profile
from dancebots.sim.setup import Arena, Placement
from dancebots.sim.stage import Stage
from dancebots.world.model import BUILTIN_ROBOT_TYPES, Obstacle

ROOM = np.array([[-5.0, -5.0], [5.0, -5.0], [5.0, 5.0], [-5.0, 5.0]])
CRATE = Obstacle("crate", np.array([[2.0, 2.0], [3.0, 2.0], [3.0, 3.5], [2.0, 3.0]]), 0.5, 1)
LAGGING = Profile("lagging", lag=0.25, linear_acceleration=1.0, angular_acceleration=4.0,
                  standstill=(0.01, 0.02))


def _stages(starts: np.ndarray, profile: Profile) -> tuple[Stage, Stage]:
    """The same stage twice: the compiled free step on, and off (the NumPy steps only)."""
    kinds = [BUILTIN_ROBOT_TYPES[name] for name in ("SIM", "HUSKY", "TURTLEBOT3")]
    types = tuple(kinds[k % 3] for k in range(len(starts)))
    placement = Placement(tuple(f"R{k}" for k in range(len(starts))), types, starts,
                          Pose(0.0, 0.0, 0.0))
    arena = Arena(ROOM, 1.0, (CRATE,), None)
    fast = Stage(arena, placement, profile, 0.1, None)
    slow = Stage(arena, placement, profile, 0.1, None)
    slow._free_step_data = None
    assert fast._free_step_data is not None
    return fast, slow


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), count=st.integers(1, 6),
       lagging=st.booleans(), spread=st.sampled_from([0.6, 1.5, 4.0]))
def test_the_free_step_moves_the_robots_as_the_numpy_steps(seed: int, count: int,
                                                           lagging: bool,
                                                           spread: float) -> None:
    """Random commands (some stale, some beyond the limits, some zero) drive robots that
    start close (contacts) or spread out, into walls and the crate: poses, corners,
    velocities and every contact the same, bit for bit."""
    rng = np.random.default_rng(seed)
    starts = np.column_stack([rng.uniform(-spread, spread, (count, 2)),
                              rng.uniform(-math.pi, math.pi, count)])
    fast, slow = _stages(starts, LAGGING if lagging else IDEAL)
    issued = np.zeros(count)
    command = np.zeros((count, 2))
    for k in range(80):
        now = 0.1 * k
        if k % 3 == 0:
            command = rng.uniform(-2.0, 2.0, (count, 2)) * rng.integers(0, 2, (count, 1))
            issued = np.where(rng.random(count) < 0.8, now, now - 1.0)
        fast.advance(now, command, issued)
        slow.advance(now, command, issued)
        assert fast.pose.tobytes() == slow.pose.tobytes()
        assert fast.velocity.tobytes() == slow.velocity.tobytes()
        assert fast.corners.tobytes() == slow.corners.tobytes()
    assert fast.collisions == slow.collisions


def test_a_step_with_a_contact_is_left_to_the_numpy_steps() -> None:
    """Two robots driven into each other and one into the wall: the contacts are counted
    (the free step declines those steps) and the robots stop at them."""
    starts = np.array([[0.0, 0.0, 0.0], [1.2, 0.0, math.pi], [4.4, -3.0, 0.0]])
    fast, slow = _stages(starts, IDEAL)
    for k in range(40):
        now = 0.1 * k
        command = np.array([[0.5, 0.0], [0.5, 0.0], [1.0, 0.0]])
        fast.advance(now, command, np.full(3, now))
        slow.advance(now, command, np.full(3, now))
    kinds = {(c.robot, c.kind) for c in fast.collisions}
    assert kinds == {("R0", "robot"), ("R2", "wall")}  # (a pair: one event, its first)
    assert fast.collisions == slow.collisions
    assert fast.pose.tobytes() == slow.pose.tobytes()


def test_numbers_that_are_not_finite_take_the_numpy_steps() -> None:
    """A command that is not a number: the free step declines, the NumPy steps decide."""
    from dancebots.sim.stage_jit import free_step

    fast, _ = _stages(np.array([[0.0, 0.0, 0.0]]), IDEAL)
    assert fast._free_step_data is not None
    for bad in (math.nan, math.inf):
        *_, free = free_step(fast.pose, fast.velocity, np.array([[bad, 0.0]]), np.zeros(1),
                             0.0, 0.1, fast.limits, *fast._free_step_data)
        assert not free
    *_, free = free_step(fast.pose, fast.velocity, np.array([[0.3, 0.1]]), np.zeros(1), 0.0,
                         0.1, fast.limits, *fast._free_step_data)
    assert free


def test_scans_cast_ahead_on_a_second_thread_are_the_same_clouds() -> None:
    """``scan_ahead``: every robot gets the same cloud at the same tick as when the stage
    scans in turn, with a spectator walking by; ``close`` lets the thread go."""
    import threading

    from dancebots.sim.lidar import LidarConfig
    from dancebots.world.model import Spectator

    starts = np.array([[-2.0, -1.0, 0.0], [0.0, 1.0, 1.0], [2.0, -1.5, 2.5]])
    kinds = [BUILTIN_ROBOT_TYPES[name] for name in ("SIM", "HUSKY", "TURTLEBOT3")]
    placement = Placement(("A", "B", "C"), tuple(kinds), starts, Pose(0.0, 0.0, 0.0))
    walker = Spectator("visitor", 0.25, 1.7, 0.8, np.array([[-4.0, 3.0], [4.0, 3.0]]),
                       np.zeros(2), False, 0.0, 1)
    arena = Arena(ROOM, 1.0, (CRATE,), None, (walker,))
    stages = [Stage(arena, placement, IDEAL, 0.1, LidarConfig(), scan_ahead=ahead)
              for ahead in (True, False)]
    for k in range(30):
        now = 0.1 * k
        got = [stage.deliveries(now) for stage in stages]
        for ahead, inturn in zip(*got, strict=True):
            assert (ahead is None) == (inturn is None)
            if ahead is not None and inturn is not None:
                assert ahead.stamp == inturn.stamp
                assert ahead.columns.tobytes() == inturn.columns.tobytes()
        for stage in stages:
            stage.advance(now, np.array([[0.3, 0.2], [0.2, -0.3], [0.1, 0.5]]), np.full(3, now))
    assert any(t.name.startswith("dancebots-lidar") for t in threading.enumerate())
    for stage in stages:
        stage.close()
    assert not any(t.name.startswith("dancebots-lidar") for t in threading.enumerate())

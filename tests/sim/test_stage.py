"""The stage's compiled step free of contacts (sim/stage_jit.py) moves the robots exactly as
its NumPy steps do, and leaves every step with a contact, or near one, to them."""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.geometry import Pose
from dancebots.sim.kinematics import IDEAL, Profile
from dancebots.sim.setup import Arena, Placement
from dancebots.sim.stage import Stage
from dancebots.world.model import BUILTIN_ROBOT_TYPES, Obstacle

ROOM = np.array([[-5.0, -5.0], [5.0, -5.0], [5.0, 5.0], [-5.0, 5.0]])
L_ROOM = np.array([[-5.0, -5.0], [5.0, -5.0], [5.0, 0.0], [0.0, 0.0], [0.0, 5.0],
                   [-5.0, 5.0]])  # not convex
CRATE = Obstacle("crate", np.array([[2.0, 2.0], [3.0, 2.0], [3.0, 3.5], [2.0, 3.0]]), 0.5, 1)
POST = Obstacle("post", np.array([[-3.0, -3.0], [-3.0, -2.5], [-2.5, -2.5], [-2.5, -3.0]]),
                1.0, 2)  # clockwise
LAGGING = Profile("lagging", lag=0.25, linear_acceleration=1.0, angular_acceleration=4.0,
                  standstill=(0.01, 0.02))


def _stages(starts: np.ndarray, profile: Profile, room: np.ndarray = ROOM,
            obstacles: tuple[Obstacle, ...] = (CRATE,)) -> tuple[Stage, Stage]:
    """The same stage twice: the compiled free step on, and off (the NumPy steps only)."""
    kinds = [BUILTIN_ROBOT_TYPES[name] for name in ("SIM", "HUSKY", "TURTLEBOT3")]
    types = tuple(kinds[k % 3] for k in range(len(starts)))
    placement = Placement(tuple(f"R{k}" for k in range(len(starts))), types, starts,
                          Pose(0.0, 0.0, 0.0))
    arena = Arena(room, 1.0, obstacles, None)
    fast = Stage(arena, placement, profile, 0.1, None)
    slow = Stage(arena, placement, profile, 0.1, None)
    slow._free_step_data = None
    assert fast._free_step_data is not None
    return fast, slow


@contextlib.contextmanager
def _free_steps_counted() -> Iterator[list[bool]]:
    """Within: every call of ``stage_jit.free_step`` appends whether it took the step."""
    import dancebots.sim.stage_jit as stage_jit

    taken: list[bool] = []
    original = stage_jit.free_step

    def counted(*args: object) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
        result = original(*args)
        taken.append(result[3])
        return result  # type: ignore[no-any-return]

    stage_jit.free_step = counted  # type: ignore[assignment]
    try:
        yield taken
    finally:
        stage_jit.free_step = original  # type: ignore[assignment]


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), count=st.integers(1, 6),
       lagging=st.booleans(), spread=st.sampled_from([0.6, 1.5, 4.0]),
       l_room=st.booleans())
def test_the_free_step_moves_the_robots_as_the_numpy_steps(seed: int, count: int,
                                                           lagging: bool, spread: float,
                                                           l_room: bool) -> None:
    """Random commands (some stale, some beyond the limits, some zero) drive robots that
    start close (contacts) or spread out, into walls and the crate, in a square room or an
    L-shaped one with a clockwise post: poses, corners, velocities and every contact the
    same, bit for bit."""
    rng = np.random.default_rng(seed)
    starts = np.column_stack([rng.uniform(-spread, spread, (count, 2)),
                              rng.uniform(-math.pi, math.pi, count)])
    if l_room:
        starts[:, :2] = np.minimum(starts[:, :2], -0.5)  # in the L's lower left
    fast, slow = _stages(starts, LAGGING if lagging else IDEAL,
                         *((L_ROOM, (POST,)) if l_room else (ROOM, (CRATE,))))
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


def test_the_free_step_takes_every_step_of_robots_that_keep_apart() -> None:
    """Four robots well apart, driving gently in the middle of the room: every step is the
    free step's (counted: the equality above holds for a free step that takes none too);
    the same poses as the NumPy steps."""
    starts = np.array([[-2.0, -2.0, 0.0], [2.0, -2.0, 1.0], [-2.0, 1.5, 2.0],
                       [1.0, 1.0, -1.0]])
    fast, slow = _stages(starts, IDEAL)
    with _free_steps_counted() as taken:
        for k in range(50):
            command = np.full((4, 2), 0.1) * np.array([[1.0, 0.5]])
            fast.advance(0.1 * k, command, np.full(4, 0.1 * k))
            slow.advance(0.1 * k, command, np.full(4, 0.1 * k))
    assert len(taken) == 50
    assert all(taken)
    assert fast.pose.tobytes() == slow.pose.tobytes()


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


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), count=st.integers(1, 4))
def test_the_free_step_moves_noisy_robots_among_people_as_the_numpy_steps(seed: int,
                                                                          count: int) -> None:
    """The realistic profile (lag, noise) with a scripted visitor walking between the robots
    and a crowd of children around them: robots, people and contacts the same, bit for bit,
    whether the free step takes a step (some it does) or leaves it to the NumPy steps."""
    from dancebots.sim.kinematics import REALISTIC
    from dancebots.world.model import Crowd, Spectator

    rng = np.random.default_rng(seed)
    corners = np.array([[-2.0, -2.0], [2.0, -2.0], [-2.0, 1.5], [1.0, 1.0]])[:count]
    starts = np.column_stack([corners + rng.uniform(-0.3, 0.3, (count, 2)),
                              rng.uniform(-math.pi, math.pi, count)])
    visitor = Spectator("visitor", 0.25, 1.7, 1.0, np.array([[-4.0, 0.2], [4.0, -0.3]]),
                        np.zeros(2), True, 0.0, 1)
    children = Crowd("child", 8, np.array([[-4.5, -4.5], [4.5, -4.5], [4.5, 4.5], [-4.5, 4.5]]),
                     "child", 1.4, 0.3, 0.18, 1.2, seed % 1000, 2)
    kinds = [BUILTIN_ROBOT_TYPES[name] for name in ("SIM", "HUSKY", "TURTLEBOT3")]
    placement = Placement(tuple(f"R{k}" for k in range(count)),
                          tuple(kinds[k % 3] for k in range(count)), starts,
                          Pose(0.0, 0.0, 0.0))
    arena = Arena(ROOM, 1.0, (CRATE,), None, (visitor,), (children,))
    fast = Stage(arena, placement, REALISTIC, 0.1, None, seed=seed % 1000)
    slow = Stage(arena, placement, REALISTIC, 0.1, None, seed=seed % 1000)
    slow._free_step_data = None
    with _free_steps_counted() as taken:
        command = np.zeros((count, 2))
        for k in range(120):
            now = 0.1 * k
            if k % 5 == 0:
                command = rng.uniform(-0.6, 0.6, (count, 2)) * rng.integers(0, 2, (count, 1))
            fast.advance(now, command, np.full(count, now))
            slow.advance(now, command, np.full(count, now))
            assert fast.pose.tobytes() == slow.pose.tobytes()
            assert fast.velocity.tobytes() == slow.velocity.tobytes()
            assert fast.discs.tobytes() == slow.discs.tobytes()
    assert fast.collisions == slow.collisions
    assert fast.corners.tobytes() == slow.corners.tobytes()
    assert fast.crowd is not None
    assert slow.crowd is not None
    assert fast.crowd.position.tobytes() == slow.crowd.position.tobytes()
    assert fast.crowd.velocity.tobytes() == slow.crowd.velocity.tobytes()
    assert any(taken)


def test_a_robot_touching_a_person_is_left_to_the_numpy_steps() -> None:
    """A robot driven into a standing visitor: the free step declines the steps of the
    contact, the NumPy steps record it and stop the robot, as without the free step."""
    from dancebots.world.model import Spectator

    visitor = Spectator("visitor", 0.25, 1.7, 0.0, np.array([[1.2, 0.0]]), np.zeros(1),
                        False, 0.0, 1)
    placement = Placement(("R0",), (BUILTIN_ROBOT_TYPES["SIM"],), np.zeros((1, 3)),
                          Pose(0.0, 0.0, 0.0))
    arena = Arena(ROOM, 1.0, (), None, (visitor,))
    fast = Stage(arena, placement, IDEAL, 0.1, None)
    slow = Stage(arena, placement, IDEAL, 0.1, None)
    slow._free_step_data = None
    with _free_steps_counted() as taken:
        for k in range(40):
            fast.advance(0.1 * k, np.array([[0.5, 0.0]]), np.full(1, 0.1 * k))
            slow.advance(0.1 * k, np.array([[0.5, 0.0]]), np.full(1, 0.1 * k))
    assert [(c.robot, c.kind) for c in fast.collisions] == [("R0", "spectator")]
    assert taken[:3] == [True] * 3  # free until the contact
    assert not all(taken)
    assert fast.collisions == slow.collisions
    assert fast.pose.tobytes() == slow.pose.tobytes()


@pytest.mark.parametrize("speed", [0.0, 1.0, 2.5])
def test_a_contact_says_how_fast_the_person_came_at_the_robot(speed: float) -> None:
    """A robot driving at 0.5 m/s into a visitor walking at it at ``speed`` m/s (or standing
    there): the contact's ``approach`` is the visitor's run-up (their fastest step at the
    robot in the last APPROACH_SPAN s: they stand rather than step into it), and its
    ``closing`` the robot's 0.5 m/s."""
    from dancebots.world.model import Spectator

    far = 1.2 + 4.0 * speed
    visitor = Spectator("visitor", 0.25, 1.7, max(speed, 0.1),
                        np.array([[far, 0.0], [-5.0, 0.0]] if speed else [[far, 0.0]]),
                        np.zeros(2 if speed else 1), False, 0.0, 1)
    placement = Placement(("R0",), (BUILTIN_ROBOT_TYPES["SIM"],), np.zeros((1, 3)),
                          Pose(0.0, 0.0, 0.0))
    stage = Stage(Arena(ROOM, 1.0, (), None, (visitor,)), placement, IDEAL, 0.1, None)
    for k in range(60):
        stage.advance(0.1 * k, np.array([[0.5, 0.0]]), np.full(1, 0.1 * k))
        if stage.collisions:
            break
    (contact,) = stage.collisions
    assert contact.kind == "spectator"
    assert contact.closing == pytest.approx(0.5)
    assert contact.approach == pytest.approx(speed)


def test_numbers_that_are_not_finite_take_the_numpy_steps() -> None:
    """A command that is not a number: the free step declines, the NumPy steps decide."""
    from dancebots.sim.stage_jit import free_step

    fast, _ = _stages(np.array([[0.0, 0.0, 0.0]]), IDEAL)
    assert fast._free_step_data is not None
    for bad in (math.nan, math.inf):
        *_, free = free_step(fast.pose, fast.velocity, np.array([[bad, 0.0]]), np.zeros(1),
                             0.0, 0.1, fast.limits, np.zeros((1, 2)), fast.discs,
                             *fast._free_step_data)
        assert not free
    *_, free = free_step(fast.pose, fast.velocity, np.array([[0.3, 0.1]]), np.zeros(1), 0.0,
                         0.1, fast.limits, np.zeros((1, 2)), fast.discs, *fast._free_step_data)
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
    try:
        _compare_scans(stages)
        assert any(t.name.startswith("dancebots-lidar") for t in threading.enumerate())
    finally:
        for stage in stages:
            stage.close()
    assert not any(t.name.startswith("dancebots-lidar") for t in threading.enumerate())


def _compare_scans(stages: list[Stage]) -> None:
    """Thirty ticks of both stages: the same clouds at the same ticks."""
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


def test_a_scan_that_failed_on_the_thread_is_not_lost(monkeypatch: pytest.MonkeyPatch) -> None:
    """A scan that raises on the second thread raises where its clouds are taken; one never
    taken raises at ``close``, unless the caller is already stopping on another error."""
    import dancebots.sim.stage as stage_module
    from dancebots.sim.lidar import LidarConfig

    def broken(*args: object) -> None:
        raise RuntimeError("caster failed")

    placement = Placement(("A",), (BUILTIN_ROBOT_TYPES["SIM"],), np.zeros((1, 3)),
                          Pose(0.0, 0.0, 0.0))
    arena = Arena(ROOM, 1.0, (), None)
    taken, untaken, stopping = (Stage(arena, placement, IDEAL, 0.1, LidarConfig(),
                                      scan_ahead=True) for _ in range(3))
    monkeypatch.setattr(stage_module, "scan_clouds", broken)  # (after the scans before t = 0)
    try:
        assert taken.deliveries(0.0)[0] is not None  # one scanned before the start: fine
        for k in (1, 2):  # (cast broken; the last scans from before t = 0 arrive)
            assert taken.deliveries(0.1 * k)[0] is not None
        with pytest.raises(RuntimeError, match="caster failed"):
            taken.deliveries(0.3)  # the scan cast at t = 0 arrives
        untaken.deliveries(0.0)  # cast, never taken
        with pytest.raises(RuntimeError, match="caster failed"):
            untaken.close()
        stopping.deliveries(0.0)
        stopping.close(check=False)
    finally:
        for stage in (taken, untaken, stopping):
            stage.close(check=False)


ANGLES = st.sampled_from([0.0, -0.0, math.pi, -math.pi, math.nextafter(math.pi, 0.0),
                          math.nextafter(-math.pi, 0.0), 0.5 * math.pi, 1.0, -2.9, 3.0,
                          6.5, -7.0, 1e-300])


@settings(max_examples=150, deadline=None)
@given(data=st.data(), count=st.integers(1, 5))
def test_the_compiled_own_poses_are_compose_poses(data: st.DataObject, count: int) -> None:
    """``stage_jit.compose_turned`` (the robots' own poses and the places they tell, every
    tick) equals ``geometry.compose_poses`` / ``compose_points`` bit for bit, headings
    wrapped alike at and around +-pi."""
    from dancebots.geometry import compose_points, compose_poses, frame_turns
    from dancebots.sim.stage_jit import compose_turned

    def rows() -> np.ndarray:
        xy = data.draw(st.lists(st.floats(-50.0, 50.0), min_size=2 * count,
                                max_size=2 * count))
        theta = data.draw(st.lists(ANGLES, min_size=count, max_size=count))
        return np.column_stack([np.reshape(xy, (count, 2)), theta])

    frames, poses = rows(), rows()
    turns = frame_turns(frames)
    assert compose_turned(frames, *turns, poses).tobytes() == compose_poses(
        frames, poses).tobytes()
    points = np.ascontiguousarray(poses[:, :2])
    assert compose_turned(frames, *turns, points).tobytes() == compose_points(
        frames, points).tobytes()


@settings(max_examples=100, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), count=st.integers(1, 5))
def test_the_compiled_standing_robots_are_the_numpy_ones(seed: int, count: int) -> None:
    """Which robots stand still among a crowd (``Stage._standing``: speeds and fresh, clipped
    commands within ``MOVING_SPEED``), compiled and with NumPy, on speeds and commands
    around the threshold, stale commands and commands beyond the limits: the same."""
    rng = np.random.default_rng(seed)
    starts = np.column_stack([np.arange(count) * 1.5 - 3.0, np.zeros(count), np.zeros(count)])
    stage, _ = _stages(starts, IDEAL)
    for _ in range(20):
        scale = rng.choice([0.0, 5e-4, 1e-3, 2e-3, 1.0, 3.0], size=(count, 2))
        stage.velocity = rng.uniform(-1.0, 1.0, (count, 2)) * scale
        command = rng.uniform(-1.0, 1.0, (count, 2)) * rng.choice(
            [0.0, 5e-4, 1e-3, 2e-3, 1.0, 10.0], size=(count, 2))
        issued = np.where(rng.random(count) < 0.7, 1.0, 0.8)
        stage._given = (command, issued, 1.0)
        stage.compiled = True
        compiled = stage._standing()
        stage.compiled = False
        assert compiled.tolist() == stage._standing().tolist()

"""The social force crowd (sim/crowd.py): H&M's forces, goals and pauses, walls, robots."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.sim.crowd import (
    CrowdState,
    SocialForceParams,
    crowd_start,
    crowd_step,
    social_acceleration,
    wall_segments,
)
from dancebots.world.model import Crowd, square_room

ROOM = square_room(10.0)
WALLS = wall_segments(ROOM, ())
NO_ROBOTS = np.zeros((0, 3))
NONE = np.zeros(0)


def _crowd(count: int = 5, kind: str = "adult", seed: int = 0) -> Crowd:
    area = np.array([[1.0, 1.0], [9.0, 1.0], [9.0, 9.0], [1.0, 9.0]])
    return Crowd("visitors", count, area, kind, 1.0, 0.2, 0.25, 1.7, seed, 1)  # type: ignore[arg-type]


def _state(positions: list[list[float]], goals: list[list[float]],
           velocities: list[list[float]] | None = None) -> CrowdState:
    start = crowd_start([_crowd(len(positions))], NO_ROBOTS, NONE, None, WALLS,
                        np.random.default_rng(0))
    count = len(positions)
    return dataclasses.replace(
        start, position=np.array(positions, float), goal=np.array(goals, float),
        velocity=np.zeros((count, 2)) if velocities is None else np.array(velocities, float),
        preferred=np.full(count, 1.0), pause=np.zeros(count))


def test_a_lone_pedestrian_accelerates_towards_its_goal_with_the_relaxation_time() -> None:
    state = _state([[5.0, 5.0]], [[8.0, 5.0]])
    accel = social_acceleration(state, np.zeros((0, 2, 2)), NO_ROBOTS, NONE, NONE)
    # H&M eq. 2: (v0 e - v) / tau = (1, 0) / 0.5
    np.testing.assert_allclose(accel, [[2.0, 0.0]], atol=1e-12)


def _potential(params: SocialForceParams, r: np.ndarray, step: np.ndarray) -> float:
    """H&M eq. 4: V0 exp(-b / sigma), 2b = sqrt((|r| + |r - s|)^2 - |s|^2)."""
    n_r, n_next, n_s = (float(np.hypot(*v)) for v in (r, r - step, step))
    b = 0.5 * math.sqrt((n_r + n_next) ** 2 - n_s ** 2)
    return params.pedestrian_strength * math.exp(-b / params.pedestrian_range)


@settings(max_examples=60, deadline=None)
@given(st.floats(-2.0, 2.0), st.floats(-2.0, 2.0), st.floats(-1.2, 1.2), st.floats(-1.2, 1.2))
def test_the_pedestrian_force_is_minus_the_gradient_of_the_ellipse_potential(
        dx: float, dy: float, vx: float, vy: float) -> None:
    """The analytic gradient of eq. 4 against central differences of the potential, with b
    in sight (weight 1) and standing still (no goal force); away from the segment b's step
    spans (the ellipse's focal line, where b has a kink: no gradient there)."""
    params = SocialForceParams()
    r, step = np.array([dx, dy]), params.step_time * np.array([vx, vy])
    along = float(np.clip(r @ step / max(float(step @ step), 1e-12), 0.0, 1.0))
    if math.hypot(dx, dy) < 0.3 or float(np.hypot(*(r - along * step))) < 1e-3:
        return
    state = _state([[5.0, 5.0], [5.0 - dx, 5.0 - dy]], [[5.0, 5.0], [5.0 - dx, 5.0 - dy]],
                   [[0.0, 0.0], [vx, vy]])
    state = dataclasses.replace(state, pause=np.array([1.0, 1.0]))  # standing: no eq. 2 pull
    accel = social_acceleration(state, np.zeros((0, 2, 2)), NO_ROBOTS, NONE, NONE, params)
    h = 1e-6
    gradient = np.array([
        (_potential(params, r + e, step) - _potential(params, r - e, step)) / (2 * h)
        for e in (np.array([h, 0.0]), np.array([0.0, h]))])
    # a standing a has no walking direction (its heading is its zero velocity's), and eq. 5
    # with phi = 100 deg > 90 deg then weighs every force 1
    np.testing.assert_allclose(accel[0], -gradient, atol=1e-5)


def test_a_pedestrian_walks_to_its_goal_and_stands_there_a_while() -> None:
    rng = np.random.default_rng(3)
    state = _state([[2.0, 5.0]], [[6.0, 5.0]])
    reached = None
    for k in range(100):
        state = crowd_step(state, 0.1, [ROOM], WALLS, NO_ROBOTS, NONE, NONE, rng)
        if state.pause[0] > 0.0:
            reached = k * 0.1
            break
    assert reached is not None
    assert 3.0 < reached < 6.0
    where = state.position.copy()
    assert np.hypot(*(where[0] - [6.0, 5.0])) < 0.5
    for _ in range(10):  # it stands (the shortest adult pause is 3 s)
        state = crowd_step(state, 0.1, [ROOM], WALLS, NO_ROBOTS, NONE, NONE, rng)
    assert float(np.hypot(*state.velocity[0])) < 0.2


def test_two_pedestrians_walking_at_each_other_pass_without_touching() -> None:
    rng = np.random.default_rng(0)
    state = _state([[2.0, 5.0], [8.0, 5.02]], [[9.0, 5.0], [1.0, 5.0]])
    closest = math.inf
    for _ in range(80):
        state = crowd_step(state, 0.1, [ROOM], WALLS, NO_ROBOTS, NONE, NONE, rng)
        closest = min(closest, float(np.hypot(*(state.position[0] - state.position[1]))))
    assert closest > 2 * 0.25  # their discs never overlap
    assert state.position[0, 0] > 6.0
    assert state.position[1, 0] < 4.0


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_a_crowd_stays_in_the_room(seed: int) -> None:
    rng = np.random.default_rng(seed)
    crowd = dataclasses.replace(_crowd(12, "child"), area=ROOM.copy())
    state = crowd_start([crowd], NO_ROBOTS, NONE, None, WALLS, rng)
    for _ in range(150):
        state = crowd_step(state, 0.1, [ROOM], WALLS, NO_ROBOTS, NONE, NONE, rng)
        inside = (state.position >= state.radius[:, None] - 1e-9) & (
            state.position <= 10.0 - state.radius[:, None] + 1e-9)
        assert inside.all()


def test_a_standing_pedestrian_steps_aside_from_a_robot_that_comes_close() -> None:
    rng = np.random.default_rng(0)
    state = _state([[5.0, 5.0]], [[5.0, 5.0]])
    state = dataclasses.replace(state, pause=np.array([100.0]))
    robot = np.array([[4.1, 5.1, 0.0]])  # its front 0.3 m from the person's centre
    size = np.array([1.2]), np.array([0.6])
    for _ in range(20):
        state = crowd_step(state, 0.1, [ROOM], WALLS, robot, *size, rng)
    assert state.position[0, 0] > 5.15  # moved away from the robot's front


def test_the_same_seed_gives_the_same_crowd_and_another_seed_another() -> None:
    def run(seed: int) -> np.ndarray:
        rng = np.random.default_rng(seed)
        robots = np.array([[5.0, 5.0, 0.3]])
        size = np.array([1.2]), np.array([0.6])
        state = crowd_start([_crowd(8)], robots, np.array([0.7]), None, WALLS, rng)
        for _ in range(50):
            state = crowd_step(state, 0.1, [_crowd().area], WALLS, robots, *size, rng)
        return state.position

    np.testing.assert_array_equal(run(4), run(4))
    assert not np.allclose(run(4), run(5))


def test_crowd_start_keeps_clear_of_robots_and_each_other() -> None:
    robots = np.array([[5.0, 5.0, 0.0], [3.0, 3.0, 1.0]])
    reach = np.array([0.7, 0.7])
    state = crowd_start([_crowd(30)], robots, reach, None, WALLS, np.random.default_rng(1))
    gaps = np.hypot(*(state.position[:, None] - robots[None, :, :2]).transpose(2, 0, 1))
    assert (gaps > reach + 0.25).all()
    apart = np.hypot(*(state.position[:, None] - state.position[None]).transpose(2, 0, 1))
    assert (apart[~np.eye(30, dtype=bool)] > 0.5).all()
    assert state.names[0] == "visitors 1"
    assert len(set(state.names)) == 30


def test_a_crowd_that_cannot_fit_is_a_clear_error() -> None:
    tiny = dataclasses.replace(_crowd(50), area=np.array([[1.0, 1.0], [2.0, 1.0], [2.0, 2.0]]))
    with pytest.raises(ValueError, match="crowd 'visitors' does not fit in its area"):
        crowd_start([tiny], NO_ROBOTS, NONE, None, WALLS, np.random.default_rng(0))


def test_what_is_behind_a_walking_pedestrian_weighs_half(  # H&M eq. 5, c = 0.5
        ) -> None:
    params = SocialForceParams()
    behind = _state([[5.0, 5.0], [4.0, 5.0]], [[9.0, 5.0], [4.0, 5.0]])
    behind = dataclasses.replace(behind, pause=np.array([0.0, 1.0]))  # a walks, b stands
    ahead = dataclasses.replace(behind, goal=np.array([[1.0, 5.0], [4.0, 5.0]]))
    none = np.zeros((0, 2, 2))
    # the same push from b on a either way; a walking away from b sees it behind (weight c)
    push_behind = social_acceleration(behind, none, NO_ROBOTS, NONE, NONE, params)[0] - (
        np.array([1.0, 0.0]) / params.relaxation)
    push_ahead = social_acceleration(ahead, none, NO_ROBOTS, NONE, NONE, params)[0] - (
        np.array([-1.0, 0.0]) / params.relaxation)
    assert push_ahead[0] > 0.0  # away from b
    np.testing.assert_allclose(push_behind, params.out_of_sight * push_ahead, atol=1e-12)


def test_a_corner_of_a_border_pushes_once() -> None:
    """H&M eq. 6 sums over borders: a pedestrian off a room's corner, nearer to it than to
    any other point of the room, is pushed by the corner once, not once per edge."""
    from dancebots.sim.crowd import wall_rings

    rings = wall_rings(ROOM, ())
    params = SocialForceParams()
    corner = _state([[0.3, 0.3]], [[0.3, 0.3]])
    corner = dataclasses.replace(corner, pause=np.array([1.0]))
    accel = social_acceleration(corner, WALLS, NO_ROBOTS, NONE, NONE, params, rings)[0]
    # the nearest point of the room's border is one of the two edges' common corner region:
    # one push along the nearest edge's normal, of U0/R exp(-d/R) with d = 0.3
    expected = params.border_strength / params.border_range * math.exp(
        -0.3 / params.border_range)
    assert abs(float(np.hypot(*accel)) - expected) < 1e-9
    doubled = social_acceleration(corner, WALLS, NO_ROBOTS, NONE, NONE, params)[0]
    assert float(np.hypot(*doubled)) > 1.4 * expected  # every edge a border: pushed twice


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), count=st.integers(1, 25), robots=st.integers(0, 4),
       obstacle=st.booleans(), per_segment=st.booleans())
def test_the_compiled_social_forces_are_the_numpy_ones(seed: int, count: int, robots: int,
                                                        obstacle: bool,
                                                        per_segment: bool) -> None:
    """``sim.crowd_jit``'s loops give the forces of ``social_acceleration`` and the wall
    distances of ``_wall_distance`` to 1e-9 for random crowds (walking and pausing, some
    inside a robot's footprint or on top of each other), robots, a room with an obstacle's
    ring or every segment a border."""
    from dancebots.sim.crowd import _wall_distance, wall_rings
    from dancebots.sim.crowd_jit import social_acceleration_loops, wall_distances
    from dancebots.world.model import Obstacle

    rng = np.random.default_rng(seed)
    obstacles = (Obstacle("box", np.array([[4.0, 4.0], [5.0, 4.0], [5.0, 5.0], [4.0, 5.0]]),
                          1.0, 1),) if obstacle else ()
    walls = wall_segments(ROOM, obstacles)
    rings = np.arange(len(walls)) if per_segment else wall_rings(ROOM, obstacles)
    state = _state(rng.uniform(0.2, 9.8, (count, 2)).tolist(),
                   rng.uniform(0.5, 9.5, (count, 2)).tolist(),
                   rng.uniform(-1.5, 1.5, (count, 2)).tolist())
    state = dataclasses.replace(state, pause=np.where(rng.random(count) < 0.3, 1.0, 0.0),
                                preferred=rng.uniform(0.5, 2.0, count))
    if count > 1 and seed % 4 == 0:
        state.position[1] = state.position[0]  # two on one spot
    poses = np.column_stack([rng.uniform(1.0, 9.0, (robots, 2)),
                             rng.uniform(-math.pi, math.pi, robots)])
    lengths, widths = rng.uniform(0.5, 1.2, robots), rng.uniform(0.4, 0.8, robots)
    if robots:
        state.position[0] = poses[0, :2]  # one inside a footprint
    if seed % 3:  # some keep a share of their range from some robots (walking out)
        state = dataclasses.replace(state, robot_share=rng.uniform(0.3, 1.0, (count, robots)))
    params = SocialForceParams()
    expected = social_acceleration(state, walls, poses, lengths, widths, params,
                                   None if per_segment else rings)
    got = social_acceleration_loops(
        state.position, state.velocity, state.goal, state.pause <= 0.0, state.preferred,
        *state.robot_push(robots), walls, rings, poses, lengths, widths, params.relaxation,
        params.pedestrian_strength, params.pedestrian_range, params.border_strength,
        params.border_range, params.step_time, math.cos(params.sight), params.out_of_sight)
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(wall_distances(state.position, walls),
                               _wall_distance(state.position, walls), rtol=1e-12, atol=0)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), people=st.integers(0, 30), robots=st.integers(0, 5))
def test_the_compiled_steps_into_robots_are_the_numpy_ones(seed: int, people: int,
                                                           robots: int) -> None:
    """``crowd_jit.steps_into_robots`` picks the people of ``Stage._steps_into_robots``'s
    NumPy rule (a step that reaches into a footprint from outside) for random people
    stepping about random robots, one starting inside a footprint."""
    from dancebots.sim.crowd_jit import steps_into_robots
    from dancebots.sim.stage import _footprint_gaps

    rng = np.random.default_rng(seed)
    poses = np.column_stack([rng.uniform(1.0, 4.0, (robots, 2)),
                             rng.uniform(-math.pi, math.pi, robots)])
    lengths, widths = rng.uniform(0.5, 1.2, robots), rng.uniform(0.4, 0.8, robots)
    before = rng.uniform(0.0, 5.0, (people, 2))
    if robots and people:
        before[0] = poses[0, :2]  # inside a footprint
    after = before + rng.normal(0.0, 0.3, (people, 2))
    radii = rng.uniform(0.1, 0.3, people)
    expected = ((_footprint_gaps(poses, lengths, widths, after) < radii)
                & (_footprint_gaps(poses, lengths, widths, before) >= radii))
    got = steps_into_robots(before, after, radii, poses, lengths, widths)
    assert got.tolist() == expected.tolist()


def test_the_pauses_are_drawn_as_generator_uniform_draws_them() -> None:
    """``crowd_step`` draws pauses as ``low + (high - low) * rng.random(n)`` (without
    ``Generator.uniform``'s broadcasting, 4 times slower here): the same numbers, bit for bit,
    and the generator left in the same state, so runs stay as they were."""
    low = np.array([3.0, 0.5, 3.0, 0.5])  # the kinds' pause_min and pause_max
    high = np.array([12.0, 5.0, 12.0, 5.0])
    ours, numpy_s = np.random.default_rng(11), np.random.default_rng(11)
    for _ in range(200):
        assert (low + (high - low) * ours.random(len(low))).tobytes() == (
            numpy_s.uniform(low, high).tobytes())
    assert ours.random() == numpy_s.random()


def test_a_compiled_crowd_walks_as_the_numpy_one() -> None:
    """Ten seconds of a crowd of children stepped with the compiled forces and with NumPy's
    from the same start and seed: the same people within a millimetre."""
    crowd = dataclasses.replace(_crowd(12, "child"), area=ROOM.copy())
    states = []
    for compiled in (False, True):
        rng = np.random.default_rng(7)
        state = crowd_start([crowd], NO_ROBOTS, NONE, None, WALLS, rng)
        for _ in range(100):
            state = crowd_step(state, 0.1, [ROOM], WALLS, NO_ROBOTS, NONE, NONE, rng,
                               compiled=compiled)
        states.append(state.position)
    np.testing.assert_allclose(states[1], states[0], atol=1e-3)


def test_a_compiled_crowd_walks_out_of_a_formation_as_the_numpy_one() -> None:
    """Ten seconds of children among four robots in a square that speak (ask for room), two
    standing still and two told to move, stepped with the compiled forces and with NumPy's:
    the same people within a millimetre, the same ones leaving the formation, the same
    shares of their range from each robot; some walked out (the shares are used)."""
    crowd = dataclasses.replace(_crowd(12, "child"), area=ROOM.copy())
    half = 0.85
    robots = np.array([[5 - half, 5 - half, 0.8], [5 + half, 5 - half, 2.3],
                       [5 + half, 5 + half, -2.3], [5 - half, 5 + half, -0.8]])
    lengths, widths = np.full(4, 0.99), np.full(4, 0.67)
    standing = np.array([True, True, False, False])
    results = []
    for compiled in (False, True):
        rng = np.random.default_rng(3)
        state = crowd_start([crowd], robots, 0.5 * np.hypot(lengths, widths), None, WALLS,
                            rng)
        state = dataclasses.replace(state, position=state.position.copy())
        state.position[:3] = [[5.0, 5.0], [4.6, 5.3], [5.3, 4.7]]  # inside the formation
        shared = 0
        for _ in range(100):
            state = crowd_step(state, 0.1, [ROOM], WALLS, robots, lengths, widths, rng,
                               speaking=np.ones(4, dtype=bool), compiled=compiled,
                               robot_standing=standing)
            shared += int(state.robot_share is not None and (state.robot_share < 0.99).any())
        results.append((state, shared))
    (numpy_state, numpy_shared), (compiled_state, compiled_shared) = results
    assert numpy_shared > 10  # people walked out keeping a share of their range
    assert compiled_shared == numpy_shared
    np.testing.assert_allclose(compiled_state.position, numpy_state.position, atol=1e-3)
    assert compiled_state.leaving is not None
    assert numpy_state.leaving is not None
    assert compiled_state.leaving.tolist() == numpy_state.leaving.tolist()
    if numpy_state.robot_share is None:
        assert compiled_state.robot_share is None
    else:
        assert compiled_state.robot_share is not None
        np.testing.assert_allclose(compiled_state.robot_share, numpy_state.robot_share,
                                   atol=1e-9)
        assert (numpy_state.robot_share[:, 2:] == 1.0).all()  # never from robots that move


def test_a_person_asked_for_room_leaves_a_formation_between_two_robots() -> None:
    """A child in the middle of a square of four robots, asked for room by the one behind
    it: walking straight away from the speaker would take it into the robot opposite; the
    way out passes between two robots (the widest gap, on the left); a person beside a lone
    robot walks straight away from it, and past a robot as far on as it walks."""
    from dancebots.sim.crowd import _way_out

    robots = np.array([[10.73, 13.58], [9.34, 13.65], [10.82, 15.17], [9.26, 15.61]])
    reach = np.array([0.6, 0.6, 0.47, 0.47])  # HUSKY, HUSKY, TRADR, TRADR half diagonals
    child = np.array([9.72, 14.68])
    way = _way_out(child, child - robots[3], robots, reach, 0.18)
    passes = child[None, :] + np.linspace(0.3, 2.0, 40)[:, None] * way[None, :]
    gaps = np.hypot(passes[:, None, 0] - robots[None, :, 0],
                    passes[:, None, 1] - robots[None, :, 1]) - reach[None, :]
    assert gaps.min() > 0.18  # clear of every robot's disc by the child's radius
    straight = (child - robots[3]) / np.hypot(*(child - robots[3]))
    straight_passes = child[None, :] + np.linspace(0.3, 2.0, 40)[:, None] * straight[None, :]
    assert (np.hypot(straight_passes[:, None, 0] - robots[None, :, 0],
                     straight_passes[:, None, 1] - robots[None, :, 1])
            - reach[None, :]).min() < 0.0  # straight away runs into R1 or R2
    eighth = math.radians(22.5)  # the 16 ways are 22.5 deg apart
    assert way.tolist() == pytest.approx([-math.cos(eighth), -math.sin(eighth)])
    alone = _way_out(np.array([1.0, 0.0]), np.array([1.0, 0.0]), np.zeros((1, 2)),
                     np.array([0.6]), 0.2)
    assert alone.tolist() == pytest.approx([1.0, 0.0])
    # a robot 2.8 m further on, as far as the person walks: the way bends 22.5 deg past it
    # (nearest to straight away among those clear of it), not into it
    beyond = _way_out(np.array([1.0, 0.0]), np.array([1.0, 0.0]),
                      np.array([[0.0, 0.0], [3.8, 0.0]]), np.array([0.6, 0.6]), 0.2)
    assert beyond.tolist() == pytest.approx([math.cos(eighth), -math.sin(eighth)])
    # a robot whose pose is not known is left out
    unknown = _way_out(np.array([1.0, 0.0]), np.array([1.0, 0.0]),
                       np.array([[0.0, 0.0], [math.nan, 0.0]]), np.array([0.6, 0.6]), 0.2)
    assert unknown.tolist() == pytest.approx([1.0, 0.0])


@pytest.mark.parametrize("compiled", [False, True])
def test_a_child_asked_for_room_squeezes_out_between_standing_robots_only(
        compiled: bool) -> None:
    """A child stands in the middle of four robots whose corners point at it (centres 1.7 m
    apart), and they ask for room. Where the robots stand still it walks out between two of
    them, keeping LEAVING_RANGE of its robot range from them (it is marked leaving); robots
    that move keep the whole range, and their pushes hold it in the middle (the trap that
    kept a standing formation waiting until the run's end)."""
    half = 0.85
    corners = (math.pi / 4, 3 * math.pi / 4, -3 * math.pi / 4, -math.pi / 4)
    robots = np.array([[5 - half, 5 - half, corners[0]], [5 + half, 5 - half, corners[1]],
                       [5 + half, 5 + half, corners[2]], [5 - half, 5 + half, corners[3]]])
    lengths, widths = np.full(4, 0.99), np.full(4, 0.67)
    area = np.array([[1.0, 1.0], [9.0, 1.0], [9.0, 9.0], [1.0, 9.0]])

    def walked(standing: bool) -> tuple[float, bool]:
        child = Crowd("kids", 1, area, "child", 1.0, 0.0, 0.18, 1.2, 3, 1)  # type: ignore[arg-type]
        rng = np.random.default_rng(1)
        state = crowd_start([child], robots, 0.5 * np.hypot(lengths, widths), None, WALLS,
                            rng)
        state = dataclasses.replace(state, position=np.array([[5.0, 5.0]]),
                                    goal=np.array([[5.0, 5.0]]), velocity=np.zeros((1, 2)),
                                    pause=np.array([100.0]))
        was_leaving = False
        for _ in range(300):
            state = crowd_step(state, 0.1, [area], WALLS, robots, lengths, widths, rng,
                               speaking=np.ones(4, dtype=bool), compiled=compiled,
                               robot_standing=np.full(4, standing))
            was_leaving |= bool(state.leaving is not None and state.leaving[0])
        return float(np.hypot(*(state.position[0] - 5.0))), was_leaving

    out, leaving = walked(standing=True)
    assert leaving
    assert out > 2.0  # beyond the robots' far corners
    trapped, leaving = walked(standing=False)
    assert leaving
    assert trapped < 0.3


def test_a_person_walking_out_keeps_a_share_of_its_range_from_standing_robots() -> None:
    """``_robot_share`` follows LEAVING_RANGE for a leaving person and a standing robot, 1
    otherwise, with the time constant SHARE_TIME (None while everyone keeps the whole
    range); ``robot_push`` keeps the push at the border (strength over range) and weakens it
    everywhere else; ``_inside_formation`` is the convex hull of the known robot centres
    (no inside for fewer than three or robots in a line)."""
    from dancebots.sim.crowd import LEAVING_RANGE, SHARE_TIME, _inside_formation, _robot_share

    leaving, standing = np.array([True, False]), np.array([True, False, True])
    assert _robot_share(None, None, standing, 2, 3, 0.1) is None
    assert _robot_share(None, leaving, np.zeros(3, dtype=bool), 2, 3, 0.1) is None
    share = _robot_share(None, leaving, standing, 2, 3, 0.1)
    assert share is not None
    step = math.exp(-0.1 / SHARE_TIME)
    low = LEAVING_RANGE + (1.0 - LEAVING_RANGE) * step
    np.testing.assert_allclose(share, [[low, 1.0, low], [1.0, 1.0, 1.0]])
    for _ in range(100):
        share = _robot_share(share, leaving, standing, 2, 3, 0.1)
    assert share is not None
    np.testing.assert_allclose(share, [[LEAVING_RANGE, 1, LEAVING_RANGE], [1, 1, 1]],
                               atol=1e-6)
    back = _robot_share(share, np.zeros(2, dtype=bool), standing, 2, 3, 0.1)
    assert back is not None  # the way back to the whole range takes its time too
    assert back[0, 0] == pytest.approx(1.0 + (LEAVING_RANGE - 1.0) * step)
    for _ in range(100):
        back = _robot_share(back, np.zeros(2, dtype=bool), standing, 2, 3, 0.1)
    assert back is None

    state = dataclasses.replace(_state([[0.0, 0.0], [1.0, 1.0]], [[0.0, 0.0], [1.0, 1.0]]),
                                robot_share=share)
    strength, reach = state.robot_push(3)
    kind = state.column("robot_range")
    np.testing.assert_allclose(reach, share * kind[:, None])
    np.testing.assert_allclose(strength / reach, 1.0 / kind[:, None] * np.ones((2, 3)))
    whole = dataclasses.replace(state, robot_share=None).robot_push(3)
    np.testing.assert_allclose(whole[0], 1.0)
    np.testing.assert_allclose(whole[1], np.repeat(kind[:, None], 3, axis=1))
    from dancebots.sim.crowd import _border_force

    gaps = np.linspace(1e-6, 1.0, 11)
    vectors = np.stack([gaps, np.zeros_like(gaps)], axis=1)[:, None, :]  # (11, 1, 2)
    weaker = _border_force(vectors, 10.0 * strength[0, 0], reach[0, 0])[:, 0]
    full = _border_force(vectors, 10.0, kind[0])[:, 0]
    assert np.all(weaker[1:] < full[1:])
    assert weaker[0] == pytest.approx(full[0], rel=1e-4)  # the same push at the border

    square = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])
    points = np.array([[1.0, 1.0], [3.0, 1.0], [1.0, -0.5]])
    assert _inside_formation(square, points).tolist() == [True, False, False]
    assert _inside_formation(square[:2], points).tolist() == [False] * 3
    line = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    assert _inside_formation(line, points).tolist() == [False] * 3
    unknown = np.array([[0.0, 0.0], [2.0, 0.0], [math.nan, 2.0]])
    assert _inside_formation(unknown, points).tolist() == [False] * 3


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), steps=st.integers(1, 40), kind=st.sampled_from(
    ["adult", "child"]))
def test_the_compiled_pauses_and_goals_are_the_numpy_ones(seed: int, steps: int,
                                                          kind: str) -> None:
    """``crowd_step``'s pauses and goals in one compiled call (``crowd_jit.pauses``, the wall
    distances of new goals) take the same draws and give the same pauses and goals as its
    NumPy branch, bit for bit, step after step (each step from the same state: the walk's
    forces agree to 1e-9, not bit for bit); robots near, some of them speaking."""
    crowd = dataclasses.replace(_crowd(10, kind, seed % 7), area=ROOM.copy())
    robots = np.array([[4.0, 4.0, 0.3], [6.0, 5.0, -1.2]])
    lengths, widths = np.full(2, 0.99), np.full(2, 0.67)
    state = crowd_start([crowd], robots, 0.5 * np.hypot(lengths, widths), None, WALLS,
                        np.random.default_rng(seed))
    for step in range(steps):
        speaking = np.array([step % 3 == 0, False])
        results = []
        for compiled in (False, True):
            rng = np.random.default_rng([seed, step])
            results.append(crowd_step(state, 0.1, [ROOM], WALLS, robots, lengths, widths,
                                      rng, speaking=speaking, compiled=compiled))
        numpy_state, compiled_state = results
        assert compiled_state.pause.tobytes() == numpy_state.pause.tobytes()
        assert compiled_state.goal.tobytes() == numpy_state.goal.tobytes()
        assert (None if compiled_state.leaving is None else compiled_state.leaving.tolist()) == (
            None if numpy_state.leaving is None else numpy_state.leaving.tolist())
        state = numpy_state


def test_the_compiled_pauses_compile_once_for_crowds_of_any_size() -> None:
    """``crowd_jit.pauses`` takes the behaviour matrix, not its column views (which NumPy
    marks contiguous for a crowd of one: another type for numba, compiled silently again)."""
    from dancebots.sim import crowd_jit

    for count in (1, 2, 7):
        rng = np.random.default_rng(count)
        state = crowd_start([_crowd(count)], NO_ROBOTS, NONE, None, WALLS, rng)
        crowd_step(state, 0.1, [ROOM], WALLS, NO_ROBOTS, NONE, NONE, rng, compiled=True)
    assert len(crowd_jit.pauses.signatures) == 1

"""Obstacle detection (thesis 5.2): crop, height filter, stop zones, lag compensation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from dancebots.perception.cloud import PointCloud
from dancebots.perception.obstacles import (
    DetectorParams,
    clear_distances,
    compensate_motion,
    footprint_clearance,
    near_any,
    obstacle_points,
    obstacle_points_from_columns,
    predicted_stop_flags,
    stop_flags,
    turn_fraction,
    turn_reach,
    turn_samples,
)

LENGTH, WIDTH = 1.2, 0.6


def test_crop_and_height_filter() -> None:
    points = np.array([
        [1.0, 0.0, 0.5],    # kept
        [2.5, 0.0, 0.5],    # outside the 4 x 4 m square
        [1.0, -1.9, 1.4],   # kept
        [1.0, 0.0, 0.1],    # the floor band: z must be above 0.10
        [1.0, 0.0, 1.5],    # z must be below 1.5
        [1.0, 0.0, 0.9],    # same x, y as the first: flattened into one point
    ])
    assert obstacle_points(points).tolist() == [[1.0, -1.9], [1.0, 0.0]]


@given(st.floats(0.6, 1.149), st.floats(-0.4, 0.4), st.floats(0.11, 1.49))
def test_any_point_in_the_front_zone_stops_forward(x: float, y: float, z: float) -> None:
    flat = obstacle_points(np.array([[x, y, z]]))
    flags = stop_flags(flat, LENGTH, WIDTH)
    assert flags.front
    assert not flags.rear


@given(st.floats(-1.149, -0.6), st.floats(-0.4, 0.4), st.floats(0.11, 1.49))
def test_any_point_in_the_rear_zone_stops_backward(x: float, y: float, z: float) -> None:
    flags = stop_flags(obstacle_points(np.array([[x, y, z]])), LENGTH, WIDTH)
    assert flags.rear
    assert not flags.front


@given(st.floats(-2, 2), st.floats(-2, 2),
       st.one_of(st.floats(1.5, 10), st.floats(-1, 0.1)))
def test_points_too_high_or_too_low_never_stop(x: float, y: float, z: float) -> None:
    flags = stop_flags(obstacle_points(np.array([[x, y, z]])), LENGTH, WIDTH)
    assert not flags.front
    assert not flags.rear


@given(st.floats(-0.55, 0.55), st.sampled_from([-1, 1]), st.floats(0.45, 2.0))
def test_neighbours_beside_the_robot_do_not_stop_it(x: float, side: int, gap: float) -> None:
    flags = stop_flags(np.array([[x, side * gap]]), LENGTH, WIDTH)
    assert not flags.front
    assert not flags.rear


columns = arrays(np.float64, st.tuples(st.integers(0, 30), st.just(4)),
                 elements=st.floats(-3, 3, allow_nan=False))


@given(columns)
@example(np.array([[1.263004e-13, 1.263004e-13, 2.526008e-13, 1.25e-01]]))  # a level 1.3e-13
# m above z_min, which the rounding allowance of the lowest level once skipped
def test_columns_give_the_same_points_as_the_expanded_cloud(data: np.ndarray) -> None:
    data = data.copy()
    data[:, 2] = np.abs(data[:, 2]) * 0.5  # z_low >= 0
    data[:, 3] = data[:, 2] + np.abs(data[:, 3])  # z_high >= z_low
    cloud = PointCloud(0.0, data, 0.1)
    from_points = obstacle_points(cloud.points())
    from_columns = obstacle_points_from_columns(data, 0.1)

    def covered(a: np.ndarray, b: np.ndarray) -> bool:  # every point of a is in b
        return all(len(b) and np.hypot(*(b - p).T).min() < 1e-8 for p in a)

    assert covered(from_points, from_columns)
    assert covered(from_columns, from_points)


knife_edge_columns = st.tuples(
    st.integers(0, 1), st.integers(0, 25), st.sampled_from([-1e-9, -1e-12, 0.0, 1e-12, 1e-9]),
    st.sampled_from([-1e-9, -1e-12, 0.0, 1e-12, 1e-9, 0.05]), st.floats(-2.5, 2.5))


@settings(max_examples=300, deadline=None)
@given(st.lists(knife_edge_columns, min_size=1, max_size=20),
       st.sampled_from([0.1, 0.07, 0.25]))
@example([(1, 1, 1e-12, 0.0, 0.5)], 0.1)  # the level just above z_min is the column's top
@example([(0, 2, 0.0, -1e-12, 0.5)], 0.07)  # the top just under a level
def test_the_compiled_column_filter_is_the_numpy_one_on_knife_edges(
        rows: list[tuple[int, int, float, float, float]], step: float) -> None:
    """Columns whose foot or top lies within 1e-9 m of a level (z_min - k step, low +
    levels step): ``perception.fast.kept_columns`` keeps exactly the columns that
    ``obstacle_points_from_columns`` does, and both the points of the expanded cloud."""
    from dancebots.perception.fast import kept_columns

    params = DetectorParams()
    low = np.maximum([params.z_min - k * step + low_edge for k, _, low_edge, _, _ in rows], 0.0)
    high = np.maximum([foot + levels * step + top_edge
                       for foot, (_, levels, _, top_edge, _) in zip(low, rows, strict=True)],
                      low)
    data = np.column_stack([[x for *_, x in rows], np.full(len(rows), 0.5), low, high])
    expected = obstacle_points_from_columns(data, step, params)
    kept = kept_columns(data, step, params.crop_half, params.z_min, params.z_max)
    np.testing.assert_array_equal(data[kept, :2], expected)
    from_points = obstacle_points(PointCloud(0.0, data, step).points(), params)
    assert {tuple(p) for p in np.round(expected, 9)} == {tuple(p) for p in from_points}


@settings(max_examples=200, deadline=None)
@given(arrays(np.float64, st.tuples(st.integers(1, 20), st.just(2)),
              elements=st.floats(-1e12, 1e12, allow_nan=False)),
       st.sampled_from([1e-3, 0.1, 1e4, 1e7]))
@example(np.array([[0.200002, 0.2]]), 1e4)  # steps or heights where rounding reaches 1e-6 m
@example(np.array([[-6.6e10, -6.6e10 + 3.0]]), 0.25)
def test_the_compiled_column_filter_is_the_numpy_one_for_any_heights(
        heights: np.ndarray, step: float) -> None:
    """Whatever the heights (to 1e12 m, a foot above its top too) and the step: the compiled
    filter keeps the columns the NumPy one keeps (its shortcut applies only where rounding
    cannot matter)."""
    from dancebots.perception.fast import kept_columns

    params = DetectorParams()
    low, high = heights[:, 0], heights[:, 1]  # (a foot above the top too: no point)
    data = np.column_stack([np.full(len(low), 0.5), np.full(len(low), 0.5), low, high])
    with np.errstate(all="ignore"):
        expected = obstacle_points_from_columns(data, step, params)
    kept = kept_columns(data, step, params.crop_half, params.z_min, params.z_max)
    np.testing.assert_array_equal(data[kept, :2], expected)


def test_compensation_moves_points_by_own_motion() -> None:
    # an obstacle 2 m ahead seen at the stamp; the robot has since driven 0.3 m forward
    seen = np.array([[2.0, 0.0]])
    now = compensate_motion(seen, (0.0, 0.0, 0.0), (0.3, 0.0, 0.0))
    np.testing.assert_allclose(now, [[1.7, 0.0]])
    # ... and turned 90 degrees left on the spot: the obstacle is now on its right
    now = compensate_motion(seen, (0.0, 0.0, 0.0), (0.0, 0.0, math.pi / 2))
    np.testing.assert_allclose(now, [[0.0, -2.0]], atol=1e-12)


def test_parameters_move_the_zones() -> None:
    point = np.array([[1.0, 0.0]])  # 0.4 m ahead of the front edge
    assert stop_flags(point, LENGTH, WIDTH).front
    assert not stop_flags(point, LENGTH, WIDTH, DetectorParams(stop_distance=0.3)).front


def test_clear_distances_in_the_corridor() -> None:
    points = np.array([[1.5, 0.1], [-2.0, -0.2], [0.9, 1.5], [-0.7, 0.35]])
    front, rear = clear_distances(points, LENGTH, WIDTH)
    assert front == pytest.approx(0.9)  # 1.5 - 0.6; the point at y = 1.5 is beside
    assert rear == pytest.approx(0.1)  # -0.7 is 0.1 behind the rear edge, y 0.35 < 0.4
    assert clear_distances(np.zeros((0, 2)), LENGTH, WIDTH) == (math.inf, math.inf)


@settings(deadline=None)  # the first call compiles the numba function
@given(arrays(np.float64, st.tuples(st.integers(1, 40), st.just(2)),
              elements=st.floats(-2, 2, allow_nan=False)),
       st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-3, 3)),
       st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-3, 3)))
def test_compiled_perception_agrees_with_the_reference(
        points: np.ndarray, seen_from: tuple[float, float, float],
        pose: tuple[float, float, float]) -> None:
    from dancebots.perception.fast import perceive_moved
    from dancebots.perception.obstacles import perceive

    params = DetectorParams()
    reference = perceive(compensate_motion(points, seen_from, pose), LENGTH, WIDTH, params,
                         1.0, 0.02)
    front, rear, nearest, fx, fy = perceive_moved(
        points, np.array(seen_from), np.array(pose), LENGTH, WIDTH, params.stop_distance,
        params.corridor_margin, 1.0, 0.02)
    assert front == pytest.approx(reference.front_free, abs=1e-9)
    assert rear == pytest.approx(reference.rear_free, abs=1e-9)
    assert (fx, fy) == pytest.approx(reference.force, abs=1e-9)
    assert nearest == pytest.approx(reference.nearest, abs=1e-9)


@settings(deadline=None)
@given(columns, st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-3, 3)))
def test_compiled_column_filter_agrees_with_the_reference(
        data: np.ndarray, pose: tuple[float, float, float]) -> None:
    from dancebots.perception.fast import perceive_columns, perceive_moved

    data = data.copy()
    data[:, 2] = np.abs(data[:, 2]) * 0.5
    data[:, 3] = data[:, 2] + np.abs(data[:, 3])
    params = DetectorParams()
    where = np.array([0.0, 0.0, 0.0])
    rest = (np.array(pose), LENGTH, WIDTH, params.stop_distance, params.corridor_margin,
            1.0, 0.02)
    assert perceive_columns(data, 0.1, params.crop_half, params.z_min, params.z_max, where,
                            *rest) == perceive_moved(
        obstacle_points_from_columns(data, 0.1), where, *rest)


def _side(y: float, x_from: float = -0.6, x_to: float = 0.6) -> np.ndarray:
    """A neighbour's side seen as points (M, 2) along y = ``y`` m, every 2 cm."""
    xs = np.arange(x_from, x_to + 1e-9, 0.02)
    return np.column_stack([xs, np.full(len(xs), y)])


def test_the_reach_of_a_turn_covers_what_the_turn_can_meet() -> None:
    """A 1.2 x 0.6 m robot turning on the spot swings its corners 0.37 m beyond its sides
    (half diagonal 0.67 m): a point 0.35 m beside its middle is out of the old 0.3 m guard's
    reach but is met; turn_reach covers it, and the guard cuts the spin."""
    beside = np.array([[0.0, 0.3 + 0.35]])
    assert footprint_clearance(beside, LENGTH, WIDTH) == pytest.approx(0.35)
    assert _nearest_on_arc(beside, 0.0, 2.0, 1.0) < 0.01  # a corner comes round onto it
    assert turn_reach(LENGTH, WIDTH, 0.0) > 0.35
    assert turn_fraction(beside, LENGTH, WIDTH, 0.0, 2.0) < 1.0
    assert footprint_clearance(np.empty((0, 2)), LENGTH, WIDTH) == math.inf


def _nearest_on_arc(points: np.ndarray, linear: float, angular: float,
                    seconds: float) -> float:
    """The nearest any point comes to the footprint of a robot driving (v, w) for
    ``seconds``, sampled every 5 ms (the reference for turn_fraction's 0.1 s samples)."""
    from dancebots.geometry import points_to_local

    best = math.inf
    for t in np.arange(0.0, seconds + 1e-9, 0.005):
        if abs(angular) < 1e-12:
            pose = (linear * t, 0.0, 0.0)
        else:
            pose = (linear * math.sin(angular * t) / angular,
                    linear * (1 - math.cos(angular * t)) / angular, angular * t)
        local = points_to_local(points, pose)
        outside = np.maximum(np.abs(local) - [LENGTH / 2, WIDTH / 2], 0.0)
        best = min(best, float(np.hypot(outside[:, 0], outside[:, 1]).min()))
    return best


def test_a_tight_turn_is_cut_where_the_tail_would_swing_into_a_neighbour() -> None:
    """A 1.2 m robot 0.3 m beside a neighbour turning right on a 0.25 m radius swings its
    tail 0.26 m out: the guard cuts the turn to a fraction that keeps the turn margin
    (10 cm; checked on a 5 ms grid); a gentle turn is left alone. 0.2 m beside it (listing
    7.4's split) no fraction keeps 10 cm."""
    params = DetectorParams()
    neighbour = _side(0.6)
    assert _nearest_on_arc(neighbour, 0.35, -1.4, 1.0) < 0.05  # the full turn comes close
    fraction = turn_fraction(neighbour, LENGTH, WIDTH, 0.35, -1.4, params)
    assert 0.0 < fraction < 1.0
    assert _nearest_on_arc(neighbour, 0.35, -1.4 * fraction, 1.0) > 0.5 * params.turn_margin
    assert turn_fraction(neighbour, LENGTH, WIDTH, 0.35, -0.1, params) == 1.0
    assert turn_fraction(_side(0.5), LENGTH, WIDTH, 0.35, -1.4, params) == 0.0
    assert turn_fraction(np.empty((0, 2)), LENGTH, WIDTH, 0.35, -1.4, params) == 1.0


HUSKY = (0.99, 0.67)  # m, the open-day show's front robots


def _outline(pose: tuple[float, float, float], frame: tuple[float, float, float]
             ) -> np.ndarray:
    """The outline of a HUSKY's footprint at ``pose`` as points (M, 2) every 2 cm, in
    ``base_link`` of a robot at ``frame`` (what its LIDAR sees of a mate)."""
    from dancebots.geometry import points_to_local, points_to_world

    half_l, half_w = 0.5 * HUSKY[0], 0.5 * HUSKY[1]
    xs = np.arange(-half_l, half_l + 1e-9, 0.02)
    ys = np.arange(-half_w, half_w + 1e-9, 0.02)
    edge = np.concatenate([np.column_stack([xs, np.full(len(xs), y)]) for y in (-half_w, half_w)]
                          + [np.column_stack([np.full(len(ys), x), ys]) for x in (-half_l, half_l)])
    return points_to_local(points_to_world(edge, pose), frame)


def _smallest_gap_both_turning(first: tuple[float, float, float], first_rate: float,
                               second: tuple[float, float, float], second_rate: float) -> float:
    """The smallest distance (m) between two HUSKY footprints turning on the spot at their
    rates (rad/s) for 1 s, sampled every 5 ms (shapely)."""
    import shapely
    from shapely import affinity

    def footprint(pose: tuple[float, float, float], turned: float) -> shapely.Polygon:
        box = shapely.box(-HUSKY[0] / 2, -HUSKY[1] / 2, HUSKY[0] / 2, HUSKY[1] / 2)
        return affinity.translate(affinity.rotate(box, pose[2] + turned, origin=(0, 0),
                                                  use_radians=True), pose[0], pose[1])

    return min(footprint(first, first_rate * t).distance(footprint(second, second_rate * t))
               for t in np.arange(0.0, 1.0 + 1e-9, 0.005))


@pytest.mark.parametrize("rates", [(2.04, -1.78), (1.0, -1.0), (0.5, -0.5)])
def test_two_mates_turning_on_the_spot_side_by_side_leave_each_other_room(
        rates: tuple[float, float]) -> None:
    """Open-day crowd seed 293 (t = 106.3 s): two HUSKYs side by side, their rears 0.25 m
    apart, both turned on the spot when the show resumed, swinging their rears towards each
    other (their poses and commands). Each guard, taking the other for standing, let its
    corners come within the 10 cm margin of it; together they touched. Taking the other's
    points as a mate's that may turn too (turn_share 0.5), each closes at most half the gap
    beyond the margin: together they keep the margin (to the 0.1 s sampling's half margin);
    a fast turn waits (the robot makes room), a gentle one goes on at a quarter."""
    params = DetectorParams()
    first, second = (0.0, 0.0, -1.40), (-1.12, 0.08, -1.85)
    first_sees = _outline(second, first)
    second_sees = _outline(first, second)
    assert footprint_clearance(first_sees, *HUSKY) == pytest.approx(0.25, abs=0.01)

    def fractions(moving: bool) -> tuple[float, float]:
        return (turn_fraction(first_sees, *HUSKY, 0.0, rates[0], params,
                              np.full(len(first_sees), moving)),
                turn_fraction(second_sees, *HUSKY, 0.0, rates[1], params,
                              np.full(len(second_sees), moving)))

    standing = fractions(False)
    assert standing == (1.0, 1.0)  # alone, each turn would keep the margin
    assert _smallest_gap_both_turning(first, rates[0], second, rates[1]) < (
        0.5 * params.turn_margin)
    shared = fractions(True)
    assert min(shared) > 0.0 or abs(rates[0]) > 0.5  # a gentle turn goes on, slower
    assert _smallest_gap_both_turning(first, shared[0] * rates[0], second,
                                      shared[1] * rates[1]) > 0.5 * params.turn_margin


def test_a_turn_on_the_spot_beside_a_wall_is_refused() -> None:
    """Turning on the spot sweeps the corners out to the half diagonal (0.67 m): with a wall
    0.1 m beside the robot no fraction of the turn keeps its distance."""
    wall = _side(0.4, -2.0, 2.0)
    assert turn_fraction(wall, LENGTH, WIDTH, 0.0, 1.0) == 0.0
    assert turn_fraction(wall, LENGTH, WIDTH, 0.0, -1.0) == 0.0


@settings(deadline=None, max_examples=300)  # the first call compiles the numba function
@given(columns, st.tuples(st.floats(-0.3, 0.3), st.floats(-0.3, 0.3), st.floats(-3, 3)),
       st.floats(-0.5, 0.5), st.floats(-3.2, 3.2), st.booleans(),
       st.sampled_from([0.5, 1.0, 0.3]),
       arrays(np.float64, st.tuples(st.integers(0, 3), st.just(2)),
              elements=st.floats(-3, 3, allow_nan=False)),
       st.sampled_from([0.0, 0.5, 0.9, 5.0]))
def test_the_compiled_turn_guard_agrees_with_the_reference(
        data: np.ndarray, pose: tuple[float, float, float], linear: float, angular: float,
        leading: bool, share: float, mates: np.ndarray, radius: float) -> None:
    """turn_fraction_columns (compiled, on the cloud's columns seen at another pose, the
    points near ``mates`` taken as moving) gives turn_fraction's answer on the same points
    moved to the pose (the tested reference)."""
    from dancebots.perception.fast import turn_fraction_columns

    data = data.copy()
    data[:, 2] = np.abs(data[:, 2]) * 0.5
    data[:, 3] = data[:, 2] + np.abs(data[:, 3])
    params = DetectorParams(turn_share=share)
    seen_from = (0.0, 0.0, 0.0)
    seen = obstacle_points_from_columns(data, 0.1)
    moving = near_any(seen, mates, radius)
    points = compensate_motion(seen, seen_from, pose)
    if leading:
        ahead = points[:, 0] * (1.0 if linear >= 0.0 else -1.0) > 0.0
        points, moving = points[ahead], moving[ahead]
    expected = turn_fraction(points, LENGTH, WIDTH, linear, angular, params, moving)
    compiled = turn_fraction_columns(data, 0.1, params.crop_half, params.z_min, params.z_max,
                                     np.array(seen_from), np.array(pose), LENGTH, WIDTH,
                                     linear, angular, params.turn_margin, params.turn_horizon,
                                     share, mates, radius, leading)
    assert compiled == expected


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), points=st.integers(0, 30), centres=st.integers(0, 4),
       radius=st.sampled_from([0.0, 1e-300, 0.3, 0.9, 5.0]))
def test_the_compiled_turn_shares_are_near_any(seed: int, points: int, centres: int,
                                               radius: float) -> None:
    """turn_shares gives the share to exactly the points near_any finds near a centre (a
    centre that is not a number is near every point)."""
    from dancebots.perception.fast import turn_shares

    rng = np.random.default_rng(seed)
    cloud = rng.uniform(-3.0, 3.0, (points, 2))
    mates = rng.uniform(-3.0, 3.0, (centres, 2))
    if centres and seed % 3 == 0:
        mates[0, seed % 2] = np.nan
    expected = np.where(near_any(cloud, mates, radius), 0.5, 1.0)
    assert turn_shares(cloud, mates, radius, 0.5).tolist() == expected.tolist()


def test_a_point_that_may_move_never_loosens_the_guard() -> None:
    """Points that may move (a mate's) only make the guard stricter, and the compiled guard
    answers as the reference, over 3,000 seeded random scenes (1-5 points, half of them a
    mate's, on the spot and driving). The standing points are checked at the same instants
    or more: with a mate's point farther out, the instants were once a grid of their own,
    and a standing point's near pass fell between them (review of c5e765f: this scene gave
    0.0 standing and 1.0 with the far point a mate's)."""
    from dancebots.perception.fast import turn_fraction_local

    params = DetectorParams()
    scene = np.array([[0.6327471533870139, 0.28070527589472216],
                      [-0.8290307017090957, -0.9104542235135349]])
    assert turn_fraction(scene, LENGTH, WIDTH, 0.01, -0.5, params) == 0.0
    assert turn_fraction(scene, LENGTH, WIDTH, 0.01, -0.5, params,
                         np.array([False, True])) == 0.0
    rng = np.random.default_rng(7)
    for _ in range(3000):
        count = int(rng.integers(1, 6))
        points = rng.uniform(-1.6, 1.6, (count, 2))
        moving = rng.random(count) < 0.5
        linear = 0.0 if rng.random() < 0.5 else float(rng.uniform(-0.5, 0.5))
        angular = float(rng.uniform(-3.0, 3.0))
        shared = turn_fraction(points, LENGTH, WIDTH, linear, angular, params, moving)
        assert shared <= turn_fraction(points, LENGTH, WIDTH, linear, angular, params)
        assert shared == turn_fraction_local(
            points, LENGTH, WIDTH, linear, angular, params.turn_margin, params.turn_horizon,
            np.where(moving, params.turn_share, 1.0), False)


def test_a_turn_that_cannot_be_predicted_is_refused() -> None:
    """Speeds that are not finite (a corrupt command) or too fast to sample give no turn."""
    neighbour = _side(0.5)
    for linear, angular in ((0.3, math.inf), (math.nan, 1.0), (0.3, math.nan)):
        assert turn_fraction(neighbour, LENGTH, WIDTH, linear, angular) == 0.0
    assert turn_samples(LENGTH, WIDTH, 1e308, 1e-300) == 0  # too fast to sample
    assert turn_fraction(neighbour, LENGTH, WIDTH, 1e308, 1e-300) == 0.0


@settings(max_examples=80, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), points=st.integers(0, 40), centres=st.integers(0, 6),
       radius=st.sampled_from([0.0, 1e-300, 0.3, 0.85, 5.0]))
def test_far_from_all_is_the_numpy_mask(seed: int, points: int, centres: int,
                                        radius: float) -> None:
    """The compiled mate mask keeps exactly the points that NumPy's (K, M) distances say are
    more than ``radius`` from every centre (all of them for no centre)."""
    from dancebots.perception.fast import far_from_all

    rng = np.random.default_rng(seed)
    columns = rng.uniform(-4.0, 4.0, (points, 4))
    mates = rng.uniform(-4.0, 4.0, (centres, 2))
    if centres and seed % 3 == 0:
        mates[0, seed % 2] = np.nan  # a place that is not a number keeps no point out
    gaps = np.hypot(columns[:, None, 0] - mates[None, :, 0],
                    columns[:, None, 1] - mates[None, :, 1])
    expected = (gaps > radius).all(axis=1)
    assert far_from_all(columns, mates, radius).tolist() == expected.tolist()


@settings(max_examples=80, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), points=st.integers(0, 60), centres=st.integers(0, 6),
       radius=st.sampled_from([0.0, 1e-300, 0.3, 0.85, 5.0]))
def test_the_split_perception_is_perceive_columns_with_and_without_the_mates(
        seed: int, points: int, centres: int, radius: float) -> None:
    """The fused kernel gives exactly what perceiving every column and then the columns
    ``far_from_all`` keeps (mates moved into ``base_link`` by ``points_to_local``) gives,
    and says whether any column was left out (columns inside and outside the crop, high and
    low)."""
    from dancebots.geometry import points_to_local
    from dancebots.perception.fast import far_from_all, perceive_columns, perceive_columns_split

    rng = np.random.default_rng(seed)
    columns = np.column_stack([rng.uniform(-3.0, 3.0, (points, 2)),
                               rng.uniform(-0.2, 0.4, points), rng.uniform(0.0, 2.0, points)])
    # some mates beyond the crop and the radius (the kernel leaves them out for the columns
    # in the crop)
    mates = rng.uniform(-3.0, 3.0, (centres, 2)) * rng.choice([1.0, 2.5], (centres, 1))
    if centres and seed % 5 == 0:
        mates[0, seed % 2] = np.nan  # a place that is not a number leaves every column out
    seen_from = rng.uniform(-1.0, 1.0, 3)
    pose = seen_from + rng.uniform(-0.05, 0.05, 3)
    common = (0.1, 2.0, 0.05, 1.0, seen_from, pose, LENGTH, WIDTH, 0.55, 0.1, 1.0, 0.02)
    everything, strangers, left_out = perceive_columns_split(columns, *common, mates, radius)
    keep = far_from_all(columns, points_to_local(mates, tuple(seen_from)), radius)
    assert everything == perceive_columns(columns, *common)
    assert left_out == (not keep.all())
    assert strangers == perceive_columns(columns[keep], *common)


def test_a_person_walking_into_the_corridor_stops_the_robot_before_the_cloud_shows_it() -> None:
    """The ``predicted`` stop rule: a SIM robot (1.2 x 0.6 m) sees a person 0.4 m ahead of its
    front and 0.8 m to its right, outside the corridor (0.4 m half width), walking left at
    1.5 m/s; the cloud is 0.4 s old, so the person is 0.2 m right by now: inside, a stop.
    Fresh data (age 0), a standing point, or the person walking away stop nothing; with the
    robot facing +y the map's -x velocity is its left."""
    person = np.array([[1.0, -0.8]])
    left = np.array([[0.0, 1.5]])
    moving = np.array([True])
    assert stop_flags(person, 1.2, 0.6) == stop_flags(np.zeros((0, 2)), 1.2, 0.6)
    assert predicted_stop_flags(person, left, moving, 0.0, 0.4, 1.2, 0.6).front
    assert not predicted_stop_flags(person, left, moving, 0.0, 0.4, 1.2, 0.6).rear
    assert not predicted_stop_flags(person, left, moving, 0.0, 0.0, 1.2, 0.6).front
    assert not predicted_stop_flags(person, left, ~moving, 0.0, 0.4, 1.2, 0.6).front
    assert not predicted_stop_flags(person, -left, moving, 0.0, 0.4, 1.2, 0.6).front
    facing_up = predicted_stop_flags(person, np.array([[-1.5, 0.0]]), moving, math.pi / 2,
                                     0.4, 1.2, 0.6)
    assert facing_up.front

"""Obstacles tracked over scans (perception/tracks.py): clusters, their velocities, walls that
stand, and how fast each point approaches the robot."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.perception.tracks import (
    NEW,
    STANDING,
    TRACKED,
    ObstacleTracks,
    TrackParams,
    cluster_points,
    point_motion,
    track_step,
)

WALL = np.column_stack([np.full(17, 5.0), np.linspace(-2.0, 2.0, 17)])  # 4 m, 0.25 m apart


def _person(centre: np.ndarray) -> np.ndarray:
    """The points a LIDAR sees of a person (a 0.25 m disc) from the origin's side."""
    angles = np.linspace(2.4, 3.9, 7)
    return centre + 0.25 * np.column_stack([np.cos(angles), np.sin(angles)])


def test_clusters_join_points_nearer_than_the_gap() -> None:
    points = np.array([[0.0, 0.0], [0.2, 0.0], [0.4, 0.0], [2.0, 0.0], [2.1, 0.1]])
    labels, count = cluster_points(points, 0.3)
    assert count == 2
    assert len(set(labels[:3].tolist())) == 1
    assert labels[3] == labels[4] != labels[0]
    assert cluster_points(np.zeros((0, 2)), 0.3)[1] == 0


def test_a_walking_person_gets_their_velocity_and_a_wall_stands() -> None:
    params, tracks = TrackParams(), ObstacleTracks()
    velocity = np.array([-1.2, 0.4])  # m/s, towards the robot at the origin
    kinds = []
    for k in range(12):
        person = _person(np.array([3.0, -1.0]) + velocity * 0.1 * k)
        points = np.concatenate([person, WALL])
        tracks, point_velocity, kind = track_step(params, tracks, points, 0.1 * k)
        kinds.append(int(kind[0]))
    assert kinds[:params.min_hits - 1] == [NEW] * (params.min_hits - 1)
    assert set(kinds[params.min_hits - 1:]) == {TRACKED}
    np.testing.assert_allclose(point_velocity[:7], np.tile(velocity, (7, 1)), atol=0.05)
    assert np.all(kind[7:] == STANDING)
    assert np.all(point_velocity[7:] == 0.0)


def test_a_track_unseen_for_long_is_dropped() -> None:
    params, tracks = TrackParams(), ObstacleTracks()
    tracks, _, _ = track_step(params, tracks, _person(np.array([1.0, 1.0])), 0.0)
    assert len(tracks.states) == 1
    for k in range(1, params.max_misses + 2):
        tracks, _, _ = track_step(params, tracks, np.zeros((0, 2)), 0.1 * k)
    assert len(tracks.states) == 0


def test_what_ssm_assumes_of_each_kind() -> None:
    velocity = np.array([[-1.0, 0.5], [0.3, 0.0], [0.2, 0.2]])
    kind = np.array([TRACKED, NEW, STANDING], dtype=np.int8)
    moving, spread = point_motion(velocity, kind, 1.6, 0.3)
    # a tracked object moves as tracked (uncertain by 0.3 m/s), a new one may walk anywhere
    # at 1.6 m/s, a wall stands
    np.testing.assert_allclose(moving, [[-1.0, 0.5], [0.0, 0.0], [0.0, 0.0]])
    np.testing.assert_allclose(spread, [0.3, 1.6, 0.0])


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(st.floats(-3, 3), st.floats(-3, 3)), min_size=0, max_size=40),
       st.integers(1, 5))
def test_any_points_give_one_velocity_and_kind_each(rows: list[tuple[float, float]],
                                                    scans: int) -> None:
    params, tracks = TrackParams(), ObstacleTracks()
    points = np.array(rows, dtype=float).reshape(-1, 2)
    for k in range(scans):
        tracks, velocity, kind = track_step(params, tracks, points, 0.1 * k)
        assert velocity.shape == (len(points), 2)
        assert kind.shape == (len(points),)
        assert np.all(np.isfinite(velocity))
        assert np.all(np.isin(kind, (STANDING, TRACKED, NEW)))
        # what stands still is seen to stand still
        assert np.all(np.abs(velocity) <= 1e-9) or scans == 1


@pytest.mark.parametrize("stamp", [0.0, 1e-300, 1e9])
def test_a_repeated_stamp_predicts_nothing(stamp: float) -> None:
    params = TrackParams()
    tracks, _, _ = track_step(params, ObstacleTracks(), _person(np.array([1.0, 0.0])), stamp)
    tracks, velocity, _ = track_step(params, tracks, _person(np.array([1.0, 0.0])), stamp)
    assert np.all(np.isfinite(velocity))
    assert np.all(velocity == 0.0)


@settings(max_examples=200, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), count=st.integers(0, 250),
       scale=st.sampled_from([1e-300, 0.05, 0.3, 1.0, 4.0]))
def test_the_clusters_are_scipys(seed: int, count: int, scale: float) -> None:
    """The NumPy reference and the kernel (``tracks_jit.cluster_labels``) give the labels of
    SciPy's k-d tree and connected components (numbered by first point), points spread thin
    or piled up, repeated points among them."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    from dancebots.perception.tracks_jit import cluster_labels

    rng = np.random.default_rng(seed)
    points = rng.uniform(-4.0, 4.0, (count, 2)) * scale
    if count > 2:
        points[rng.integers(0, count, count // 3)] = points[0]
    pairs = cKDTree(points).query_pairs(0.3, output_type="ndarray").reshape(-1, 2)
    clusters, scipy_labels = connected_components(coo_matrix(
        (np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(count, count)),
        directed=False)
    labels, reference_clusters = cluster_points(points, 0.3)
    compiled, compiled_clusters = cluster_labels(points, 0.3)
    assert reference_clusters == compiled_clusters == (clusters if count else 0)
    assert labels.tolist() == compiled.tolist() == scipy_labels.tolist()


def test_a_chain_of_points_is_one_cluster_and_far_or_no_number_points_are_alone() -> None:
    """Label propagation crosses a long chain (each point joins only its neighbours);
    points that are not numbers join nothing, as in the kernel."""
    chain = np.column_stack([np.linspace(0.0, 60.0, 301)[::-1], np.zeros(301)])
    labels, count = cluster_points(chain, 0.3)
    assert count == 1
    assert not labels.any()
    odd = np.array([[0.0, 0.0], [np.nan, 0.0], [0.1, 0.0], [np.inf, 0.0], [np.inf, 0.0],
                    [5.0, np.nan]])
    labels, count = cluster_points(odd, 0.3)
    assert labels.tolist() == [0, 1, 0, 2, 3, 4]
    assert count == 5


@settings(max_examples=200, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(0, 12), cols=st.integers(0, 12),
       whole=st.booleans())
def test_the_compiled_assignment_is_scipys(seed: int, rows: int, cols: int,
                                           whole: bool) -> None:
    """``assignment.least_cost_assignment`` (the NumPy reference's) and ``tracks_jit.assign``
    (the same function compiled): SciPy's ``linear_sum_assignment``, wide and tall, with ties
    (whole-number costs) resolved the same way."""
    from scipy.optimize import linear_sum_assignment

    from dancebots.perception.assignment import least_cost_assignment
    from dancebots.perception.tracks_jit import assign

    rng = np.random.default_rng(seed)
    cost = rng.integers(0, 4, (rows, cols)).astype(float) if whole else rng.random((rows, cols))
    expected_rows, expected_cols = linear_sum_assignment(cost)
    for solve in (assign, least_cost_assignment):
        got_rows, got_cols = solve(cost)
        assert got_rows.tolist() == expected_rows.tolist()
        assert got_cols.tolist() == expected_cols.tolist()


@pytest.mark.parametrize(("cost", "expected"), [
    (np.full((2, 2), np.nan), []), (np.array([[np.inf, np.inf], [1.0, np.inf]]), []),
    (np.array([[0.5, np.nan, 0.2]]), [(0, 2)]), (np.array([[np.nan], [0.3]]), [(1, 0)])])
def test_costs_that_are_no_number_are_no_way(cost: np.ndarray,
                                             expected: list[tuple[int, int]]) -> None:
    """Where SciPy raises on NaN or on infinities that leave no finite assignment, both take
    a NaN for no way and give the least-cost assignment of the rest, or none (the compiled
    search looped for ever on NaN)."""
    from dancebots.perception.assignment import least_cost_assignment
    from dancebots.perception.tracks_jit import assign

    for solve in (assign, least_cost_assignment):
        rows, cols = solve(cost)
        assert list(zip(rows.tolist(), cols.tolist(), strict=True)) == expected


def test_both_trackers_pick_the_same_tracks_where_costs_tie() -> None:
    """Two tracks and two people placed symmetrically (every pairing costs the same): the
    compiled tracker and the NumPy reference keep the same tracks (an earlier reference
    assigned by another SciPy routine that breaks ties the other way)."""
    params = TrackParams(min_hits=1)
    people = [np.array([[-5.0, 0.2]]), np.array([[-5.0, -0.2]])]
    later = [np.array([[-5.2, 0.0]]), np.array([[-4.8, 0.0]])]
    first = np.concatenate(people)
    second = np.concatenate(later)
    results = []
    for compiled in (False, True):
        tracks, _, _ = track_step(params, ObstacleTracks(), first, 0.0, compiled)
        tracks, _, _ = track_step(params, tracks, second, 0.1, compiled)
        results.append(tracks.states)
    np.testing.assert_allclose(results[0], results[1], rtol=0.0, atol=1e-12)


@pytest.mark.parametrize("compiled", [False, True])
def test_a_stamp_that_is_not_a_number_predicts_nothing(compiled: bool) -> None:
    params = TrackParams()
    tracks, _, _ = track_step(params, ObstacleTracks(), _person(np.array([1.0, 0.0])), 0.0,
                              compiled)
    tracks, velocity, _ = track_step(params, tracks, _person(np.array([1.1, 0.0])), np.nan,
                                     compiled)
    assert np.all(np.isfinite(tracks.states))
    assert np.all(np.isfinite(velocity))


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), people=st.integers(0, 6), scans=st.integers(1, 12))
def test_the_compiled_tracker_follows_the_same_tracks(seed: int, people: int,
                                                      scans: int) -> None:
    """``track_step(compiled=True)`` (``tracks_jit.track_cloud``): the same tracks, kinds and
    hits as the NumPy and SciPy reference for people walking, meeting and leaving past a
    wall, with the filter's figures to rounding."""
    rng = np.random.default_rng(seed)
    start = rng.uniform(-3.0, 3.0, (people, 2))
    velocity = rng.uniform(-1.5, 1.5, (people, 2))
    params = TrackParams()
    reference, compiled = ObstacleTracks(), ObstacleTracks()
    for k in range(scans):
        seen = [p for p in range(people) if rng.random() > 0.15]  # some missed at times
        points = np.concatenate([WALL, *(_person(start[p] + velocity[p] * 0.1 * k)
                                         for p in seen)])
        reference, ref_velocity, ref_kind = track_step(params, reference, points, 0.1 * k)
        compiled, velocity_now, kind = track_step(params, compiled, points, 0.1 * k,
                                                  compiled=True)
        assert kind.tolist() == ref_kind.tolist()
        np.testing.assert_allclose(velocity_now, ref_velocity, rtol=1e-9, atol=1e-9)
        assert compiled.hits.tolist() == reference.hits.tolist()
        assert compiled.misses.tolist() == reference.misses.tolist()
        np.testing.assert_allclose(compiled.states, reference.states, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(compiled.covariances, reference.covariances, rtol=1e-9,
                                   atol=1e-9)


def test_the_compiled_kinds_are_the_references() -> None:
    from dancebots.perception import tracks_jit

    assert (tracks_jit.STANDING, tracks_jit.TRACKED, tracks_jit.NEW) == (
        STANDING, TRACKED, NEW)


@pytest.mark.parametrize("compiled", [False, True])
def test_ignored_points_are_not_tracked_and_stand(compiled: bool) -> None:
    """``ignore`` (the ``predicted`` rule's formation mates): those points stand with no
    velocity and make no track; the others are tracked as without them."""
    params = TrackParams()
    tracks, alone = ObstacleTracks(), ObstacleTracks()
    mate = np.array([0.0, -2.0])
    velocity = np.array([1.0, 0.0])
    for k in range(6):
        person = _person(np.array([-2.0, 1.0]) + velocity * 0.1 * k)
        mate_points = _person(mate + velocity * 0.1 * k)
        points = np.concatenate([mate_points, person])
        ignore = np.arange(len(points)) < len(mate_points)
        tracks, point_velocity, kind = track_step(params, tracks, points, 0.1 * k, compiled,
                                                  ignore)
        alone, alone_velocity, alone_kind = track_step(params, alone, person, 0.1 * k,
                                                       compiled)
        assert np.all(kind[ignore] == STANDING)
        assert np.all(point_velocity[ignore] == 0.0)
        assert kind[~ignore].tolist() == alone_kind.tolist()
        np.testing.assert_array_equal(point_velocity[~ignore], alone_velocity)
        assert len(tracks.states) == len(alone.states) == 1
    assert np.all(kind[~ignore] == TRACKED)


def test_the_pairs_are_tested_in_blocks_with_the_same_labels(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """Blocks of a few candidate pairs (a wall along y puts every point in every x-window:
    the blocks bound the memory) give the kernel's labels; a 3,000-point wall is one
    cluster."""
    import dancebots.perception.tracks as tracks
    from dancebots.perception.tracks_jit import cluster_labels

    monkeypatch.setattr(tracks, "PAIR_BLOCK", 7)
    rng = np.random.default_rng(1)
    for _ in range(100):
        points = rng.uniform(-2.0, 2.0, (int(rng.integers(0, 60)), 2))
        if len(points) > 3:
            points[: len(points) // 3, 0] = points[0, 0]  # a wall along y
        labels, count = cluster_points(points, 0.3)
        expected, expected_count = cluster_labels(points, 0.3)
        assert count == expected_count
        assert labels.tolist() == expected.tolist()
    wall = np.column_stack([np.zeros(3000), np.linspace(0.0, 300.0, 3000)])
    assert cluster_points(wall, 0.3)[1] == 1

"""The simulated LIDAR: ray casting kernels and the thesis's height columns."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.geometry import footprint_corners
from dancebots.sim.lidar import LidarConfig, LidarScene, scan_clouds
from dancebots.sim.raycast import (
    ray_directions,
    rays_to_discs,
    rays_to_segments,
    rays_to_segments_culled,
)

ROOM = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]])


def test_ray_hits_segment_and_disc_at_known_distances() -> None:
    origins = np.array([[0.0, 0.0]])
    directions = ray_directions(np.zeros(1), np.array([0.0, np.pi / 2, np.pi]))
    segment = np.array([[[2.0, -1.0], [2.0, 1.0]]])
    distance, which = rays_to_segments(origins, directions, segment)
    assert distance[0, 0] == 2.0
    assert np.isinf(distance[0, 1:]).all()
    assert which.tolist() == [[0, -1, -1]]
    disc = np.array([[0.0, 3.0, 0.5]])
    distance, which = rays_to_discs(origins, directions, disc)
    assert distance[0, 1] == 2.5
    assert which.tolist() == [[-1, 0, -1]]


@settings(max_examples=50, deadline=None)
@given(st.integers(0, 10_000))
def test_culled_casting_equals_brute_force(seed: int) -> None:
    rng = np.random.default_rng(seed)
    origins = rng.uniform(0, 10, (6, 2))
    headings = rng.uniform(-3, 3, 6)
    angles = -np.pi + np.arange(64) * (2 * np.pi / 64)
    start = rng.uniform(0, 10, (25, 2))
    segments = np.stack([start, start + rng.uniform(-2, 2, (25, 2))], axis=1)
    visible = rng.uniform(size=(6, 25)) > 0.3
    dense, _ = rays_to_segments(origins, ray_directions(headings, angles), segments, ~visible)
    culled, _ = rays_to_segments_culled(origins, headings, angles, segments, visible)
    np.testing.assert_allclose(culled, dense)


def cloud_of_first_robot(poses: np.ndarray, discs: np.ndarray | None = None,
                         config: LidarConfig | None = None) -> np.ndarray:
    corners = footprint_corners(poses[:, 0], poses[:, 1], poses[:, 2], np.full(len(poses), 1.2),
                                np.full(len(poses), 0.6))
    discs = np.zeros((0, 3)) if discs is None else discs
    clouds = scan_clouds(config or LidarConfig(), 1.5, poses, corners,
                         LidarScene.build(ROOM, 2.0, []), discs,
                         np.full(len(discs), 1.7))
    assert clouds[0].stamp == 1.5
    return clouds[0].points()


def test_robot_ahead_hides_the_lower_wall() -> None:
    points = cloud_of_first_robot(np.array([[5.0, 5.0, 0.0], [7.0, 5.0, 0.0]]))
    ahead = points[(np.abs(points[:, 1]) < 1e-9) & (points[:, 0] > 0)]
    robot = ahead[np.isclose(ahead[:, 0], 1.4)]  # the other robot's rear edge: 7 - 0.6 - 5
    wall = ahead[np.isclose(ahead[:, 0], 5.0)]
    np.testing.assert_allclose(robot[:, 2], np.arange(11) * 0.1)  # 0 to 1 m every 10 cm
    np.testing.assert_allclose(wall[:, 2], 1.0 + np.arange(11) * 0.1)  # upper half only
    behind = points[(np.abs(points[:, 1]) < 1e-9) & (points[:, 0] < 0)]
    np.testing.assert_allclose(np.sort(behind[:, 2]), np.arange(21) * 0.1)  # the whole wall


def test_spectator_seen_to_its_height_and_own_body_never() -> None:
    points = cloud_of_first_robot(np.array([[5.0, 5.0, 0.0]]), np.array([[5.0, 7.0, 0.3]]))
    left = points[(np.abs(points[:, 0]) < 1e-9) & (points[:, 1] > 0)]
    person = left[np.isclose(left[:, 1], 1.7)]
    assert person[:, 2].max() == pytest.approx(1.7)
    assert np.hypot(points[:, 0], points[:, 1]).min() >= 0.3


def test_nothing_nearer_than_min_range_or_beyond_max_range() -> None:
    points = cloud_of_first_robot(np.array([[5.0, 5.0, 0.0], [5.9, 5.0, np.pi / 2]]),
                                  config=LidarConfig(max_range=4.0))
    distance = np.hypot(points[:, 0], points[:, 1])
    assert distance.min() >= 0.3
    assert distance.max() <= 4.0 + 1e-9


def test_ray_count_and_1024_rays() -> None:
    assert len(LidarConfig().angles()) == 256
    poses = np.array([[5.0, 5.0, 0.3]])
    dense = cloud_of_first_robot(poses, config=LidarConfig(rays=1024))
    sparse = cloud_of_first_robot(poses)
    assert len(dense) == 4 * len(sparse)


@settings(max_examples=50, deadline=None)
@given(st.integers(0, 10_000))
def test_convex_room_walls_equal_brute_force(seed: int) -> None:
    from dancebots.sim.raycast import rays_to_convex_walls

    rng = np.random.default_rng(seed)
    corners = np.linspace(0, 2 * np.pi, 7)[:-1] + rng.uniform(-0.3, 0.3, 6)
    room = np.stack([5 + 4 * np.cos(corners), 5 + 3 * np.sin(corners)], axis=1)  # convex,
    # holding the square 4..6 x 4..6 where the sensors are
    origins = 5 + rng.uniform(-1, 1, (5, 2))
    directions = ray_directions(rng.uniform(-3, 3, 5), -np.pi + np.arange(64) * np.pi / 32)
    segments = np.stack([room, np.roll(room, -1, axis=0)], axis=1)
    expected, _ = rays_to_segments(origins, directions, segments)
    np.testing.assert_allclose(rays_to_convex_walls(origins, directions, room), expected)


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000))
def test_compiled_and_numpy_scans_agree(seed: int) -> None:
    rng = np.random.default_rng(seed)
    count = int(rng.integers(1, 6))
    poses = np.column_stack([rng.uniform(1, 9, (count, 2)), rng.uniform(-3, 3, count)])
    corners = footprint_corners(poses[:, 0], poses[:, 1], poses[:, 2], np.full(count, 1.2),
                                np.full(count, 0.6))
    obstacles = [(np.array([[6.0, 6.0], [7.0, 6.5], [6.5, 7.5]]), 1.0)]
    discs = np.array([[3.0, 7.0, 0.3], [8.0, 2.0, 0.25]])
    heights = np.array([1.7, 1.2])
    args = (1.0, poses, corners, LidarScene.build(ROOM, 2.0, obstacles), discs, heights)
    compiled = scan_clouds(LidarConfig(rays=64), *args)
    reference = scan_clouds(LidarConfig(rays=64, compiled=False), *args)
    for a, b in zip(compiled, reference, strict=True):
        np.testing.assert_allclose(a.columns, b.columns, atol=1e-9)


def test_the_ray_angles_handed_out_are_a_copy() -> None:
    """The scans share one array of ray angles per ray count; what ``angles()`` hands out
    may be written to without turning every later scan."""
    config = LidarConfig(rays=16)
    mine = config.angles()
    mine[:] = 0.0
    assert config.angles()[0] == -np.pi
    assert config.angles()[1] == pytest.approx(-np.pi + 2.0 * np.pi / 16)

"""The vectorised frame transforms agree with the scalar Pose operations."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from dancebots.geometry import (
    Pose,
    compose_points,
    compose_poses,
    points_in_frames,
    points_to_local,
    points_to_world,
    wrap_angle,
    wrap_angles,
)

values = st.floats(-20.0, 20.0, allow_nan=False)
poses = st.tuples(values, values, st.floats(-7.0, 7.0, allow_nan=False))


@given(poses, st.lists(poses, min_size=1, max_size=8))
def test_compose_poses_is_pose_compose(frame, others) -> None:  # type: ignore[no-untyped-def]
    composed = compose_poses(np.array(frame), np.array(others))
    for row, other in zip(composed, others, strict=True):
        expected = Pose(*frame).compose(Pose(*other))
        np.testing.assert_allclose(row, (expected.x, expected.y, expected.theta), atol=1e-9)


@given(poses, st.lists(st.tuples(values, values), min_size=1, max_size=8))
def test_points_to_world_is_pose_to_world(pose, points) -> None:  # type: ignore[no-untyped-def]
    moved = points_to_world(np.array(points), pose)
    np.testing.assert_allclose(moved, points_to_world(np.array(points), Pose(*pose)))
    for row, (x, y) in zip(moved, points, strict=True):
        np.testing.assert_allclose(row, Pose(*pose).to_world(x, y), atol=1e-9)


@given(st.lists(poses, min_size=1, max_size=8), st.lists(st.tuples(values, values), min_size=1,
                                                         max_size=8))
def test_compose_points_is_compose_poses_without_heading(frames, points) -> None:  # type: ignore[no-untyped-def]
    count = min(len(frames), len(points))
    frame_array, point_array = np.array(frames[:count]), np.array(points[:count])
    with_heading = np.column_stack([point_array, np.zeros(count)])
    np.testing.assert_array_equal(compose_points(frame_array, point_array),
                                  compose_poses(frame_array, with_heading)[:, :2])
    # one frame for all points broadcasts
    np.testing.assert_array_equal(compose_points(frame_array[0], point_array),
                                  compose_poses(frame_array[0], with_heading)[:, :2])


@given(poses, st.lists(st.tuples(values, values), min_size=1, max_size=8))
def test_points_to_local_is_pose_to_local(pose, points) -> None:  # type: ignore[no-untyped-def]
    local = points_to_local(np.array(points), pose)
    np.testing.assert_array_equal(local, points_to_local(np.array(points), Pose(*pose)))
    for row, (x, y) in zip(local, points, strict=True):
        assert tuple(row) == Pose(*pose).to_local(x, y)  # the same operations, bit for bit
    np.testing.assert_allclose(points_to_world(local, pose), points, atol=1e-9)


@given(st.lists(st.floats(-50.0, 50.0, allow_nan=False), min_size=1, max_size=8))
def test_one_wrap_convention(angles) -> None:  # type: ignore[no-untyped-def]
    wrapped = wrap_angles(np.array(angles))
    assert ((wrapped > -np.pi) & (wrapped <= np.pi)).all()
    for value, angle in zip(wrapped, angles, strict=True):
        assert -math.pi < wrap_angle(angle) <= math.pi
        assert math.isclose(math.cos(value), math.cos(wrap_angle(angle)), abs_tol=1e-9)
        assert math.isclose(math.sin(value), math.sin(wrap_angle(angle)), abs_tol=1e-9)
    assert wrap_angle(-math.pi) == math.pi
    assert wrap_angles(np.array([-np.pi]))[0] == np.pi


def test_points_in_frames_is_to_local_for_every_point_and_frame() -> None:
    rng = np.random.default_rng(7)
    points = rng.uniform(-5, 5, (4, 2))
    frames = np.column_stack([rng.uniform(-5, 5, (3, 2)), rng.uniform(-4, 4, 3)])
    local = points_in_frames(points[None, :, :], frames[:, None, :])
    assert local.shape == (3, 4, 2)
    for r, frame in enumerate(frames):
        pose = Pose(*frame)
        for c, point in enumerate(points):
            np.testing.assert_allclose(local[r, c], pose.to_local(*point), rtol=0,
                                       atol=1e-12)

"""The vectorised frame transforms agree with the scalar Pose operations."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from dancebots.geometry import Pose, compose_poses, points_to_world

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

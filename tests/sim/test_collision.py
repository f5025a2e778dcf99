"""Collision tests: the compiled pair search agrees with the NumPy separating-axis test and
with shapely; boundary contacts agree with shapely's distances."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import example, given, settings
from hypothesis import strategies as st

from dancebots.geometry import footprint_corners
from dancebots.sim.collision import (
    Boundaries,
    closing_speed,
    overlapping_pairs,
    rectangles_overlap,
)


def random_footprints(seed: int, count: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    lengths, widths = rng.uniform(0.3, 1.5, count), rng.uniform(0.3, 1.0, count)
    corners = footprint_corners(rng.uniform(0, 4, count), rng.uniform(0, 4, count),
                                rng.uniform(-3.2, 3.2, count), lengths, widths)
    return corners, 0.5 * np.hypot(lengths, widths)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 100_000), st.integers(0, 12))
@example(26793, 12)
def test_overlapping_pairs_agree_with_shapely(seed: int, count: int) -> None:
    corners, reach = random_footprints(seed, count)
    shapes = shapely.polygons(corners) if count else []
    expected = [(i, j) for i in range(count) for j in range(i + 1, count)
                if shapely.intersection(shapes[i], shapes[j]).area > 1e-6]
    found = overlapping_pairs(corners, reach)
    assert found == sorted(found)
    assert set(expected) <= set(found)
    # a pair found beyond those is one that grazes (seed 26793: an overlap of 1.3e-10 m2)
    for i, j in set(found) - set(expected):
        assert shapely.distance(shapes[i], shapes[j]) < 1e-9
        assert shapely.intersection(shapes[i], shapes[j]).area <= 1e-6
    for i, j in found:  # and with the NumPy separating-axis test
        assert rectangles_overlap(corners[i:i + 1], corners[j:j + 1])[0]
    assert overlapping_pairs(corners, reach, compiled=False) == found  # the NumPy path


def test_touching_rectangles_do_not_overlap() -> None:
    corners = footprint_corners(np.array([0.0, 1.0]), np.zeros(2), np.zeros(2), 1.0, 0.5)
    assert overlapping_pairs(corners, np.full(2, 0.56)) == []
    corners = footprint_corners(np.array([0.0, 0.99]), np.zeros(2), np.zeros(2), 1.0, 0.5)
    assert overlapping_pairs(corners, np.full(2, 0.56)) == [(0, 1)]


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 100_000))
def test_boundary_contacts_agree_with_shapely(seed: int) -> None:
    room = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [2.0, 3.0], [2.0, 4.0], [0.0, 4.0]])
    pillar = np.array([[2.5, 1.0], [3.0, 1.0], [3.0, 1.5], [2.5, 1.5]])
    boundaries = Boundaries(room, [pillar])
    corners, reach = random_footprints(seed, 8)
    expected = []
    room_shape, pillar_shape = shapely.Polygon(room), shapely.Polygon(pillar)
    for robot, outline in enumerate(shapely.polygons(corners)):
        if not room_shape.contains(outline):
            expected.append((robot, -1))
        if pillar_shape.intersects(outline):
            expected.append((robot, 0))
    assert sorted(boundaries.contacts(corners, reach)) == expected
    numpy_only = Boundaries(room, [pillar], compiled=False)
    assert sorted(numpy_only.contacts(corners, reach)) == expected


def test_walls_and_obstacles_are_contacts() -> None:
    room = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]])
    pillar = np.array([[5.0, 5.0], [6.0, 5.0], [6.0, 6.0], [5.0, 6.0]])
    boundaries = Boundaries(room, [pillar])
    poses = np.array([[2.0, 2.0, 0.0], [0.3, 5.0, 0.0], [5.5, 5.5, 0.0], [4.5, 5.5, 0.0],
                      [20.0, 20.0, 0.0]])
    corners = footprint_corners(poses[:, 0], poses[:, 1], poses[:, 2], np.full(5, 1.2),
                                np.full(5, 0.6))
    contacts = boundaries.contacts(corners, np.full(5, 0.67))
    assert sorted(contacts) == [(1, -1), (2, 0), (3, 0), (4, -1)]
    numpy_only = Boundaries(room, [pillar], compiled=False)
    assert sorted(numpy_only.contacts(corners, np.full(5, 0.67))) == sorted(contacts)


HUSKY = (0.99, 0.67)  # length, width (m)


@pytest.mark.parametrize(("velocity", "point", "expected"), [
    ((0.5, 0.0), (0.7, 0.0), 0.5),     # driving at a person ahead
    ((0.5, 0.0), (-0.7, 0.0), -0.5),   # driving away from one behind
    ((-0.3, 0.0), (-0.7, 0.1), 0.3),   # reversing into one behind
    ((0.5, 0.0), (0.0, 0.5), 0.0),     # sliding past one at the side
    ((0.0, 1.0), (0.495, 0.435), 0.495),   # turning left: the front left corner sweeps at
    ((0.0, -1.0), (0.495, 0.435), -0.495),  # them; right: away (issue 13's seed 0)
    ((0.0, 0.0), (0.7, 0.0), 0.0),     # standing
])
def test_the_closing_speed_is_the_footprints_speed_towards_the_person(
        velocity: tuple[float, float], point: tuple[float, float], expected: float) -> None:
    """A HUSKY at the origin facing +x (and the same turned by 2 rad about a point elsewhere:
    the speed does not depend on the frame)."""
    length, width = HUSKY
    assert closing_speed(np.zeros(3), np.array(velocity), length, width,
                         np.array(point)) == pytest.approx(expected, abs=1e-12)
    pose = np.array([3.0, -2.0, 2.0])
    c, s = np.cos(2.0), np.sin(2.0)
    moved = pose[:2] + np.array([c * point[0] - s * point[1], s * point[0] + c * point[1]])
    assert closing_speed(pose, np.array(velocity), length, width, moved) == pytest.approx(
        expected, abs=1e-12)

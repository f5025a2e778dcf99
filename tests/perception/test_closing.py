"""People closing in (``perception.closing``, the ``closing`` stop rule): the sector gaps,
their closing speeds, S_p, and the compiled kernels against the NumPy reference."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dancebots.geometry import points_to_local, points_to_world
from dancebots.perception.closing import ClosingParams, closing_speeds, sector_gaps, too_near
from dancebots.perception.obstacles import DetectorParams, obstacle_points_from_columns
from dancebots.perception.ssm import protective_distance

LENGTH, WIDTH = 1.0, 0.6


def test_a_sector_holds_the_smallest_gap_of_its_points_to_the_footprint() -> None:
    points = np.array([[1.5, 0.0], [0.9, 0.05], [-2.0, 0.0], [0.0, 1.3], [0.8, 0.9]])
    gaps = sector_gaps(points, LENGTH, WIDTH, 8)
    # 8 sectors of 45 deg from -180 deg: ahead is sector 4, left 6, behind 0 (or 7 at +180)
    assert gaps[4] == pytest.approx(0.4)  # 0.9 - 0.5: the nearer of the two ahead
    assert gaps[6] == pytest.approx(1.0)  # 1.3 - 0.3
    assert gaps[5] == pytest.approx(math.hypot(0.3, 0.6))  # beyond the corner, at 48 deg
    assert gaps[7] == pytest.approx(1.5)  # atan2(0, -2) = +pi: the last sector
    assert np.isinf(gaps[[0, 1, 2, 3]]).all()
    assert np.isinf(sector_gaps(np.zeros((0, 2)), LENGTH, WIDTH, 8)).all()
    not_a_number = np.array([[math.nan, 0.0], [1.5, math.inf], [0.9, 0.05]])
    assert sector_gaps(not_a_number, LENGTH, WIDTH, 8)[4] == pytest.approx(0.4)


def test_a_gap_closes_only_by_what_moved_towards_the_robot() -> None:
    inf = math.inf
    # sector 0: a person 2.0 -> 1.8 m: 2 m/s at 0.1 s; sector 2: unchanged; sector 4: a
    # person appears from nothing near: no speed known
    speeds = closing_speeds(np.array([2.0, inf, 1.0, inf, inf, inf]),
                            np.array([1.8, inf, 1.0, inf, 0.5, inf]), 0.1, 3.0)
    assert speeds.tolist() == pytest.approx([2.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    # a person walking round the robot from sector 1 into sector 2, 5 cm nearer: sector 1
    # emptied, so its gap before counts for sector 2 (0.5 m/s), not as a 10 m/s sprint
    round_robot = closing_speeds(np.array([inf, 1.0, inf, inf]),
                                 np.array([inf, inf, 0.95, inf]), 0.1, 3.0)
    assert round_robot.tolist() == pytest.approx([0.0, 0.0, 0.5, 0.0])
    # a watcher standing in sector 0 hides nothing: the runner in sector 1 closes at 2 m/s
    beside = closing_speeds(np.array([0.9, 1.7, inf, inf]), np.array([0.9, 1.5, inf, inf]),
                            0.1, 3.0)
    assert beside.tolist() == pytest.approx([0.0, 2.0, 0.0, 0.0])
    assert closing_speeds(np.array([2.0, inf]), np.zeros(2), 0.1, 3.0).max() == 3.0  # capped
    for elapsed in (0.0, -0.1, math.nan, math.inf):
        assert closing_speeds(np.array([2.0]), np.array([1.0]), elapsed, 3.0).tolist() == [0.0]


def test_an_approach_is_too_near_within_the_protective_separation_distance() -> None:
    params = ClosingParams()
    needed = float(protective_distance(0.3, 1.6, 0.3, 0.35, 1.0, params.margin))
    gaps = np.array([needed - 0.01, needed + 0.01])
    assert too_near(gaps[:1], np.array([1.6]), 0.3, 0.3, 0.35, 1.0, params)
    assert too_near(gaps[:1], np.array([1.6]), -0.3, 0.3, 0.35, 1.0, params)  # reversing
    assert not too_near(gaps[1:], np.array([1.6]), -0.3, 0.3, 0.35, 1.0, params)
    # a watcher stepping up slowly is left to the fixed stop distance
    assert not too_near(np.array([0.3]), np.array([0.4]), 0.3, 0.3, 0.35, 1.0, params)
    assert not too_near(np.array([math.inf]), np.array([0.0]), 0.3, 0.3, 0.35, 1.0, params)


@pytest.mark.parametrize("bad", [{"sectors": 3}, {"sectors": 16.0}, {"min_speed": -1.0},
                                 {"max_speed": math.nan}, {"min_speed": 2.0, "max_speed": 1.0},
                                 {"margin": math.inf}])
def test_bad_parameters_are_refused(bad: dict[str, float]) -> None:
    with pytest.raises(ValueError, match="closing parameters"):
        ClosingParams(**bad)  # type: ignore[arg-type]


@settings(max_examples=80, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), points=st.integers(0, 60), centres=st.integers(0, 4),
       radius=st.sampled_from([0.0, 1e-300, 0.85]), sectors=st.sampled_from([4, 16, 360]))
def test_the_compiled_kernels_are_the_numpy_reference(seed: int, points: int, centres: int,
                                                      radius: float, sectors: int) -> None:
    """``stranger_points_columns`` keeps the points far from every mate, crops them and
    takes them to the map frame as NumPy does; ``sector_gaps_moved`` is ``sector_gaps`` of
    the points taken to ``base_link`` at the pose."""
    from dancebots.perception.closing_jit import sector_gaps_moved, stranger_points_columns

    rng = np.random.default_rng(seed)
    columns = np.column_stack([rng.uniform(-5.0, 5.0, (points, 2)),
                               rng.uniform(-0.2, 0.4, points), rng.uniform(0.0, 2.0, points)])
    if points and seed % 4 == 0:
        columns[0, seed % 2] = np.nan  # a corrupt column is no point
    mates = rng.uniform(-5.0, 5.0, (centres, 2))
    seen_from = (*rng.uniform(-1.0, 1.0, 2), rng.uniform(-math.pi, math.pi))
    detection = DetectorParams(crop_half=4.0)
    compiled = stranger_points_columns(columns, 0.1, detection.crop_half, detection.z_min,
                                       detection.z_max, np.array(seen_from), mates, radius)
    local = points_to_local(mates, seen_from)
    far = np.hypot(columns[:, None, 0] - local[None, :, 0],
                   columns[:, None, 1] - local[None, :, 1]).min(axis=1, initial=math.inf) > radius
    expected = points_to_world(obstacle_points_from_columns(
        columns[far | (centres == 0)], 0.1, detection), seen_from)
    np.testing.assert_allclose(compiled, expected, atol=1e-12)
    pose = np.array([*rng.uniform(-1.0, 1.0, 2), rng.uniform(-math.pi, math.pi)])
    if seed % 5 == 0:
        pose[seed % 3] = math.nan  # a pose that is not a number leaves no point (both ways)
    np.testing.assert_allclose(
        sector_gaps_moved(expected, pose, LENGTH, WIDTH, sectors),
        sector_gaps(points_to_local(expected, tuple(pose)), LENGTH, WIDTH, sectors),
        atol=1e-12)

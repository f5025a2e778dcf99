"""Detectors A1 and A2 on synthetic scans with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from tests.leader_follower.scans import box, legs, make_scan

from dancebots.leader_follower.detectors import (
    ClusterParams,
    ClusterState,
    TrackingParams,
    TrackingState,
    bin_scan,
    cluster_step,
    tracking_step,
)

WALL = [((3.0, -3.0), (3.0, 3.0))]


def a1(scan, state=None):  # type: ignore[no-untyped-def]
    return cluster_step(ClusterParams(), state or ClusterState(), scan)


def test_bins_cover_140_degrees_in_2_degree_steps() -> None:
    scan = make_scan(segments=[((1.0, -10.0), (1.0, 10.0))])
    points = bin_scan(scan, ClusterParams())
    bearings = np.degrees(np.arctan2(points[:, 1], points[:, 0]))
    assert len(points) == 70  # 140 deg / 2 deg, every cone holds a reading of the wall
    assert bearings.min() == pytest.approx(-69.0)
    assert bearings.max() == pytest.approx(69.0)


def test_a1_finds_the_legs_ahead_and_ignores_the_wall() -> None:
    _, detection = a1(make_scan(legs(1.0, 0.1), WALL))
    assert detection.target is not None
    assert math.dist(detection.target.position, (1.0, 0.1)) < 0.12


def test_a1_finds_a_robot_ahead() -> None:
    _, detection = a1(make_scan(segments=box(0.8, -0.2) + WALL))
    assert detection.target is not None
    assert math.dist(detection.target.position, (0.8, -0.2)) < 0.12


def test_a1_sees_nothing_to_follow_in_a_wall_or_behind_the_robot() -> None:
    _, detection = a1(make_scan(legs(-1.0, 0.0), WALL))
    assert detection.target is None


def test_a1_ignores_single_beam_noise() -> None:
    scan = make_scan(segments=WALL)
    ranges = scan.ranges.copy()
    ranges[180] = 0.7  # one stray reading straight ahead
    _, detection = a1(type(scan)(scan.stamp, ranges, scan.angles, scan.pose))
    assert detection.target is None


def test_a1_keeps_its_target_against_a_nearer_newcomer() -> None:
    state, first = a1(make_scan(legs(1.2, 0.0), WALL))
    assert first.target is not None
    state, second = a1(make_scan(legs(1.3, 0.0) + legs(0.6, 0.5), WALL, stamp=0.2), state)
    assert second.target is not None
    assert math.dist(second.target.position, (1.3, 0.0)) < 0.15


def test_a1_reports_in_the_odometry_frame() -> None:
    pose = (2.0, 1.0, math.pi / 2)
    _, detection = a1(make_scan(legs(2.0, 2.2, apart=0.0), pose=pose))
    assert detection.target is not None
    assert math.dist(detection.target.position, (2.0, 2.2)) < 0.12


def track(scans, params=None):  # type: ignore[no-untyped-def]
    params = params or TrackingParams()
    state = TrackingState()
    detections = []
    for scan in scans:
        state, detection = tracking_step(params, state, scan)
        detections.append(detection)
    return state, detections


def test_a2_estimates_a_walking_persons_velocity() -> None:
    scans = [make_scan([(1.0 + 0.3 * t, 0.5, 0.15)], WALL, stamp=t)
             for t in np.arange(0.0, 3.0, 0.2)]
    _, detections = track(scans)
    target = detections[-1].target
    assert target is not None
    assert target.velocity == pytest.approx((0.3, 0.0), abs=0.05)


def test_a2_sees_a_standing_person_stand_while_the_robot_moves() -> None:
    """Tracks live in the odometry frame: the robot's own motion is not the person's."""
    scans = [make_scan([(2.0, 0.0, 0.15)], WALL, pose=(0.4 * t, 0.1 * t, 0.05 * t), stamp=t)
             for t in np.arange(0.0, 3.0, 0.2)]
    _, detections = track(scans)
    target = detections[-1].target
    assert target is not None
    assert math.hypot(*target.velocity) < 0.05
    assert math.dist(target.position, (2.0, 0.0)) < 0.12


def crossing_scans() -> list:  # type: ignore[type-arg]
    """A target walking ahead at 0.15 m/s; from 1 s a person walks across just in front of
    it (0.4 m between their centres as it passes) at 0.6 m/s, hiding it for a few scans."""
    scans = []
    for t in np.arange(0.0, 6.0, 0.2):
        target = (1.6 + 0.15 * t, 0.0, 0.15)
        crosser = (1.6 + 0.15 * 3.5 - 0.4, -1.5 + 0.6 * max(t - 1.0, 0.0), 0.2)
        scans.append(make_scan([target, crosser], stamp=float(t)))
    return scans


def test_a2_seed_rule_is_kidnapped_by_a_crossing_person() -> None:
    _, detections = track(crossing_scans(), TrackingParams(rule="seed"))
    final = detections[-1].target
    assert final is not None
    crosser = (1.6 + 0.15 * 3.5 - 0.4, -1.5 + 0.6 * 4.8)  # where the crosser is at 5.8 s
    assert math.dist(final.position, crosser) < 0.3  # it follows the crosser now


def test_a2_track_rule_keeps_its_target_through_the_crossing() -> None:
    _, detections = track(crossing_scans(), TrackingParams(rule="track"))
    for t, detection in zip(np.arange(0.0, 6.0, 0.2), detections, strict=True):
        if t < 0.5:
            continue  # the first scans confirm the track
        assert detection.target is not None
        assert math.dist(detection.target.position, (1.6 + 0.15 * t, 0.0)) < 0.35


@settings(max_examples=60, deadline=None)
@given(st.lists(st.one_of(st.floats(0.0, 5.0), st.just(math.inf), st.just(math.nan)),
                min_size=360, max_size=360),
       st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(-4, 4)))
def test_detectors_take_any_scan(readings: list[float], pose) -> None:  # type: ignore[no-untyped-def]
    """Any readings (NaN and inf included) give a detection; a target lies within the field
    of view and range it was sought in."""
    scan = make_scan(pose=pose)
    scan = type(scan)(0.0, np.array(readings), scan.angles, pose)
    _, detection = cluster_step(ClusterParams(), ClusterState(), scan)
    state, tracked = tracking_step(TrackingParams(), TrackingState(), scan)
    _, tracked = tracking_step(TrackingParams(), state, type(scan)(0.2, scan.ranges,
                                                                   scan.angles, pose))
    for found in (detection.target, tracked.target):
        if found is None:
            continue
        dx, dy = found.position[0] - pose[0], found.position[1] - pose[1]
        bearing = math.atan2(math.sin(math.atan2(dy, dx) - pose[2]),
                             math.cos(math.atan2(dy, dx) - pose[2]))
        assert abs(bearing) <= math.radians(70) + 0.2  # centre of what was seen ahead
        assert math.hypot(dx, dy) <= 3.5

"""The second seed's detectors (MAGESys 2019, sec. 2.1) as pure functions of state and scan.

A1 ``cluster_step``, clustering (sec. 2.1.1): the field of view reduced to 140 deg, the scan
aggregated into 2 deg bins each summarising a 1 deg cone (median range: robust to a stray
beam), DBSCAN (scikit-learn) on the bin points, clusters kept by point count, spread and
range, the closest centroid chosen; the target is kept from scan to scan (a new one must lie
within ``max_jump`` of the previous, else the target is lost; after ``lost_scans`` lost
scans the closest cluster is taken again).

A2 ``tracking_step``, tracking (sec. 2.1.2): the scan split into segments where neighbouring
readings are far apart, each small segment a circle, tracked by constant-velocity Kalman
filters (``kalman.py``) in the odometry frame with Hungarian assignment (SciPy). Two target
rules: ``seed`` as the paper describes it ("coordinates, speed and displacement between two
successive detections": the track nearest to where the target was), which a person crossing
close to the target can take over (a "kidnapping", sec. 3.3.2); and ``track`` (an addition):
the target is its track; while hidden the track coasts on its prediction for ``coast_time``
s, and only then is a new target sought near the prediction.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field, replace
from typing import Literal, get_args

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment
from sklearn.cluster import DBSCAN

from dancebots.leader_follower.scan import Detection, Scan, TrackedObject, to_odom
from dancebots.perception.kalman import kalman_predict, kalman_update

__all__ = ["DETECTORS", "ClusterParams", "ClusterState", "QueueDetector", "TargetRule",
           "TrackingParams", "TrackingState", "bin_scan", "cluster_step", "scan_objects",
           "tracking_step"]

FloatArray = NDArray[np.float64]
QueueDetector = Literal["a1", "a2", "a2-track"]
DETECTORS: tuple[QueueDetector, ...] = get_args(QueueDetector)
"""a1: clustering; a2: tracking with the seed's target rule; a2-track: tracking, target by
its track (an addition)."""


@dataclass(frozen=True, slots=True)
class ClusterParams:
    """A1. field_of_view, bin_width, cone: rad (seed: 140 deg, 2 deg, 1 deg; the cone is
    widened to one beam where beams are sparser); eps: DBSCAN neighbourhood, m; min_samples:
    DBSCAN core size; min_points, max_points: bins per kept cluster; max_spread: largest
    distance between two points of a kept cluster, m (legs and robots, not walls);
    min_range, max_range: kept centroid distances, m; max_jump: how far the target may move
    between scans, m; lost_scans: scans without the target before any cluster is taken."""

    field_of_view: float = math.radians(140.0)
    bin_width: float = math.radians(2.0)
    cone: float = math.radians(1.0)
    eps: float = 0.2
    min_samples: int = 2
    min_points: int = 2
    max_points: int = 40
    max_spread: float = 0.8
    min_range: float = 0.15
    max_range: float = 3.0
    max_jump: float = 0.5
    lost_scans: int = 10


@dataclass(frozen=True, slots=True)
class ClusterState:
    target: tuple[float, float] | None = None  # odometry frame
    lost: int = 0


def bin_scan(scan: Scan, params: ClusterParams) -> FloatArray:
    """The seed's aggregation: one point (M, 2) in ``base_link`` per 2 deg bin within the
    field of view whose 1 deg cone holds a reading (the median range of its readings)."""
    half = 0.5 * params.field_of_view
    centres = np.arange(-half + 0.5 * params.bin_width, half, params.bin_width)  # (B,)
    spacing = float(np.median(np.diff(scan.angles))) if len(scan.angles) > 1 else 0.0
    cone = max(params.cone, spacing * 1.01)
    inside = np.abs(scan.angles[None, :] - centres[:, None]) <= 0.5 * cone  # (B, N)
    ranges = np.where(inside & np.isfinite(scan.ranges)[None, :], scan.ranges[None, :], np.nan)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an empty cone's median is NaN
        median = np.nanmedian(ranges, axis=1)
    keep = np.isfinite(median)
    result: FloatArray = np.column_stack([median[keep] * np.cos(centres[keep]),
                                          median[keep] * np.sin(centres[keep])])
    return result


def cluster_step(params: ClusterParams, state: ClusterState, scan: Scan,
                 ) -> tuple[ClusterState, Detection]:
    """One scan of detector A1. Returns the new state and the detection (odometry frame)."""
    points = bin_scan(scan, params)
    objects: list[TrackedObject] = []
    if len(points):
        labels = DBSCAN(eps=params.eps, min_samples=params.min_samples).fit(points).labels_
        for label in np.unique(labels[labels >= 0]):
            cluster = points[labels == label]
            if not params.min_points <= len(cluster) <= params.max_points:
                continue
            spread = float(np.max(np.linalg.norm(cluster[:, None] - cluster[None], axis=2)))
            centroid = cluster.mean(axis=0)
            if spread > params.max_spread or not (
                    params.min_range <= float(np.hypot(*centroid)) <= params.max_range):
                continue
            position = to_odom(centroid[None], scan.pose)[0]
            objects.append(TrackedObject((float(position[0]), float(position[1])),
                                         radius=0.5 * spread))
    robot = np.array(scan.pose[:2])
    candidates = objects
    if state.target is not None and state.lost < params.lost_scans:
        candidates = [o for o in objects if math.dist(o.position, state.target)
                      <= params.max_jump]
    if not candidates:
        return ClusterState(state.target, state.lost + 1), Detection(None, tuple(objects))
    chosen = min(candidates, key=lambda o: float(np.hypot(*(np.array(o.position) - robot))))
    return ClusterState(chosen.position, 0), Detection(chosen, tuple(objects))


TargetRule = Literal["seed", "track"]
"""How A2 picks its target among the tracks (see the module)."""


@dataclass(frozen=True, slots=True)
class TrackingParams:
    """A2. gap: readings further apart than max(gap, gap_factor x range x beam spacing) start
    a new segment, m; max_radius: larger segments are walls, split into static pieces of this
    radius for collision avoidance, m; acceleration_noise: q, m^2/s^3; measurement_noise: m;
    gate: largest distance for assigning a detection to a track, m; min_hits: updates before a
    track is confirmed; max_misses: scans a track survives unseen; field_of_view: where a
    new target is sought, rad; max_range: m; rule: "seed" or "track"; max_jump: the seed
    rule's largest displacement of the target between scans, m; lost_scans: scans without
    the target before the nearest object ahead is taken; coast_time: the track rule's time a
    hidden target coasts on its prediction, s."""

    gap: float = 0.12
    gap_factor: float = 3.0
    max_radius: float = 0.35
    acceleration_noise: float = 0.5
    measurement_noise: float = 0.05
    gate: float = 0.5
    min_hits: int = 2
    max_misses: int = 10
    field_of_view: float = math.radians(140.0)
    max_range: float = 3.0
    rule: TargetRule = "seed"
    max_jump: float = 0.5
    lost_scans: int = 10
    coast_time: float = 2.0


@dataclass(frozen=True, slots=True, eq=False)
class TrackingState:
    """Tracks: ids (K,), states (K, 4) and covariances (K, 4, 4) in the odometry frame,
    radii (K,), hits and misses (K,), last_seen (K,) stamps; the target's track id, last
    position and scans lost; the stamp of the last scan."""

    ids: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    states: FloatArray = field(default_factory=lambda: np.zeros((0, 4)))
    covariances: FloatArray = field(default_factory=lambda: np.zeros((0, 4, 4)))
    radii: FloatArray = field(default_factory=lambda: np.zeros(0))
    hits: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    misses: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    next_id: int = 0
    last_seen: FloatArray = field(default_factory=lambda: np.zeros(0))
    target: int = -1
    target_position: tuple[float, float] | None = None
    lost: int = 0
    stamp: float | None = None


def scan_objects(scan: Scan, params: TrackingParams) -> tuple[FloatArray, FloatArray,
                                                              FloatArray, FloatArray]:
    """Segments of the scan as circles in the odometry frame: small ones (objects to track)
    as centres (K, 2) and radii (K,), larger ones (walls, obstacle faces) cut into static
    circles (S, 2), (S,). A segment of chord c is a circle of radius c/2 whose centre lies
    behind the points' mean, by 2/pi of the radius (the mean of a half circle's arc)."""
    points, angles = scan.points()
    if len(points) == 0:
        empty = np.zeros((0, 2))
        return empty, np.zeros(0), empty, np.zeros(0)
    spacing = float(np.median(np.diff(scan.angles))) if len(scan.angles) > 1 else 0.0
    ranges = np.hypot(points[:, 0], points[:, 1])
    step = np.hypot(*(np.roll(points, -1, axis=0) - points).T)  # to the next reading
    limit = np.maximum(params.gap, params.gap_factor * ranges * spacing)
    adjacent = np.abs(np.roll(angles, -1) - angles) <= 1.5 * spacing + 1e-9
    adjacent[-1] = abs(angles[0] + 2.0 * math.pi - angles[-1]) <= 1.5 * spacing + 1e-9
    joined = adjacent & (step <= limit)  # reading i joins reading i + 1
    breaks = np.flatnonzero(~joined)
    if len(breaks) == 0:  # one closed outline around the robot
        segments = [np.arange(len(points))]
    else:
        first = breaks[-1] + 1  # start after a break, wrapping around the circle
        order = np.roll(np.arange(len(points)), -first)
        cut = np.flatnonzero(~joined[order]) + 1
        segments = np.split(order, cut[:-1])
    small_centres, small_radii, static_centres, static_radii = [], [], [], []
    for segment in segments:
        chunk = points[segment]
        chord = float(np.hypot(*(chunk[-1] - chunk[0])))
        if 0.5 * chord <= params.max_radius:
            radius = max(0.5 * chord, 0.05)
            mean = chunk.mean(axis=0)
            centre = mean + (2.0 / math.pi) * radius * mean / max(float(np.hypot(*mean)), 1e-9)
            small_centres.append(centre)
            small_radii.append(radius)
        else:
            pieces = math.ceil(0.5 * chord / params.max_radius)
            for piece in np.array_split(chunk, pieces):
                static_centres.append(piece.mean(axis=0))
                static_radii.append(max(0.5 * float(np.hypot(*(piece[-1] - piece[0]))),
                                        0.05))
    def odom(centres: list[FloatArray]) -> FloatArray:
        return to_odom(np.array(centres).reshape(-1, 2), scan.pose)

    return (odom(small_centres), np.array(small_radii), odom(static_centres),
            np.array(static_radii))


def tracking_step(params: TrackingParams, state: TrackingState, scan: Scan,
                  ) -> tuple[TrackingState, Detection]:
    """One scan of detector A2 (rule ``seed`` or ``track``, see the module)."""
    centres, radii, static, static_radii = scan_objects(scan, params)
    dt = 0.0 if state.stamp is None else max(scan.stamp - state.stamp, 0.0)
    states, covariances = kalman_predict(state.states, state.covariances, dt,
                                         params.acceleration_noise)
    ids, hits, misses, track_radii = state.ids, state.hits, state.misses, state.radii
    matched_tracks = np.zeros(len(ids), dtype=bool)
    matched_detections = np.zeros(len(centres), dtype=bool)
    if len(ids) and len(centres):
        cost = np.hypot(*(states[:, None, :2] - centres[None]).transpose(2, 0, 1))
        rows, cols = linear_sum_assignment(cost)
        good = cost[rows, cols] <= params.gate
        rows, cols = rows[good], cols[good]
        if len(rows):
            states[rows], covariances[rows] = kalman_update(
                states[rows], covariances[rows], centres[cols], params.measurement_noise)
            track_radii = track_radii.copy()
            track_radii[rows] = radii[cols]
        matched_tracks[rows] = True
        matched_detections[cols] = True
    hits = np.where(matched_tracks, hits + 1, hits)
    misses = np.where(matched_tracks, 0, misses + 1)
    last_seen = np.where(matched_tracks, scan.stamp, state.last_seen)
    new = np.flatnonzero(~matched_detections)
    new_states = np.column_stack([centres[new], np.zeros((len(new), 2))])
    new_cov = np.tile(np.diag([params.measurement_noise**2] * 2 + [1.0, 1.0]), (len(new), 1, 1))
    ids = np.concatenate([ids, state.next_id + np.arange(len(new))])
    states = np.concatenate([states, new_states])
    covariances = np.concatenate([covariances, new_cov])
    track_radii = np.concatenate([track_radii, radii[new]])
    hits = np.concatenate([hits, np.ones(len(new), dtype=np.int64)])
    misses = np.concatenate([misses, np.zeros(len(new), dtype=np.int64)])
    last_seen = np.concatenate([last_seen, np.full(len(new), scan.stamp)])
    alive = misses <= params.max_misses
    ids, states, covariances = ids[alive], states[alive], covariances[alive]
    track_radii, hits, misses = track_radii[alive], hits[alive], misses[alive]
    last_seen = last_seen[alive]
    confirmed = hits >= params.min_hits
    objects = [TrackedObject((float(s[0]), float(s[1])), (float(s[2]), float(s[3])),
                             float(r), int(i))
               for i, s, r, ok, gone in zip(ids, states, track_radii, confirmed, misses,
                                            strict=True) if ok and gone == 0]
    objects += [TrackedObject((float(c[0]), float(c[1])), radius=float(r))
                for c, r in zip(static, static_radii, strict=True)]
    new_state = TrackingState(ids, states, covariances, track_radii, hits, misses,
                              state.next_id + len(new), last_seen, state.target,
                              state.target_position, state.lost, scan.stamp)
    target = _choose_target(params, new_state, scan, confirmed)
    if target is None:
        return replace(new_state, lost=state.lost + 1), Detection(None, tuple(objects))
    return (replace(new_state, target=target.track, target_position=target.position, lost=0),
            Detection(target, tuple(objects)))


def _choose_target(params: TrackingParams, state: TrackingState, scan: Scan,
                   confirmed: NDArray[np.bool_]) -> TrackedObject | None:
    """The target of this scan (see the module for the two rules)."""
    seen = confirmed & (state.misses == 0)
    index = {int(i): k for k, i in enumerate(state.ids)}

    def tracked(k: int) -> TrackedObject:
        s = state.states[k]
        return TrackedObject((float(s[0]), float(s[1])), (float(s[2]), float(s[3])),
                             float(state.radii[k]), int(state.ids[k]))

    if params.rule == "track" and state.target in index:
        k = index[state.target]
        if scan.stamp - state.last_seen[k] <= params.coast_time:
            return tracked(k)  # seen now, or hidden and coasting on its prediction
    if state.target_position is not None and state.lost < params.lost_scans:
        # the seed's rule: the object nearest to where the target was (its displacement
        # between successive detections); the track rule uses it once its track is gone
        near = [int(k) for k in np.flatnonzero(seen)
                if math.dist(state.states[k, :2], state.target_position) <= params.max_jump]
        if not near:
            return None
        last = state.target_position
        return tracked(min(near, key=lambda k: math.dist(state.states[k, :2], last)))
    # no target yet, or lost for lost_scans scans: the nearest confirmed object ahead
    x, y, theta = scan.pose
    ahead = []
    for k in np.flatnonzero(seen).tolist():
        dx, dy = state.states[k, 0] - x, state.states[k, 1] - y
        bearing = math.atan2(dy, dx) - theta
        bearing = math.atan2(math.sin(bearing), math.cos(bearing))
        distance = math.hypot(dx, dy)
        if abs(bearing) <= 0.5 * params.field_of_view and distance <= params.max_range:
            ahead.append((distance, int(k)))
    return tracked(min(ahead)[1]) if ahead else None

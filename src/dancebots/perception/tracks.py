"""Obstacles tracked over scans, for the ``predicted`` stop rule and speed and separation
monitoring (``perception.ssm``): an addition, the formation robot's counterpart of the
second seed's detector A2.

Each cloud's obstacle points (in the robot's own map frame, m; for the ``predicted`` rule
without the formation mates where they should be) are clustered (points at most
``TrackParams.cluster_gap`` apart join, transitively); a
cluster wider than a person (``max_width``) is a wall or an obstacle face and stands still.
The small clusters' centres are assigned to the tracks of the last scan (least-cost
assignment, ``perception.assignment``, gated) and filtered by the project's
constant-velocity Kalman filter (``perception.kalman``), which gives their velocity. A track
seen fewer than ``min_hits`` times has no trusted velocity yet: SSM takes the walking speed
for it. The compiled tracker: ``perception.tracks_jit``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from dancebots.perception.assignment import least_cost_assignment
from dancebots.perception.kalman import kalman_predict, kalman_update

__all__ = [
    "NEW",
    "STANDING",
    "TRACKED",
    "ObstacleTracks",
    "TrackParams",
    "cluster_points",
    "point_motion",
    "track_step",
]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
STANDING, TRACKED, NEW = 0, 1, 2
"""Kinds of obstacle point (``track_step``): a wall or obstacle face, a tracked object, an
object seen too few times to trust its velocity."""


@dataclass(frozen=True, slots=True)
class TrackParams:
    """cluster_gap: points nearer than this join one cluster, m; max_width: a cluster wider
    than this (its bounding box's diagonal) is a wall or obstacle face, taken as standing, m;
    gate: the farthest a track may move between scans to keep a cluster, m; min_hits: scans
    before a track's velocity is trusted; max_misses: scans a track survives unseen;
    acceleration_noise: q of the Kalman filter, m^2/s^3 (people change speed quickly);
    measurement_noise: m."""

    cluster_gap: float = 0.3
    max_width: float = 0.9
    gate: float = 0.6
    min_hits: int = 3
    max_misses: int = 3
    acceleration_noise: float = 2.0
    measurement_noise: float = 0.05


@dataclass(frozen=True, slots=True, eq=False)
class ObstacleTracks:
    """Tracks in the robot's own map frame: states (K, 4) x, y, vx, vy (m, m/s), covariances
    (K, 4, 4), hits and misses (K,), and the stamp of the last scan (s)."""

    states: FloatArray = field(default_factory=lambda: np.zeros((0, 4)))
    covariances: FloatArray = field(default_factory=lambda: np.zeros((0, 4, 4)))
    hits: IntArray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    misses: IntArray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    stamp: float | None = None


def cluster_points(points: FloatArray, gap: float, compiled: bool = False,
                   ) -> tuple[IntArray, int]:
    """Cluster labels (N,) of points (N, 2) (points at most ``gap`` m apart join,
    transitively; clusters numbered in the order of their first point) and the number of
    clusters. ``compiled``: the numba kernel ``tracks_jit.cluster_labels`` (the same labels,
    faster per cloud) instead of this NumPy reference: the pairs the kernel's x-sweep joins
    (the same arithmetic), then the connected components by label propagation with
    short-cutting (each point takes the least label of its neighbours, then its label's
    label, until none changes: every point ends with its component's first index). SciPy's
    ``connected_components`` gives the same labels (tested) but costs 0.2 s to import."""
    count = len(points)
    if count == 0:
        return np.zeros(0, dtype=np.int64), 0
    if compiled:
        from dancebots.perception.tracks_jit import cluster_labels  # imports numba

        labels, clusters = cluster_labels(np.ascontiguousarray(points, dtype=np.float64), gap)
        return labels, int(clusters)
    first, second = _pairs_within(np.asarray(points, dtype=np.float64), gap)
    labels = np.arange(count)
    while True:
        joined = labels.copy()
        np.minimum.at(joined, first, labels[second])
        np.minimum.at(joined, second, labels[first])
        while True:  # short-cut to the end of each chain of labels
            further = joined[joined]
            if np.array_equal(further, joined):
                break
            joined = further
        if np.array_equal(joined, labels):
            break
        labels = joined
    roots, numbered = np.unique(labels, return_inverse=True)  # roots in index order
    return numbered.astype(np.int64), len(roots)


PAIR_BLOCK = 1_000_000
"""Candidate pairs :func:`_pairs_within` tests at once (its memory: some 50 bytes each)."""


def _pairs_within(points: FloatArray, gap: float) -> tuple[IntArray, IntArray]:
    """The index pairs (P,), (P,) of points (N, 2) at most ``gap`` m apart, as the kernel's
    sweep over the points sorted by x finds them (``tracks_jit.cluster_labels``: dx after
    the sort at most ``gap``, then dx^2 + dy^2 at most gap^2). The candidates (each point
    with those after it in x within the gap) are tested in blocks of rows of at most about
    :data:`PAIR_BLOCK` (a wall along y puts every point in every window)."""
    order = np.argsort(points[:, 0], kind="mergesort")
    ordered = points[order]
    xs = ordered[:, 0]
    rows = np.arange(len(xs))
    with np.errstate(invalid="ignore", over="ignore"):  # (inf - inf: no number, no pair)
        # a window a little wide, then the kernel's own test: x_b - x_a <= gap, as it
        # subtracts
        ends = np.searchsorted(xs, xs + abs(gap) * (1.0 + 1e-9) + 1e-300, side="right")
    counts = np.maximum(ends, rows + 1) - rows - 1
    total = np.cumsum(counts)
    firsts, seconds = [], []
    begin = 0
    while begin < len(xs):
        # rows begin..stop-1 hold at most PAIR_BLOCK candidates (a row with more: alone)
        stop = max(int(np.searchsorted(total, total[begin] - counts[begin] + PAIR_BLOCK,
                                       side="right")), begin + 1)
        block = counts[begin:stop]
        a = np.repeat(rows[begin:stop], block)
        b = a + 1 + np.arange(len(a)) - np.repeat(np.cumsum(block) - block, block)
        with np.errstate(invalid="ignore", over="ignore"):
            dx = xs[b] - xs[a]
            dy = ordered[b, 1] - ordered[a, 1]
            near = (dx <= gap) & (dx * dx + dy * dy <= gap * gap)
        firsts.append(order[a[near]])
        seconds.append(order[b[near]])
        begin = stop
    return np.concatenate(firsts), np.concatenate(seconds)


def track_step(params: TrackParams, tracks: ObstacleTracks, points: FloatArray,
               stamp: float, compiled: bool = False, ignore: NDArray[np.bool_] | None = None,
               ) -> tuple[ObstacleTracks, FloatArray, NDArray[np.int8]]:
    """One scan: obstacle points (N, 2) in the map frame at ``stamp`` s. Returns the new
    tracks, each point's velocity (N, 2) in the map frame (0 for walls) and its kind (N,):
    :data:`STANDING` (a wall or obstacle face), :data:`TRACKED` (a small cluster seen at least
    ``min_hits`` times: its velocity is trusted) or :data:`NEW`. ``compiled``: the numba
    kernel ``tracks_jit.track_cloud`` (the same clusters and assignments, ties included,
    the filter's figures to rounding). ``ignore`` (N,): points left out of the tracking
    (formation mates where they should be, for the ``predicted`` rule), standing with no
    velocity."""
    if ignore is not None and ignore.any():
        kept = ~ignore
        tracks, some_velocity, some_kind = track_step(params, tracks, points[kept], stamp,
                                                      compiled)
        velocity = np.zeros((len(points), 2))
        kind = np.full(len(points), STANDING, dtype=np.int8)
        velocity[kept], kind[kept] = some_velocity, some_kind
        return tracks, velocity, kind
    if compiled:
        from dancebots.perception.tracks_jit import track_cloud  # imports numba

        states, covariances, hits, misses, velocity, kind = track_cloud(
            tracks.states, tracks.covariances, tracks.hits, tracks.misses,
            math.nan if tracks.stamp is None else tracks.stamp,
            np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2), stamp,
            params.cluster_gap, params.max_width, params.gate, params.min_hits,
            params.max_misses, params.acceleration_noise, params.measurement_noise)
        return ObstacleTracks(states, covariances, hits, misses, stamp), velocity, kind
    labels, count = cluster_points(points, params.cluster_gap)
    velocity = np.zeros((len(points), 2))
    kind = np.full(len(points), STANDING, dtype=np.int8)
    lows = np.full((count, 2), math.inf)
    highs = np.full((count, 2), -math.inf)
    np.minimum.at(lows, labels, points)
    np.maximum.at(highs, labels, points)
    small = np.hypot(*(highs - lows).T) <= params.max_width if count else np.zeros(0, bool)
    sums = np.zeros((count, 2))
    np.add.at(sums, labels, points)
    centres = (sums / np.maximum(np.bincount(labels, minlength=count), 1)[:, None])[small]
    step = math.nan if tracks.stamp is None else stamp - tracks.stamp
    dt = step if step > 0.0 else 0.0  # (a first scan, or a stamp that is not a number)
    states, covariances = kalman_predict(tracks.states, tracks.covariances, dt,
                                         params.acceleration_noise)
    hits, misses = tracks.hits, tracks.misses
    of_centre = np.full(len(centres), -1, dtype=np.int64)  # each centre's track
    if len(states) and len(centres):
        cost = np.hypot(states[:, None, 0] - centres[None, :, 0],
                        states[:, None, 1] - centres[None, :, 1])
        rows, cols = least_cost_assignment(cost)
        good = cost[rows, cols] <= params.gate
        rows, cols = rows[good], cols[good]
        if len(rows):
            states = states.copy()
            covariances = covariances.copy()
            states[rows], covariances[rows] = kalman_update(
                states[rows], covariances[rows], centres[cols], params.measurement_noise)
        of_centre[cols] = rows
    matched = np.zeros(len(states), dtype=bool)
    matched[of_centre[of_centre >= 0]] = True
    hits = np.where(matched, hits + 1, hits)
    misses = np.where(matched, 0, misses + 1)
    new = np.flatnonzero(of_centre < 0)
    of_centre[new] = len(states) + np.arange(len(new))
    states = np.concatenate([states, np.column_stack([centres[new], np.zeros((len(new), 2))])])
    covariances = np.concatenate([covariances, np.tile(np.diag(
        [params.measurement_noise ** 2] * 2 + [1.0, 1.0]), (len(new), 1, 1))])
    hits = np.concatenate([hits, np.ones(len(new), dtype=np.int64)])
    misses = np.concatenate([misses, np.zeros(len(new), dtype=np.int64)])
    # each point of a small cluster takes its track's velocity
    track_of_cluster = np.full(count, -1, dtype=np.int64)
    track_of_cluster[np.flatnonzero(small)] = of_centre
    point_track = track_of_cluster[labels]
    moving = point_track >= 0
    velocity[moving] = states[point_track[moving], 2:]
    kind[moving] = np.where(hits[point_track[moving]] >= params.min_hits, TRACKED, NEW)
    alive = misses <= params.max_misses
    # keep the indices of the tracks consistent: drop the dead ones after the lookup above
    return (ObstacleTracks(states[alive], covariances[alive], hits[alive], misses[alive], stamp),
            velocity, kind)


def point_motion(velocity: FloatArray, kind: NDArray[np.int8], walking_speed: float,
                 speed_margin: float) -> tuple[FloatArray, FloatArray]:
    """What SSM assumes of each point (``perception.ssm.ssm_speed_limit``): its velocity (N, 2)
    (the track's for a tracked object, else 0) and how fast the uncertainty about where it is
    grows (N,), m/s: ``speed_margin`` for a tracked object (it may change its mind),
    ``walking_speed`` for a new one (it may walk any way), 0 for what stands (walls)."""
    tracked = kind == TRACKED
    moving: FloatArray = np.where(tracked[:, None], velocity, 0.0)
    spread: FloatArray = np.select([tracked, kind == NEW], [speed_margin, walking_speed], 0.0)
    return moving, spread

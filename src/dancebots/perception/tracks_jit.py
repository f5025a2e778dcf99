"""The obstacle tracker (``perception.tracks.track_step``) as numba kernels.

:func:`cluster_labels` gives the labels of SciPy's ``cKDTree.query_pairs`` and
``connected_components`` (points within the gap join, transitively; components numbered in
the order of their first point) by a sweep along x and a union-find; :func:`assign` is
``perception.assignment.least_cost_assignment`` compiled (Crouse's shortest augmenting path
as SciPy's ``linear_sum_assignment`` runs it, the same assignment where two are equally
cheap; the NumPy reference runs the same function uncompiled); :func:`track_cloud` is
``track_step`` on them with the constant-velocity Kalman filter of ``perception.kalman``
written out for its 4 x 4 matrices. The tracker ran at 0.55
ms a cloud in NumPy and SciPy (a third of a robot's tick with the ``predicted`` stop rule);
here it costs microseconds. The labels and the assignment are SciPy's exactly, the filter's
figures agree to rounding (``tests/perception/test_tracks.py``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import NDArray

from dancebots.perception.assignment import least_cost_assignment

__all__ = ["assign", "cluster_labels", "track_cloud"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
STANDING, TRACKED, NEW = 0, 1, 2
"""``perception.tracks``'s kinds of point (a test holds them equal)."""


@njit(cache=True)
def _root(parent: IntArray, node: int) -> int:
    """The root of ``node``'s set, halving the path on the way."""
    while parent[node] != node:
        parent[node] = parent[parent[node]]
        node = parent[node]
    return node


@njit(cache=True)
def cluster_labels(points: FloatArray, gap: float) -> tuple[IntArray, int]:
    """Cluster labels (N,) of points (N, 2): two points at most ``gap`` m apart join,
    transitively; clusters are numbered in the order of their first point. Returns the
    labels and the number of clusters."""
    count = points.shape[0]
    parent = np.arange(count)
    order = np.argsort(points[:, 0], kind="mergesort")
    limit = gap * gap
    for a in range(count):
        i = order[a]
        for b in range(a + 1, count):
            j = order[b]
            dx = points[j, 0] - points[i, 0]
            if dx > gap:
                break
            dy = points[j, 1] - points[i, 1]
            if dx * dx + dy * dy <= limit:
                first, second = _root(parent, i), _root(parent, j)
                if first != second:
                    parent[max(first, second)] = min(first, second)
    labels = np.full(count, -1, dtype=np.int64)
    clusters = 0
    for i in range(count):
        root = _root(parent, i)
        if labels[root] < 0:
            labels[root] = clusters
            clusters += 1
        labels[i] = labels[root]
    return labels, clusters


assign = njit(cache=True)(least_cost_assignment)
"""``perception.assignment.least_cost_assignment`` compiled: SciPy's
``linear_sum_assignment`` (the same search), empty where no finite assignment exists."""


@njit(cache=True)
def _predict(states: FloatArray, covariances: FloatArray, dt: float, q: float) -> None:
    """``kalman.kalman_predict`` in place: x' = F x, P' = F P F^T + Q."""
    n3, n2 = dt ** 3 / 3.0 * q, dt ** 2 / 2.0 * q
    for k in range(states.shape[0]):
        states[k, 0] += dt * states[k, 2]
        states[k, 1] += dt * states[k, 3]
        p = covariances[k]
        # F P: rows 0, 1 gain dt times rows 2, 3; then (F P) F^T: columns likewise
        for c in range(4):
            p[0, c] += dt * p[2, c]
            p[1, c] += dt * p[3, c]
        for r in range(4):
            p[r, 0] += dt * p[r, 2]
            p[r, 1] += dt * p[r, 3]
        p[0, 0] += n3
        p[1, 1] += n3
        p[0, 2] += n2
        p[2, 0] += n2
        p[1, 3] += n2
        p[3, 1] += n2
        p[2, 2] += dt * q
        p[3, 3] += dt * q


@njit(cache=True)
def _update(state: FloatArray, p: FloatArray, zx: float, zy: float, sigma: float) -> None:
    """``kalman.kalman_update`` of one track in place: S = H P H^T + R, K = P H^T S^-1,
    x += K (z - H x), P = (I - K H) P."""
    s00, s01 = p[0, 0] + sigma * sigma, p[0, 1]
    s10, s11 = p[1, 0], p[1, 1] + sigma * sigma
    det = s00 * s11 - s01 * s10
    i00, i01, i10, i11 = s11 / det, -s01 / det, -s10 / det, s00 / det
    gain = np.empty((4, 2))
    for r in range(4):
        gain[r, 0] = p[r, 0] * i00 + p[r, 1] * i10
        gain[r, 1] = p[r, 0] * i01 + p[r, 1] * i11
    rx, ry = zx - state[0], zy - state[1]
    for r in range(4):
        state[r] += gain[r, 0] * rx + gain[r, 1] * ry
    top = p[:2].copy()
    for r in range(4):
        for c in range(4):
            p[r, c] -= gain[r, 0] * top[0, c] + gain[r, 1] * top[1, c]


@njit(cache=True)
def track_cloud(states: FloatArray, covariances: FloatArray, hits: IntArray,
                misses: IntArray, last_stamp: float, points: FloatArray, stamp: float,
                cluster_gap: float, max_width: float, gate: float, min_hits: int,
                max_misses: int, acceleration_noise: float, measurement_noise: float,
                ) -> tuple[FloatArray, FloatArray, IntArray, IntArray, FloatArray,
                           NDArray[np.int8]]:
    """``tracks.track_step`` of tracks (K, 4) states, (K, 4, 4) covariances, (K,) hits and
    misses, last scanned at ``last_stamp`` s (NaN: never), and obstacle points (N, 2) of the
    map frame taken at ``stamp`` s, with ``TrackParams``' figures. Returns the new tracks'
    four arrays, each point's velocity (N, 2) and kind (N,)."""
    count_points = points.shape[0]
    labels, count = cluster_labels(points, cluster_gap)
    velocity = np.zeros((count_points, 2))
    kind = np.full(count_points, STANDING, dtype=np.int8)
    lows = np.full((count, 2), math.inf)
    highs = np.full((count, 2), -math.inf)
    sums = np.zeros((count, 2))
    sizes = np.zeros(count, dtype=np.int64)
    for i in range(count_points):
        c = labels[i]
        for d in range(2):
            lows[c, d] = min(lows[c, d], points[i, d])
            highs[c, d] = max(highs[c, d], points[i, d])
            sums[c, d] += points[i, d]
        sizes[c] += 1
    small = np.zeros(count, dtype=np.bool_)
    centres = np.empty((count, 2))
    found = 0
    for c in range(count):
        small[c] = math.hypot(highs[c, 0] - lows[c, 0], highs[c, 1] - lows[c, 1]) <= max_width
        if small[c]:
            centres[found, 0] = sums[c, 0] / max(sizes[c], 1)
            centres[found, 1] = sums[c, 1] / max(sizes[c], 1)
            found += 1
    centres = centres[:found]
    dt = stamp - last_stamp  # (a first scan, or a stamp that is not a number: no step)
    dt = dt if dt > 0.0 else 0.0
    states = states.copy()
    covariances = covariances.copy()
    _predict(states, covariances, dt, acceleration_noise)
    tracks = states.shape[0]
    of_centre = np.full(found, -1, dtype=np.int64)
    if tracks and found:
        cost = np.empty((tracks, found))
        for k in range(tracks):
            for c in range(found):
                cost[k, c] = math.hypot(states[k, 0] - centres[c, 0],
                                        states[k, 1] - centres[c, 1])
        rows, cols = assign(cost)
        for n in range(rows.shape[0]):
            k, c = rows[n], cols[n]
            if cost[k, c] <= gate:
                _update(states[k], covariances[k], centres[c, 0], centres[c, 1],
                        measurement_noise)
                of_centre[c] = k
    matched = np.zeros(tracks, dtype=np.bool_)
    for c in range(found):
        if of_centre[c] >= 0:
            matched[of_centre[c]] = True
    new = 0
    for c in range(found):
        if of_centre[c] < 0:
            new += 1
    total = tracks + new
    all_states = np.zeros((total, 4))
    all_covariances = np.zeros((total, 4, 4))
    all_hits = np.empty(total, dtype=np.int64)
    all_misses = np.empty(total, dtype=np.int64)
    for k in range(tracks):
        all_states[k] = states[k]
        all_covariances[k] = covariances[k]
        all_hits[k] = hits[k] + 1 if matched[k] else hits[k]
        all_misses[k] = 0 if matched[k] else misses[k] + 1
    k = tracks
    for c in range(found):
        if of_centre[c] < 0:
            of_centre[c] = k
            all_states[k, 0], all_states[k, 1] = centres[c, 0], centres[c, 1]
            all_covariances[k, 0, 0] = measurement_noise ** 2
            all_covariances[k, 1, 1] = measurement_noise ** 2
            all_covariances[k, 2, 2] = 1.0
            all_covariances[k, 3, 3] = 1.0
            all_hits[k], all_misses[k] = 1, 0
            k += 1
    track_of_cluster = np.full(count, -1, dtype=np.int64)
    c = 0
    for cluster in range(count):
        if small[cluster]:
            track_of_cluster[cluster] = of_centre[c]
            c += 1
    for i in range(count_points):
        t = track_of_cluster[labels[i]]
        if t >= 0:
            velocity[i, 0], velocity[i, 1] = all_states[t, 2], all_states[t, 3]
            kind[i] = TRACKED if all_hits[t] >= min_hits else NEW
    alive = all_misses <= max_misses
    return (all_states[alive], all_covariances[alive], all_hits[alive], all_misses[alive],
            velocity, kind)

"""Cost of the second seed's parts: detectors A1 and A2 per scan (256 and 1024 beams) and the
controllers per tick.

Run: ``.venv/bin/python benchmarks/bench_follow.py [--repeat N]``. Scans are synthetic: a
person's legs and a robot ahead, a wall, and a person beside (what a follower sees in the
queue). Medians over ``repeat`` runs of 50 calls; the machine is shared: compare ratios.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from dancebots.leader_follower.controllers import (
    PidParams,
    PidState,
    VoParams,
    VoState,
    pid_step,
    vo_step,
)
from dancebots.leader_follower.detectors import (
    ClusterParams,
    ClusterState,
    TrackingParams,
    TrackingState,
    cluster_step,
    tracking_step,
)
from dancebots.leader_follower.scan import Scan
from dancebots.sim.raycast import ray_directions, rays_to_discs, rays_to_segments

CALLS = 50


def scene_scan(beams: int, stamp: float) -> Scan:
    angles = -np.pi + np.arange(beams) * (2 * np.pi / beams)
    directions = ray_directions(np.array([0.0]), angles)
    origin = np.zeros((1, 2))
    discs = np.array([[1.0 + 0.03 * stamp, -0.1, 0.06], [1.0 + 0.03 * stamp, 0.1, 0.06],
                      [0.3, 1.2, 0.2]])
    walls = np.array([[[3.0, -3.0], [3.0, 3.0]], [[-3.0, 2.0], [3.0, 2.0]],
                      [[1.8, -0.5], [1.8, -0.3]]])
    ranges = np.minimum(rays_to_discs(origin, directions, discs)[0][0],
                        rays_to_segments(origin, directions, walls)[0][0])
    return Scan(stamp, np.where(ranges <= 3.5, ranges, np.inf), angles, (0.0, 0.0, 0.0))


def median_call(function, repeat: int) -> float:  # type: ignore[no-untyped-def]
    times = []
    for _ in range(repeat):
        started = time.perf_counter()
        for k in range(CALLS):
            function(k)
        times.append((time.perf_counter() - started) / CALLS)
    return statistics.median(times)


def detector_costs(beams: int, repeat: int) -> tuple[float, float]:
    """Median seconds per scan of A1 (fresh state) and A2 (tracks carried over)."""
    scans = [scene_scan(beams, 0.2 * k) for k in range(CALLS)]
    cluster = ClusterParams()
    a1 = median_call(lambda k: cluster_step(cluster, ClusterState(), scans[k]), repeat)
    tracking = TrackingParams()
    state = [TrackingState()]

    def a2(k: int) -> None:
        state[0], _ = tracking_step(tracking, state[0], scans[k])

    return a1, median_call(a2, repeat)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    for beams in (256, 1024):
        a1, a2 = detector_costs(beams, args.repeat)
        print(f"{beams:>5} beams: A1 (DBSCAN) {a1 * 1e3:6.2f} ms per scan, "
              f"A2 (Kalman tracks) {a2 * 1e3:6.2f} ms per scan")
    _, detection = cluster_step(ClusterParams(), ClusterState(), scene_scan(360, 0.0))
    pid = median_call(lambda k: pid_step(PidParams(), PidState(), (0, 0, 0), detection),
                      args.repeat)
    vo = median_call(lambda k: vo_step(VoParams(), VoState(), (0, 0, 0), detection),
                     args.repeat)
    rvo = median_call(lambda k: vo_step(VoParams(reciprocal=True), VoState(), (0, 0, 0),
                                        detection), args.repeat)
    print(f"controllers: B1 (PID) {pid * 1e6:7.1f} us per tick, B2 (VO, "
          f"{len(detection.objects)} objects, {VoParams().speeds * VoParams().headings + 2} "
          f"candidates) {vo * 1e6:7.1f} us, RVO {rvo * 1e6:7.1f} us")


if __name__ == "__main__":
    main()

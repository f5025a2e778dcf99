"""Cost of one simulated LIDAR scan per robot, for 256 and 1024 rays.

Robots in rows of five (1.5 m apart, rows 2 m apart) in a room; every robot scans once per
call, as the simulator does at 10 Hz. Prints the median wall time per scan call and per
robot. Run: ``.venv/bin/python benchmarks/bench_lidar.py [--repeat N]``.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from dancebots.geometry import footprint_corners
from dancebots.sim.lidar import LidarConfig, LidarScene, scan_clouds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=20)
    args = parser.parse_args()
    for count in (4, 20, 100):
        rows = max(1, count // 5)
        xs, ys = np.meshgrid(np.arange(min(count, 5)) * 1.5, np.arange(rows) * 2.0)
        poses = np.stack([xs.ravel()[:count] + 2.0, ys.ravel()[:count] + 2.0,
                          np.zeros(count)], axis=1)
        corners = footprint_corners(poses[:, 0], poses[:, 1], poses[:, 2], np.full(count, 1.2),
                                    np.full(count, 0.6))
        room = np.array([[0.0, 0.0], [12.0, 0.0], [12.0, 2.0 * rows + 4.0],
                         [0.0, 2.0 * rows + 4.0]])
        scene = LidarScene.build(room, 2.0, [])
        for rays in (256, 1024):
            config = LidarConfig(rays=rays)
            times = []
            for _ in range(args.repeat):
                started = time.perf_counter()
                scan_clouds(config, 0.0, poses, corners, scene, np.zeros((0, 3)),
                            np.zeros(0))
                times.append(time.perf_counter() - started)
            median = statistics.median(times)
            print(f"{count:>4} robots, {rays:>4} rays: {median * 1e3:7.2f} ms per scan of all "
                  f"robots = {median / count * 1e6:7.1f} us per robot")


if __name__ == "__main__":
    main()

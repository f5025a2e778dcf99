"""How much the LIDAR lag compensation reduces near misses (thesis 7.2.2's crash).

Runs examples/crash_7_2_2.dance (the left robot turns into its neighbour's way) with the
``thesis`` detector (the latest cloud used as if current) and the ``compensated`` one, in both
profiles, for several latencies and noise seeds, and prints collisions and the smallest gap
between the robots. Run: ``.venv/bin/python benchmarks/bench_lag_compensation.py``.
"""

from __future__ import annotations

import argparse
import statistics
from pathlib import Path

from dancebots.plan.compile import compile_scenario
from dancebots.plan.placement import place_show
from dancebots.robot import BrainOptions
from dancebots.shows.formation import SimConfig, simulate
from dancebots.sim import PROFILES, prepare_show
from dancebots.sim.lidar import LidarConfig

SCENARIO = Path(__file__).resolve().parent.parent / "examples" / "crash_7_2_2.dance"


def main() -> None:
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    _, plan, diagnostics = compile_scenario(SCENARIO.read_text(), SCENARIO.name)
    assert plan is not None, diagnostics
    arena, placement = prepare_show(place_show(plan, None))
    print(f"{'detector':<12} {'profile':<10} {'latency':>7} {'runs':>4} {'collisions':>10} "
          f"{'median gap m':>12} {'min gap m':>9}")
    for detector in ("thesis", "compensated"):
        for profile in ("ideal", "realistic"):
            for latency in (0.1, 0.3, 0.5):
                seeds = range(5) if profile == "realistic" else range(1)
                gaps, collisions = [], 0
                for seed in seeds:
                    result = simulate(plan, arena, placement, SimConfig(
                        profile=PROFILES[profile], seed=seed, brain=BrainOptions(detector=detector),
                        lidar=LidarConfig(latency=latency)))
                    gaps.append(result.min_clearance or 0.0)
                    collisions += len(result.collisions)
                print(f"{detector:<12} {profile:<10} {latency:>7.1f} {len(gaps):>4} "
                      f"{collisions:>10} {statistics.median(gaps):>12.3f} {min(gaps):>9.3f}")


if __name__ == "__main__":
    main()

"""Simulation speed: simulated seconds per wall second for 4, 20 and 100 robots.

Run: ``.venv/bin/python benchmarks/bench_sim.py [--repeat N]``. Ideal profile, one core,
wall clock of ``simulate`` (brains, kinematics, collisions, and with LIDAR on: 10 Hz scans,
obstacle detection, force field, safety). Targets (issues 3 and 4): >= 300x real time for
four robots, >= 10x for 100, with LIDAR off and on. Machines are shared: compare medians.
"""

from __future__ import annotations

import argparse
import statistics
import time

from dancebots.plan.compile import compile_scenario
from dancebots.plan.placement import place_show
from dancebots.shows.formation import SimConfig, simulate
from dancebots.sim import prepare_show

TARGETS = {4: 300.0, 100: 10.0}


def grid_show(robots: int) -> str:
    """``robots`` robots in rows of up to five (a row of four for four robots) driving a
    gentle course of moves and wide circles, ending on a straight line long enough for the
    last row of 100 robots to leave the last circle (about four minutes)."""
    names = [f"R{i + 1}" for i in range(robots)]
    per_row = 4 if robots == 4 else 5
    rows = [names[i:i + per_row] for i in range(0, robots, per_row)]
    shape = "row" if len(rows) == 1 else "square"
    arrangement = ";".join(",".join(row) for row in rows)
    return "\n".join([
        "robots " + " ".join(names), f"{shape} {arrangement} 2 1.5",
        "move 6 0", "circle 12 30 0.02", "move 4 2", "circle -12 30 0.02", "move 6 -2",
        "circle 12 20 0.02", "move 45 0"]) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    for lidar in (False, True):
        for count in (4, 20, 100):
            _, plan, diagnostics = compile_scenario(grid_show(count), f"grid{count}.dance")
            assert plan is not None, diagnostics
            arena, placement = prepare_show(place_show(plan, None))
            config = SimConfig() if lidar else SimConfig(lidar=None)
            walls, sims = [], []
            for _ in range(args.repeat):
                started = time.perf_counter()
                result = simulate(plan, arena, placement, config)
                walls.append(time.perf_counter() - started)
                sims.append(float(result.times[-1]))
            wall = statistics.median(walls)
            speed = sims[0] / wall
            target = TARGETS.get(count)
            verdict = "" if target is None else (
                f"  target >= {target:g}x: {'meets' if speed >= target else 'MISSES'} it")
            print(f"LIDAR {'on ' if lidar else 'off'} {count:>4} robots: {sims[0]:6.1f} simulated "
                  f"s in {wall:6.3f} s wall (median of {args.repeat}) = {speed:7.1f}x real "
                  f"time, {len(result.collisions)} collisions{verdict}")


if __name__ == "__main__":
    main()

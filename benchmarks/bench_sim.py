"""Simulation speed: simulated seconds per wall second for 4, 20 and 100 robots.

Run: ``.venv/bin/python benchmarks/bench_sim.py [--repeat N] [--follower F]``. Ideal
profile, one core, wall clock of ``simulate`` (brains, kinematics, collisions, and with LIDAR
on: 10 Hz scans, obstacle detection, force field, safety), for the follower the commands use
by default (``path``; ``--follower thesis`` for eq. 4.4); for the ``path`` and ``tracking``
followers both ways of ticking the brains: all in one compiled pass (``batched``, the default,
``robot_batch``) and each ``RobotBrain`` in turn (``one by one``, the reference), with their
ratio. Targets (issues 3 and 4): >= 300x real time for four robots, >= 10x for 100, with LIDAR
off and on. Machines are shared: compare medians and ratios.
"""

from __future__ import annotations

import argparse
import statistics
import time
from dataclasses import replace

from dancebots.plan.compile import compile_scenario
from dancebots.plan.placement import place_show
from dancebots.robot import FOLLOWERS, BrainOptions
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
    parser.add_argument("--follower", choices=FOLLOWERS, default="path")
    args = parser.parse_args()
    ways = ((True, "batched"), (False, "one by one")) if args.follower != "thesis" else (
        (True, "one by one"),)
    print(f"follower {args.follower}; medians of {args.repeat} runs")
    for lidar in (False, True):
        for count in (4, 20, 100):
            _, plan, diagnostics = compile_scenario(grid_show(count), f"grid{count}.dance")
            assert plan is not None, diagnostics
            arena, placement = prepare_show(place_show(plan, None))
            config = SimConfig(brain=BrainOptions(follower=args.follower))
            config = config if lidar else replace(config, lidar=None)
            speeds = []
            for batched, name in ways:
                walls, sims = [], []
                for _ in range(args.repeat):
                    started = time.perf_counter()
                    result = simulate(plan, arena, placement, replace(config, batched=batched))
                    walls.append(time.perf_counter() - started)
                    sims.append(float(result.times[-1]))
                wall = statistics.median(walls)
                speeds.append(sims[0] / wall)
                target = TARGETS.get(count)
                verdict = "" if target is None else (
                    f"  target >= {target:g}x: "
                    f"{'meets' if speeds[-1] >= target else 'MISSES'} it")
                print(f"LIDAR {'on ' if lidar else 'off'} {count:>4} robots, {name:<10}: "
                      f"{sims[0]:6.1f} simulated s in {wall:6.3f} s wall = {speeds[-1]:7.1f}x "
                      f"real time, {len(result.collisions)} collisions{verdict}")
            if len(speeds) == 2:
                print(f"    batched / one by one: {speeds[0] / speeds[1]:.2f}x")


if __name__ == "__main__":
    main()

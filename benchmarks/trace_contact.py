"""Trace a robot and the person nearest to it, tick by tick, over a window of a crowd run: how a
contact (``metrics.json`` ``collision_events``) came about.

Run: ``.venv/bin/python benchmarks/trace_contact.py WORLD SEED ROBOT T0 T1 [--show DANCE]``
(the realistic profile, the ``path`` follower and the default stop rule and hold strategy, as
``dancebots certify`` runs each seed; WORLD a world file with crowds, e.g.
``examples/worlds/open_day_dense.toml``; T0, T1 the run's time in s). To trace the rules of
an older commit, run it with ``PYTHONPATH`` set to a worktree's ``src``.

Prints, per tick: the robot's command and actual speeds (m/s, rad/s), its status (0 moving,
1 stopped by the stop rule: ``shows.formation.STATUS``), its show time, and the person
nearest to its centre at the window's end: their centre in the robot's ``base_link`` (x
ahead, y left, m), their velocity there (m/s, from the last tick) and their disc's radius.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("world")
    parser.add_argument("seed", type=int)
    parser.add_argument("robot")
    parser.add_argument("t0", type=float)
    parser.add_argument("t1", type=float)
    parser.add_argument("--show", default=str(ROOT / "src/dancebots/data/open_day.dance"))
    args = parser.parse_args(argv)

    from dancebots.report.certify import CertifyJob, load_job
    from dancebots.robot import BrainOptions
    from dancebots.shows.formation import SimConfig, simulate
    from dancebots.sim.kinematics import PROFILES
    from dancebots.sim.lidar import LidarConfig
    from dancebots.sim.setup import prepare_show

    job = CertifyJob(scenario=args.show, world=args.world)
    show = load_job(job)
    if not show.valid or show.plan is None or show.report is None or (
            show.report.placement is None):
        print("; ".join(d.message for d in show.diagnostics), file=sys.stderr)
        return 2
    arena, placement = prepare_show(show.report.placement)
    if args.robot not in placement.robots:
        print(f"no robot {args.robot!r}; the show has {', '.join(placement.robots)}",
              file=sys.stderr)
        return 2
    config = SimConfig(profile=PROFILES[job.profile], seed=args.seed, lidar=LidarConfig(),
                       brain=BrainOptions(follower="path", stop_rule="predicted"),
                       scan_ahead=False)
    result = simulate(show.plan, arena, placement, config)
    for contact in result.collisions:
        print(f"contact t = {contact.time:.1f} s: {contact.robot} with {contact.other}, "
              f"robot moving: {contact.moving}, closing {contact.closing} m/s")
    if not len(result.spectators):
        print("no people in this world", file=sys.stderr)
        return 2
    i = placement.robots.index(args.robot)
    times = result.times
    window = np.flatnonzero((times >= args.t0) & (times <= args.t1))
    if not len(window):
        print(f"no tick in [{args.t0}, {args.t1}] s (the run lasted {times[-1]:.1f} s)",
              file=sys.stderr)
        return 2
    last = window[-1]
    gaps = np.hypot(*(result.spectators[:, last] - result.poses[i, last, :2]).T)
    person = int(np.argmin(gaps))
    print(f"{args.robot} and person {person} (radius {result.spectator_radii[person]:.2f} m)")
    print("     t   v_cmd  w_cmd      v      w stat  show   person_x person_y  vx_ahead vy_left")
    for k in window.tolist():
        x, y, heading = result.poses[i, k]
        c, s = np.cos(heading), np.sin(heading)
        dx, dy = result.spectators[person, k] - (x, y)
        step = result.spectators[person, k] - result.spectators[person, max(k - 1, 0)]
        dt = times[k] - times[max(k - 1, 0)] or 1.0
        vx, vy = step / dt
        show_time = result.show_time[i, k]
        print(f"{times[k]:6.1f} {result.commands[i, k, 0]:6.3f} {result.commands[i, k, 1]:6.3f} "
              f"{result.velocities[i, k, 0]:6.3f} {result.velocities[i, k, 1]:6.3f} "
              f"{result.status[i, k]:4d} {show_time:5.1f} {c * dx + s * dy:9.2f} "
              f"{-s * dx + c * dy:8.2f} {c * vx + s * vy:9.2f} {-s * vx + c * vy:7.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

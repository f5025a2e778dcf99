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

    from dancebots.geometry import Pose
    from dancebots.report.certify import CertifyJob, simulate_seed

    job = CertifyJob(scenario=args.show, world=args.world)
    try:
        result = simulate_seed(job, args.seed)
    except ValueError as error:  # (the show's diagnostics)
        print(error, file=sys.stderr)
        return 2
    if args.robot not in result.robots:
        print(f"no robot {args.robot!r}; the show has {', '.join(result.robots)}",
              file=sys.stderr)
        return 2
    for contact in result.collisions:
        print(f"contact t = {contact.time:.1f} s: {contact.robot} with {contact.other}, "
              f"robot moving: {contact.moving}, closing {contact.closing} m/s")
    if not len(result.spectators):
        print("no people in this world", file=sys.stderr)
        return 2
    i = list(result.robots).index(args.robot)
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
        x, y, heading = (float(q) for q in result.poses[i, k])
        ahead, left = Pose(x, y, heading).to_local(*result.spectators[person, k])
        step = result.spectators[person, k] - result.spectators[person, max(k - 1, 0)]
        dt = times[k] - times[max(k - 1, 0)] or 1.0
        v_ahead, v_left = Pose(0.0, 0.0, heading).to_local(*(step / dt))  # (a velocity)
        show_time = result.show_time[i, k]
        print(f"{times[k]:6.1f} {result.commands[i, k, 0]:6.3f} {result.commands[i, k, 1]:6.3f} "
              f"{result.velocities[i, k, 0]:6.3f} {result.velocities[i, k, 1]:6.3f} "
              f"{result.status[i, k]:4d} {show_time:5.1f} {ahead:9.2f} "
              f"{left:8.2f} {v_ahead:9.2f} {v_left:7.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

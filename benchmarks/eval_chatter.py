"""How calm the robots look among people (issue 13, docs/safety.md "No turn onto a standing
place"): per seed of a crowd, the run ``dancebots run --world W --profile realistic --seed N``
makes, and what a spectator would see of it.

Run: ``.venv/bin/python benchmarks/eval_chatter.py [--world W] [--seeds 0-9]`` (to measure an
older commit: ``PYTHONPATH=<worktree of it>/src`` in front).

Prints per seed and summed over the seeds: the commanded turn rates' sign changes
(``angular_sign_flips`` of ``metrics.json``, every robot's summed: the left-right-left a
spectator sees), spins (robot-ticks commanded 1 rad/s or more below 5 cm/s during the show:
turns on the spot), the time the shared show clock stood, how often it started again and how
often it ran 0.35 s or less before it stood again (``clock_restarts``, ``clock_brief_runs``:
the formation lurching on a few cm), the turning beyond what the robots track (the most of any
robot, deg: ``max_excess_turn_deg``, spins and wiggles), and the run's length (s), the
smallest robot-person gap (m) and the contacts. The runs are deterministic per seed; the
figures are counts, not times, so the machine's load does not change them.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from dancebots.report.certify import CertifyJob
    from dancebots.shows.formation import RunResult

ROOT = Path(__file__).resolve().parents[1]
SPIN_RATE = 1.0
"""rad/s: a commanded turn at least this fast ..."""
SPIN_SPEED = 0.05
"""... below this speed (m/s) is a spin."""


def seeds_of(text: str) -> list[int]:
    """``"0-9"`` or ``"3,5,8"`` as seeds."""
    if "-" in text:
        first, last = text.split("-", 1)
        return list(range(int(first), int(last) + 1))
    return [int(part) for part in text.split(",") if part]


def run(job: CertifyJob, seed: int) -> RunResult:
    """The run of ``job`` (a ``CertifyJob``) with ``seed``: as ``report.certify.run_seed``
    simulates it (the realistic profile's noise and every crowd's draw), the result kept."""
    from dancebots.report.certify import load_job
    from dancebots.robot import BrainOptions
    from dancebots.shows.formation import SimConfig, simulate
    from dancebots.sim.kinematics import PROFILES
    from dancebots.sim.lidar import LidarConfig
    from dancebots.sim.setup import prepare_show

    show = load_job(job)
    if not show.valid or show.report is None or show.report.placement is None:
        raise SystemExit("; ".join(d.message for d in show.diagnostics))
    assert show.plan is not None
    arena, placement = prepare_show(show.report.placement)
    config = SimConfig(profile=PROFILES[job.profile], seed=seed, lidar=LidarConfig(),
                       brain=BrainOptions(follower=job.follower,  # type: ignore[arg-type]
                                          stop_rule=job.stop_rule),  # type: ignore[arg-type]
                       hold=job.hold, scan_ahead=False)  # type: ignore[arg-type]
    return simulate(show.plan, arena, placement, config)


def main() -> None:
    from dancebots.report.certify import CertifyJob
    from dancebots.report.metrics import run_metrics

    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--world", default=str(ROOT / "src" / "dancebots" / "data"
                                               / "open_day_crowd.toml"))
    parser.add_argument("--seeds", default="0-9", help="first-last or a comma list (0-9)")
    args = parser.parse_args()
    job = CertifyJob(str(ROOT / "src" / "dancebots" / "data" / "open_day.dance"), args.world)
    totals = np.zeros(7)
    contacts = 0
    gap = np.inf
    print(f"{Path(args.world).name}, realistic profile: per seed")
    for seed in seeds_of(args.seeds):
        result = run(job, seed)
        metrics = run_metrics(result)
        during = result.during_show
        commands = result.commands[:, during]
        spins = int(np.sum((np.abs(commands[..., 1]) >= SPIN_RATE)
                           & (np.abs(commands[..., 0]) < SPIN_SPEED)))
        row = np.array([metrics.angular_sign_flips, spins, metrics.clock_stood,
                        metrics.run_duration, metrics.clock_restarts,
                        metrics.clock_brief_runs, metrics.max_excess_turn])
        totals += row
        contacts += len(metrics.collision_events)
        if metrics.min_person_gap is not None:
            gap = min(gap, metrics.min_person_gap)
        print(f"  seed {seed:4d}: sign flips {row[0]:5.0f}, spins {row[1]:4.0f}, clock stood "
              f"{row[2]:6.1f} s (restarts {row[4]:3.0f}, brief {row[5]:3.0f}), turned beyond "
              f"{row[6]:4.0f} deg, run "
              f"{row[3]:6.1f} s, smallest person gap "
              f"{metrics.min_person_gap or float('nan'):.3f} m, contacts "
              f"{len(metrics.collision_events)}", flush=True)
    print(f"summed: sign flips {totals[0]:.0f}, spins {totals[1]:.0f}, clock stood "
          f"{totals[2]:.1f} s (restarts {totals[4]:.0f}, brief {totals[5]:.0f}), turned "
          f"beyond {totals[6]:.0f} deg, runs "
          f"{totals[3]:.1f} s, smallest person gap {gap:.3f} m, "
          f"contacts {contacts}")


if __name__ == "__main__":
    main()

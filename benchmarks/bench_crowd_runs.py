"""Time of one certification run among a crowd (issue 13's "1,000 runs in under 10 minutes").

Run: ``.venv/bin/python benchmarks/bench_crowd_runs.py [--world W] [--runs N]`` (default: the
bundled open-day show in its crowd, ``data/open_day_crowd.toml``, seeds 1-6). Runs
``report.certify.run_seed`` in this process, as each of ``dancebots certify``'s workers does
(realistic profile, the defaults), after one warm-up run (seed 0: loading, numba's start),
and prints each run's wall time, their median, and the projected wall time of 1,000 runs on
2 processes (median x 1,000 / 2, without the workers' start). To compare two versions, run
it from each checkout in turn, alternating (``PYTHONPATH=CHECKOUT/src``): the machine is
shared, so compare medians of alternated runs, not single times.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--world", default=str(ROOT / "src/dancebots/data/open_day_crowd.toml"),
                        help="world file with crowds (default: the open-day crowd)")
    parser.add_argument("--show", default=str(ROOT / "src/dancebots/data/open_day.dance"),
                        help="choreography (default: the bundled open-day show)")
    parser.add_argument("--runs", type=int, default=6, help="timed runs (seeds 1..N)")
    args = parser.parse_args()
    if args.runs < 1:
        parser.error("--runs must be 1 or more")
    from dancebots.report.certify import CertifyJob, run_seed

    job = CertifyJob(args.show, args.world)
    started = time.perf_counter()
    run_seed(job, 0)
    print(f"warm-up (seed 0: load, plan, numba): {time.perf_counter() - started:.2f} s")
    walls = []
    for seed in range(1, args.runs + 1):
        started = time.perf_counter()
        summary = run_seed(job, seed)
        walls.append(time.perf_counter() - started)
        print(f"seed {seed}: {walls[-1]:.3f} s, contacts of a moving robot "
              f"{summary.contacts_moving}, finished {summary.finished}")
    median = statistics.median(walls)
    print(f"median {median:.3f} s a run (min {min(walls):.3f}, max {max(walls):.3f}); "
          f"1,000 runs on 2 processes: about {median * 1000 / 2:.0f} s (target 600 s)")


if __name__ == "__main__":
    main()

"""Start-up time of the ``dancebots`` command (targets on a 2-core machine: at most 0.3 s for
``--help`` and for ``check --rigid-only`` of a thesis listing; at most 1 s for ``check`` with
its simulation pass, every thesis listing, issue 12).

Run: ``.venv/bin/python benchmarks/bench_startup.py [--repeat N]``. Each command runs N times
(default 10) as a fresh process, after one warm-up run that fills the OS file cache; prints
the median and the spread of the wall time, and the ratio to ``python -c pass`` (the
interpreter's own start), so that a shared, noisy machine can still be compared.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = Path(sys.executable).parent / "dancebots"
TARGET = 0.3
"""s: the wall-time target of --help and the rigid check."""
SIMULATED_TARGET = 1.0
"""s: the wall-time target of check with its simulation pass."""
LISTINGS = ("6_1", "6_2", "6_3", "7_1", "7_2", "7_3", "7_4")
"""The thesis listings (``examples/thesis_*.dance``) whose check is timed."""


def wall_times(command: list[str], repeat: int) -> list[float]:
    """Wall times (s) of ``repeat`` runs of ``command`` (after one untimed warm-up run)."""
    subprocess.run(command, cwd=ROOT, capture_output=True, check=False)
    times = []
    for _ in range(repeat):
        started = time.perf_counter()
        subprocess.run(command, cwd=ROOT, capture_output=True, check=False)
        times.append(time.perf_counter() - started)
    return times


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=10, help="runs of each command (10)")
    args = parser.parse_args()
    dancebots = [str(SCRIPT)] if SCRIPT.exists() else [sys.executable, "-m", "dancebots.cli"]
    commands = {
        "python -c pass": [sys.executable, "-c", "pass"],
        "dancebots --help": [*dancebots, "--help"],
        "dancebots check --rigid-only 7_1": [*dancebots, "check", "--rigid-only",
                                             "examples/thesis_7_1.dance"],
        "dancebots check --rigid-only 6_3": [*dancebots, "check", "--rigid-only",
                                             "examples/thesis_6_3.dance"],
        **{f"dancebots check thesis_{listing}": [*dancebots, "check",
                                                  f"examples/thesis_{listing}.dance"]
           for listing in LISTINGS},
        "dancebots check thesis_7_1 eq4.4": [*dancebots, "check", "--follower", "thesis",
                                             "--timing", "thesis",
                                             "examples/thesis_7_1.dance"],
        "dancebots check thesis_6_3 eq4.4": [*dancebots, "check", "--follower", "thesis",
                                             "--timing", "thesis",
                                             "examples/thesis_6_3.dance"],
        "dancebots demo": [*dancebots, "demo"],
    }
    baseline = None
    over = []
    print(f"{'command':<30} {'median s':>9} {'min s':>7} {'max s':>7} {'x python':>9}")
    for name, command in commands.items():
        times = wall_times(command, args.repeat)
        median = statistics.median(times)
        baseline = baseline or median
        print(f"{name:<30} {median:>9.3f} {min(times):>7.3f} {max(times):>7.3f} "
              f"{median / baseline:>9.1f}")
        simulated = name.startswith("dancebots check thesis")
        if name.startswith("dancebots") and median > (SIMULATED_TARGET if simulated
                                                      else TARGET):
            over.append(name)
    print(f"target: at most {TARGET} s median ({SIMULATED_TARGET} s for check with its "
          "simulation); "
          + ("met" if not over else f"NOT met by {', '.join(over)}"))
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())

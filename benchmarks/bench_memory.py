"""Memory of a simulated show per robot-second (the figure behind check's size limit,
``plan.placement.MAX_SIMULATED_ROBOT_SECONDS``).

Run: ``.venv/bin/python benchmarks/bench_memory.py``. Simulates the same 20-robot formation
(LIDAR on, no animation) for a short and a three times longer show, each in a fresh
``dancebots run`` process, reads each process's peak resident memory (``os.wait4``), and
prints the growth per robot-second of simulated time and the base it grows from.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

DANCEBOTS = Path(sys.executable).parent / "dancebots"


def show(laps: int, robots: int = 20) -> str:
    """A square formation of ``robots`` driving 40 m out and back ``laps`` times."""
    names = [f"R{i}" for i in range(robots)]
    rows = ";".join(",".join(names[k:k + 5]) for k in range(0, robots, 5))
    return (f"robots {' '.join(names)}\nsquare {rows} 2 1.6\n"
            + "move 40 0\nmove 40 180\n" * laps)


def peak(scenario: Path, out: Path) -> tuple[float, float]:
    """(peak resident memory in kB, simulated s) of one run."""
    process = subprocess.Popen([str(DANCEBOTS), "run", str(scenario), "--no-animation",
                                "--json", "--out", str(out)], stdout=subprocess.PIPE,
                               stderr=subprocess.DEVNULL, text=True)
    stdout = process.stdout.read() if process.stdout else ""
    _, status, usage = os.wait4(process.pid, 0)
    if os.waitstatus_to_exitcode(status) not in (0, 1):
        raise SystemExit(f"dancebots run {scenario} failed")
    return float(usage.ru_maxrss), float(json.loads(stdout)["metrics"]["run_duration_s"])


def main() -> None:
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    with tempfile.TemporaryDirectory() as folder:
        results = []
        for laps in (2, 6):
            scenario = Path(folder) / f"laps{laps}.dance"
            scenario.write_text(show(laps))
            results.append(peak(scenario, Path(folder) / f"out{laps}"))
    (small, short), (large, long) = results
    per = (large - small) / (20 * (long - short))
    print(f"20 robots: {short:.0f} s simulated -> {small / 1024:.0f} MB peak, {long:.0f} s -> "
          f"{large / 1024:.0f} MB")
    base = small - per * 20 * short
    print(f"growth: {per:.1f} kB per robot-second; base {base / 1024:.0f} MB; 200,000 "
          f"robot-seconds -> about {(base + per * 200_000) / 1024**2:.1f} GB")


if __name__ == "__main__":
    main()

"""Where ``check``'s simulation pass spends a 20-robot, 1,000-line show (issue 12's 5 s target).

Run: ``.venv/bin/python benchmarks/bench_check_ticks.py [--show FILE] [--stop-rule R]``
(default: ``bench_compile.big_scenario()``, the 1,000-instruction, 20-robot show, written to a
temporary directory). Runs ``dancebots check SHOW --simulation-limit 50000`` in this process
with timers around its stages (loading and planning the show with the rigid check, building
the brains, the run's loop, collecting the result) and inside the loop around the brains'
kernel (``robot_batch_jit.brains_tick``, main thread) and the LIDAR's scans
(``sim.stage.scan_clouds``, cast on the second thread for 8 robots or more), and prints each,
the kernel's and the rays' time per tick (mean and median of the calls) and the loop's
Python around the kernel per tick. The compiled work, kernel plus rays, bounds what 2 cores
can do at this fidelity: at best half of it. The rays' time is their wall time on the second
thread, which the kernel's thread slows where the two cores share a physical one. One run:
the machine is shared, so compare ratios and repeat before quoting a figure.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_compile import big_scenario

STAGES = ("load and plan the show, rigid check", "build the brains", "run the ticks",
          "collect the result")
"""The stages of ``check``'s run that the benchmark times (wall, main thread)."""


def timed(calls: list[float], function: Callable[..., Any]) -> Callable[..., Any]:
    """``function`` that appends each call's wall time (s) to ``calls`` (lock-free: one
    list per thread's function)."""

    def wrapper(*args: Any, **kwargs: Any) -> Any:
        start = time.perf_counter()
        try:
            return function(*args, **kwargs)
        finally:
            calls.append(time.perf_counter() - start)

    return wrapper


def per_tick(calls: list[float], ticks: int) -> str:
    if not calls:
        return "none"
    return (f"{sum(calls):6.2f} s in {len(calls):,} calls: {sum(calls) / ticks * 1e6:6.0f} us a "
            f"tick (median call {statistics.median(calls) * 1e6:.0f} us)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--show", type=Path, help="choreography (default: the 1,000-line show)")
    parser.add_argument("--stop-rule", default=None, help="check's --stop-rule (default: its)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        show = args.show
        if show is None:
            show = Path(folder) / "big.dance"
            show.write_text(big_scenario())
        from dancebots import loading, robot_batch_jit
        from dancebots.shows import formation
        from dancebots.sim import stage

        kernel: list[float] = []
        rays: list[float] = []
        stages: dict[str, list[float]] = {name: [] for name in STAGES}
        robot_batch_jit.brains_tick = timed(kernel, robot_batch_jit.brains_tick)
        stage.scan_clouds = timed(rays, stage.scan_clouds)  # type: ignore[assignment]
        loading.load_show = timed(stages["load and plan the show, rigid check"],
                                  loading.load_show)  # type: ignore[assignment]
        formation.brain_for = timed(stages["build the brains"], formation.brain_for)
        formation.run_show = timed(stages["run the ticks"], formation.run_show)
        formation._result = timed(stages["collect the result"], formation._result)
        command = ["dancebots", "check", str(show), "--simulation-limit", "50000"]
        if args.stop_rule:
            command += ["--stop-rule", args.stop_rule]
        cli = importlib.import_module("dancebots.cli.main")
        sys.argv = command
        start = time.perf_counter()
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            try:
                cli.main()
            except SystemExit as stop:
                status = stop.code
            else:
                status = 0
        wall = time.perf_counter() - start
    ticks = len(kernel)
    if not ticks:
        print(f"check exited {status} without running the batched brains: nothing to time")
        raise SystemExit(1)
    compiled = sum(kernel) + sum(rays)
    print(f"check {show.name}: exit {status}, {wall:.2f} s wall in this process, "
          f"{ticks:,} ticks")
    for name, calls in stages.items():
        print(f"  {name}: {sum(calls):.2f} s")
    print(f"  in the ticks, the brains' kernel: {per_tick(kernel, ticks)}")
    print(f"  in the ticks, the LIDAR's rays:   {per_tick(rays, ticks)}")
    loop = sum(stages["run the ticks"])
    print(f"  in the ticks, the rest on the main thread (Python around the kernel): "
          f"{(loop - sum(kernel)) / ticks * 1e6:.0f} us a tick")
    print(f"  compiled work {compiled:.2f} s: on 2 cores at least {compiled / 2:.2f} s "
          f"at this fidelity, before any Python (target 5 s)")


if __name__ == "__main__":
    main()

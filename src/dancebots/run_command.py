"""``dancebots run``: the shell that simulates a show and writes its outputs.

It only moves data: it compiles the files, prepares the arena, runs the simulator, computes
metrics and hands the result to the writers. Outputs are written into a staging directory
next to the target and renamed into place at the end, so an interrupted or failed run never
leaves a directory that looks complete.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn
from rich.table import Table

from dancebots.cli import EXIT_INVALID, EXIT_OK, bundled, compile_files, print_diagnostics
from dancebots.diagnostics import has_errors
from dancebots.report.metrics import RunMetrics, run_metrics
from dancebots.sim.kinematics import PROFILES
from dancebots.sim.lidar import LidarConfig
from dancebots.sim.setup import SetupError, prepare_show
from dancebots.sim.simulator import RunResult, SimConfig, simulate

__all__ = ["OUTPUT_FILES", "run_show"]

OUTPUT_FILES = ("metrics.json", "speeds_distances.png", "trajectories.png", "log.csv")
"""Written by every run; plus animation.gif (and animation.mp4 when ffmpeg is present)."""
MARKER = "metrics.json"


def _short(path: str) -> str:
    """The path relative to the working directory when that is shorter (for titles)."""
    relative = os.path.relpath(path)
    return relative if len(relative) < len(path) else path


def _fail(message: str) -> int:
    print(f"dancebots run: error: {message}", file=sys.stderr)
    return EXIT_INVALID


def _output_directory(args: argparse.Namespace) -> Path:
    if args.out:
        return Path(args.out)
    return Path("out") / Path(args.scenario).stem


def _check_output(target: Path) -> str | None:
    """None if ``target`` can receive a run's outputs, else why not."""
    if target.exists() and not target.is_dir():
        return f"{target} exists and is not a directory; choose another --out"
    if target.is_dir() and any(target.iterdir()) and not (target / MARKER).exists():
        return (f"{target} is not empty and holds no earlier run (no {MARKER}); choose an "
                "empty or new --out")
    parent = target.parent if str(target.parent) else Path(".")
    probe = parent
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir():
        return f"cannot create {target}: {probe} is not a directory; choose another --out"
    if not os.access(probe, os.W_OK):
        return f"cannot write to {probe}; choose a writable --out"
    return None


def write_staged(target: Path, write: Callable[[Path], list[str]]) -> list[str]:
    """Let ``write`` fill a staging directory beside ``target``, then rename it into place
    (replacing an earlier run), so a failed or interrupted run leaves no half directory."""
    target.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{target.name}.partial-", dir=target.parent))
    umask = os.umask(0)
    os.umask(umask)
    staging.chmod(0o777 & ~umask)  # mkdtemp makes it private; a run's outputs are not
    try:
        written = write(staging)
        if target.exists():
            shutil.rmtree(target)
        staging.rename(target)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    return written


@contextmanager
def _progress(console: Console, label: str) -> Iterator[Callable[[float, float], None]]:
    """A rich progress bar on a terminal; nothing when output is redirected."""
    if not console.is_terminal:
        yield lambda done, total: None
        return
    with Progress(TextColumn("{task.description}"), BarColumn(), TextColumn(
            "{task.completed:.0f}/{task.total:.0f}"), TimeRemainingColumn(),
            console=console, transient=True) as bar:
        task = bar.add_task(label, total=1.0)

        def update(done: float, total: float) -> None:
            bar.update(task, completed=done, total=total)

        yield update


def run_show(args: argparse.Namespace) -> int:
    if args.scenario is None:  # the bundled open-day show in its hall
        args.scenario = _short(bundled("open_day.dance"))
        if args.world is None:
            args.world = _short(bundled("open_day.toml"))
    sources: dict[str, list[str]] = {}
    plan, world, diagnostics = compile_files(args, sources)
    if has_errors(diagnostics) or plan is None:
        print_diagnostics(diagnostics, sources)
        return EXIT_INVALID
    target = _output_directory(args)
    problem = _check_output(target)
    if problem:
        return _fail(problem)
    try:
        arena, placement = prepare_show(plan, world)
    except SetupError as exc:
        return _fail(str(exc))
    if args.sound:
        from dancebots.report.sound import espeak_available

        if not espeak_available():
            return _fail("--sound needs espeak-ng (Debian package espeak-ng; scripts/dev.sh "
                         "installs it)")
    console = Console(stderr=True)
    if diagnostics:
        console.print(f"{args.scenario}: {len(diagnostics)} check warnings (see `dancebots "
                      f"check {args.scenario}`)", style="yellow", highlight=False)
    if not 0.0 <= args.latency <= 2.0:
        return _fail(f"--latency {args.latency} is outside 0 to 2 s")
    lidar = None if args.no_lidar else LidarConfig(rays=args.rays, latency=args.latency)
    config = SimConfig(profile=PROFILES[args.profile], seed=args.seed, lidar=lidar,
                       detector=args.detector, force_steering=args.force_steering,
                       record_lidar=args.show_lidar and lidar is not None
                       and not args.no_animation)
    started = time.perf_counter()
    with _progress(console, "simulating  (show s)") as update:
        result = simulate(plan, arena, placement, config, update)
    wall = time.perf_counter() - started
    metrics = run_metrics(result)
    written = write_staged(target, lambda staging: _write_outputs(
        result, metrics, staging, console, not args.no_animation, args.sound))
    _summary(console, result, metrics, wall, target, written)
    return EXIT_OK


def _write_outputs(result: RunResult, metrics: RunMetrics, directory: Path, console: Console,
                   animation: bool, sound: bool = False) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from dancebots.report.animation import animate_run, ffmpeg_available
    from dancebots.report.run_plots import plot_speeds_and_distances, plot_trajectories
    from dancebots.report.runlog import write_log

    with open(directory / "log.csv", "w", encoding="utf-8") as handle:
        write_log(result, handle)
    for name, draw in (("speeds_distances.png", plot_speeds_and_distances),
                       ("trajectories.png", plot_trajectories)):
        figure = draw(result)
        figure.savefig(directory / name, dpi=110)
        plt.close(figure)
    written = ["log.csv", "speeds_distances.png", "trajectories.png"]
    if animation:
        kinds = ["gif"] + (["mp4"] if ffmpeg_available() else [])
        for kind in kinds:
            with _progress(console, f"animation.{kind} (frames)") as update:
                animate_run(result, str(directory / f"animation.{kind}"),
                            progress=lambda done, total: update(done, total))
            written.append(f"animation.{kind}")
    if sound:
        from dancebots.report.sound import render_events_wav

        render_events_wav(result.events, float(result.times[-1]), str(directory / "sound.wav"))
        written.append("sound.wav")
    # metrics.json last: its presence marks a complete output directory
    (directory / MARKER).write_text(json.dumps(metrics.to_json(), indent=2) + "\n",
                                    encoding="utf-8")
    return [*written, MARKER]


def _summary(console: Console, result: RunResult, metrics: RunMetrics, wall: float,
             target: Path, written: list[str]) -> None:
    out = Console()
    table = Table(title=f"{result.plan.scenario.path} ({metrics.profile} profile, seed "
                  f"{metrics.seed})", title_justify="left")
    for column in ("robot", "RMS error m", "max error m", "max |d_vl - d_req| m", "stops",
                   "stopped s", "state"):
        table.add_column(column, justify="right" if column != "robot" else "left")
    for robot in metrics.robots:
        table.add_row(robot.robot, f"{robot.rms_error:.3f}", f"{robot.max_error:.3f}",
                      f"{robot.max_leader_distance_deviation:.3f}", str(robot.stops),
                      f"{robot.stopped_time:.1f}", "ok" if robot.error is None else
                      f"error: {robot.error}")
    out.print(table)
    change = metrics.max_spacing_change
    clearance = metrics.min_clearance
    out.print(f"show {metrics.show_duration:.1f} s, simulated {metrics.run_duration:.1f} s in "
              f"{wall:.2f} s ({metrics.run_duration / max(wall, 1e-9):.0f}x real time)",
              highlight=False)
    out.print("max change of the distance between row neighbours: "
              + ("n/a" if change is None else f"{change:.3f} m")
              + "; smallest gap between robots: "
              + ("n/a" if clearance is None else f"{clearance:.3f} m"), highlight=False)
    style = "bold red" if metrics.collisions else "green"
    out.print(f"collisions: {metrics.collisions}", style=style, highlight=False)
    out.print(f"wrote {target}/: {', '.join(written)}", highlight=False)

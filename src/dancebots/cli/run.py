"""``dancebots run``: simulate a show and write its metrics, plots, animation and log.

A thin shell: it loads and checks the show (refusing what ``check`` calls an error), makes
sure the output directory can be written, simulates, computes the metrics and the verdict,
writes everything through the output writer of ``cli.common`` and exits 0 when the show ran
clean, 1 when it did not.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from dancebots.cli.common import (
    PROFILES,
    ShowOutcome,
    add_follower_argument,
    add_hold_argument,
    add_show_arguments,
    add_stop_rule_argument,
    add_timing_argument,
    bundled,
    in_range,
    positive,
    print_diagnostics,
    print_verdict,
    profile_missing,
    progress,
    refuse,
    run_show_into,
    say_compiling,
    short_path,
)

if TYPE_CHECKING:
    from rich.console import Console

    from dancebots.loading import LoadedShow
    from dancebots.report.metrics import RunMetrics
    from dancebots.report.verdict import Verdict
    from dancebots.shows.formation import RunResult
    from dancebots.sim.setup import Arena, Placement

NAME = "run"
HELP = "simulate a show and write metrics, plots, an animation and a log"
DESCRIPTION = ("Simulate a show in the 2D simulator (robots with LIDAR, stops and the force "
               "field) and write metrics.json, plots, an animation and a CSV log. Exit 0 when "
               "the show ran clean; 1 when it did not (a collision, a contact with a person, a "
               "robot in its error state, a robot far from its final slot or heading, a robot "
               "driving against its slot's direction, a robot that leaves its formation, a show "
               "that did not finish); 2 when the input is invalid.")

OUTPUT_NAMES = ("show.html", "log.csv", "run.mcap", "speeds_distances.png", "trajectories.png",
                "animation.gif", "animation.mp4", "sound.wav", "preview.mp4", "metrics.json")
"""Every file a run may write into its output directory (besides the manifest)."""
DETECTORS = ("compensated", "thesis")
FORCE_STEERINGS = ("blend", "thesis")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_show_arguments(parser, scenario_help="choreography file (default: the bundled "
                       "open-day show, thesis listing 6.3, in its hall with two HUSKY and two "
                       "TRADR robots)", world_help="world file (TOML, docs/worlds.md); "
                       "default: an open arena around the show")
    parser.add_argument("--out", metavar="DIR", help="output directory (default: out/NAME); "
                        "a new or empty directory, or one of an earlier run, whose files "
                        "dancebots replaces (other files there are never touched)")
    parser.add_argument("--profile", choices=PROFILES, default="ideal",
                        help="ideal: commands act at once (thesis 2D); realistic: inertia, lag "
                        "and noise; physics: the robots' bodies, wheels and slip in MuJoCo, "
                        "drivers that widen the track for the slip as real ones do; "
                        "physics-geometric: the same with the plain track (docs/physics.md; "
                        "both need `pip install 'dancebots[physics]'`) (default: ideal)")
    parser.add_argument("--seed", type=in_range(0, 2**32 - 1, integer=True), default=0,
                        metavar="N", help="seed of the noise of the realistic profile (default 0)")
    parser.add_argument("--no-animation", action="store_true", help="skip the GIF/MP4")
    parser.add_argument("--sound", action="store_true",
                        help="also write sound.wav: the robots' speech and beeps on the show's "
                        "time line (needs espeak-ng)")
    parser.add_argument("--music", metavar="FILE",
                        help="also write preview.mp4: the show in real time with this music "
                        "from its start (WAV, MP3, OGG, ... anything ffmpeg reads) and the "
                        "robots' speech and beeps mixed in (needs ffmpeg; the speech "
                        "espeak-ng); default: the music the show's `tempo` line names, if "
                        "any")
    parser.add_argument("--show-lidar", action="store_true",
                        help="draw each robot's latest LIDAR scan in the animation")
    parser.add_argument("--no-lidar", action="store_true",
                        help="robots without LIDAR: no obstacle detection, stops or force "
                        "field (they drive into people)")
    parser.add_argument("--rays", type=int, default=256, choices=(256, 1024),
                        help="LIDAR rays per scan (default 256 as in the thesis's simulator)")
    parser.add_argument("--latency", type=in_range(0.0, 2.0), default=0.3, metavar="S",
                        help="LIDAR latency, s, 0 to 2 (default 0.3, the thesis's robots)")
    parser.add_argument("--detector", choices=DETECTORS, default="compensated",
                        help="thesis: use the latest cloud as if current; compensated "
                        "(default): move its points by the robot's motion since the scan")
    parser.add_argument("--force-steering", choices=FORCE_STEERINGS, default="blend",
                        help="how the virtual force field steers (docs/safety.md)")
    add_follower_argument(parser)
    add_timing_argument(parser)
    add_hold_argument(parser)
    add_stop_rule_argument(parser)
    parser.add_argument("--final-tolerance", type=positive, default=None, metavar="M",
                        help="a robot ending further than this from its final slot fails the "
                        "show, m (default 0.5)")
    parser.add_argument("--json", action="store_true",
                        help="print the summary and the verdict as JSON on stdout")


def run(args: argparse.Namespace) -> int:
    from rich.console import Console

    from dancebots.check import CheckOptions
    from dancebots.loading import load_show
    from dancebots.plan.placement import places_followed

    if args.scenario is None:  # the bundled open-day show in its hall
        args.scenario = short_path(bundled("open_day.dance"))
        if args.world is None:
            args.world = short_path(bundled("open_day.toml"))
    show = load_show(args.scenario, args.world, args.vmax, check=CheckOptions(
        places=places_followed(args.follower)), timing=args.timing)
    if not show.valid or show.report is None or show.report.placement is None:
        return refuse(NAME, args.json, diagnostics=show.diagnostics, sources=show.sources)
    from dancebots.sim.setup import SetupError, prepare_show

    try:
        arena, placement = prepare_show(show.report.placement)  # placed once, by the check
    except SetupError as exc:
        return refuse(NAME, args.json, str(exc))
    show = replace(show, report=None)  # the placement's samples are not needed any more
    console = Console(stderr=True, soft_wrap=True)
    missing = profile_missing(args.profile)
    if missing is not None:
        return refuse(NAME, args.json, missing)
    if args.sound:
        from dancebots.report.sound import espeak_available

        if not espeak_available():
            return refuse(NAME, args.json, "--sound needs espeak-ng (Debian package espeak-ng; "
                        "scripts/dev.sh installs it)")
    tempo = show.plan.scenario.tempo if show.plan is not None else None
    if args.music is None and tempo is not None and tempo.music is not None:
        from dancebots.loading import music_path

        found = music_path(args.scenario, tempo.music)
        if found is not None:  # the show's own music (its tempo line) goes into the preview
            args.music = str(found)
    if args.music is not None:
        from dancebots.report.frames import ffmpeg_available
        from dancebots.report.preview import audio_streams

        if not ffmpeg_available():
            return refuse(NAME, args.json, "--music needs ffmpeg (Debian package ffmpeg; "
                          "scripts/dev.sh installs it)")
        if not Path(args.music).is_file():
            return refuse(NAME, args.json, f"--music {args.music}: no such file")
        if audio_streams(args.music) == 0:
            return refuse(NAME, args.json, f"--music {args.music}: ffmpeg finds no sound in "
                          "it; give a WAV, MP3, OGG or FLAC file")
    target = Path(args.out) if args.out else Path("out") / Path(args.scenario).stem
    return run_show_into(NAME, target, OUTPUT_NAMES, args.json, lambda staging: _simulate(
        args, show, (arena, placement), staging, console, target))


def _simulate(args: argparse.Namespace, show: LoadedShow, setup: tuple[Arena, Placement],
              staging: Path, console: Console, target: Path) -> ShowOutcome:
    from dancebots.report.metrics import run_metrics
    from dancebots.report.verdict import FINAL_SLOT_TOLERANCE, run_verdict
    from dancebots.robot import BrainOptions, default_stop_rule
    from dancebots.shows.formation import SimConfig, simulate
    from dancebots.sim.kernels import kernels_to_compile
    from dancebots.sim.kinematics import PROFILES as CORE_PROFILES
    from dancebots.sim.lidar import LidarConfig

    assert show.plan is not None
    plan, (arena, placement) = show.plan, setup
    if show.diagnostics:  # check's warnings, in full, before the long work
        print_diagnostics(show.diagnostics, show.sources)
    if args.no_lidar and arena.spectators:
        console.print(f"WARNING: --no-lidar with {len(arena.spectators)} spectator"
                      f"{'s' if len(arena.spectators) > 1 else ''} in the world: the robots "
                      "cannot see people and will drive into them", style="bold red",
                      highlight=False)
    compile_first = kernels_to_compile(crowds=bool(arena.crowds), stop_rule=default_stop_rule(
        args.follower, args.stop_rule))
    if compile_first:
        say_compiling(console, len(compile_first))
    lidar = None if args.no_lidar else LidarConfig(rays=args.rays, latency=args.latency)
    brain = BrainOptions(follower=args.follower, detector=args.detector,
                         force_steering=args.force_steering, stop_rule=args.stop_rule)
    config = SimConfig(profile=CORE_PROFILES[args.profile], seed=args.seed, lidar=lidar,
                       brain=brain, hold=args.hold, record_lidar=args.show_lidar
                       and lidar is not None and not args.no_animation)
    started = time.perf_counter()
    with progress(console, "simulating  (show s)") as update:
        result = simulate(plan, arena, placement, config, update)
    wall = time.perf_counter() - started
    metrics = run_metrics(result)
    verdict = run_verdict(metrics, args.final_tolerance or FINAL_SLOT_TOLERANCE)
    written = _write_outputs(result, metrics, verdict, staging, console,
                             not args.no_animation, args.sound,
                             show.sources.get(plan.scenario.path), args.music)
    return ShowOutcome(written, wall, verdict, metrics.to_json(), lambda: _summary(
        result, metrics, verdict, wall, target, written))


def _write_outputs(result: RunResult, metrics: RunMetrics, verdict: Verdict, directory: Path,
                   console: Console, animation: bool, sound: bool = False,
                   source_lines: list[str] | None = None,
                   music: str | None = None) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from dancebots.report.animation import animate_run
    from dancebots.report.frames import ffmpeg_available
    from dancebots.report.mcap_log import write_run_mcap
    from dancebots.report.replay import write_replay_html
    from dancebots.report.run_plots import plot_speeds_and_distances, plot_trajectories
    from dancebots.report.runlog import write_log

    with open(directory / "log.csv", "w", encoding="utf-8") as handle:
        write_log(result, handle)
    with progress(console, "run.mcap (ticks)") as update:
        write_run_mcap(result, str(directory / "run.mcap"), update)
    for name, draw in (("speeds_distances.png", plot_speeds_and_distances),
                       ("trajectories.png", plot_trajectories)):
        figure = draw(result)
        figure.savefig(directory / name, dpi=110)
        plt.close(figure)
    write_replay_html(result, str(directory / "show.html"), source_lines)
    written = ["show.html", "log.csv", "run.mcap", "speeds_distances.png", "trajectories.png"]
    if animation:
        names = ["animation.gif"] + (["animation.mp4"] if ffmpeg_available() else [])
        with progress(console, f"{' and '.join(names)} (frames)") as update:
            animate_run(result, [str(directory / name) for name in names],
                        progress=lambda done, total: update(done, total))
        written.extend(names)
    if sound:
        from dancebots.report.sound import render_events_wav

        render_events_wav(result.events, float(result.times[-1]), str(directory / "sound.wav"))
        written.append("sound.wav")
    if music is not None:
        from dancebots.report.preview import write_preview
        from dancebots.report.sound import espeak_available, render_events_wav

        events_wav = None
        if espeak_available():  # the robots' voices over the music
            events_wav = str(directory / ".preview-events.wav")
            render_events_wav(result.events, float(result.times[-1]), events_wav)
        else:
            console.print("preview.mp4: the music only (the robots' speech needs espeak-ng)",
                          style="yellow", highlight=False)
        try:
            with progress(console, "preview.mp4 (frames, real time)") as update:
                write_preview(result, music, str(directory / "preview.mp4"), events_wav,
                              lambda done, total: update(done, total))
        finally:
            if events_wav is not None:
                Path(events_wav).unlink(missing_ok=True)  # written here, removed here
        written.append("preview.mp4")
    (directory / "metrics.json").write_text(json.dumps(
        {**metrics.to_json(), "verdict": verdict.to_json()}, indent=2) + "\n", encoding="utf-8")
    return [*written, "metrics.json"]


def _summary(result: RunResult, metrics: RunMetrics, verdict: Verdict, wall: float,
             target: Path, written: list[str]) -> None:
    from rich.console import Console
    from rich.table import Table

    out = Console(soft_wrap=True, width=None if sys.stdout.isatty() else 120)
    table = Table(title=f"{result.plan.scenario.path} ({metrics.profile} profile, seed "
                  f"{metrics.seed})", title_justify="left")
    for column in ("robot", "RMS slot err m", "max slot err m", "final err m",
                   "max heading err °", "final heading err °", "reverse %",
                   "max |d_vl - d_req| m", "stops", "stopped s", "state"):
        table.add_column(column, justify="right" if column != "robot" else "left")
    for robot in metrics.robots:
        table.add_row(robot.robot, f"{robot.rms_error:.3f}", f"{robot.max_error:.3f}",
                      f"{robot.final_error:.3f}", f"{robot.max_heading_error:.0f}",
                      f"{robot.final_heading_error:.0f}", f"{100 * robot.reverse_fraction:.1f}",
                      f"{robot.max_leader_distance_deviation:.3f}",
                      str(robot.stops), f"{robot.stopped_time:.1f}",
                      "ok" if robot.error is None else f"error: {robot.error}")
    out.print(table)
    change = metrics.max_spacing_change
    clearance = metrics.min_clearance
    formation = metrics.max_formation_error
    if formation is not None:
        out.print(f"formation error (every two robots of a formation, distance against their "
                  f"slots'): RMS {metrics.rms_formation_error or 0.0:.3f} m, max "
                  f"{formation:.3f} m", highlight=False)
    out.print("angular speed sign flips (chatter): " + ", ".join(
        f"{robot.robot} {robot.angular_sign_flips}" for robot in metrics.robots),
        highlight=False)
    out.print("turned beyond what it tracks (spins, wiggles): " + ", ".join(
        f"{robot.robot} {robot.excess_turn:.0f}°" for robot in metrics.robots),
        highlight=False)
    out.print("driven against the slot's direction, longest way / all ways: " + ", ".join(
        f"{robot.robot} {robot.max_reverse_distance:.2f} / {robot.reverse_distance:.2f} m"
        for robot in metrics.robots), highlight=False)
    out.print(f"show {metrics.show_duration:.1f} s, simulated {metrics.run_duration:.1f} s in "
              f"{wall:.2f} s ({metrics.run_duration / max(wall, 1e-9):.0f}x real time)",
              highlight=False)
    out.print("max change of the distance between row neighbours: "
              + ("n/a" if change is None else f"{change:.3f} m")
              + "; smallest gap between robots: "
              + ("n/a" if clearance is None else f"{clearance:.3f} m")
              + ("" if metrics.min_person_gap is None else
                 f"; smallest gap to a person: {metrics.min_person_gap:.3f} m"), highlight=False)
    if metrics.held_place_error is not None:
        out.print(f"farthest a robot was from its place while a robot was held: "
                  f"{metrics.held_place_error:.2f} m", highlight=False)
    if metrics.clock_stood > 0.0:
        out.print(f"the shared show clock stood {metrics.clock_stood:.1f} s, "
                  f"{metrics.clock_stood_for_people:.1f} s of it with a person near a robot that "
                  f"held it; it started again {metrics.clock_restarts} times, "
                  f"{metrics.clock_brief_runs} of them for 0.35 s or less (the formation "
                  "lurching on)", highlight=False)
    style = "bold red" if metrics.collisions else "green"
    out.print(f"collisions: {metrics.collisions}", style=style, highlight=False)
    out.print(f"wrote {target}/: {', '.join(written)}", highlight=False)
    print_verdict(out, verdict, "show")

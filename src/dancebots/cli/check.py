"""``dancebots check``: compile a choreography (and place it in a world) and report."""

from __future__ import annotations

import argparse
import json
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from dancebots.cli.common import (
    EXIT_INVALID,
    EXIT_OK,
    EXIT_WARNINGS,
    add_follower_argument,
    add_hold_argument,
    add_show_arguments,
    add_stop_rule_argument,
    add_timing_argument,
    positive,
    print_diagnostics,
    say_compiling,
)

if TYPE_CHECKING:
    from dancebots.check import CheckReport
    from dancebots.diagnostics import Diagnostic
    from dancebots.plan.planner import Plan, TimelineEntry

NAME = "check"
HELP = "check a choreography and summarise its plan"
DESCRIPTION = ("Check a choreography like a compiler checks code: every problem with its "
               "file:line:col and a hint, and a summary of the plan. Two passes: the rigid "
               "desired poses (clearances, speeds, the room), then the show simulated in the "
               "ideal profile (contacts, robots driving against their slot's direction or far "
               "from it, robots that miss their final slot), each at the line of the "
               "instruction concerned. Exit 0 when valid, 2 when not, 1 with --strict when "
               "there are warnings.")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_show_arguments(parser)
    add_timing_argument(parser)
    add_hold_argument(parser)
    add_stop_rule_argument(parser)
    add_follower_argument(parser)
    parser.add_argument("--rigid-only", action="store_true",
                        help="skip the simulation pass: only the checks on the rigid desired "
                        "poses (fast)")
    parser.add_argument("--simulation-limit", type=positive, default=SIMULATION_LIMIT,
                        metavar="ROBOT_S",
                        help="simulate shows up to this many robot-seconds (robots times show "
                        f"duration; default {SIMULATION_LIMIT:,}); a larger show gets a "
                        "warning instead")
    parser.add_argument("--timeline", action="store_true",
                        help="also print when each instruction runs: its line, start and end "
                        "show time (s), with a tempo its beats, where the feasible timing "
                        "slowed the leader how much, where a cue set its pace that pace, and "
                        "each missed cue (in the JSON: \"timeline\")")
    parser.add_argument("--json", action="store_true", help="print the report as JSON")
    parser.add_argument("--strict", action="store_true", help="exit 1 when there are warnings")
    parser.add_argument("--clearance", type=positive, default=0.2, metavar="M",
                        help="smallest allowed gap between robot footprints, m (default 0.2)")


def run(args: argparse.Namespace) -> int:
    from dataclasses import asdict

    from dancebots.check import CheckOptions
    from dancebots.diagnostics import has_errors
    from dancebots.loading import load_show
    from dancebots.plan.placement import places_followed
    from dancebots.plan.planner import instruction_timeline

    show = load_show(args.scenario, args.world, args.vmax, check=CheckOptions(
        clearance=args.clearance, places=places_followed(args.follower)), timing=args.timing)
    diagnostics = show.diagnostics
    invalid = has_errors(diagnostics)
    report = show.report if not invalid else None
    if report is not None and not args.rigid_only:
        diagnostics = (*diagnostics, *_simulated(args, report))
    warnings = [d for d in diagnostics if d.severity.value == "warning"]  # notes do not count
    timeline = instruction_timeline(show.plan) if (
        args.timeline and show.plan is not None) else None
    if args.json:
        print(json.dumps({
            **({"timeline": [asdict(entry) for entry in timeline]
                if timeline is not None else None} if args.timeline else {}),
            "valid": not invalid,
            "diagnostics": [d.to_json() for d in sorted(
                diagnostics, key=lambda d: (d.path, d.line, d.col))],
            "report": report.to_json() if report is not None else None,
        }, indent=2))
    else:
        if report is not None:
            print(summary_text(report, show.plan))
        if timeline:
            print(timeline_text(timeline, show.sources.get(args.scenario, [])))
        print_diagnostics(diagnostics, show.sources)
        if not invalid:
            count = len(warnings)
            print(f"{args.scenario}: ok" + (
                f" ({count} warning{'s' if count > 1 else ''})" if count else ""))
    if invalid:
        return EXIT_INVALID
    return EXIT_WARNINGS if args.strict and warnings else EXIT_OK


def timeline_text(timeline: Sequence[TimelineEntry], lines: Sequence[str]) -> str:
    """The timeline as a table: line, start and end show time (s), with a tempo the beats
    then, the leader's slowest speed there as a share of the planned one where the feasible
    timing slowed it, the pace a cue set (where one did), and the instruction's text
    (``lines``: the scenario's lines; its kind without them), marked where its cue is missed
    and by how much."""
    beats = any(entry.start_beat is not None for entry in timeline)
    paced = any(entry.pace != 1.0 for entry in timeline)
    header = f"{'line':>5} {'start s':>8} {'end s':>8}"
    header += f" {'beat':>6} {'to beat':>7}" if beats else ""
    header += f" {'speed':>6}" + (f" {'pace':>5}" if paced else "") + "  instruction"
    rows = [header]
    for entry in timeline:
        text = (lines[entry.line - 1].strip() if 0 < entry.line <= len(lines)
                else entry.kind)
        if entry.cue_missed_by:
            text += f"   <- cue missed by {entry.cue_missed_by:.1f} s"
        speed = f"{100 * entry.speed_fraction:.0f} %" if entry.speed_fraction < 1.0 else ""
        row = f"{entry.line:>5} {entry.start:>8.1f} {entry.end:>8.1f}"
        if beats:
            row += (f" {entry.start_beat:>6.1f} {entry.end_beat:>7.1f}"
                    if entry.start_beat is not None and entry.end_beat is not None else
                    f" {'':>6} {'':>7}")
        row += f" {speed:>6}"
        if paced:
            row += f" {f'{entry.pace:.2f}' if entry.pace != 1.0 else '':>5}"
        rows.append(f"{row}  {text}")
    return "\n".join(rows)


def summary_text(report: CheckReport, plan: Plan | None) -> str:
    """The plan's summary: robots, groups, duration, gaps, placement, per-robot figures."""
    lines = [f"{report.path}: {len(report.robots)} robots ({' '.join(report.robots)})"]
    if report.groups:
        groups = ", ".join(f"{name}: {' '.join(members)}" for name, members in report.groups)
        lines.append(f"groups: {groups}")
    formations = len(plan.formations) if plan else 0
    gap = "n/a" if report.min_clearance is None else f"{report.min_clearance:.2f} m"
    lines.append(f"show duration {report.duration:.1f} s, {formations} formation"
                 f"{'' if formations == 1 else 's'}, "
                 f"smallest gap between footprints {gap}")
    if report.world_transform is not None:
        t = report.world_transform
        lines.append(f"show frame in the world: x {t.x:.2f} m, y {t.y:.2f} m, "
                     f"yaw {math.degrees(t.theta):.1f} deg")
    header = f"{'robot':<10} {'type':<6} {'path m':>8} {'max |v| m/s':>12} {'max |w| rad/s':>14}"
    lines.append(header)
    for s in report.summaries:
        lines.append(f"{s.name:<10} {s.robot_type.name:<6} {s.path_length:>8.2f} "
                     f"{s.max_speed:>12.2f} {s.max_angular_speed:>14.2f}")
    return "\n".join(lines)


SIMULATION_LIMIT = 10_000
"""Robots times show duration (s) up to which check simulates a show by default: 20 robots
for about 8 minutes, about 3 s of simulation here; a larger show gets a warning that it was
not simulated (``--simulation-limit`` raises it)."""
COMPILED_FROM = 100
"""Robot-seconds from which check simulates with the numba-compiled kernels; a shorter show
runs on their NumPy references (``SimConfig.compiled``), which simulate 3-4 times slower
but need no numba, whose import and start take about 0.45 s (listing 7.1, 66
robot-seconds: its whole check 0.59 s on the references)."""
SIMULATION_RATE = 3700
"""Robot-seconds check simulates per second of wall time, about, on the project's 2-core
machines (the 20-robot, 1,000-line show of ``benchmarks/bench_compile.py`` with the defaults
and LIDAR, 47,050 robot-seconds: 12.4-13.7 s in all): the hint's rough estimate."""


def _simulated(args: argparse.Namespace, report: CheckReport) -> list[Diagnostic]:
    """The second pass: the show run in the ideal profile with LIDAR, and what went wrong."""
    import sys

    from rich.console import Console

    from dancebots.diagnostics import Diagnostic, Severity

    assert report.placement is not None  # a valid show is placed
    plan = report.placement.plan
    size = len(plan.robots) * plan.duration
    limit = args.simulation_limit
    if size > limit:
        where = plan.scenario.robots_span
        return [Diagnostic(
            plan.scenario.path, where.line, where.col, Severity.WARNING,
            f"not simulated: {len(plan.robots)} robots for {plan.duration:.0f} s is "
            f"{size:,.0f} robot-seconds, more than check simulates ({limit:,.0f})",
            f"`--simulation-limit {math.ceil(size)}` simulates it too (about "
            f"{math.ceil(size / SIMULATION_RATE):,} s here), as `dancebots run` does; "
            "check's rigid pass above still applies")]

    from dancebots.cli.common import progress
    from dancebots.report.findings import simulated_findings
    from dancebots.robot import BrainOptions, default_stop_rule
    from dancebots.shows.formation import SimConfig, simulate
    from dancebots.sim.kernels import kernels_to_compile
    from dancebots.sim.setup import SetupError, prepare_show

    arena, placement = prepare_show(report.placement)
    console = Console(stderr=True, soft_wrap=True)
    # a crowd walks differently on the compiled forces (chaotic runs): as ``run`` has it
    compiled = size > COMPILED_FROM or bool(arena.crowds)
    compile_first = kernels_to_compile(
        crowds=bool(arena.crowds), stop_rule=default_stop_rule(
            args.follower, args.stop_rule)) if compiled else ()
    if compile_first:
        say_compiling(console, len(compile_first))
    config = SimConfig(brain=BrainOptions(follower=args.follower, stop_rule=args.stop_rule),
                       compiled=compiled,
                       hold=args.hold)
    try:
        with progress(console, "simulating  (show s)") as update:
            result = simulate(plan, arena, placement, config, update)
    except SetupError as exc:  # e.g. a crowd that does not fit
        where = plan.scenario.robots_span
        return [Diagnostic(plan.scenario.path, where.line, where.col, Severity.WARNING,
                           f"not simulated: {exc}", "`dancebots run` refuses it too")]
    sys.stderr.flush()
    return simulated_findings(result, f"ideal profile, {args.follower} follower")


"""The ``dancebots`` command: a thin shell that reads files, calls the core, prints results.

Exit status: 0 valid; 1 warnings with ``--strict``; 2 invalid input or unusable arguments.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections.abc import Sequence
from importlib import resources

from dancebots import __version__
from dancebots.check import CheckOptions, CheckReport, check_plan, compile_scenario
from dancebots.diagnostics import (
    Diagnostic,
    DiagnosticError,
    format_diagnostics,
    has_errors,
    read_source_file,
)
from dancebots.plan.planner import Plan, PlanParameters
from dancebots.sim.kinematics import PROFILES
from dancebots.world import World, load_world

__all__ = ["main"]

EXIT_OK, EXIT_WARNINGS, EXIT_INVALID = 0, 1, 2


def bundled(name: str) -> str:
    """Path of a file shipped inside the package (``dancebots/data``)."""
    return str(resources.files("dancebots") / "data" / name)


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError(f"{text!r} must be a finite number > 0")
    return value


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="dancebots",
        description="Choreograph formations of ground robots: check a choreography, plan it, "
        "preview it.",
    )
    parser.add_argument("--version", action="version", version=f"dancebots {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)

    def common(sub: argparse.ArgumentParser) -> None:
        sub.add_argument("scenario", metavar="FILE", help="choreography file (.dance)")
        sub.add_argument("--world", metavar="W", help="world file (TOML, docs/worlds.md)")
        sub.add_argument("--vmax", type=_positive, metavar="V",
                         help="max speed of the slowest robot, m/s (default: from the world's "
                         "robot types, else 0.5); the virtual leader moves at 0.7 V")

    check = commands.add_parser("check", help="check a choreography and summarise its plan")
    common(check)
    check.add_argument("--json", action="store_true", help="print the report as JSON")
    check.add_argument("--strict", action="store_true", help="exit 1 when there are warnings")
    check.add_argument("--clearance", type=_positive, default=0.2, metavar="M",
                       help="smallest allowed gap between robot footprints, m (default 0.2)")

    plan = commands.add_parser("plan", help="draw the virtual leaders' and robots' paths")
    common(plan)
    plan.add_argument("--png", required=True, metavar="OUT", help="image file to write")

    commands.add_parser("demo", help="print a commented scenario that explains every "
                        "instruction")

    run = commands.add_parser("run", help="simulate a show and write metrics, plots, an "
                              "animation and a log")
    run.add_argument("scenario", metavar="SCENARIO", nargs="?",
                     help="choreography file (default: the bundled open-day show, thesis "
                     "listing 6.3, in its hall with two HUSKY and two TRADR robots)")
    run.add_argument("--world", metavar="W", help="world file (TOML, docs/worlds.md); default: "
                     "an open arena around the show")
    run.add_argument("--out", metavar="DIR", help="output directory (default: out/NAME)")
    run.add_argument("--profile", choices=sorted(PROFILES), default="ideal",
                     help="ideal: commands act at once (thesis 2D); realistic: inertia, lag and "
                     "noise (default: ideal)")
    run.add_argument("--seed", type=int, default=0, help="seed of the noise (default 0)")
    run.add_argument("--vmax", type=_positive, metavar="V",
                     help="max speed of the slowest robot, m/s (default: from the world, else "
                     "0.5)")
    run.add_argument("--no-animation", action="store_true", help="skip the GIF/MP4")
    run.add_argument("--sound", action="store_true",
                     help="also write sound.wav: the robots' speech and beeps on the show's "
                     "time line (needs espeak-ng)")
    run.add_argument("--show-lidar", action="store_true",
                     help="draw each robot's latest LIDAR scan in the animation")
    run.add_argument("--no-lidar", action="store_true",
                     help="robots without LIDAR: no obstacle detection, stops or force field")
    run.add_argument("--rays", type=int, default=256, choices=(256, 1024),
                     help="LIDAR rays per scan (default 256 as in the thesis's simulator)")
    run.add_argument("--latency", type=float, default=0.3, metavar="S",
                     help="LIDAR latency, s (default 0.3, the thesis's robots)")
    run.add_argument("--detector", choices=("compensated", "thesis"), default="compensated",
                     help="thesis: use the latest cloud as if current; compensated (default): "
                     "move its points by the robot's motion since the scan")
    run.add_argument("--force-steering", choices=("blend", "thesis"), default="blend",
                     help="how the virtual force field steers (docs/safety.md)")
    from dancebots.follow_command import add_follow_parser
    from dancebots.ros_command import add_ros_parser

    add_ros_parser(commands)
    add_follow_parser(commands)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.command == "demo":
            return _demo()
        if args.command == "check":
            return _check(args)
        if args.command == "run":
            from dancebots.run_command import run_show

            return run_show(args)
        if args.command == "follow":
            from dancebots.follow_command import run_follow

            return run_follow(args)
        if args.command == "ros":
            from dancebots.ros_command import run_ros

            return run_ros(args)
        return _plan(args)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


def _demo() -> int:
    with open(bundled("demo.dance"), encoding="utf-8") as handle:
        sys.stdout.write(handle.read())
    return EXIT_OK


def print_diagnostics(diagnostics: Sequence[Diagnostic], sources: dict[str, list[str]]) -> None:
    if diagnostics:
        sys.stdout.flush()
        print(format_diagnostics(diagnostics, sources), file=sys.stderr)
        sys.stderr.flush()


def compile_files(args: argparse.Namespace, sources: dict[str, list[str]]
             ) -> tuple[Plan | None, World | None, list[Diagnostic]]:
    """Read the world and the scenario and plan it; every failure becomes a diagnostic."""
    diagnostics: list[Diagnostic] = []
    world = None
    if args.world:
        try:
            world = load_world(args.world)
        except DiagnosticError as exc:
            diagnostics.extend(exc.diagnostics)
            text, _ = read_source_file(args.world)
            if text is not None:
                sources[args.world] = text.splitlines()
    text, read_problems = read_source_file(args.scenario)
    diagnostics.extend(read_problems)
    if text is None:
        return None, world, diagnostics
    sources[args.scenario] = text.splitlines()
    vmax = args.vmax or (world.slowest_speed() if world is not None else None)
    _, plan, problems = compile_scenario(text, args.scenario, PlanParameters(vmax=vmax or 0.5))
    diagnostics.extend(problems)
    if has_errors(diagnostics):
        return None, world, diagnostics
    return plan, world, diagnostics


def _check(args: argparse.Namespace) -> int:
    sources: dict[str, list[str]] = {}
    plan, world, diagnostics = compile_files(args, sources)
    report = None
    if plan is not None:
        report = check_plan(plan, world, CheckOptions(clearance=args.clearance))
        diagnostics = diagnostics + list(report.diagnostics)
    invalid = has_errors(diagnostics)
    if args.json:
        print(json.dumps({
            "valid": not invalid,
            "diagnostics": [d.to_json() for d in sorted(
                diagnostics, key=lambda d: (d.path, d.line, d.col))],
            "report": report.to_json() if report and not invalid else None,
        }, indent=2))
    else:
        if report is not None and not invalid:
            print(_summary_text(report, plan))
        print_diagnostics(diagnostics, sources)
        if not invalid:
            count = len(diagnostics)
            print(f"{args.scenario}: ok" + (
                f" ({count} warning{'s' if count > 1 else ''})" if count else ""))
    if invalid:
        return EXIT_INVALID
    return EXIT_WARNINGS if args.strict and diagnostics else EXIT_OK


def _summary_text(report: CheckReport, plan: Plan | None) -> str:
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


def _plan(args: argparse.Namespace) -> int:
    sources: dict[str, list[str]] = {}
    plan, world, diagnostics = compile_files(args, sources)
    print_diagnostics(diagnostics, sources)
    if plan is None:
        return EXIT_INVALID
    directory = os.path.dirname(os.path.abspath(args.png))
    if not os.path.isdir(directory) or not os.access(directory, os.W_OK):
        print(f"{args.png}: error: cannot write here: {directory} is not a writable directory",
              file=sys.stderr)
        return EXIT_INVALID
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from dancebots.check import place_plan_in_world
    from dancebots.report.plan_plot import plot_plan

    transform = None
    if world is not None:
        placement: list[Diagnostic] = []
        transform = place_plan_in_world(plan, world, placement)
        print_diagnostics(placement, sources)
        if has_errors(placement):
            return EXIT_INVALID
    figure = plot_plan(plan, world, transform)
    temporary = args.png + ".partial"
    try:
        figure.savefig(temporary, dpi=120, format=_image_format(args.png))
        os.replace(temporary, args.png)
    except (OSError, ValueError) as exc:
        if os.path.exists(temporary):
            os.remove(temporary)
        print(f"{args.png}: error: cannot write the image: {exc}", file=sys.stderr)
        return EXIT_INVALID
    finally:
        plt.close(figure)
    print(f"wrote {args.png}")
    return EXIT_OK


def _image_format(path: str) -> str:
    extension = os.path.splitext(path)[1].lower().lstrip(".")
    return extension if extension in ("png", "svg", "pdf") else "png"


if __name__ == "__main__":
    sys.exit(main())

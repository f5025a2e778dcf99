"""Loading a show: a scenario file and an optional world file in, a plan or diagnostics out.

The one way every shell (the ``dancebots`` commands, the ROS nodes) turns files into a plan,
so that they all compute the same plan from the same files. No argparse, no printing: every
problem, including an unreadable file, is a :class:`~dancebots.diagnostics.Diagnostic`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from dancebots.check import CheckOptions, CheckReport, check_plan
from dancebots.diagnostics import (
    Diagnostic,
    Severity,
    has_errors,
    read_source_file,
    source_lines,
)
from dancebots.plan.compile import compile_scenario
from dancebots.plan.planner import Plan, PlanParameters, Timing
from dancebots.world import MISSING_WORLD_HINT, World, parse_world

__all__ = ["DEFAULT_VMAX", "LoadedShow", "load_show", "music_path", "show_digests"]

DEFAULT_VMAX = 0.5
"""m/s: the slowest robot's maximum speed when neither the caller nor a world gives one."""


@dataclass(frozen=True, slots=True, eq=False)
class LoadedShow:
    """The result of loading a show.

    plan: None when there are errors; world: None without a world file or when it is
    invalid; diagnostics: every problem found (compiler, world and, if asked, check);
    sources: the lines of each file read, by path (to print diagnostics with their source);
    report: the check's report when ``load_show(..., check=...)`` asked for one and the
    show compiled.
    """

    scenario_path: str
    world_path: str | None
    plan: Plan | None
    world: World | None
    diagnostics: tuple[Diagnostic, ...]
    sources: Mapping[str, list[str]] = field(default_factory=dict)
    report: CheckReport | None = None

    @property
    def valid(self) -> bool:
        """True when the show compiled without errors (warnings allowed)."""
        return self.plan is not None and not has_errors(self.diagnostics)


def load_show(scenario_path: str, world_path: str | None = None, vmax: float | None = None,
              check: CheckOptions | None = None, timing: Timing = "thesis") -> LoadedShow:
    """Read and compile ``scenario_path`` (and place it in ``world_path``).

    vmax: the slowest robot's maximum speed, m/s (default: the world's slowest robot type,
    else :data:`DEFAULT_VMAX`); the virtual leader moves at 0.7 vmax (thesis 6.1).
    check: also run :func:`~dancebots.check.check_plan` with these options; its diagnostics
    (warnings, and errors for shows that cannot run in the world) join the others.
    """
    diagnostics: list[Diagnostic] = []
    sources: dict[str, list[str]] = {}
    world = None
    if world_path:  # read once: for the world and for showing its lines under diagnostics
        text, problems = read_source_file(world_path, MISSING_WORLD_HINT)
        if text is not None:
            sources[world_path] = source_lines(text)
            world, problems = parse_world(text, world_path)
        if world is None:
            diagnostics.extend(problems)
    text, read_problems = read_source_file(scenario_path)
    diagnostics.extend(read_problems)
    if text is None:
        return LoadedShow(scenario_path, world_path, None, world, tuple(diagnostics), sources)
    sources[scenario_path] = source_lines(text)
    speed = vmax or (world.slowest_speed() if world is not None else None) or DEFAULT_VMAX
    footprint = (world.largest_footprint() if world is not None else None) or (
        PlanParameters().footprint)
    _, plan, problems = compile_scenario(text, scenario_path, PlanParameters(
        vmax=speed, timing=timing, footprint=footprint))
    diagnostics.extend(problems)
    if plan is None or has_errors(diagnostics):
        return LoadedShow(scenario_path, world_path, None, world, tuple(diagnostics), sources)
    tempo = plan.scenario.tempo
    if tempo is not None and tempo.music is not None and music_path(
            scenario_path, tempo.music) is None:
        diagnostics.append(Diagnostic(
            scenario_path, tempo.span.line, tempo.span.col, Severity.WARNING,
            f"the music file {tempo.music} is not there (looked next to the scenario: "
            f"{Path(scenario_path).parent / tempo.music})",
            "fix the path (relative to the scenario file), or leave `music` out; `dancebots "
            "run --music FILE` takes one too", tempo.span.end_col))
    report = None
    if check is not None:
        report = check_plan(plan, world, check)
        diagnostics.extend(report.diagnostics)
        if has_errors(report.diagnostics):
            return LoadedShow(scenario_path, world_path, None, world, tuple(diagnostics),
                              sources, report)
    return LoadedShow(scenario_path, world_path, plan, world, tuple(diagnostics), sources,
                      report)


def music_path(scenario_path: str, music: str) -> Path | None:
    """The music file a show's tempo names (``music``, relative to the scenario file's
    directory), or None when there is no such file."""
    path = Path(scenario_path).parent / music
    return path if path.is_file() else None


def show_digests(scenario_path: str, world_path: str | None,
                 parameters: Mapping[str, object]) -> tuple[str, str, str]:
    """What a robot runs, as digests (16 hexadecimal digits of SHA-256) of the scenario
    file's bytes, the world file's (``-`` without one) and the motion ``parameters``
    (name -> value, sorted by name: vmax, timing, follower, ... as the node resolved them):
    the ``show`` message of the start agreement (``sync.start.agreement_show``). Raises
    OSError when a file cannot be read (the node has read both already)."""
    import hashlib

    def digest(data: bytes) -> str:
        return hashlib.sha256(data).hexdigest()[:16]

    world = "-" if not world_path else digest(Path(world_path).read_bytes())
    text = "\n".join(f"{name}={parameters[name]!r}" for name in sorted(parameters))
    return digest(Path(scenario_path).read_bytes()), world, digest(text.encode())

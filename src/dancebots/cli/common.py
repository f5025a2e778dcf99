"""What every ``dancebots`` command shares: exit statuses, argument types, printing of
diagnostics and progress, and the output writer that never destroys a user's files.

Light on purpose: importing this module imports nothing beyond the standard library, so that
``dancebots --help`` starts at once. Commands import the core inside their ``run``.
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import json
import math
import os
import shutil
import sys
import tempfile
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from rich.console import Console

    from dancebots.diagnostics import Diagnostic
    from dancebots.report.verdict import Verdict

__all__ = [
    "EXIT_BUG",
    "EXIT_FAILED",
    "EXIT_INTERRUPTED",
    "EXIT_INVALID",
    "EXIT_OK",
    "EXIT_WARNINGS",
    "MANIFEST",
    "PROFILES",
    "OutputError",
    "ShowOutcome",
    "StagedOutput",
    "add_show_arguments",
    "bundled",
    "fail",
    "in_range",
    "interrupted",
    "on_interrupt",
    "positive",
    "print_diagnostics",
    "print_verdict",
    "profile_missing",
    "progress",
    "raise_if_interrupted",
    "refuse",
    "reset_interrupt",
    "run_show_into",
    "say_compiling",
    "short_path",
    "stage_output",
    "write_file",
]

EXIT_OK = 0
"""The input is valid; a show ran clean."""
EXIT_WARNINGS = 1
"""``check --strict``: the input has warnings."""
EXIT_FAILED = 1
"""``run``/``follow``: the show ran but not clean (a collision, a contact with a person, a
robot in its error state, a robot far from its final slot, a broken queue)."""
EXIT_INVALID = 2
"""Invalid input or unusable arguments; nothing was simulated or written."""
EXIT_INTERRUPTED = 130
"""Ctrl-C (128 + SIGINT), as shells report it."""
EXIT_BUG = 70
"""An internal error: a bug in dancebots, not in the input (EX_SOFTWARE of sysexits.h), so
that a script can tell it from a show that ran but not clean (1)."""

MANIFEST = "dancebots-manifest.json"
"""Written into every output directory: the files dancebots wrote there (name -> SHA-256).
Only these files are ever replaced or removed by a later run into the same directory."""


def bundled(name: str) -> str:
    """Path of a file shipped inside the package (``dancebots/data``)."""
    return str(resources.files("dancebots") / "data" / name)


def short_path(path: str) -> str:
    """The path relative to the working directory when that is shorter (for titles)."""
    relative = os.path.relpath(path)
    return relative if len(relative) < len(path) else path


def positive(text: str) -> float:
    """argparse type: a finite number > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError(f"{text!r} must be a finite number > 0")
    return value


def in_range(low: float, high: float, integer: bool = False) -> Callable[[str], float]:
    """argparse type: a number in [low, high] (an integer if ``integer``)."""
    def parse(text: str) -> float:
        try:
            value: float = int(text) if integer else float(text)
        except ValueError:
            kind = "an integer" if integer else "a number"
            raise argparse.ArgumentTypeError(f"{text!r} is not {kind}") from None
        if not (math.isfinite(value) and low <= value <= high):
            bounds = (f"{int(low)} to {int(high)}" if integer else f"{low:g} to {high:g}")
            raise argparse.ArgumentTypeError(f"{text} is outside {bounds}")
        return value

    parse.__name__ = "integer" if integer else "number"  # argparse names it in errors
    return parse


PROFILES = ("ideal", "realistic", "physics", "physics-geometric")
"""The simulator's profiles (``sim.kinematics.PROFILES``; the CLI imports only the standard
library at start-up; a test keeps them equal)."""


def profile_missing(profile: str) -> str | None:
    """Why the simulator's ``profile`` cannot run here (the physics profile without MuJoCo,
    with how to install it), or None."""
    import importlib.util

    if profile.startswith("physics") and importlib.util.find_spec("mujoco") is None:
        from dancebots.sim.physics import INSTALL_HINT

        return INSTALL_HINT
    return None


def fail(command: str, message: str) -> int:
    """Print ``dancebots COMMAND: error: MESSAGE`` on stderr; returns EXIT_INVALID."""
    print(f"dancebots {command}: error: {message}", file=sys.stderr)
    return EXIT_INVALID


def refuse(command: str, json_output: bool, message: str | None = None,
           diagnostics: Sequence[Diagnostic] = (),
           sources: Mapping[str, list[str]] | None = None) -> int:
    """Refuse to run: the diagnostics (with their source lines) or ``dancebots COMMAND:
    error: MESSAGE`` on stderr and, for ``--json``, ``{"ran": false, "error": ...,
    "diagnostics": [...]}`` on stdout; returns EXIT_INVALID."""
    if diagnostics:
        print_diagnostics(diagnostics, sources or {})
    if message is not None:
        fail(command, message)
    if json_output:
        print(json.dumps({"ran": False, "error": message,
                          "diagnostics": [d.to_json() for d in diagnostics]}, indent=2))
    return EXIT_INVALID


def print_diagnostics(diagnostics: Sequence[Diagnostic],
                      sources: Mapping[str, list[str]]) -> None:
    """Diagnostics on stderr with their source lines (after anything printed on stdout)."""
    if diagnostics:
        from dancebots.diagnostics import format_diagnostics

        sys.stdout.flush()
        print(format_diagnostics(diagnostics, dict(sources)), file=sys.stderr)
        sys.stderr.flush()


def print_verdict(console: Console, verdict: Verdict, noun: str) -> None:
    """The verdict's last lines: clean in green, or NOT CLEAN in red with every failure."""
    if verdict.clean:
        console.print(f"verdict: the {noun} ran clean", style="bold green", highlight=False)
        return
    console.print("verdict: NOT CLEAN", style="bold red", highlight=False)
    for failure in verdict.failures:
        console.print(f"  - {failure}", style="red", highlight=False)


# --- interrupts ----------------------------------------------------------------------------

_interrupted = False


def on_interrupt(signum: int, frame: object) -> None:
    """The SIGINT handler while a command runs: remember it and raise KeyboardInterrupt. The
    flag survives where the exception is swallowed (in a finalizer, or by a library), so
    :func:`raise_if_interrupted` still stops the command at its next step."""
    global _interrupted
    _interrupted = True
    raise KeyboardInterrupt


def reset_interrupt() -> None:
    global _interrupted
    _interrupted = False


def interrupted() -> bool:
    """Was Ctrl-C pressed since the command started?"""
    return _interrupted


def raise_if_interrupted() -> None:
    """Raise KeyboardInterrupt if Ctrl-C was pressed (and swallowed somewhere) meanwhile."""
    if _interrupted:
        raise KeyboardInterrupt


def say_compiling(console: Console, kernels: int | None = None) -> None:
    """Tell that the simulator's kernels compile before the first run (numba caches them on
    disk): ``kernels`` of them, or "kernels" when not counted. About a minute on this
    project's 2-core machine (72 s with the first 2 runs of a certification, 2026-11-28)."""
    what = ("kernels" if kernels is None else
            "1 kernel" if kernels == 1 else f"{kernels} kernels")
    console.print(f"compiling the simulator's {what} (numba; first run on this machine "
                  "only, about a minute)", style="yellow", highlight=False)


@contextlib.contextmanager
def progress(console: Console, label: str) -> Iterator[Callable[[float, float], None]]:
    """A rich progress bar on a terminal; nothing when output is redirected. Each update
    also stops the work if Ctrl-C was pressed."""
    if not console.is_terminal:
        def quiet(done: float, total: float) -> None:
            raise_if_interrupted()

        yield quiet
        return
    from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

    with Progress(TextColumn("{task.description}"), BarColumn(), TextColumn(
            "{task.completed:.0f}/{task.total:.0f}"), TimeRemainingColumn(),
            console=console, transient=True) as bar:
        task = bar.add_task(label, total=1.0)

        def update(done: float, total: float) -> None:
            raise_if_interrupted()
            bar.update(task, completed=done, total=total)

        yield update


# --- the output writer -------------------------------------------------------------------


class OutputError(Exception):
    """The output cannot be written where asked; ``str(error)`` says why and what to do."""


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _is_working_directory_or_above(target: Path) -> bool:
    here = Path.cwd().resolve()
    there = target.resolve()
    return there == here or there in here.parents


def _read_record(path: Path, what: str) -> dict[str, list[str]]:
    """A JSON record ``{"files": {name: [sha256, ...]}}`` of files dancebots wrote."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        files = data["files"]
        if not isinstance(files, dict):
            raise TypeError
        result: dict[str, list[str]] = {}
        for name, digests in files.items():
            if (not isinstance(name, str) or Path(name).name != name or name in (".", "..")
                    or not isinstance(digests, list)
                    or not all(isinstance(d, str) for d in digests)):
                raise TypeError
            result[name] = list(digests)
        return result
    except (OSError, ValueError, KeyError, TypeError):
        raise OutputError(f"{path} is not a {what} dancebots can read, so dancebots does "
                          "not know which files there are its own; choose another --out") \
            from None


def _ours(path: Path, digests: Sequence[str]) -> bool:
    """Is ``path`` a regular file (not a link) whose content dancebots wrote?"""
    return (not path.is_symlink() and path.is_file() and _sha256(path) in digests)


def _foreign(directory: Path, names: Sequence[str], record: Mapping[str, list[str]],
             ) -> Path | None:
    """The first of ``names`` in ``directory`` that exists and is not dancebots's own
    unchanged file (per ``record``), or None."""
    for name in names:
        path = directory / name
        if os.path.lexists(path) and not _ours(path, record.get(name, ())):
            return path
    return None


def _write_atomically(path: Path, write: Callable[[Path], None]) -> None:
    """Let ``write`` fill a new temporary file beside ``path`` (made by mkstemp: never a
    link), then replace ``path`` with it; the temporary file never outlives the call."""
    handle, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(handle)
    temporary = Path(name)
    try:
        write(temporary)
        temporary.chmod(0o666 & ~_umask())
        os.replace(temporary, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            temporary.unlink()


def _write_json(path: Path, data: Any) -> None:
    """Write JSON atomically (:func:`_write_atomically`)."""
    def write(temporary: Path) -> None:
        temporary.write_text(json.dumps(data, indent=2) + "\n", encoding="utf-8")

    _write_atomically(path, write)


@dataclass(frozen=True, slots=True)
class StagedOutput:
    """An output directory being written: the files go into ``staging`` (made by
    :func:`stage_output`, so the target is known to be writable before any work) and
    :meth:`commit` moves them into ``target``."""

    target: Path
    staging: Path
    command: str
    previous: Mapping[str, list[str]] | None
    created: tuple[Path, ...]

    def commit(self, written: Sequence[str], version: str) -> None:
        """Move the staged files into the target. A target that did not exist is renamed
        into place at once; in an earlier run's directory each file replaces its namesake
        (the earlier run's files stay intact until the new run is complete) and files of
        the earlier run that this one did not write are removed. Nothing else is touched:
        if a file at one of these names was changed or created during the run, nothing is
        replaced and the new files are kept beside it (an :class:`OutputError` says where)."""
        new = {name: [_sha256(self.staging / name)] for name in written}
        manifest = {"dancebots": version, "command": self.command, "files": new}
        if self.previous is None:
            _write_json(self.staging / MANIFEST, manifest)
            try:
                self.staging.rename(self.target)
            except OSError:
                kept = self._keep(self.target.parent / f"{self.target.name}.unsaved-")
                raise OutputError(f"{self.target} was made by someone else during the run, "
                                  f"so the new run was not moved there; its files are in "
                                  f"{kept}") from None
            return
        changed = _foreign(self.target, written, self.previous)
        if changed is not None:
            _write_json(self.staging / MANIFEST, manifest)  # the kept run is a run directory
            kept = self._keep(self.target / "unsaved-run-")
            raise OutputError(f"{changed} was changed or made during the run, so nothing in "
                              f"{self.target} was replaced; the new run's files are in {kept}")
        # a crash from here on leaves files that the manifest still calls ours
        interim = {name: sorted({*self.previous.get(name, []), *new.get(name, [])})
                   for name in {*self.previous, *new}}
        _write_json(self.target / MANIFEST, {**manifest, "files": interim})
        for name in written:
            os.replace(self.staging / name, self.target / name)
        for name, digests in self.previous.items():
            old = self.target / name
            if name not in new and _ours(old, digests):
                old.unlink()
        _write_json(self.target / MANIFEST, manifest)
        shutil.rmtree(self.staging)

    def _keep(self, prefix: Path) -> Path:
        """Move the staging directory to a new visible directory named ``prefix...``."""
        kept = Path(tempfile.mkdtemp(prefix=prefix.name, dir=prefix.parent))
        for entry in self.staging.iterdir():
            os.replace(entry, kept / entry.name)
        self.staging.rmdir()
        return kept

    def abandon(self) -> None:
        """Remove the staging directory and the parents :func:`stage_output` created."""
        shutil.rmtree(self.staging, ignore_errors=True)
        for directory in self.created:  # innermost first
            with contextlib.suppress(OSError):
                directory.rmdir()  # only if still empty


def stage_output(target: Path, command: str, names: Sequence[str] = ()) -> StagedOutput:
    """Check that ``target`` may receive a run's outputs and make the staging directory.

    names: every file name the command may write there. Refused with an
    :class:`OutputError`: the working directory or one above it, a symbolic link, something
    that is not a directory, a non-empty directory without a dancebots manifest, an earlier
    run whose files were changed since, a file at one of ``names`` that dancebots did not
    write, and a place that cannot be written. Missing parents are created (and removed
    again by :meth:`StagedOutput.abandon`).
    """
    shown = str(target)
    if _is_working_directory_or_above(target):
        raise OutputError(f"--out {shown} is the working directory or one above it; give a "
                          "directory of its own, e.g. out/NAME")
    if target.is_symlink():
        raise OutputError(f"--out {shown} is a symbolic link; give a real directory "
                          "(dancebots does not write through links)")
    previous: dict[str, list[str]] | None = None
    if target.exists():
        if not target.is_dir():
            raise OutputError(f"--out {shown} exists and is not a directory; choose another "
                              "--out")
        if os.path.lexists(target / MANIFEST):
            previous = _read_record(target / MANIFEST, "manifest")
            changed = _foreign(target, list(previous), previous)
            if changed is not None:
                raise OutputError(f"{changed} was changed since dancebots wrote it; move it "
                                  "away (dancebots replaces only its own unchanged files) or "
                                  "choose another --out")
            clash = _foreign(target, names, previous)
            if clash is not None:
                raise OutputError(f"{clash} is not a file of the earlier run (its "
                                  f"{MANIFEST} does not list it), and this run would write "
                                  "it; move it away or choose another --out")
        elif any(target.iterdir()):
            hint = (" (it looks like a run of an older dancebots: delete it if you no longer "
                    "need it)" if (target / "metrics.json").exists() else "")
            raise OutputError(f"--out {shown} holds files that dancebots did not write (no "
                              f"{MANIFEST}){hint}; choose a new or empty directory")
        else:
            previous = {}
    created: list[Path] = []
    try:
        missing = []
        probe = target.parent
        while not probe.exists():
            missing.append(probe)
            probe = probe.parent
        if not probe.is_dir():
            raise OutputError(f"cannot create {shown}: {probe} is not a directory; choose "
                              "another --out")
        for directory in reversed(missing):
            directory.mkdir()
            created.insert(0, directory)
        home = target if previous is not None else target.parent
        prefix = ".dancebots-partial-" if previous is not None else f".{target.name}.partial-"
        staging = Path(tempfile.mkdtemp(prefix=prefix, dir=home))
        staging.chmod(0o777 & ~_umask())  # mkdtemp makes it private; a run's outputs are not
    except OSError as exc:
        for directory in created:
            with contextlib.suppress(OSError):
                directory.rmdir()
        raise OutputError(f"cannot write {shown}: {exc.strerror or exc}; choose a writable "
                          "--out") from None
    return StagedOutput(target, staging, command, previous, tuple(created))


@dataclass(frozen=True, slots=True)
class ShowOutcome:
    """What a show command's simulation wrote into the staging directory: the file names,
    the wall time (s), the verdict, the metrics (as metrics.json holds them, without the
    verdict) and how to print the human summary."""

    written: list[str]
    wall: float
    verdict: Verdict
    metrics: Mapping[str, object]
    summary: Callable[[], None]


def run_show_into(command: str, target: Path, names: Sequence[str], json_output: bool,
                  simulate_and_write: Callable[[Path], ShowOutcome]) -> int:
    """The shell of ``run`` and ``follow``: make sure ``target`` may receive the outputs
    (``names``: every file the command may write) before any work, let
    ``simulate_and_write`` fill the staging directory, put its files in place, then print the
    summary (or, for ``--json``, the summary as JSON) and return the exit status of the
    verdict. Write problems are one-line refusals (exit 2) that leave ``target`` as it was;
    any other exception (and Ctrl-C) removes the staging directory and propagates."""
    from dancebots import __version__

    try:
        staged = stage_output(target, command, names)
    except OutputError as exc:
        return refuse(command, json_output, str(exc))
    try:
        outcome = simulate_and_write(staged.staging)
        raise_if_interrupted()  # a Ctrl-C swallowed on the way: do not replace an earlier run
        staged.commit(outcome.written, __version__)
    except OutputError as exc:  # the outputs could not be put in place; nothing was lost
        staged.abandon()
        return refuse(command, json_output, str(exc))
    except OSError as exc:  # e.g. a full disk while writing: the earlier run is intact
        staged.abandon()
        return refuse(command, json_output, f"cannot write the outputs to {target}: "
                      f"{exc.strerror or exc}; nothing there was changed")
    except Exception as exc:
        from dancebots.sim.setup import SetupError

        staged.abandon()
        if isinstance(exc, SetupError):  # e.g. a crowd that does not fit: nothing written
            return refuse(command, json_output, str(exc))
        raise
    except BaseException:
        staged.abandon()
        raise
    verdict = outcome.verdict.to_json()
    if json_output:
        print(json.dumps({"ran": True, "output": str(target), "files": outcome.written,
                          "wall_s": round(outcome.wall, 3), "verdict": verdict,
                          "metrics": {**outcome.metrics, "verdict": verdict}}, indent=2))
    else:
        outcome.summary()
    return EXIT_OK if outcome.verdict.clean else EXIT_FAILED


IMAGE_RECORD = ".dancebots-images.json"
"""Beside images that ``dancebots plan`` wrote: their names and SHA-256, so that only its own
unchanged images are ever replaced."""


def write_file(path: Path, write: Callable[[Path], None], version: str) -> None:
    """Write one file through a temporary file beside it, replaced into place when complete.

    An existing file is replaced only if dancebots wrote it and nobody changed it since (its
    SHA-256 is in the directory's :data:`IMAGE_RECORD`); directories, symbolic links and
    other files are refused with an :class:`OutputError`.
    """
    shown = str(path)
    if path.is_symlink():
        raise OutputError(f"{shown} is a symbolic link; give the path of a file")
    if path.is_dir():
        raise OutputError(f"{shown} is a directory; give a file name, e.g. {path / 'plan.png'}")
    directory = path.parent if str(path.parent) else Path(".")
    if not directory.is_dir():
        raise OutputError(f"cannot write {shown}: the directory {directory} does not exist")
    record_path = directory / IMAGE_RECORD
    record = (_read_record(record_path, "record of images") if os.path.lexists(record_path)
              else {})
    if os.path.lexists(path) and not _ours(path, record.get(path.name, ())):
        raise OutputError(f"{shown} exists and was not written by dancebots (or was changed "
                          "since); remove it or choose another name")
    digest: list[str] = []

    def write_and_hash(temporary: Path) -> None:
        write(temporary)
        digest.append(_sha256(temporary))

    try:
        _write_atomically(path, write_and_hash)
        _write_json(record_path, {"dancebots": version, "files": {
            **record, path.name: digest}})
    except OSError as exc:
        raise OutputError(f"cannot write {shown}: {exc.strerror or exc}") from None


def _umask() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return umask


FOLLOWERS = ("thesis", "tracking", "path")
"""``robot.FOLLOWERS`` (the CLI imports only the standard library at start-up)."""
TIMINGS = ("thesis", "feasible")
"""``plan.planner.TIMINGS`` (the CLI imports only the standard library at start-up)."""
DEFAULT_TIMING = "feasible"
"""The timing of ``run``, ``check``, ``plan`` and ``ros`` unless ``--timing`` says otherwise
(the thesis's is ``--timing thesis``)."""
DEFAULT_FOLLOWER = "path"
"""The follower of ``run``, ``check`` and ``ros`` unless ``--follower`` says otherwise (the
thesis's eq. 4.4 is ``--follower thesis``)."""


def add_timing_argument(parser: argparse.ArgumentParser) -> None:
    """--timing: how fast the virtual leader moves (``PlanParameters.timing``)."""
    parser.add_argument("--timing", choices=TIMINGS, default=DEFAULT_TIMING,
                        help="feasible (default): the leader slows wherever a robot's slot or "
                        "place on the path would move faster than 0.8 V (the outer robots of "
                        "a turn), keeping its path, and formations that would meet leave in "
                        "turn; thesis: the leader's speeds as the thesis gives them")


STOP_RULES = ("fixed", "closing", "ssm", "predicted")
"""``robot.STOP_RULES`` (the CLI imports only the standard library at start-up)."""


def add_stop_rule_argument(parser: argparse.ArgumentParser) -> None:
    """--stop-rule: when a robot stops for what it sees (``BrainOptions.stop_rule``)."""
    parser.add_argument("--stop-rule", choices=STOP_RULES, default=None,
                        help="predicted (default; fixed with --follower thesis): fixed on the "
                        "points of tracked people moved on at their speed for the data's age, "
                        "within 0.55 m plus the robot's own way until it stands; "
                        "fixed (thesis 5.2): a robot stops when a point is within "
                        "0.55 m ahead of it (behind, reversing); closing: fixed, and a robot "
                        "stands while a person approaches it (at 0.5 m/s or more, measured "
                        "between scans) faster than it could stop; ssm: speed and separation "
                        "monitoring (ISO/TS 15066): its speed is limited so that it can stop "
                        "before a person, approaching at the tracked speed or at 1.6 m/s "
                        "when new, comes within 0.25 m of it (docs/safety.md)")


HOLDS = ("together", "alone", "paced")
"""``sync.hold.HOLD_STRATEGIES`` (the CLI imports only the standard library at start-up)."""


def add_hold_argument(parser: argparse.ArgumentParser) -> None:
    """--hold: whether the formation waits for a robot held by a person
    (``SimConfig.hold``)."""
    parser.add_argument("--hold", choices=HOLDS, default=None,
                        help="paced (default): when a robot is held by a person, every "
                        "robot's virtual leader waits, and all resume together (a shared "
                        "show clock); a robot a person slows and leaves behind says how much "
                        "of the plan's speed it drives, and every leader runs at that pace "
                        "(the formation slows together instead of stopping and starting); "
                        "together: such a robot holds the show too; alone (the default with "
                        "--follower thesis, whose robots know no mates' places): each "
                        "robot's leader runs on from the start whatever the others do "
                        "(thesis 4.2)")


def add_follower_argument(parser: argparse.ArgumentParser) -> None:
    """--follower: how each robot follows its slot (``BrainOptions.follower``)."""
    parser.add_argument("--follower", choices=FOLLOWERS, default=DEFAULT_FOLLOWER,
                        help="path (default): each robot tracks its place on the leader's path "
                        "(Kanayama's law, docs/control.md; columns follow the path round "
                        "corners); tracking: the same law on its rigid slot's motion; thesis: "
                        "eq. 4.4 as written")


def add_show_arguments(parser: argparse.ArgumentParser, scenario_help: str | None = None,
                       world_help: str | None = None) -> None:
    """The arguments that name a show: SCENARIO, --world, --vmax."""
    if scenario_help is None:
        parser.add_argument("scenario", metavar="SCENARIO",
                            help="choreography file (.dance; `dancebots demo` prints one)")
    else:
        parser.add_argument("scenario", metavar="SCENARIO", nargs="?", help=scenario_help)
    parser.add_argument("--world", metavar="W", help=world_help or "world file (TOML, "
                        "docs/worlds.md): the room, obstacles, robots and spectators")
    parser.add_argument("--vmax", type=positive, metavar="V",
                        help="max speed of the slowest robot, m/s (default: from the world's "
                        "robot types, else 0.5); the virtual leader moves at 0.7 V")

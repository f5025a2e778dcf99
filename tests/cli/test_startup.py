"""The command starts at once and stops cleanly (issue 10, part 4); its choices match the
core's. Start-up *times* are measured by benchmarks/bench_startup.py, not here."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[2]
LIGHT = """
import sys
from dancebots.cli import main
try:
    main(sys.argv[1:])
except SystemExit:
    pass
heavy = sorted(m for m in ("numpy", "numba", "sklearn", "scipy", "matplotlib", "shapely",
                           "pandas", "rich") if m in sys.modules)
print("HEAVY:", " ".join(heavy))
"""


def imported_by(*args: str) -> list[str]:
    out = subprocess.run([sys.executable, "-c", LIGHT, *args], cwd=ROOT, capture_output=True,
                         text=True, check=True, timeout=120)
    return out.stdout.rsplit("HEAVY:", 1)[1].split()


def test_help_and_demo_import_no_heavy_library() -> None:
    assert imported_by("--help") == []
    assert imported_by("demo") == []
    assert imported_by("run", "--help") == []


def test_check_imports_only_what_checking_needs() -> None:
    """The rigid pass needs NumPy and shapely; the simulation pass the simulator and rich for
    its progress (7.1 has 66 robot-seconds, below COMPILED_FROM, so it runs on the NumPy
    references, the default ``predicted`` stop rule's tracker among them: no SciPy), numba
    (which brings SciPy) only for a longer show, but never the plots or the queue's
    scikit-learn."""
    assert imported_by("check", "--rigid-only", "examples/thesis_7_1.dance") == [
        "numpy", "shapely"]
    assert imported_by("check", "examples/thesis_7_1.dance") == [
        "numpy", "rich", "shapely"]
    assert imported_by("check", "--stop-rule", "fixed", "examples/thesis_7_1.dance") == [
        "numpy", "rich", "shapely"]
    assert imported_by("check", "examples/thesis_6_3.dance") == [
        "numba", "numpy", "rich", "scipy", "shapely"]


DANCEBOTS = Path(sys.executable).parent / "dancebots"


def _default_sigint() -> None:
    """In the child before it runs dancebots: SIGINT's default disposition."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.mark.parametrize("delay", [0.3, 0.8, 1.2, 1.6])
def test_ctrl_c_while_starting_or_running_exits_130_and_leaves_nothing(
        tmp_path: Path, delay: float) -> None:
    """SIGINT while the command imports its libraries (numba, matplotlib) or simulates: exit
    130 with one line, no traceback, and no output directory left behind. (A Ctrl-C in the
    first ~20 ms, while the Python interpreter itself starts and before any dancebots code
    runs, is Python's own: it prints KeyboardInterrupt.)"""
    command = [str(DANCEBOTS)] if DANCEBOTS.exists() else [sys.executable, "-m",
                                                           "dancebots.cli"]
    # a Ctrl-C as a terminal delivers it: a test run in a background job without job
    # control inherits SIGINT ignored, and Python then keeps ignoring it
    process = subprocess.Popen([*command, "run", "examples/thesis_6_3.dance", "--out",
                                str(tmp_path / "run")], cwd=ROOT, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True,
                               preexec_fn=_default_sigint)
    try:
        time.sleep(delay)
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=120)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert "Traceback" not in err
    assert process.returncode == 130
    assert err.endswith("dancebots: interrupted\n")
    assert list(tmp_path.iterdir()) == []


def test_choices_match_the_core() -> None:
    from dancebots.cli import follow, ros, run
    from dancebots.cli.common import FOLLOWERS as CLI_FOLLOWERS
    from dancebots.cli.common import TIMINGS as CLI_TIMINGS
    from dancebots.control.follower import FORCE_STEERINGS
    from dancebots.leader_follower.controllers import CONTROLLERS
    from dancebots.leader_follower.detectors import DETECTORS
    from dancebots.plan.planner import TIMINGS
    from dancebots.robot import DETECTORS as BRAIN_DETECTORS
    from dancebots.robot import FOLLOWERS
    from dancebots.shows.queue import LEADERS
    from dancebots.sim.kinematics import PROFILES
    from dancebots.sync.start import START_STRATEGIES

    assert set(run.PROFILES) == set(follow.PROFILES) == set(ros.PROFILES) == set(PROFILES)
    assert follow.DETECTORS == DETECTORS
    assert follow.CONTROLLERS == CONTROLLERS
    assert follow.LEADERS == LEADERS
    assert set(ros.START_STRATEGIES) == set(START_STRATEGIES)
    assert set(CLI_FOLLOWERS) == set(FOLLOWERS)
    assert set(run.DETECTORS) == set(BRAIN_DETECTORS)
    assert set(run.FORCE_STEERINGS) == set(FORCE_STEERINGS)
    assert set(CLI_TIMINGS) == set(TIMINGS)


def test_a_ctrl_c_that_python_wrapped_is_an_interrupt_not_a_bug(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    """A KeyboardInterrupt raised while a library creates a class at import reaches the
    command as ``RuntimeError: Error calling __set_name__`` with the interrupt as its cause
    (seen in CI: Ctrl-C while scikit-learn imported narwhals): exit 130, one line; an error
    without an interrupt in its causes stays a bug (exit 3, traceback)."""
    import argparse
    import importlib

    cli_main = importlib.import_module("dancebots.cli.main")  # (the package exports main)

    def parser_raising(error: Exception) -> argparse.ArgumentParser:
        parser = argparse.ArgumentParser()

        def handler(_: argparse.Namespace) -> int:
            raise error

        parser.set_defaults(handler=handler)
        return parser

    def wrapped() -> Exception:
        try:
            try:
                raise KeyboardInterrupt
            except KeyboardInterrupt as interrupt:
                raise RuntimeError("Error calling __set_name__") from interrupt
        except RuntimeError as error:
            return error

    monkeypatch.setattr(cli_main, "build_parser", lambda: parser_raising(wrapped()))
    assert cli_main.main([]) == 130
    assert capsys.readouterr().err == "dancebots: interrupted\n"
    monkeypatch.setattr(cli_main, "build_parser",
                        lambda: parser_raising(RuntimeError("a real bug")))
    status = cli_main.main([])
    err = capsys.readouterr().err
    assert status == cli_main.EXIT_BUG
    assert "Traceback" in err
    assert err.endswith("please report it with the lines above\n")

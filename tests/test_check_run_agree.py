"""`dancebots check` and `dancebots run` agree (issue 10, part 3), through the commands
themselves: for generated world files and shows, `check` exits 0 (or 1 with warnings under
--strict) exactly when `run` goes on to simulate, and `run` refuses (exit 2) exactly when
`check` exits 2. The simulation itself is replaced by a stub: what is compared is the
decision to simulate.
"""

from __future__ import annotations

import contextlib
import io
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, event, given, settings
from tests.sim.test_setup import worlds_and_shows

import dancebots.cli.run
from dancebots.cli.main import main

SIMULATED = 99
"""What the stubbed simulation returns: run got past every refusal."""


def quietly(argv: list[str]) -> int:
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        return main(argv)


@pytest.fixture(autouse=True)
def no_simulation(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(dancebots.cli.run, "run_show_into",
                        lambda *args, **kwargs: SIMULATED)


@settings(max_examples=150, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(worlds_and_shows())
def test_check_exit_0_is_exactly_a_show_run_simulates(case: tuple[str, str]) -> None:
    world_text, show_text = case
    with tempfile.TemporaryDirectory() as folder:
        world, show = Path(folder) / "w.toml", Path(folder) / "show.dance"
        world.write_text(world_text)
        show.write_text(show_text)
        checked = quietly(["check", str(show), "--world", str(world)])
        ran = quietly(["run", str(show), "--world", str(world), "--no-animation",
                       "--out", str(Path(folder) / "out")])
    event(f"check {checked}, run {'simulates' if ran == SIMULATED else ran}")
    assert checked in (0, 2)
    assert (checked == 0) == (ran == SIMULATED), (checked, ran)
    if ran != SIMULATED:
        assert ran == 2


def test_the_readme_example_is_refused_by_both(examples: Path, data: Path,
                                               tmp_path: Path) -> None:
    """It used to pass `check` with a warning while `run` refused it."""
    show = str(examples / "thesis_7_1.dance")
    world = str(data / "worlds" / "two_robots.toml")
    assert quietly(["check", show, "--world", world]) == 2
    assert quietly(["run", show, "--world", world, "--out", str(tmp_path / "out")]) == 2
    fitting = str(examples / "thesis_7_3.dance")  # the README's example now
    assert quietly(["check", fitting, "--world", world]) == 0
    assert quietly(["run", fitting, "--world", world, "--no-animation",
                    "--out", str(tmp_path / "out")]) == SIMULATED

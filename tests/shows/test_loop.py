"""The shows' loop: ticks, the commands' issue times, recording by name, progress, settling."""

from __future__ import annotations

import numpy as np
import pytest

from dancebots.shows.loop import STILL, Clock, Tick, robots_moving, run_show, settled_since


class FakeStage:
    """Two robots that move at the commanded speed; remembers every advance."""

    def __init__(self) -> None:
        self.pose = np.zeros((2, 3))
        self.velocity = np.zeros((2, 2))
        self.advances: list[tuple[float, list[float], list[float]]] = []

    def advance(self, now: float, command: np.ndarray, issued: np.ndarray) -> None:
        self.advances.append((now, command[:, 0].tolist(), issued.tolist()))
        self.velocity = command.copy()
        self.pose[:, 0] += 0.1 * command[:, 0]


def test_ticks_record_by_name_and_commands_hold_between_ticks() -> None:
    stage = FakeStage()

    def step(now: float) -> Tick:
        command = np.full((2, 2), round(now, 6))
        return Tick(command, {"poses": stage.pose, "speed": command[:, 0]})

    recorder = run_show(stage, step, Clock(0.1, 0.55, steps_per_tick=2))  # type: ignore[arg-type]
    assert recorder.times == pytest.approx([0.0, 0.2, 0.4, 0.6])
    assert recorder.series("speed").shape == (2, 4)
    assert recorder.series("poses").shape == (2, 4, 3)
    assert recorder.series("poses")[0, :, 0] == pytest.approx([0.0, 0.0, 0.04, 0.12])
    # each step acts with the last tick's commands, issued at that tick
    assert [(round(t, 6), c[0], i[0]) for t, c, i in stage.advances] == [
        (0.0, 0.0, 0.0), (0.1, 0.0, 0.0), (0.2, 0.2, 0.2), (0.3, 0.2, 0.2), (0.4, 0.4, 0.4),
        (0.5, 0.4, 0.4)]


def test_a_settling_show_ends_once_everything_stood_still() -> None:
    stage = FakeStage()
    reports: list[tuple[float, float]] = []

    def step(now: float) -> Tick:
        return Tick(np.full((2, 2), 0.5 if now < 2.0 else 0.0), {"poses": stage.pose})

    recorder = run_show(stage, step, Clock(0.1, 30.0, settle_from=1.0),  # type: ignore[arg-type]
                        progress=lambda now, end: reports.append((round(now, 6), end)))
    # still from 2.1 s (the first step without a command has stopped the robots) for STILL s
    assert recorder.times[-1] == pytest.approx(2.1 + STILL)
    assert reports == [(0.0, 30.0), (1.0, 30.0), (2.0, 30.0), (3.0, 30.0), (30.0, 30.0)]


def test_a_show_with_a_robot_waiting_to_move_has_not_settled() -> None:
    """Robots that stand because a person holds one (``Tick.waiting``) keep the show going
    until it no longer waits, then it settles after STILL s; without that it would end
    STILL s after they stood."""
    stage = FakeStage()

    def step(now: float) -> Tick:
        return Tick(np.zeros((2, 2)), {"poses": stage.pose}, waiting=now < 5.0)

    recorder = run_show(stage, step, Clock(0.1, 30.0, settle_from=1.0))  # type: ignore[arg-type]
    assert recorder.times[-1] == pytest.approx(5.0 + STILL)


def test_a_show_is_settled_from_its_end_while_nothing_moves() -> None:
    """``settled_since`` (the loop's and the ROS bridge's end): settled from the first tick
    at or past the show's end with nothing moving, kept while that lasts, lost when anything
    moves, is told to, or the show time is short of the end."""
    assert settled_since(None, 10.0, 19.0, 19.5, moving=False) is None  # before the end
    assert settled_since(None, 10.0, 19.5, 19.5, moving=False) == 10.0
    assert settled_since(10.0, 10.5, 19.6, 19.5, moving=False) == 10.0
    assert settled_since(10.0, 10.6, 19.7, 19.5, moving=True) is None
    still, told = np.zeros((2, 2)), np.zeros((2, 2))
    assert not robots_moving(still, told)
    told[1, 1] = 0.01  # a robot told to turn
    assert robots_moving(still, told)
    still[0, 0] = 0.002  # a robot creeping
    assert robots_moving(still, np.zeros((2, 2)))
    assert not robots_moving(np.zeros((0, 2)), np.zeros((0, 2)))  # no robots

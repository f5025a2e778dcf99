"""The planner meets cues by the leader's pace and says where it cannot; waits stand; shows
without cues plan as before."""

from __future__ import annotations

import numpy as np
import pytest

from dancebots.plan.compile import compile_scenario
from dancebots.plan.planner import (
    CUE_TOLERANCE,
    PlanParameters,
    _clock,
    instruction_timeline,
)
from dancebots.scenario import Wait
from tests_support import plan_of

HEAD = "robots A B\ntempo 120\nstart\nrow A,B 0 1.2\n"
FEASIBLE = PlanParameters(timing="feasible")


def timeline_by_line(text: str, parameters: PlanParameters = FEASIBLE) -> dict[int, object]:
    return {entry.line: entry for entry in instruction_timeline(plan_of(text, parameters))}


@pytest.mark.parametrize("parameters", [FEASIBLE, PlanParameters()])
def test_an_at_cue_starts_its_instruction_then_and_slows_what_comes_before(
        parameters: PlanParameters) -> None:
    plain = timeline_by_line(HEAD + "move 3 0\nmove 2 0\n", parameters)
    cued = timeline_by_line(HEAD + "move 3 0\nmove 2 0 at 0:20\n", parameters)
    assert plain[5].start < 12.0  # 3 m at 0.35 m/s
    assert 20.0 - 2 * parameters.step <= cued[6].start <= 20.0  # the leader stands < 2 steps
    assert cued[6].cue == "at 20"
    assert cued[6].cue_missed_by == 0.0
    assert cued[5].pace < 1.0  # the move before it slowed ...
    assert cued[6].pace == 1.0  # ... the cued one runs at its own speed
    assert cued[6].end - cued[6].start == pytest.approx(plain[6].end - plain[6].start, abs=0.06)


def test_a_by_cue_on_a_beat_ends_its_instruction_then() -> None:
    entries = timeline_by_line(HEAD + "move 2 0\ncircle 2 90 0.1 by beat 61\nwait 2 beats\n")
    # beat 61 at 120 bpm from 0 s: 30 s
    assert 30.0 - CUE_TOLERANCE <= entries[6].end <= 30.0
    assert entries[6].cue == "by beat 61"
    assert entries[6].cue_missed_by == 0.0
    assert entries[6].end_beat == pytest.approx(61.0, abs=0.2)
    assert entries[7].kind == "wait"
    assert entries[7].end - entries[7].start == pytest.approx(1.0)  # 2 beats at 120 bpm


def test_a_wait_stands_the_leader_and_its_robots() -> None:
    plan = plan_of(HEAD + "move 2 0\nwait 3\nmove 2 0\n", FEASIBLE)
    [formation] = plan.formations
    wait = next(t for t in formation.timings if isinstance(t.instruction, Wait))
    assert wait.end - wait.start == pytest.approx(3.0)
    inside = np.linspace(wait.start + 0.01, wait.end - 0.01, 20)
    assert np.all(formation.leader.commands_at(inside) == 0.0)
    desired = plan.desired_poses("A", inside)
    assert np.ptp(desired[:, :2], axis=0).max() == 0.0


def test_a_cue_that_has_passed_is_a_warning_at_the_cue() -> None:
    text = HEAD + "move 4 0\nmove 1 0 at 3\n"
    _, plan, diagnostics = compile_scenario(text, "late.dance", FEASIBLE)
    assert plan is not None
    [warning] = [d for d in diagnostics if d.severity.value == "warning"]
    assert (warning.line, warning.col, warning.end_col) == (6, 10, 14)
    start = instruction_timeline(plan)[-1].start
    assert warning.message == (f"the cue `at 3.0` cannot be met: this instruction starts at "
                               f"{_clock(start)}, {start - 3.0:.1f} s late")
    assert warning.hint is not None
    assert warning.hint.startswith("the instructions since 0.0 drive ")
    assert warning.hint.endswith("cue a later time, or drive less before it")
    assert instruction_timeline(plan)[-1].cue_missed_by == pytest.approx(start - 3.0)


def test_a_cue_before_its_formation_starts_says_when_it_can() -> None:
    text = ("robots A B C D\ngroups\nleft A C\nright B D\nstart\nsquare A,B;C,D 2 1.5\n"
            "move 4 0\ncolumn A;C 2 0\ncolumn B;D 2 0\nnewVL\nmove 1 0 left at 2\n")
    _, plan, diagnostics = compile_scenario(text, "early.dance", FEASIBLE)
    assert plan is not None
    [warning] = [d for d in diagnostics if "cue" in d.message]
    assert warning.line == 11
    assert warning.hint is not None
    assert warning.hint.endswith("at the earliest: cue a later time, or cue the instructions "
                                 "before it earlier")


def test_a_cue_that_needs_more_than_the_robots_can_is_a_warning_with_the_speed() -> None:
    text = HEAD + "move 6 0 by 5\n"
    _, plan, diagnostics = compile_scenario(text, "fast.dance", FEASIBLE)
    assert plan is not None
    [warning] = diagnostics
    assert warning.message.startswith("the cue `by 5.0` cannot be met: this instruction ends at ")
    assert warning.hint is not None
    assert ("drive 5.9 m in 14.9 s even at the fastest the robots allow (0.40 m/s on average); "
            "the cue leaves 5.0 s, 1.18 m/s") in warning.hint  # 6 m less the 0.1 m tolerance


def test_shows_without_cues_plan_exactly_as_before_cues_existed() -> None:
    """Cues are an addition: a show without them has paces of 1 and no cue fields (its
    numbers are held by the golden corpus, tests/scenario/test_golden.py)."""
    entries = instruction_timeline(plan_of(HEAD + "move 3 0\ncircle 2 90 0.2\n", FEASIBLE))
    assert all(e.pace == 1.0 and e.cue is None and e.cue_missed_by is None for e in entries)

"""Timing in the language: the tempo, cues (`at`/`by` a time or a beat) and `wait`, parsed
into the model, and every mistake a positioned diagnostic with the exact message."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from dancebots.scenario import Cue, Move, Span, Tempo, Wait, parse_scenario

HEAD = "robots A B\nstart\nrow A,B 0 1.2\n"


def test_tempo_cues_and_waits_parse_into_the_model() -> None:
    text = ("robots A B\ntempo 120 from 0.5 music song.wav\nstart\nrow A,B 0 1.2\n"
            "move 2 0 at 0:04\nwait 4 beats\ncircle 1 90 0.3 by beat 20\nwait 1.5 at 12\n"
            "move 1 0 by 1:02.5\n")
    scenario, diagnostics = parse_scenario(text, "music.dance")
    assert diagnostics == []
    assert scenario is not None
    assert scenario.tempo == Tempo(120.0, 0.5, "song.wav", Span(2, 1, 34))
    _, move, wait, circle, pause, last = scenario.instructions
    assert isinstance(move, Move)
    assert move.cue == Cue("at", 4.0, Span(5, 10, 17))
    assert wait == Wait(2.0, None, ("A", "B"), Span(6, 1, 5), None, 4.0)  # 4 beats at 120
    assert circle.cue == Cue("by", 10.0, Span(7, 17, 27), 20.0)  # 0.5 + 19 * 0.5 s
    assert pause == Wait(1.5, None, ("A", "B"), Span(8, 1, 5), Cue("at", 12.0, Span(8, 10, 15)))
    assert last.cue is not None
    assert last.cue.time == 62.5


def test_a_cue_may_follow_a_group() -> None:
    text = ("robots A B C D\ngroups\nleft A C\nright B D\nstart\nsquare A,B;C,D 2 1.5\n"
            "column A;C 2 0\ncolumn B;D 2 0\nnewVL\nmove 2 0 left at 5\nwait 3 right by 8\n")
    scenario, diagnostics = parse_scenario(text)
    assert diagnostics == []
    assert scenario is not None
    move, wait = scenario.instructions[-2:]
    assert isinstance(move, Move)
    assert (move.group, move.cue) == ("left", Cue("at", 5.0, Span(10, 15, 19)))
    assert isinstance(wait, Wait)
    assert (wait.group, wait.duration, wait.cue) == ("right", 3.0,
                                                    Cue("by", 8.0, Span(11, 14, 18)))


@pytest.mark.parametrize(("body", "line", "col", "message", "hint"), [
    ("move 2 0 at", 4, 12, "`at` needs a time",
     "e.g. `at 12.5`, `at 0:12.5` (minutes:seconds) or `at beat 32`"),
    ("move 2 0 by beat", 4, 17, "`beat` needs the beat's number",
     "e.g. `by 12.5`, `by 0:12.5` (minutes:seconds) or `by beat 32`"),
    ("move 2 0 at beat 3", 4, 13, "a beat needs the show's tempo",
     "declare it after the robots line: `tempo 120` (beats per minute)"),
    ("move 2 0 at 1:75", 4, 13, "the `at` time '1:75' is not a time",
     "write seconds (`12.5`) or minutes:seconds with two digits of seconds below 60 "
     "(`1:02.5`)"),
    ("move 2 0 at -1", 4, 13, "the `at` time must be at least 0, not -1", None),
    ("move 2 0 at nan", 4, 13, "the `at` time must be a finite number, not 'nan'", None),
    ("move 2 0 at 1e308", 4, 13, "the `at` time must be at most 3600, not 1e308", None),
    ("move 2 0 at 61:00", 4, 13, "the `at` time must be at most 3600 s (1 h), not 61:00", None),
    ("move 1 0 by 2 extra", 4, 15, "unexpected 'extra' after the cue",
     "the cue ends the line: `by 12.5`, `by 0:12.5` (minutes:seconds) or `by beat 32`"),
    ("wait", 4, 5, "wait takes a duration in s (or `N beats`) and an optional group",
     "e.g. `wait 2`, `wait 4 beats` or `wait 2 group1`"),
    ("wait 0", 4, 6, "the wait must be greater than 0, not 0", None),
    ("wait 1e-300x", 4, 6, "the wait must be a number, not '1e-300x'", None),
    ("wait 4 beats", 4, 8, "a wait in beats needs the show's tempo",
     "declare it after the robots line: `tempo 120` (beats per minute), or give the wait in "
     "seconds"),
    ("tempo 120", 4, 1, "the tempo belongs before the first formation",
     "move this line up, right after the robots line"),
])
def test_timing_mistakes_are_positioned_errors(body: str, line: int, col: int, message: str,
                                               hint: str | None) -> None:
    scenario, diagnostics = parse_scenario(HEAD + body + "\n", "t.dance")
    assert scenario is None
    [diagnostic] = diagnostics
    assert (diagnostic.line, diagnostic.col, diagnostic.message, diagnostic.hint) == (
        line, col, message, hint)


@pytest.mark.parametrize(("tempo", "col", "message"), [
    ("tempo", 6, "the tempo needs its beats per minute"),
    ("tempo 5", 7, "the tempo must be at least 10, not 5"),
    ("tempo 1e309", 7, "the tempo 1e309 is too large"),
    ("tempo 120 from", 15, "`from` needs a time: `from 0.35`"),
    ("tempo 120 music", 16, "`music` needs a file: `music song.wav`"),
    ("tempo 120 from 1 from 2", 18, "`from` is given twice"),
    ("tempo 120 loud", 11, "unexpected 'loud' in the tempo"),
])
def test_tempo_mistakes_are_positioned_errors(tempo: str, col: int, message: str) -> None:
    scenario, diagnostics = parse_scenario(f"robots A B\n{tempo}\nstart\nrow A,B 0 1.2\n")
    assert scenario is None
    [diagnostic] = diagnostics
    assert (diagnostic.line, diagnostic.col, diagnostic.message) == (2, col, message)


def test_a_second_tempo_and_keywords_as_names_are_errors() -> None:
    _, diagnostics = parse_scenario("robots A B\ntempo 120\ntempo 90\nstart\nrow A,B 0 1.2\n")
    assert [(d.line, d.message) for d in diagnostics] == [
        (3, "the tempo is already declared at line 2")]
    _, diagnostics = parse_scenario("robots A at\nstart\nrow A,at 0 1.2\n")
    assert diagnostics[0].message == "'at' is a keyword and cannot name a robot"


@given(bpm=st.floats(10.0, 600.0), first=st.floats(0.0, 60.0),
       beat=st.floats(1.0, 1e4, allow_subnormal=False))
def test_beats_and_times_are_inverse_and_evenly_spaced(bpm: float, first: float,
                                                       beat: float) -> None:
    tempo = Tempo(bpm, first, None, Span(1))
    assert tempo.beat_time(1.0) == first
    assert math.isclose(tempo.beat_at(tempo.beat_time(beat)), beat, rel_tol=1e-9)
    assert math.isclose(tempo.beat_time(beat + 1.0) - tempo.beat_time(beat), 60.0 / bpm,
                        rel_tol=1e-6, abs_tol=1e-9)
    assert tempo.beat_time(beat + 0.5) > tempo.beat_time(beat)

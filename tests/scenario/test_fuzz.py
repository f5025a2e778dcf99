"""Fuzzing the compiler: no input raises anything; every problem is a positioned diagnostic."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dancebots.check import check_plan
from dancebots.diagnostics import Diagnostic, read_text_source, source_lines
from dancebots.plan.compile import compile_scenario

KEYWORDS = ["robots", "groups", "start", "row", "column", "triangle", "square", "move",
            "circle", "newVL", "newvl", "#", "# note", "Move", "mvoe", "tempo", "wait", "at",
            "by", "beat", "beats", "from", "music", "song.wav"]
NAMES = ["R1", "R2", "R3", "R4", "g1", "g2", "R1,R2", "R1;R2", "R1,R2;R3,R4", "R3,R4;R1,R2",
         "R1;R3", "R2;R4", "R1,R3", "R1,,R2", ";", ",", "R5", "\x00", "é"]
NUMBERS = ["0", "1", "-1", "2.5", "90", "-45", "270", "0.1", "1.2", "1;1", "1,1", "1e308",
           "nan", "inf", "-inf", "1,5", "1000", "360", "-3", "1e-9", ".5", "5.", "+2", "1e3"]
HOSTILE = ["5e-324", "-5e-324", "1e-300", "1e-320", "-0", "-0.0", "1" + "0" * 400, "36000",
           "-1000", "999.999", "0.001", "0.01", "10", "1e-3", "NaN", "Infinity", "0x10", "1_0",
           "١", "1e99999", "0:12.5", "1:02", "59:59.9", "60:00", "1:60", ":5", "1:", "9" * 30 +
           ":00", "at 1e308", "at beat 1e308", "at beat 0", "by beat 1"]

token = st.sampled_from(KEYWORDS + NAMES + NUMBERS + HOSTILE)
line = st.lists(token, min_size=0, max_size=6).map(" ".join)
header = st.sampled_from([
    "robots R1 R2 R3 R4\n",
    "robots R1 R2 R3 R4\ntempo 120\n",
    "robots R1 R2\ntempo 600 from 3599 music m.wav\n",
    "robots R1 R2 R3 R4\ntempo 10\ngroups\ng1 R1 R3\ng2 R2 R4\nstart\n",
    "robots R1 R2 R3 R4\ngroups\ng1 R1 R3\ng2 R2 R4\nstart\n",
    "robots R1 R2\n",
    "",
])
formation = st.sampled_from([
    "square R1,R2;R3,R4 1.2 1;1\n", "row R1,R2,R3,R4 0 1\n", "row R1,R2 0 1.2\n",
    "column R1;R3 1.2 0\ncolumn R2;R4 1.2 0\nnewVL\n", "",
])


def assert_well_formed(diagnostics: list[Diagnostic], text: str) -> None:
    """Every diagnostic points at a real line and column of ``text``."""
    lines = max(1, len(source_lines(text)))
    for d in diagnostics:
        assert isinstance(d, Diagnostic)
        assert d.message
        assert 1 <= d.line <= lines, d.headline()
        assert d.col >= 1, d.headline()
        assert "Traceback" not in d.format(source_lines(text))


def compile_and_check(text: str) -> None:
    _, plan, diagnostics = compile_scenario(text, "fuzz.dance")
    assert_well_formed(diagnostics, text)
    if any(d.is_error for d in diagnostics):
        assert plan is None
    if plan is not None:
        report = check_plan(plan)
        assert_well_formed(list(report.diagnostics), text)
        assert report.duration >= 0.0


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(header, formation, st.lists(line, max_size=12))
def test_random_token_streams_give_only_diagnostics(head: str, shape: str,
                                                    body: list[str]) -> None:
    compile_and_check(head + shape + "\n".join(body))


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=400))
def test_random_bytes_give_only_diagnostics(data: bytes) -> None:
    text, problems = read_text_source("fuzz.dance", data)
    assert_well_formed(problems, data.decode("utf-8", errors="replace"))
    if text is not None:
        compile_and_check(text)


@settings(max_examples=200, deadline=None)
@given(st.text(max_size=300))
def test_random_text_gives_only_diagnostics(text: str) -> None:
    compile_and_check(text)


@settings(max_examples=100, deadline=None)
@given(st.lists(st.sampled_from(["move 1 0", "move 0.5 30", "move 1 -60", "circle 2 45 0.2",
                                 "circle -1.5 90 0.1", "move 0 90", "move 0 0"]), max_size=8))
def test_valid_random_shows_plan_and_check(moves: list[str]) -> None:
    text = "robots R1 R2\nrow R1,R2 0 1.2\n" + "\n".join(moves) + "\n"
    scenario, plan, diagnostics = compile_scenario(text, "fuzz.dance")
    assert plan is not None, diagnostics
    assert len(scenario.instructions) == 1 + len(moves)  # type: ignore[union-attr]
    compile_and_check(text)


BREAKS = ["\n", "\r\n", "\r", "\x0b", "\x0c", "\x1c", "\x1d", "\x1e", "\x85", "\u2028",
          "\u2029"]


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(line, st.sampled_from(BREAKS)), max_size=10))
def test_odd_line_breaks_never_move_a_diagnostic_past_the_last_line(
        parts: list[tuple[str, str]]) -> None:
    text = "robots R1 R2 R3 R4\n" + "".join(body + brk for body, brk in parts)
    compile_and_check(text)


@settings(max_examples=100, deadline=None)
@given(st.lists(st.sampled_from(["move 1000 0", "move 999 180", "circle 1000 36000 10",
                                 "circle 0.01 36000 0.001", "circle -1000 360 0.001",
                                 "move 0 360", "circle 5 36000 0.01"]), min_size=1, max_size=6))
def test_long_shows_are_refused_in_closed_form(moves: list[str]) -> None:
    """Whatever its numbers, a show compiles or is refused before its leader runs for more
    than the longest show; either way only diagnostics come out."""
    compile_and_check("robots R1 R2\nrow R1,R2 0 1.2\n" + "\n".join(moves) + "\n")


CUES = ["", " at 0", " at 1e-300", " by 5", " at 0:30", " by 59:59.9", " at 3600", " by 3600",
        " at beat 1", " by beat 9", " at beat 7200", " by beat 1e6", " at 1", " by 0.05"]


@settings(max_examples=80, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(["move 1 0", "move 3 90", "circle 2 45 0.2",
                                           "wait 1e-300", "wait 2", "wait 4 beats",
                                           "wait 3600", "move 1000 0", "move 0 180"]),
                          st.sampled_from(CUES)), min_size=1, max_size=5))
def test_cued_shows_with_hostile_times_plan_or_say_why(parts: list[tuple[str, str]]) -> None:
    """Cues at 0 s, at the last second of the longest show, on beats past its end, waits of
    1e-300 s and of an hour: every show plans (missed cues are warnings at the cue) or is
    refused with a positioned error, in bounded time."""
    compile_and_check("robots R1 R2\ntempo 120\nrow R1,R2 0 1.2\n"
                      + "\n".join(body + cue for body, cue in parts) + "\n")

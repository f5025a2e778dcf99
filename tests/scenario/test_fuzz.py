"""Fuzzing the compiler: no input raises anything; every problem is a positioned diagnostic."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dancebots.check import check_plan, compile_scenario
from dancebots.diagnostics import Diagnostic, read_text_source

KEYWORDS = ["robots", "groups", "start", "row", "column", "triangle", "square", "move",
            "circle", "newVL", "newvl", "#", "# note", "Move", "mvoe"]
NAMES = ["R1", "R2", "R3", "R4", "g1", "g2", "R1,R2", "R1;R2", "R1,R2;R3,R4", "R3,R4;R1,R2",
         "R1;R3", "R2;R4", "R1,R3", "R1,,R2", ";", ",", "R5", "\x00", "é"]
NUMBERS = ["0", "1", "-1", "2.5", "90", "-45", "270", "0.1", "1.2", "1;1", "1,1", "1e308",
           "nan", "inf", "-inf", "1,5", "1000", "360", "-3", "1e-9", ".5", "5.", "+2", "1e3"]

token = st.sampled_from(KEYWORDS + NAMES + NUMBERS)
line = st.lists(token, min_size=0, max_size=6).map(" ".join)
header = st.sampled_from([
    "robots R1 R2 R3 R4\n",
    "robots R1 R2 R3 R4\ngroups\ng1 R1 R3\ng2 R2 R4\nstart\n",
    "robots R1 R2\n",
    "",
])
formation = st.sampled_from([
    "square R1,R2;R3,R4 1.2 1;1\n", "row R1,R2,R3,R4 0 1\n", "row R1,R2 0 1.2\n",
    "column R1;R3 1.2 0\ncolumn R2;R4 1.2 0\nnewVL\n", "",
])


def assert_well_formed(diagnostics: list[Diagnostic], text: str) -> None:
    lines = max(1, len(text.splitlines()))
    for d in diagnostics:
        assert isinstance(d, Diagnostic)
        assert d.message
        assert 0 <= d.line <= lines + 1
        assert d.col >= (1 if d.line else 0)
        assert "Traceback" not in d.format(text.splitlines())


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
    assert_well_formed(problems, "")
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

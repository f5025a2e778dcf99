"""Hostile numbers and sizes: each is a positioned diagnostic with a hint, never a traceback,
found before anything is planned (issue 10, part 2)."""

from __future__ import annotations

import pytest

from dancebots.check import check_plan
from dancebots.diagnostics import Diagnostic, source_lines
from dancebots.plan.compile import compile_scenario
from dancebots.scenario import parse_scenario

HEAD = "robots A B\nrow A,B 0 1.2\n"


def only_error(text: str) -> Diagnostic:
    _, plan, diagnostics = compile_scenario(text, "hostile.dance")
    assert plan is None
    [diagnostic] = diagnostics
    assert diagnostic.is_error
    assert diagnostic.line >= 1
    assert diagnostic.col >= 1
    return diagnostic


@pytest.mark.parametrize(("body", "col", "message"), [
    ("circle 1 90 5e-324", 13, "the angular speed must be at least 0.001, not 5e-324"),
    ("circle 1 90 1e-300", 13, "the angular speed must be at least 0.001, not 1e-300"),
    ("circle 1 90 0", 13, "the angular speed must be greater than 0, not 0"),
    ("circle 1 90 -0", 13, "the angular speed must be greater than 0, not -0"),
    ("circle 1 90 nan", 13, "the angular speed must be a finite number, not 'nan'"),
    ("circle 1 90 1e308", 13, "the angular speed must be at most 10, not 1e308"),
    ("circle 1e-300 90 1", 8, "the circle radius must be at least 0.1 m in size, not 1e-300"),
    ("circle -5e-324 90 1", 8, "the circle radius must be at least 0.1 m in size, not -5e-324"),
    ("circle -0 90 1", 8, "the circle radius must not be 0"),
    ("circle 1 0 1", 10, "the central angle must be greater than 0, not 0"),
    ("move 1" + "0" * 400 + " 0", 6, "the move distance 1" + "0" * 400 + " is too large"),
    ("move 1 inf", 8, "the move angle must be a finite number, not 'inf'"),
    ("move 1 -1e308", 8, "the move angle must be at least -360, not -1e308"),
])
def test_hostile_numbers_are_positioned_errors(body: str, col: int, message: str) -> None:
    diagnostic = only_error(HEAD + body + "\n")
    assert (diagnostic.line, diagnostic.col, diagnostic.message) == (3, col, message)


def test_hostile_numbers_have_a_hint_where_one_helps() -> None:
    assert only_error(HEAD + "circle 1e-300 90 1\n").hint == (
        "for a turn on the spot use `move 0 ANGLE`")


def test_tiny_positive_numbers_are_harmless_where_zero_is_allowed() -> None:
    _, plan, diagnostics = compile_scenario(
        "robots A B\nrow A,B 5e-324 1.2\nmove 5e-324 1e-300\ncircle 0.1 1e-300 10\n",
        "tiny.dance")
    assert plan is not None, diagnostics
    assert plan.duration < 1.0


def test_ten_thousand_robots_are_refused_at_the_robots_line() -> None:
    names = [f"R{i}" for i in range(10_000)]
    text = "robots " + " ".join(names) + "\nrow " + ",".join(names) + " 0 1.2\nmove 2 0\n"
    scenario, diagnostics = parse_scenario(text, "crowd.dance")
    assert scenario is None
    first = diagnostics[0]
    assert (first.line, first.col) == (1, 8 + sum(len(n) + 1 for n in names[:1000]))
    assert first.message == "a show has at most 1000 robots, this line lists 10000"
    assert first.hint == "split the show into several shows"
    assert all(d.line >= 1 and d.col >= 1 for d in diagnostics)


def test_a_thousand_robots_compile_and_check() -> None:
    names = [f"R{i}" for i in range(1000)]
    text = "robots " + " ".join(names) + "\nrow " + ",".join(names) + " 0 1.2\nmove 2 0\n"
    _, plan, diagnostics = compile_scenario(text, "crowd.dance")
    assert plan is not None, diagnostics[:3]
    report = check_plan(plan)
    assert report.min_clearance == pytest.approx(0.6)
    assert report.diagnostics == ()


@pytest.mark.parametrize("separator", ["\x0c", "\x1c", "\x1d", "\x1e", "\x85", "\u2028",
                                       "\u2029", "\x0b"])
def test_only_newlines_end_lines(separator: str) -> None:
    """`row A,B 0 1.2<FF>move -1 0` is one line: its diagnostics are on line 2 of 2."""
    text = f"robots A B\nrow A,B 0 1.2{separator}move -1 0"
    assert len(source_lines(text)) == 2
    _, _, diagnostics = compile_scenario(text, "ff.dance")
    assert diagnostics
    assert all(d.line == 2 for d in diagnostics), [d.headline() for d in diagnostics]


@pytest.mark.parametrize("newline", ["\n", "\r\n", "\r"])
def test_every_newline_convention_counts_lines_alike(newline: str) -> None:
    text = newline.join(["robots A B", "row A,B 0 1.2", "move -1 0", ""])
    _, _, diagnostics = compile_scenario(text, "nl.dance")
    assert [(d.line, d.col) for d in diagnostics] == [(3, 6)]


def test_only_the_first_hundred_unknown_names_get_a_suggestion() -> None:
    """A "did you mean" search compares a name with every robot: after 100 of them the
    unknown names are reported without one, so a file of unknown names stays cheap."""
    names = [f"R{i}" for i in range(1000)]
    text = "robots " + " ".join(names) + "\nrow " + ",".join(f"R{i}x" for i in range(150)) + \
        " 0 1.2\n"
    _, diagnostics = parse_scenario(text, "typos.dance")
    unknown = [d for d in diagnostics if d.message.startswith("unknown robot")]
    assert len(unknown) == 150
    listing = "the robots are " + " ".join(names[:20]) + " and 980 more"
    assert unknown[0].hint == "did you mean 'R0'? " + listing
    assert unknown[99].hint == "did you mean 'R99'? " + listing
    assert unknown[100].hint == listing


def test_a_list_of_active_formations_is_cut_short() -> None:
    names = [f"R{i}" for i in range(12)]
    text = ("robots " + " ".join(names) + "\nrow " + ",".join(names) + " 0 1.2\n"
            + "".join(f"row R{i} 0 0\n" for i in range(7)) + "move 1 0\n")
    _, diagnostics = parse_scenario(text, "split.dance")
    assert diagnostics[-1].message == (
        "8 formations are active (R7 R8 R9 R10 R11 | R0 | R1 | R2 | R3 | and 3 more); name the "
        "group this instruction moves")

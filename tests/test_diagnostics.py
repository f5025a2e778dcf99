"""Diagnostics show a readable piece of a very long source line, the caret on the problem."""

from __future__ import annotations

from dancebots.diagnostics import MAX_SNIPPET, Diagnostic, Severity

LINE = "row " + ",".join(f"R{i}" for i in range(300)) + " 0 x"


def caret_text(diagnostic: Diagnostic) -> tuple[str, str]:
    """The text shown under the caret, and the shown line."""
    _, shown, carets = diagnostic.format(["robots", LINE]).splitlines()[:3]
    start = carets.index("^")
    return shown[start:start + carets.count("^")], shown


def test_a_short_line_is_shown_whole() -> None:
    text = Diagnostic("a.dance", 1, 1, Severity.ERROR, "m", end_col=7).format(["robots"])
    assert text.splitlines()[1:] == ["    1 | robots", "      | ^^^^^^"]


def test_long_lines_are_cut_around_the_problem() -> None:
    for col, width in ((5, 2), (600, 3), (len(LINE), 1), (len(LINE) - 2, 1)):
        under, shown = caret_text(Diagnostic("a.dance", 2, col, Severity.ERROR, "m",
                                             end_col=col + width))
        assert under == LINE[col - 1:col - 1 + width]
        assert len(shown) <= len("    2 | ") + MAX_SNIPPET + 6
    assert caret_text(Diagnostic("a.dance", 2, 600, Severity.ERROR, "m"))[1].startswith(
        "    2 | ...")

"""The choreography language of thesis ch. 6: text -> :class:`Scenario` + diagnostics.

The grammar and every decision about the thesis's ambiguities are in ``docs/language.md``.
The parser never raises on any input: it reports every problem it finds in one pass as a
:class:`Diagnostic` and returns ``None`` instead of a scenario when there is an error.
"""

from __future__ import annotations

import difflib
import itertools
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Literal

from dancebots.diagnostics import Diagnostic, Severity, source_lines
from dancebots.scenario.model import (
    Circle,
    Cue,
    Formation,
    Instruction,
    Move,
    Scenario,
    Shape,
    Span,
    Tempo,
    Wait,
)

__all__ = ["IDENTIFIER", "MAX_DISTANCE", "MAX_ROBOTS", "MAX_TIME", "MIN_RADIUS", "TEMPO_RANGE",
           "parse_scenario"]

MAX_DISTANCE = 1000.0
"""Largest accepted length in m (move distance, radius, row distance, spacing)."""
MAX_OMEGA = 10.0
"""Largest accepted desired angular speed of a circle in rad/s."""
MIN_OMEGA = 0.001
"""Smallest accepted desired angular speed of a circle in rad/s (a turn in 105 min)."""
MAX_ARC_DEGREES = 36000.0
"""Largest accepted central angle of a circle in degrees (100 turns)."""
MIN_RADIUS = 0.1
"""Smallest accepted circle radius in m (|r|). The leader's tightest turn has the radius
MIN_LINEAR / ANGULAR_LIMIT = 0.1 / (pi / 2) = 0.064 m (eq. 4.1a, 4.1b): a leader that must
steer back onto a tighter arc could only orbit it."""
MAX_SUGGESTIONS = 100
"""At most this many unknown names of a file get a "did you mean" hint."""
MAX_ROBOTS = 1000
"""Most robots a show may list: the cost of checking grows with robots x show length."""
MAX_TIME = 3600.0
"""Latest show time (s) a cue, a tempo's first beat or a wait may name: the longest show
that is planned (``PlanParameters.max_duration``)."""
TEMPO_RANGE = (10.0, 600.0)
"""Accepted tempos, beats per minute."""

_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?\Z")
_NONFINITE = re.compile(r"[+-]?(?:nan|inf|infinity)\Z", re.IGNORECASE)
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_.-]*\Z")
"""A robot or group name of the language: an ASCII letter or _ then letters, digits, _ . -"""
_SHAPES = {shape.value: shape for shape in Shape}
_KEYWORDS = ("robots", "groups", "start", "tempo", "move", "circle", "wait", "newVL", *_SHAPES)
_CUES = ("at", "by")
_RESERVED = {k.lower() for k in _KEYWORDS} | set(_CUES)
_CLOCK = re.compile(r"(\d{1,4}):([0-5]\d(?:\.\d*)?)\Z")
"""A time written ``M:SS`` or ``M:SS.s`` (up to 4 digits of minutes, then seconds below
60; longer ones are no time: at most 1 h is accepted, and ``int`` refuses thousands of
digits)."""


@dataclass(frozen=True, slots=True)
class _Token:
    text: str
    col: int  # 1-based column of the first character

    @property
    def end(self) -> int:
        return self.col + len(self.text)


def _quote(text: str) -> str:
    """``'text'`` for display; control characters escaped, long text cut."""
    short = text[:40]
    return f"'{short}'" if short.isprintable() else repr(short)


def _tokenize(line: str) -> list[_Token]:
    return [_Token(m.group(), m.start() + 1) for m in re.finditer(r"[^ \t\f\v]+", line)]


@dataclass
class _State:
    """Mutable bookkeeping of one parse; never escapes :func:`parse_scenario`."""

    path: str
    diagnostics: list[Diagnostic] = field(default_factory=list)
    robots: tuple[str, ...] | None = None
    robots_known: bool = False  # False after a broken robots line: no unknown-robot errors
    robots_span: Span = field(default_factory=lambda: Span(1))
    robot_set: frozenset[str] = frozenset()  # the robots, for lookups in O(1)
    suggestions: int = 0  # "did you mean" searches made (each costs the names it compares)

    def close_match(self, name: str, known: Sequence[str]) -> str | None:
        """The known name most like ``name`` for a "did you mean" hint; None when there is
        none, or after :data:`MAX_SUGGESTIONS` searches (a file of thousands of unknown
        names would otherwise cost names x known names)."""
        if self.suggestions >= MAX_SUGGESTIONS:
            return None
        self.suggestions += 1
        close = difflib.get_close_matches(name, known, n=1)
        return close[0] if close else None
    groups: dict[str, tuple[str, ...]] = field(default_factory=dict)
    instructions: list[Instruction] = field(default_factory=list)
    formations: list[frozenset[str]] = field(default_factory=list)  # active formations
    block: list[int] = field(default_factory=list)  # indices of the last formation block
    placed: bool = False  # a first formation (of every robot) has been seen
    tempo: Tempo | None = None
    uncertain: bool = False  # an earlier formation line was broken: skip resolution errors

    def error(self, line: int, col: int, message: str, hint: str | None = None,
              end_col: int | None = None) -> None:
        self.diagnostics.append(
            Diagnostic(self.path, line, col, Severity.ERROR, message, hint, end_col))

    def warning(self, line: int, col: int, message: str, hint: str | None = None,
                end_col: int | None = None) -> None:
        self.diagnostics.append(
            Diagnostic(self.path, line, col, Severity.WARNING, message, hint, end_col))


def parse_scenario(text: str, path: str = "<scenario>") -> tuple[Scenario | None, list[Diagnostic]]:
    """Parse choreography text. Returns (scenario or None if any error, all diagnostics)."""
    state = _State(path)
    section = "header"
    lines = source_lines(text)
    last_line = len(lines)
    for number, raw in enumerate(lines, start=1):
        tokens = _tokenize(raw)
        if not tokens:
            continue
        head = tokens[0]
        if head.text.startswith("#"):
            continue  # a comment on its own line (thesis ch. 6: "# ...")
        for token in tokens[1:]:
            if "#" in token.text:
                col = token.col + token.text.index("#")
                state.error(number, col, "a comment must be on a line of its own",
                            "move the comment to the line above")
                tokens = [t for t in tokens if t.col < col]
                break
        if not tokens:
            continue
        keyword = tokens[0].text
        if section == "header":
            if keyword == "robots":
                _parse_robots(state, number, tokens)
                section = "body"
                continue
            state.error(number, head.col, "a scenario must begin with the list of its robots",
                        "start the file with a line like `robots R1 R2 R3 R4`", head.end)
            section = "body"
        if keyword == "robots":
            state.error(number, head.col, "the robots are already listed",
                        "list every robot on the first `robots` line", head.end)
        elif keyword == "groups":
            if section == "groups" or state.groups:
                state.error(number, head.col, "there is only one groups section", None, head.end)
            elif state.instructions:
                state.error(number, head.col,
                            "the groups section must come before the first formation",
                            "move the groups section right after the robots line", head.end)
            else:
                _expect_no_arguments(state, number, tokens)
            section = "groups"
        elif keyword == "start":
            _expect_no_arguments(state, number, tokens)
            if section != "groups" and state.instructions:
                state.error(number, head.col, "`start` belongs after the groups section",
                            "remove this line", head.end)
            section = "body"
        elif keyword == "tempo":
            _parse_tempo(state, number, tokens)
            if section == "groups":
                state.error(number, head.col, "the groups section is not closed by `start`",
                            "declare the tempo before `groups`, or close the groups with "
                            "`start` first", head.end)
                section = "body"
        elif section == "groups" and keyword.lower() not in _RESERVED:
            _parse_group(state, number, tokens)
        else:
            if section == "groups":
                state.error(number, head.col, "the groups section is not closed by `start`",
                            "add a line `start` after the last group", head.end)
                section = "body"
            _parse_instruction(state, number, tokens)
    if section == "header":
        state.error(max(1, last_line), 1, "the scenario is empty",
                    "begin with `robots R1 R2`, a formation and moves; `dancebots demo` "
                    "prints a commented example")
    elif section == "groups":
        state.error(last_line, 1, "the groups section is not closed by `start`",
                    "add a line `start` after the last group")
    elif state.robots is not None and not state.placed and not state.uncertain:
        state.error(last_line, 1, "the scenario has no formation",
                    "add a formation of every robot, e.g. `row "
                    + ",".join(state.robots[:4]) + " 0 1.2`")
    if any(d.is_error for d in state.diagnostics) or state.robots is None:
        return None, state.diagnostics
    scenario = Scenario(path, state.robots, tuple(state.groups.items()),
                        tuple(state.instructions), state.robots_span, state.tempo)
    return scenario, state.diagnostics


def _expect_no_arguments(state: _State, line: int, tokens: Sequence[_Token]) -> None:
    if len(tokens) > 1:
        state.error(line, tokens[1].col, f"`{tokens[0].text}` takes no arguments",
                    f"put `{tokens[0].text}` alone on its line", tokens[-1].end)


def _check_identifier(state: _State, line: int, token: _Token, what: str) -> bool:
    if token.text.lower() in _RESERVED:
        state.error(line, token.col, f"'{token.text}' is a keyword and cannot name a {what}",
                    f"choose another {what} name", token.end)
        return False
    if not IDENTIFIER.match(token.text):
        state.error(line, token.col, f"invalid {what} name {_quote(token.text)}",
                    f"a {what} name is a letter or '_' followed by letters, digits, '_', '-' "
                    "or '.'", token.end)
        return False
    return True


def _parse_robots(state: _State, line: int, tokens: Sequence[_Token]) -> None:
    roles: dict[str, None] = {}
    ok = True
    state.robots_span = Span(line, tokens[0].col, tokens[0].end)
    if len(tokens) - 1 > MAX_ROBOTS:
        extra = tokens[MAX_ROBOTS + 1]
        state.error(line, extra.col, f"a show has at most {MAX_ROBOTS} robots, this line lists "
                    f"{len(tokens) - 1}", "split the show into several shows", tokens[-1].end)
        tokens = tokens[:MAX_ROBOTS + 1]
        ok = False
    for token in tokens[1:]:
        if not _check_identifier(state, line, token, "robot"):
            ok = False
            continue
        if token.text in roles:
            state.error(line, token.col, f"robot '{token.text}' is listed twice",
                        "every robot role must be unique", token.end)
            ok = False
            continue
        roles[token.text] = None
    if len(tokens) == 1:
        state.error(line, tokens[0].end, "the robots line lists no robots",
                    "name the robots: `robots R1 R2 R3 R4`")
        ok = False
    state.robots = tuple(roles)
    state.robot_set = frozenset(roles)
    state.robots_known = ok


def _parse_group(state: _State, line: int, tokens: Sequence[_Token]) -> None:
    name = tokens[0]
    if not _check_identifier(state, line, name, "group"):
        return
    if name.text in state.groups:
        state.error(line, name.col, f"group '{name.text}' is defined twice",
                    "give every group a unique name", name.end)
        return
    if state.robots is not None and name.text in state.robots:
        state.error(line, name.col, f"'{name.text}' is a robot and cannot name a group",
                    "choose another group name", name.end)
        return
    if len(tokens) == 1:
        state.error(line, name.end, f"group '{name.text}' has no robots",
                    f"list its robots: `{name.text} R1 R2`")
        return
    members: list[str] = []
    for token in tokens[1:]:
        if _known_robot(state, line, token) and token.text in members:
            state.error(line, token.col, f"robot '{token.text}' is listed twice in the group",
                        None, token.end)
        members.append(token.text)
    state.groups[name.text] = tuple(members)


def _known_robot(state: _State, line: int, token: _Token | tuple[str, int]) -> bool:
    text, col = (token.text, token.col) if isinstance(token, _Token) else token
    if state.robots is None or text in state.robot_set:
        return True
    if not state.robots_known:
        return False
    close = state.close_match(text, state.robots)
    hint = f"did you mean '{close}'? " if close else ""
    state.error(line, col, f"unknown robot '{text}'",
                f"{hint}the robots are {_listing(state.robots)}", col + len(text))
    return False


def _parse_instruction(state: _State, line: int, tokens: Sequence[_Token]) -> None:
    head = tokens[0]
    keyword = head.text
    if keyword in _SHAPES:
        _parse_formation(state, line, tokens, _SHAPES[keyword])
        return
    if keyword.lower() == "newvl":
        _parse_new_vl(state, line, tokens)
        return
    if keyword in ("move", "circle", "wait"):
        if not state.placed and not state.uncertain:
            state.error(line, head.col, "the first instruction must be a formation",
                        "place the robots first, e.g. `row "
                        + ",".join((state.robots or ("R1", "R2"))[:4]) + " 0 1.2`", head.end)
            return
        # after a broken formation its own arguments are still checked (the group it moves
        # is not resolved: _resolve_group is silent while the formations are uncertain)
        state.block = []
        tokens, cue, ok = _split_cue(state, line, tokens)
        if keyword == "move":
            _parse_move(state, line, tokens, cue, ok)
        elif keyword == "circle":
            _parse_circle(state, line, tokens, cue, ok)
        else:
            _parse_wait(state, line, tokens, cue, ok)
        return
    close = difflib.get_close_matches(keyword.lower(), [k.lower() for k in _KEYWORDS], n=1)
    originals = {k.lower(): k for k in _KEYWORDS}
    hint = (f"did you mean `{originals[close[0]]}`?" if close else
            "an instruction is one of: row, column, triangle, square, newVL, move, circle, "
            "wait")
    state.error(line, head.col, f"unknown instruction {_quote(keyword)}", hint, head.end)


# --- numbers ---------------------------------------------------------------------------------

def _number(state: _State, line: int, text: str, col: int, what: str, *, low: float | None = None,
            high: float | None = None, positive: bool = False) -> float | None:
    """Parse a decimal number; report a diagnostic and return None when it is not acceptable."""
    end = col + len(text)
    if _NONFINITE.match(text):
        state.error(line, col, f"{what} must be a finite number, not '{text}'", None, end)
        return None
    if not _NUMBER.match(text):
        hint = "use a decimal point, not a comma" if re.fullmatch(r"[+-]?\d+,\d+", text) else None
        state.error(line, col, f"{what} must be a number, not {_quote(text)}", hint, end)
        return None
    value = float(text)
    if not math.isfinite(value):
        state.error(line, col, f"{what} {text} is too large", None, end)
        return None
    if positive and value <= 0:
        state.error(line, col, f"{what} must be greater than 0, not {text}", None, end)
        return None
    if low is not None and value < low:
        state.error(line, col, f"{what} must be at least {_fmt(low)}, not {text}", None, end)
        return None
    if high is not None and value > high:
        state.error(line, col, f"{what} must be at most {_fmt(high)}, not {text}", None, end)
        return None
    return value


def _listing(names: Sequence[str], shown: int = 20) -> str:
    """The first ``shown`` names separated by spaces, and how many more there are."""
    more = f" and {len(names) - shown} more" if len(names) > shown else ""
    return " ".join(names[:shown]) + more


def _values(count: int) -> str:
    return f"{count} value" + ("" if count == 1 else "s")


def _fmt(value: float) -> str:
    return f"{value:g}"


def _split(text: str, col: int, sep: str) -> list[tuple[str, int]]:
    """Split ``text`` (starting at ``col``) on ``sep``; returns (part, column) pairs."""
    parts: list[tuple[str, int]] = []
    for part in text.split(sep):
        parts.append((part, col))
        col += len(part) + 1
    return parts


# --- formations ------------------------------------------------------------------------------

_FORMATION_USAGE = {
    Shape.ROW: "row R1,R2 0 1.2",
    Shape.COLUMN: "column R1;R2 1.2 0",
    Shape.TRIANGLE: "triangle R1;R2,R3 1.2 1",
    Shape.SQUARE: "square R1,R2;R3,R4 1.2 1;1",
}


def _parse_formation(state: _State, line: int, tokens: Sequence[_Token], shape: Shape) -> None:
    head = tokens[0]
    usage = (f"write `{shape.value} ARRANGEMENT ROW_DISTANCES SPACINGS` without spaces inside "
             f"the lists, e.g. `{_FORMATION_USAGE[shape]}`")
    if len(tokens) != 4:
        state.error(line, head.col, f"{shape.value} takes 3 values (arrangement, row distances, "
                    f"spacings), found {len(tokens) - 1}", usage, tokens[-1].end)
        state.uncertain = True
        state.block = []
        return
    arrangement, distances_token, spacings_token = tokens[1], tokens[2], tokens[3]
    rows = _parse_arrangement(state, line, arrangement)
    if rows is None:
        state.uncertain = True
        state.block = []
        return
    ok = _check_shape(state, line, arrangement, shape, rows)
    row_distances = _parse_row_distances(state, line, distances_token, rows)
    spacings = _parse_spacings(state, line, spacings_token, rows)
    robots = frozenset(r for row in rows for r in row)
    if not state.placed and state.robots is not None and state.robots_known:
        missing = [r for r in state.robots if r not in robots]
        if missing:
            state.error(line, arrangement.col,
                        f"the first formation must place every robot; missing {' '.join(missing)}",
                        "list all robots in the first formation; split it later with "
                        "formations of fewer robots and `newVL`", arrangement.end)
            ok = False
    if not ok or row_distances is None or spacings is None:
        state.uncertain = True
        state.block = []
        return
    formation = Formation(shape, rows, row_distances, spacings, Span(line, head.col, head.end))
    # thesis ch. 6: the formation takes its robots out of their current formations; whatever is
    # left of those keeps moving as before (docs/language.md, "Formations over time").
    remaining = [f - robots for f in state.formations]
    state.formations = [f for f in remaining if f] + [robots]
    state.placed = True
    state.block.append(len(state.instructions))
    state.instructions.append(formation)


def _parse_arrangement(state: _State, line: int,
                       token: _Token) -> tuple[tuple[str, ...], ...] | None:
    rows: list[tuple[str, ...]] = []
    seen: set[str] = set()
    ok = True
    for row_text, row_col in _split(token.text, token.col, ";"):
        row: list[str] = []
        for role, col in _split(row_text, row_col, ","):
            if not role:
                state.error(line, col, "empty robot name in the arrangement",
                            "rows are separated by ';', robots in a row by ','", col + 1)
                ok = False
                continue
            if not IDENTIFIER.match(role):
                state.error(line, col, f"invalid robot name {_quote(role)} in the arrangement",
                            "rows are separated by ';', robots in a row by ','", col + len(role))
                ok = False
                continue
            if not _known_robot(state, line, (role, col)):
                ok = False
                continue
            if role in seen:
                state.error(line, col, f"robot '{role}' appears twice in the formation", None,
                            col + len(role))
                ok = False
                continue
            seen.add(role)
            row.append(role)
        rows.append(tuple(row))
    return tuple(rows) if ok else None


def _check_shape(state: _State, line: int, token: _Token, shape: Shape,
                 rows: tuple[tuple[str, ...], ...]) -> bool:
    counts = [len(row) for row in rows]
    described = " + ".join(str(c) for c in counts)
    problem: str | None = None
    if shape is Shape.ROW and len(rows) != 1:
        problem = f"a row has one row of robots, this arrangement has {len(rows)} rows"
    elif shape is Shape.COLUMN and any(c != 1 for c in counts):
        problem = f"a column has one robot per row, this arrangement has {described}"
    elif shape is Shape.TRIANGLE and (
        len(rows) < 2 or counts[0] != 1 or any(b <= a for a, b in itertools.pairwise(counts))
    ):
        problem = ("a triangle has one robot in the first row and more robots in each next row, "
                   f"this arrangement has {described}")
    elif shape is Shape.SQUARE and (len(rows) < 2 or counts[0] < 2 or len(set(counts)) != 1):
        problem = ("a square has two or more rows of the same number (at least 2) of robots, "
                   f"this arrangement has {described}")
    if problem is None:
        return True
    state.error(line, token.col, problem, _suggest_shape(counts), token.end)
    return False


def _suggest_shape(counts: Sequence[int]) -> str:
    if len(counts) == 1:
        return "use `row` for robots side by side"
    if all(c == 1 for c in counts):
        return "use `column` for robots one behind the other"
    if counts[0] == 1 and all(b > a for a, b in itertools.pairwise(counts)):
        return "use `triangle` for this arrangement"
    if len(set(counts)) == 1:
        return "use `square` for rows of equal size"
    return "rows are separated by ';', robots in a row by ','"


def _parse_row_distances(state: _State, line: int, token: _Token,
                         rows: tuple[tuple[str, ...], ...]) -> tuple[float, ...] | None:
    parts = _split(token.text, token.col, ",")
    gaps = len(rows) - 1
    expected = "1 value" if gaps <= 1 else f"1 value or {gaps} values"
    if len(parts) != 1 and len(parts) != gaps:
        state.error(line, token.col, f"{len(rows)} rows take {expected} of row distance, "
                    f"found {len(parts)}", "separate several row distances by ','", token.end)
        return None
    values = [_number(state, line, text, col, "the row distance", low=0.0, high=MAX_DISTANCE)
              for text, col in parts]
    if any(v is None for v in values):
        return None
    floats = [v for v in values if v is not None]
    if gaps == 0:
        if floats[0] != 0.0:
            state.warning(line, token.col, f"a single row has no row distance; {token.text} is "
                          "ignored", "write 0", token.end)
        return ()
    return tuple(floats) if len(floats) == gaps else tuple(floats[:1] * gaps)


def _parse_spacings(state: _State, line: int, token: _Token,
                    rows: tuple[tuple[str, ...], ...]) -> tuple[tuple[float, ...], ...] | None:
    parts = _split(token.text, token.col, ";")
    if len(parts) != 1 and len(parts) != len(rows):
        state.error(line, token.col, f"{len(rows)} rows take 1 or {len(rows)} spacings "
                    f"separated by ';', found {len(parts)}",
                    "give one spacing for all rows or one per row", token.end)
        return None
    per_row = parts if len(parts) == len(rows) else parts * len(rows)
    per_row_given = len(parts) == len(rows)
    all_single = all(len(row) == 1 for row in rows)
    result: list[tuple[float, ...]] = []
    ok = True
    reported: set[int] = set()  # one spacing text may apply to several rows: report it once
    for row, (text, col) in zip(rows, per_row, strict=True):
        values = _split(text, col, ",")
        gaps = len(row) - 1
        if len(values) != 1 and len(values) != gaps:
            if col not in reported:
                takes = "1 spacing" if gaps <= 1 else f"1 or {gaps} spacings separated by ','"
                state.error(line, col, f"a row of {len(row)} robots takes {takes}, found "
                            f"{len(values)}", None, col + len(text))
                reported.add(col)
            ok = False
            continue
        if col in reported:
            ok = False
            continue
        numbers = [_number(state, line, v, c, "the spacing", low=0.0, high=MAX_DISTANCE)
                   for v, c in values]
        if any(n is None for n in numbers):
            reported.add(col)
        if any(n is None for n in numbers):
            ok = False
            continue
        floats = [n for n in numbers if n is not None]
        if gaps == 0:
            if floats[0] != 0.0 and (per_row_given or all_single) and col not in reported:
                state.warning(line, col, f"a row of one robot has no spacing; {text} is ignored",
                              "write 0", col + len(text))
                reported.add(col)
            result.append(())
        else:
            result.append(tuple(floats) if len(floats) == gaps else tuple(floats * gaps))
    return tuple(result) if ok else None


def _parse_new_vl(state: _State, line: int, tokens: Sequence[_Token]) -> None:
    head = tokens[0]
    _expect_no_arguments(state, line, tokens)
    if not state.block:
        if not state.uncertain:
            state.error(line, head.col, "newVL must directly follow a formation description",
                        "put `newVL` on the line after the formation(s) whose virtual leader it "
                        "re-places", head.end)
        return
    span = Span(line, head.col, head.end)
    for index in state.block:
        formation = state.instructions[index]
        assert isinstance(formation, Formation)
        state.instructions[index] = replace(formation, new_vl=True, new_vl_span=span)
    state.block = []


# --- motion ----------------------------------------------------------------------------------

def _resolve_group(state: _State, line: int, token: _Token | None,
                   usage: str) -> tuple[str | None, tuple[str, ...]] | None:
    """The formation a motion instruction applies to: (group name or None, its robots)."""
    if token is None:
        if len(state.formations) == 1:
            only = state.formations[0]
            return None, tuple(r for r in (state.robots or ()) if r in only)
        if state.uncertain:
            return None
        listing = _formations_listing(state)
        names = _group_names_for(state)
        state.error(line, 1, f"{len(state.formations)} formations are active ({listing}); "
                    "name the group this instruction moves",
                    f"e.g. `{usage} {names[0]}`" if names else
                    "define groups for the formations in the groups section")
        return None
    name = token.text
    if name not in state.groups:
        if name in state.robot_set:
            state.error(line, token.col, f"'{name}' is a robot, not a group",
                        "instructions move groups; define a group of this robot in the groups "
                        "section", token.end)
            return None
        known = list(state.groups)
        close = state.close_match(name, known)
        hint = (f"did you mean '{close}'? " if close else "") + (
            f"the groups are {_listing(known)}" if known else
            "define it in a groups section closed by `start`")
        state.error(line, token.col, f"unknown group {_quote(name)}", hint, token.end)
        return None
    members = frozenset(state.groups[name])
    if members in state.formations:
        return name, _ordered(state, members)
    if state.uncertain:
        return None
    listing = _formations_listing(state)
    state.error(line, token.col, f"group '{name}' ({' '.join(state.groups[name])}) is not a "
                f"formation here; the formations are {listing}",
                f"describe a formation of exactly {' '.join(state.groups[name])} before moving "
                "the group", token.end)
    return None


def _ordered(state: _State, robots: frozenset[str]) -> tuple[str, ...]:
    return tuple(r for r in (state.robots or sorted(robots)) if r in robots)


def _group_names_for(state: _State) -> list[str]:
    active = set(state.formations)
    return [g for g, members in state.groups.items() if frozenset(members) in active]


def _formations_listing(state: _State, shown: int = 5) -> str:
    """The active formations' robots, ``a b | c d``: at most ``shown`` formations of at most
    8 robots each (a message stays short, and cheap, however many robots a show has)."""
    parts = [_listing(_ordered(state, f), 8) for f in state.formations[:shown]]
    if len(state.formations) > shown:
        parts.append(f"and {len(state.formations) - shown} more")
    return " | ".join(parts)


def _parse_move(state: _State, line: int, tokens: Sequence[_Token], cue: Cue | None = None,
                cue_ok: bool = True) -> None:
    head = tokens[0]
    usage = "move 2 -90"
    if len(tokens) not in (3, 4):
        state.error(line, head.col, f"move takes a distance in m, an angle in degrees and an "
                    f"optional group, found {_values(len(tokens) - 1)}",
                    f"e.g. `{usage}` or `{usage} group1`", tokens[-1].end)
        return
    distance = _number(state, line, tokens[1].text, tokens[1].col, "the move distance",
                       low=0.0, high=MAX_DISTANCE)
    angle = _number(state, line, tokens[2].text, tokens[2].col, "the move angle",
                    low=-360.0, high=360.0)
    if distance is None and tokens[1].text.startswith("-") and _NUMBER.match(tokens[1].text):
        state.diagnostics[-1] = replace(
            state.diagnostics[-1],
            hint="the virtual leader never reverses; turn around with an angle: `move 2 180`")
    target = _resolve_group(state, line, tokens[3] if len(tokens) == 4 else None, usage)
    if distance is None or angle is None or target is None or not cue_ok:
        return
    state.instructions.append(Move(distance, math.radians(angle), target[0], target[1],
                                   Span(line, head.col, head.end), cue))


def _parse_circle(state: _State, line: int, tokens: Sequence[_Token], cue: Cue | None = None,
                  cue_ok: bool = True) -> None:
    head = tokens[0]
    usage = "circle -3 270 0.1"
    if len(tokens) not in (4, 5):
        state.error(line, head.col, "circle takes a radius in m, a central angle in degrees, "
                    f"an angular speed in rad/s and an optional group, found "
                    f"{_values(len(tokens) - 1)}", f"e.g. `{usage}` or `{usage} group1`",
                    tokens[-1].end)
        return
    radius = _number(state, line, tokens[1].text, tokens[1].col, "the circle radius",
                     low=-MAX_DISTANCE, high=MAX_DISTANCE)
    if radius == 0.0:
        state.error(line, tokens[1].col, "the circle radius must not be 0",
                    "a positive radius puts the centre on the left, a negative one on the right",
                    tokens[1].end)
        radius = None
    elif radius is not None and abs(radius) < MIN_RADIUS:
        state.error(line, tokens[1].col, f"the circle radius must be at least {_fmt(MIN_RADIUS)} m "
                    f"in size, not {tokens[1].text}",
                    "for a turn on the spot use `move 0 ANGLE`", tokens[1].end)
        radius = None
    angle = _number(state, line, tokens[2].text, tokens[2].col, "the central angle",
                    positive=True, high=MAX_ARC_DEGREES)
    if angle is None and _NUMBER.match(tokens[2].text) and float(tokens[2].text) <= 0:
        state.diagnostics[-1] = replace(
            state.diagnostics[-1],
            hint="the central angle is positive; the sign of the radius sets the direction")
    omega = _number(state, line, tokens[3].text, tokens[3].col, "the angular speed",
                    positive=True, low=MIN_OMEGA, high=MAX_OMEGA)
    target = _resolve_group(state, line, tokens[4] if len(tokens) == 5 else None, usage)
    if radius is None or angle is None or omega is None or target is None or not cue_ok:
        return
    state.instructions.append(Circle(radius, math.radians(angle), omega, target[0], target[1],
                                     Span(line, head.col, head.end), cue))


# --- timing: tempo, cues, wait ----------------------------------------------------------------

def _parse_tempo(state: _State, line: int, tokens: Sequence[_Token]) -> None:
    """``tempo BPM [from TIME] [music FILE]``, once, before the first formation."""
    head = tokens[0]
    usage = "e.g. `tempo 120`, `tempo 120 from 0.35` or `tempo 120 music song.wav`"
    if state.tempo is not None:
        state.error(line, head.col, f"the tempo is already declared at line "
                    f"{state.tempo.span.line}", "declare the tempo once", head.end)
        return
    if state.instructions or state.placed:
        state.error(line, head.col, "the tempo belongs before the first formation",
                    "move this line up, right after the robots line", head.end)
        return
    if len(tokens) < 2:
        state.error(line, head.end, "the tempo needs its beats per minute", usage)
        return
    bpm = _number(state, line, tokens[1].text, tokens[1].col, "the tempo",
                  low=TEMPO_RANGE[0], high=TEMPO_RANGE[1])
    first_beat: float | None = 0.0
    music: str | None = None
    seen: set[str] = set()
    rest = list(tokens[2:])
    ok = bpm is not None
    while rest:
        word = rest.pop(0)
        if word.text not in ("from", "music"):
            state.error(line, word.col, f"unexpected {_quote(word.text)} in the tempo",
                        f"after the beats per minute come `from TIME` (when beat 1 is) and "
                        f"`music FILE`: {usage}", word.end)
            return
        if word.text in seen:
            state.error(line, word.col, f"`{word.text}` is given twice", None, word.end)
            return
        seen.add(word.text)
        if not rest:
            what = "a time: `from 0.35`" if word.text == "from" else "a file: `music song.wav`"
            state.error(line, word.end, f"`{word.text}` needs {what}")
            return
        value = rest.pop(0)
        if word.text == "from":
            first_beat = _time(state, line, value, "the first beat's time")
            ok = ok and first_beat is not None
        else:
            music = value.text
    if ok and bpm is not None and first_beat is not None:
        state.tempo = Tempo(bpm, first_beat, music, Span(line, head.col, tokens[-1].end))


def _time(state: _State, line: int, token: _Token, what: str) -> float | None:
    """A show time: seconds (``12.5``) or minutes and seconds (``0:12.5``), 0 to
    :data:`MAX_TIME`; a diagnostic and None when it is not one."""
    clock = _CLOCK.match(token.text)
    if clock:
        value = int(clock.group(1)) * 60.0 + float(clock.group(2))
        if value > MAX_TIME:
            state.error(line, token.col, f"{what} must be at most {_fmt(MAX_TIME)} s (1 h), "
                        f"not {token.text}", None, token.end)
            return None
        return value
    if ":" in token.text:
        state.error(line, token.col, f"{what} {_quote(token.text)} is not a time",
                    "write seconds (`12.5`) or minutes:seconds with two digits of seconds "
                    "below 60 (`1:02.5`)", token.end)
        return None
    return _number(state, line, token.text, token.col, what, low=0.0, high=MAX_TIME)


def _split_cue(state: _State, line: int, tokens: Sequence[_Token],
               ) -> tuple[Sequence[_Token], Cue | None, bool]:
    """A motion instruction's tokens without its cue (``at TIME``, ``by TIME``, ``at beat
    N``, ``by beat N`` at its end), the cue, and whether the cue was valid."""
    where = next((k for k, token in enumerate(tokens) if k > 0 and token.text in _CUES), None)
    if where is None:
        return tokens, None, True
    word, rest = tokens[where], tokens[where + 1:]
    kind: Literal["at", "by"] = "at" if word.text == "at" else "by"
    usage = (f"`{kind} 12.5`, `{kind} 0:12.5` (minutes:seconds) or `{kind} beat 32`")
    if not rest:
        state.error(line, word.end, f"`{kind}` needs a time", f"e.g. {usage}")
        return tokens[:where], None, False
    beat: float | None = None
    if rest[0].text == "beat":
        if len(rest) < 2:
            state.error(line, rest[0].end, "`beat` needs the beat's number", f"e.g. {usage}")
            return tokens[:where], None, False
        value_token = rest[1]
        extra = rest[2:]
        beat = _number(state, line, value_token.text, value_token.col, "the beat", low=1.0,
                       high=1e6)
        if beat is not None and state.tempo is None:
            state.error(line, rest[0].col, "a beat needs the show's tempo",
                        "declare it after the robots line: `tempo 120` (beats per minute)",
                        value_token.end)
            beat = None
        time = state.tempo.beat_time(beat) if beat is not None and state.tempo else None
        if time is not None and not 0.0 <= time <= MAX_TIME:
            state.error(line, value_token.col, f"beat {value_token.text} is at {time:.1f} s, "
                        f"outside the show (0 to {_fmt(MAX_TIME)} s)", None, value_token.end)
            time = None
        ok = time is not None
    else:
        value_token = rest[0]
        extra = rest[1:]
        time = _time(state, line, value_token, f"the `{kind}` time")
        ok = time is not None
    if extra:
        state.error(line, extra[0].col, f"unexpected {_quote(extra[0].text)} after the cue",
                    f"the cue ends the line: {usage}", extra[-1].end)
        ok = False
    if not ok or time is None:
        return tokens[:where], None, False
    return tokens[:where], Cue(kind, time, Span(line, word.col, value_token.end), beat), True


def _parse_wait(state: _State, line: int, tokens: Sequence[_Token], cue: Cue | None,
                cue_ok: bool) -> None:
    """``wait S [group]`` or ``wait N beats [group]`` (a cue already split off)."""
    head = tokens[0]
    usage = "wait 2"
    if len(tokens) < 2:
        state.error(line, head.end, "wait takes a duration in s (or `N beats`) and an "
                    "optional group", f"e.g. `{usage}`, `wait 4 beats` or `{usage} group1`")
        return
    rest = list(tokens[2:])
    in_beats = bool(rest) and rest[0].text in ("beats", "beat")
    if in_beats:
        rest.pop(0)
    if len(rest) > 1:
        state.error(line, rest[1].col, "wait takes a duration in s (or `N beats`) and an "
                    f"optional group, found more: {_quote(rest[1].text)}",
                    f"e.g. `{usage}`, `wait 4 beats` or `{usage} group1`", rest[-1].end)
        return
    amount = _number(state, line, tokens[1].text, tokens[1].col,
                     "the wait in beats" if in_beats else "the wait", positive=True,
                     high=MAX_TIME)
    duration = amount
    if amount is not None and in_beats:
        if state.tempo is None:
            state.error(line, tokens[2].col, "a wait in beats needs the show's tempo",
                        "declare it after the robots line: `tempo 120` (beats per minute), "
                        "or give the wait in seconds", tokens[2].end)
            duration = None
        else:
            duration = amount * 60.0 / state.tempo.bpm
            if duration > MAX_TIME:
                state.error(line, tokens[1].col, f"{tokens[1].text} beats last "
                            f"{duration:.0f} s, more than the longest show "
                            f"({_fmt(MAX_TIME)} s)", None, tokens[1].end)
                duration = None
    target = _resolve_group(state, line, rest[0] if rest else None, usage)
    if duration is None or target is None or not cue_ok:
        return
    state.instructions.append(Wait(duration, target[0], target[1],
                                   Span(line, head.col, head.end), cue,
                                   amount if in_beats else None))

"""The choreography as data: what the parser produces and the planner consumes.

Angles are in rad (the text's degrees are converted at parse time), lengths in m, angular
speeds in rad/s. Every instruction keeps the :class:`Span` of its source text.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Literal

__all__ = [
    "Circle",
    "Cue",
    "Formation",
    "Instruction",
    "Motion",
    "Move",
    "Scenario",
    "Shape",
    "Span",
    "Tempo",
    "Wait",
]


@dataclass(frozen=True, slots=True)
class Span:
    """A position in the source text: 1-based line, 1-based column, end column (exclusive)."""

    line: int
    col: int = 1
    end_col: int | None = None


@dataclass(frozen=True, slots=True)
class Cue:
    """When an instruction must start (``at``) or end (``by``): ``time`` in s of show time;
    ``beat``: the beat it was written as (None: written as a time); ``span``: the cue's
    text, from its ``at`` or ``by`` to its value."""

    kind: Literal["at", "by"]
    time: float
    span: Span
    beat: float | None = None


@dataclass(frozen=True, slots=True)
class Tempo:
    """``tempo BPM [from S] [music FILE]``: ``bpm`` beats per minute, beat 1 at show time
    ``first_beat`` s; ``music``: the music file that goes with the show, as written (relative
    to the scenario file), or None."""

    bpm: float
    first_beat: float
    music: str | None
    span: Span

    def beat_time(self, beat: float) -> float:
        """Show time (s) of ``beat`` (1 is the first beat; fractions between beats)."""
        return self.first_beat + (beat - 1.0) * 60.0 / self.bpm

    def beat_at(self, time: float) -> float:
        """The beat (1 the first, fractional between beats) at show time ``time`` s."""
        return 1.0 + (time - self.first_beat) * self.bpm / 60.0


class Shape(enum.Enum):
    """The four formation shapes of thesis ch. 6."""

    ROW = "row"
    COLUMN = "column"
    TRIANGLE = "triangle"
    SQUARE = "square"


@dataclass(frozen=True, slots=True)
class Formation:
    """A formation description (thesis ch. 6), normalised.

    ``rows[0]`` is the front row; in each row the first robot is the leftmost (largest y).
    ``row_distances[i]`` is the gap in m between row i and row i + 1 (len(rows) - 1 values).
    ``spacings[i][j]`` is the gap in m between robots j and j + 1 of row i (len(row) - 1 values).
    ``new_vl`` is true when a ``newVL`` line follows this description's block.
    """

    shape: Shape
    rows: tuple[tuple[str, ...], ...]
    row_distances: tuple[float, ...]
    spacings: tuple[tuple[float, ...], ...]
    span: Span
    new_vl: bool = False
    new_vl_span: Span | None = None

    @property
    def robots(self) -> tuple[str, ...]:
        """The robots of the formation, front row first, left to right."""
        return tuple(role for row in self.rows for role in row)


@dataclass(frozen=True, slots=True)
class Move:
    """``move x angle [group]``: rotate by ``angle`` (rad, CCW positive), then go ``distance``
    (m) along the new x axis, starting from the previous waypoint (thesis fig. 6.2a).

    ``robots`` is the formation the move applies to, resolved from the group at parse time.
    """

    distance: float
    angle: float
    group: str | None
    robots: tuple[str, ...]
    span: Span
    cue: Cue | None = None


@dataclass(frozen=True, slots=True)
class Circle:
    """``circle r angle omega [group]``: an arc of signed radius ``radius`` (m; > 0 centre on
    the left) over the central angle ``angle`` (rad, > 0) at the desired angular speed
    ``omega`` (rad/s, > 0) (thesis fig. 6.2b, eq. 4.2-4.3)."""

    radius: float
    angle: float
    omega: float
    group: str | None
    robots: tuple[str, ...]
    span: Span
    cue: Cue | None = None


@dataclass(frozen=True, slots=True)
class Wait:
    """``wait S [group]`` or ``wait N beats [group]``: the formation's virtual leader stands
    for ``duration`` s (an addition: a pause in place); ``beats``: the beats it was written
    as (None: seconds)."""

    duration: float
    group: str | None
    robots: tuple[str, ...]
    span: Span
    cue: Cue | None = None
    beats: float | None = None


Motion = Move | Circle | Wait
"""What a formation's virtual leader executes (its program)."""
Instruction = Formation | Move | Circle | Wait


@dataclass(frozen=True, slots=True)
class Scenario:
    """A parsed and resolved choreography.

    ``groups`` keeps the order of the groups section. ``instructions`` are in file order; the
    first one is a formation of every robot. ``robots_span`` is the ``robots`` line;
    ``tempo`` the show's tempo (None: none declared).
    """

    path: str
    robots: tuple[str, ...]
    groups: tuple[tuple[str, tuple[str, ...]], ...]
    instructions: tuple[Instruction, ...]
    robots_span: Span = Span(1)
    tempo: Tempo | None = None

    def group_robots(self, name: str) -> tuple[str, ...]:
        """The robots of a group, in the order the groups section lists them."""
        for group, members in self.groups:
            if group == name:
                return members
        raise KeyError(name)

"""Compiler-style diagnostics: ``file:line:col: error: message`` with an optional hint.

Every problem found in user input (choreographies, world files) is a :class:`Diagnostic`.
Positions are 1-based; ``col`` counts characters (a tab is one column). ``end_col`` marks the
end (exclusive) of the offending text for the caret line under the source snippet.
"""

from __future__ import annotations

import enum
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

__all__ = [
    "Diagnostic",
    "DiagnosticError",
    "Severity",
    "format_diagnostics",
    "has_errors",
    "read_source_file",
    "read_text_source",
    "source_lines",
]

MAX_INPUT_BYTES = 2 * 1024 * 1024
"""Text inputs larger than this are refused (a choreography of 2 MiB is ~200,000 lines)."""

MAX_SNIPPET = 100
"""Characters of a source line shown under a diagnostic; longer lines are cut around it."""

MAX_REPORTED = 100
"""At most this many diagnostics are printed; the rest are counted."""


class Severity(enum.Enum):
    """error: the input cannot be used; warning: it can, but something will look wrong or be
    unsafe; note: what dancebots decided for you (``check --strict`` ignores notes)."""

    ERROR = "error"
    WARNING = "warning"
    NOTE = "note"


@dataclass(frozen=True, slots=True)
class Diagnostic:
    """One problem at a position of a text input."""

    path: str
    line: int
    col: int
    severity: Severity
    message: str
    hint: str | None = None
    end_col: int | None = None

    @property
    def is_error(self) -> bool:
        return self.severity is Severity.ERROR

    def headline(self) -> str:
        """The one-line form ``path:line:col: severity: message`` (``path: ...`` if line is 0)."""
        where = f"{self.path}:{self.line}:{self.col}" if self.line > 0 else self.path
        return f"{where}: {self.severity.value}: {self.message}"

    def format(self, source_lines: Sequence[str] | None = None) -> str:
        """Headline, the source line with a caret under the problem (if given), and the hint."""
        parts = [self.headline()]
        if source_lines is not None and 1 <= self.line <= len(source_lines):
            text = _printable(source_lines[self.line - 1])
            if text.strip():
                col = self.col
                width = max(1, (self.end_col or col + 1) - col)
                if len(text) > MAX_SNIPPET:  # a window around the problem, marked with ...
                    start = max(0, min(col - 1 - MAX_SNIPPET // 3, len(text) - MAX_SNIPPET))
                    shown = text[start:start + MAX_SNIPPET]
                    prefix = "..." if start > 0 else ""
                    suffix = "..." if start + MAX_SNIPPET < len(text) else ""
                    text, col = prefix + shown + suffix, col - start + len(prefix)
                    width = min(width, max(1, len(prefix) + len(shown) - col + 1))
                gutter = f"{self.line:>5} | "
                parts.append(gutter + text)
                width = min(width, max(1, len(text) - col + 1))
                parts.append(" " * (len(gutter) - 2) + "| " + " " * (col - 1) + "^" * width)
        if self.hint:
            parts.append(f"  hint: {self.hint}")
        return "\n".join(parts)

    def to_json(self) -> dict[str, object]:
        return {
            "path": self.path,
            "line": self.line,
            "col": self.col,
            "severity": self.severity.value,
            "message": self.message,
            "hint": self.hint,
        }


class DiagnosticError(Exception):
    """Raised by loaders when an input is invalid; carries all its diagnostics."""

    def __init__(self, diagnostics: Sequence[Diagnostic]) -> None:
        self.diagnostics = tuple(diagnostics)
        super().__init__("\n".join(d.headline() for d in self.diagnostics))


def has_errors(diagnostics: Iterable[Diagnostic]) -> bool:
    return any(d.is_error for d in diagnostics)


def format_diagnostics(
    diagnostics: Sequence[Diagnostic], sources: Mapping[str, Sequence[str]] | None = None
) -> str:
    """All diagnostics sorted by position, at most :data:`MAX_REPORTED`, then a count line."""
    ordered = sorted(diagnostics, key=lambda d: (d.path, d.line, d.col, d.severity.value))
    shown = ordered[:MAX_REPORTED]
    blocks = [d.format((sources or {}).get(d.path)) for d in shown]
    hidden = len(ordered) - len(shown)
    if hidden:
        blocks.append(f"... and {hidden} more diagnostics not shown")
    errors = sum(d.is_error for d in ordered)
    notes = sum(d.severity is Severity.NOTE for d in ordered)
    warnings = len(ordered) - errors - notes
    if ordered:
        blocks.append(f"{_plural(errors, 'error')}, {_plural(warnings, 'warning')}"
                      + (f", {_plural(notes, 'note')}" if notes else ""))
    return "\n".join(blocks)


_LINE_BREAK = re.compile(r"\r\n|\r|\n")


def source_lines(text: str) -> list[str]:
    """The lines of a text input as positions count them: split at ``\\n``, ``\\r\\n`` and
    ``\\r`` only (``str.splitlines`` also splits at form feeds, ``\\x1c``-``\\x1e``,
    ``\\x85`` and ``\\u2028``, which would shift every later line number)."""
    lines = _LINE_BREAK.split(text)
    if lines and lines[-1] == "":
        lines.pop()
    return lines


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")


def _printable(text: str) -> str:
    """The line with control characters escaped so that a terminal shows it safely."""
    if text.isprintable():
        return text
    return "".join(ch if ch.isprintable() or ch == " " else "?" for ch in text)


def read_text_source(path: str, data: bytes) -> tuple[str | None, list[Diagnostic]]:
    """Decode UTF-8 input (an optional BOM is dropped); a decoding failure is a diagnostic.

    Returns (text, []) or (None, [diagnostic at the first invalid byte]).
    """
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        return data.decode("utf-8"), []
    except UnicodeDecodeError as exc:
        before = _LINE_BREAK.split(data[: exc.start].decode("utf-8"))  # valid up to there
        line, col = len(before), len(before[-1]) + 1
        bad = data[exc.start : exc.end].hex(" ")
        return None, [
            Diagnostic(
                path,
                line,
                col,
                Severity.ERROR,
                f"the file is not valid UTF-8 text (byte {bad} at byte offset {exc.start})",
                hint="save the file as UTF-8 text; binary files cannot be read",
            )
        ]


def read_source_file(path: str, missing_hint: str = "check the path; `dancebots demo` prints "
                     "an example") -> tuple[str | None, list[Diagnostic]]:
    """Read and decode a text input file; every failure is a diagnostic, never an exception.
    missing_hint: the hint when there is no such file (the default suits scenarios)."""

    def fail(message: str, hint: str | None = None) -> tuple[None, list[Diagnostic]]:
        return None, [Diagnostic(path, 0, 0, Severity.ERROR, message, hint)]

    try:
        with open(path, "rb") as handle:
            data = handle.read(MAX_INPUT_BYTES + 1)
    except FileNotFoundError:
        return fail("no such file", missing_hint)
    except IsADirectoryError:
        return fail("is a directory, not a file", "give the path of a file inside it")
    except PermissionError:
        return fail("permission denied", "make the file readable")
    except OSError as exc:
        return fail(f"cannot read the file: {exc.strerror or exc}")
    if len(data) > MAX_INPUT_BYTES:
        return fail(
            f"the file is larger than {MAX_INPUT_BYTES // (1024 * 1024)} MiB",
            "split the show into smaller files; is this the right file?",
        )
    return read_text_source(path, data)

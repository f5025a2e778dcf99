"""The golden corpus: valid files compile to their recorded plan summaries, invalid files
produce exactly their recorded diagnostics (tests/regenerate_golden.py rewrites both)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from dancebots.cli import main
from golden import INVALID_SOURCES, VALID_SOURCES, plan_summary


@pytest.mark.parametrize("path", VALID_SOURCES, ids=lambda p: p.name)
def test_valid_file_compiles_to_recorded_plan(path: Path) -> None:
    expected_file = Path(__file__).parent.parent / "data" / "scenarios" / "valid" / (
        path.stem + ".expected.json")
    expected = json.loads(expected_file.read_text(encoding="utf-8"))
    assert plan_summary(path) == expected


@pytest.mark.parametrize("path", INVALID_SOURCES, ids=lambda p: p.name)
def test_invalid_file_gives_recorded_diagnostics(
    path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(path.parent)
    status = main(["check", path.name])
    captured = capsys.readouterr()
    assert status == 2
    assert captured.err == path.with_suffix(".expected").read_text(encoding="utf-8")
    assert "Traceback" not in captured.err


def test_corpus_is_not_empty() -> None:
    assert len(VALID_SOURCES) >= 10
    assert len(INVALID_SOURCES) >= 10

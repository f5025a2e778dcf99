"""Refactorings change no behaviour: the golden runs' metrics.json and log.csv are
byte-identical to the stored ones (tests/golden_runs.py says how they were made)."""

from __future__ import annotations

from pathlib import Path

import pytest

from golden_runs import COMPARED, RUNS, run_into, stored

ROOT = Path(__file__).resolve().parents[1]


def first_difference(expected: bytes, got: bytes) -> str:
    """Where two outputs first differ, as a line number and both lines."""
    for number, (a, b) in enumerate(zip(expected.splitlines(), got.splitlines(),
                                        strict=False), start=1):
        if a != b:
            return f"line {number}:\n  golden: {a.decode()}\n  now:    {b.decode()}"
    return f"lengths differ: {len(expected)} vs {len(got)} bytes"


@pytest.mark.parametrize("name", sorted(RUNS))
def test_outputs_are_byte_identical(name: str, tmp_path: Path,
                                    monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)  # the runs name example files relative to the repository
    run_into(name, tmp_path / name)
    for file in COMPARED:
        got = (tmp_path / name / file).read_bytes()
        expected = stored(name, file)
        assert got == expected, f"{name}/{file} changed at {first_difference(expected, got)}"


def test_a_changed_output_is_caught_and_located() -> None:
    golden = stored("open_day", "log.csv")
    lines = golden.splitlines(keepends=True)
    changed = b"".join([*lines[:40], lines[40].replace(b",", b";", 1), *lines[41:]])
    assert changed != golden
    assert first_difference(golden, changed).startswith("line 41:")

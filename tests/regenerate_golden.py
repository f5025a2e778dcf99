"""Rewrite the golden files of tests/data/scenarios from the current code.

Run ``python tests/regenerate_golden.py`` only after a deliberate change of the output, and
read the diff: the golden files are the specification the tests hold the code to.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from dancebots.cli import main
from golden import DATA, VALID_SOURCES, plan_summary


def main_regenerate() -> None:
    invalid = DATA / "scenarios" / "invalid"
    os.chdir(invalid)
    for path in sorted(invalid.glob("*.dance")):
        err = io.StringIO()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            main(["check", path.name])
        path.with_suffix(".expected").write_text(err.getvalue(), encoding="utf-8")
    for path in VALID_SOURCES:
        target = DATA / "scenarios" / "valid" / (path.stem + ".expected.json")
        target.write_text(json.dumps(plan_summary(path), indent=2) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main_regenerate()

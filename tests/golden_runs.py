"""The golden runs: outputs that a refactoring must leave byte-identical.

Each run is a command line of ``dancebots`` (without ``--out``) and the files of its output
directory that are compared byte for byte: ``metrics.json`` as it is, ``log.csv`` gzipped.
``python tests/golden_runs.py`` rewrites them from the current code; do that only after a
deliberate change of behaviour, and read the diff of ``metrics.json`` first.

The runs are deterministic on one machine; NumPy's vectorised sin/cos may differ in the last
bit between CPU families, and a closed loop can grow that into a visible difference, so a
failure on a new kind of machine is checked against a run of the previous commit there.
"""

from __future__ import annotations

import contextlib
import gzip
import io
import sys
from pathlib import Path

GOLDEN = Path(__file__).resolve().parent / "data" / "golden_runs"

RUNS: dict[str, tuple[str, ...]] = {
    # the bundled open-day show (thesis listing 6.3) in its hall: stops, force field, 4 robots
    "open_day": ("run", "--no-animation"),
    # scenario 7.1 in the realistic profile: inertia, lag and seeded noise
    "thesis_7_1_realistic": ("run", "examples/thesis_7_1.dance", "--profile", "realistic",
                             "--seed", "3", "--no-animation"),
    # the leader-follower queue: DBSCAN detector (A1), PID (B1)
    "follow": ("follow", "--no-animation"),
    # the queue with Kalman tracks (A2), velocity obstacles (B2), realistic profile
    "follow_a2_vo": ("follow", "--detector", "a2", "--controller", "vo", "--profile",
                     "realistic", "--no-animation"),
}

COMPARED = ("metrics.json", "log.csv")


def run_into(name: str, out: Path) -> int:
    """Run the golden run ``name`` from the repository root into ``out``; its exit status."""
    from dancebots.cli import main

    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        return main([*RUNS[name], "--out", str(out)])


def stored(name: str, file: str) -> bytes:
    """The golden bytes of ``file`` of run ``name``."""
    if file.endswith(".csv"):
        return gzip.decompress((GOLDEN / name / f"{file}.gz").read_bytes())
    return (GOLDEN / name / file).read_bytes()


def regenerate() -> None:
    import os
    import tempfile

    os.chdir(Path(__file__).resolve().parents[1])
    for name in RUNS:
        with tempfile.TemporaryDirectory() as tmp:
            out = Path(tmp) / name
            status = run_into(name, out)
            target = GOLDEN / name
            target.mkdir(parents=True, exist_ok=True)
            for file in COMPARED:
                data = (out / file).read_bytes()
                if file.endswith(".csv"):  # mtime 0: the same bytes every time
                    (target / f"{file}.gz").write_bytes(gzip.compress(data, 9, mtime=0))
                else:
                    (target / file).write_bytes(data)
            print(f"{name}: exit {status}, wrote {target}", file=sys.stderr)


if __name__ == "__main__":
    regenerate()

"""A formation run loads only what it uses: not the queue's detectors (scikit-learn; SciPy
comes with numba anyway)."""

from __future__ import annotations

import subprocess
import sys


def test_the_formation_show_and_its_report_do_not_load_the_queue() -> None:
    code = ("import sys, dancebots.shows.formation, dancebots.report.metrics, "
            "dancebots.report.verdict; "
            "print(sorted(m for m in ('sklearn', 'dancebots.shows.queue') "
            "if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, timeout=120)
    assert done.stdout.strip() == "[]"

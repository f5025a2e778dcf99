"""How a large show.html behaves in a real browser: 100 robots for 10 minutes at 10 Hz
(6,000 ticks), 20 people, 200 instructions and 500 events, synthetic (robots on circles).

Prints the page's size, and from Debian's headless Chromium (as ``tests/report/test_replay.py``
opens it) the median over a few scrubbed times of the time the page took to unpack its data
(``data-load-ms``) and to draw one frame (``data-draw-ms``): a frame well under 16 ms plays
at 60 frames per second. Run: ``.venv/bin/python benchmarks/bench_replay.py [--times N]``.
"""

from __future__ import annotations

import argparse
import base64
import re
import shutil
import statistics
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from dancebots.report.replay import replay_page


def packed(array: np.ndarray, dtype: str = "<f4") -> str:
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).tobytes()).decode()


def synthetic(robots: int = 100, ticks: int = 6000, people: int = 20) -> dict[str, object]:
    times = np.arange(ticks) * 0.1
    phase = np.linspace(0.0, 2.0 * np.pi, robots, endpoint=False)[:, None]
    radius = 5.0 + 10.0 * np.arange(robots)[:, None] / robots
    angle = phase + 0.02 * times[None, :]
    poses = np.stack([20 + radius * np.cos(angle), 20 + radius * np.sin(angle),
                      angle + np.pi / 2], axis=-1)  # (R, T, 3)
    walk = np.stack([20 + 18 * np.cos(0.01 * times[None, :] + np.arange(people)[:, None]),
                     20 + 18 * np.sin(0.013 * times[None, :] + np.arange(people)[:, None])],
                    axis=-1)
    return {
        "title": "synthetic", "profile": "ideal", "duration": float(times[-1]),
        "count": ticks, "times": packed(times),
        "robots": [{"name": f"R{i + 1}", "length": 1.2, "width": 0.6,
                    "colour": "#1f77b4"} for i in range(robots)],
        "poses": packed(poses), "desired": packed(poses), "leaders": packed(poses),
        "status": packed(np.zeros((robots, ticks)), "u1"),
        "status_names": ["ok", "stopped", "error"],
        "people": packed(walk), "radii": [0.25] * people,
        "room": [[0, 0], [40, 0], [40, 40], [0, 40]], "obstacles": [],
        "instructions": [{"line": k + 3, "text": f"move 2 {k}", "start": 3.0 * k,
                          "end": 3.0 * k + 3.0, "lane": k % 4} for k in range(200)],
        "events": [{"t": 1.2 * k, "robot": f"R{k % robots + 1}", "kind": "beep", "text": ""}
                   for k in range(500)],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--times", type=int, default=5)
    args = parser.parse_args()
    chromium = shutil.which("chromium")
    if chromium is None:
        raise SystemExit("needs Debian's chromium (scripts/dev.sh test installs it)")
    with tempfile.TemporaryDirectory() as name:
        page = Path(name) / "show.html"
        page.write_text(replay_page(synthetic()), encoding="utf-8")
        loads, draws = [], []
        for t in np.linspace(0.0, 599.0, args.times):
            done = subprocess.run(
                [chromium, "--headless", "--no-sandbox", "--disable-gpu",
                 f"--user-data-dir={Path(name) / 'profile'}", "--virtual-time-budget=20000",
                 "--window-size=1400,900", "--dump-dom", f"{page.as_uri()}#t={t:.1f}"],
                capture_output=True, text=True, timeout=300, check=True)
            state = dict(re.findall(r'data-([a-z-]+)="([^"]*)"',
                                    re.search(r"<body([^>]*)>", done.stdout).group(1)))
            assert state["ready"] == "1", state
            loads.append(float(state["load-ms"]))
            draws.append(float(state["draw-ms"]))
        size = page.stat().st_size / 1e6
    print(f"100 robots x 6,000 ticks, 20 people: page {size:.1f} MB; "
          f"unpack {statistics.median(loads):.0f} ms, "
          f"one frame {statistics.median(draws):.1f} ms (median of {args.times} times)")


if __name__ == "__main__":
    main()

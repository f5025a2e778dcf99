"""show.html (report/replay.py): the run's data as the page gets it, and the page itself in a
real browser (Debian's headless Chromium) scrubbed to chosen times, read from the state the
page keeps in its DOM for the purpose."""

from __future__ import annotations

import base64
import os
import re
import shutil
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from dancebots.check import CheckOptions
from dancebots.loading import load_show
from dancebots.report.replay import replay_data, write_replay_html
from dancebots.shows.formation import RunResult, SimConfig, simulate
from dancebots.sim import prepare_show

ROOT = Path(__file__).parents[2]
SHOW = ROOT / "src" / "dancebots" / "data" / "open_day.dance"  # 134 s, visitors, a stop
WORLD = ROOT / "src" / "dancebots" / "data" / "open_day.toml"


@pytest.fixture(scope="module")
def run() -> tuple[RunResult, list[str]]:
    show = load_show(str(SHOW), str(WORLD), None, check=CheckOptions())
    assert show.report is not None
    assert show.report.placement is not None
    arena, placement = prepare_show(show.report.placement)
    result = simulate(show.report.placement.plan, arena, placement, SimConfig())
    return result, SHOW.read_text(encoding="utf-8").splitlines()


def unpacked(text: str, dtype: str) -> np.ndarray[Any, Any]:
    return np.frombuffer(base64.b64decode(text), dtype=dtype)


def test_the_page_gets_the_runs_samples_instructions_and_events(
        run: tuple[RunResult, list[str]]) -> None:
    result, lines = run
    data = replay_data(result, lines)
    count, robots = len(result.times), len(result.robots)
    assert data["count"] == count
    np.testing.assert_array_equal(unpacked(data["poses"], "<f4").reshape(robots, count, 3),
                                  result.poses.astype(np.float32))
    np.testing.assert_array_equal(unpacked(data["times"], "<f8"), result.times)
    np.testing.assert_array_equal(unpacked(data["status"], "u1").reshape(robots, count),
                                  result.status)
    assert [r["name"] for r in data["robots"]] == list(result.robots)
    for instruction in data["instructions"]:  # the line's own text, as the file has it
        assert instruction["text"] == lines[instruction["line"] - 1].strip()
        assert instruction["start"] <= instruction["end"]
    assert {i["line"] for i in data["instructions"]} == {
        n for n, text in enumerate(lines, start=1)
        if text.strip().split(" ")[0] in ("row", "column", "square", "move", "circle")}
    assert [(e["t"], e["robot"], e["kind"]) for e in data["events"]] == [
        (e.time, e.robot, e.kind) for e in result.events]
    assert any(e["kind"] == "speech" for e in data["events"])  # a visitor stops R2


def browser() -> str:
    found = shutil.which("chromium")
    if found is None:
        if os.environ.get("DANCEBOTS_REQUIRE_BROWSER") == "1":
            pytest.fail("chromium is not installed (scripts/dev.sh test installs it)")
        pytest.skip("chromium is not installed (scripts/dev.sh test installs it)")
    return found


def open_in_browser(page: Path, fragment: str, profile: Path) -> tuple[str, str]:
    """The page's DOM after its scripts ran (headless Chromium) and the browser's log."""
    done = subprocess.run(
        [browser(), "--headless", "--no-sandbox", "--disable-gpu", f"--user-data-dir={profile}",
         "--enable-logging=stderr", "--v=0", "--virtual-time-budget=5000",
         "--window-size=1200,800", "--dump-dom", f"{page.as_uri()}#{fragment}"],
        capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout, done.stderr


def body_state(dom: str) -> dict[str, str]:
    body = re.search(r"<body([^>]*)>", dom)
    assert body is not None, dom[:500]
    return dict(re.findall(r'data-([a-z-]+)="([^"]*)"', body.group(1)))


def test_the_page_scrubbed_in_a_real_browser_shows_that_moment(
        run: tuple[RunResult, list[str]], tmp_path: Path) -> None:
    """From the output directory, with no network: at each time asked for in the address
    (show.html#t=...), the page shows that tick, the instructions active then, every robot
    and person, and logs nothing to its console (no error)."""
    result, lines = run
    page = tmp_path / "show.html"
    write_replay_html(result, str(page), lines)
    data = replay_data(result, lines)
    # past 32 s float32 rounds some times of the 0.1 s grid up by more than the page's
    # tolerance: such a time must still open at its own tick
    rounded_up = next(float(t) for t in result.times if t > 32.0 and np.float32(t) > t + 1e-6)
    for wanted in (0.0, 12.3, rounded_up, float(result.times[-1])):
        dom, log = open_in_browser(page, f"t={wanted}", tmp_path / "profile")
        state = body_state(dom)
        tick = int(np.searchsorted(result.times, wanted + 1e-6) - 1)
        active = {str(i["line"]) for i in data["instructions"]
                  if i["start"] <= result.times[tick] + 1e-6 < i["end"]}
        shown = state.pop("instruction")
        assert float(state.pop("load-ms")) >= 0.0
        assert float(state.pop("draw-ms")) >= 0.0
        assert state.pop("scan-points") == "0"  # no scans recorded
        assert set(filter(None, shown.split(","))) == active
        assert state == {"ready": "1", "time": f"{result.times[tick]:.1f}", "tick": str(tick),
                         "robots": str(len(result.robots)),
                         "people": str(len(result.spectator_radii)), "playing": "0"}
        assert "CONSOLE" not in log, log[-2000:]
    # nothing to fetch: no address but the page's own in it
    assert not re.search(r"(src|href)=", page.read_text(encoding="utf-8"))


def test_a_queue_replays_its_targets_and_when_they_were_lost(tmp_path: Path) -> None:
    """``follow``'s page: the targets as the detector had them (NaN where none), the head of
    the queue, and an event at every tick a follower lost its target (or had it back); the
    page opens in the browser with them and an empty console."""
    from dancebots.cli.common import bundled
    from dancebots.report.replay import queue_replay_data, write_queue_replay_html
    from dancebots.shows.queue import QueueConfig, simulate_queue
    from dancebots.world import load_world

    result = simulate_queue(load_world(bundled("follow_crossing.toml")),
                            QueueConfig(robots=2, detector="a1", controller="pid"))
    data = queue_replay_data(result)
    count = len(result.times)
    targets = unpacked(data["targets"], "<f4").reshape(2, count, 2)
    np.testing.assert_array_equal(targets, result.targets.astype(np.float32))
    lost = ~np.isfinite(result.targets).all(axis=2)
    onsets = [(float(result.times[k]), robot) for i, robot in enumerate(result.robots)
              for k in range(count) if lost[i, k] and (k == 0 or not lost[i, k - 1])]
    assert onsets  # the crossing person hides the one in front
    assert sorted((e["t"], e["robot"]) for e in data["events"] if e["kind"] == "lost") == \
        sorted(onsets)
    page = tmp_path / "show.html"
    write_queue_replay_html(result, str(page))
    dom, log = open_in_browser(page, f"t={onsets[0][0]}", tmp_path / "profile")
    state = body_state(dom)
    tick = int(np.searchsorted(result.times, onsets[0][0] + 1e-6) - 1)
    assert (state["ready"], state["robots"], state["instruction"], state["tick"],
            state["time"]) == ("1", "2", "", str(tick), f"{result.times[tick]:.1f}")
    assert "CONSOLE" not in log, log[-2000:]


def test_a_robots_latest_scan_is_drawn_when_its_toggle_is_on(tmp_path: Path) -> None:
    """With the scans recorded (run --show-lidar) the page gets every delivered scan of every
    robot; turned on for R1 (here by the address, #scans=R1), it draws R1's latest scan
    delivered by that time: as many dots as that scan has hits."""
    show = load_show(str(SHOW), str(WORLD), None, check=CheckOptions())
    assert show.report is not None
    assert show.report.placement is not None
    arena, placement = prepare_show(show.report.placement)
    result = simulate(show.report.placement.plan, arena, placement,
                      SimConfig(record_lidar=True))
    data = replay_data(result)
    robots = len(result.robots)
    offsets = unpacked(data["scans"]["offsets"], "<i4")
    points = unpacked(data["scans"]["points"], "<f4").reshape(-1, 2)
    assert len(offsets) == len(result.lidar) * robots + 1
    s, r = len(result.lidar) // 2, 1
    np.testing.assert_array_equal(points[offsets[s * robots + r]:offsets[s * robots + r + 1]],
                                  np.asarray(result.lidar[s][1][r], dtype=np.float32))
    page = tmp_path / "show.html"
    write_replay_html(result, str(page))
    wanted = 10.0
    tick = int(np.searchsorted(result.times, wanted + 1e-6) - 1)
    times = np.array([t for t, _ in result.lidar], dtype=np.float32)
    latest = int(np.flatnonzero(times <= np.float32(result.times[tick]) + 1e-4)[-1])
    expected = len(result.lidar[latest][1][0])
    assert expected > 0
    dom, log = open_in_browser(page, f"t={wanted}&scans=R1", tmp_path / "profile")
    assert body_state(dom)["scan-points"] == str(expected)
    assert "CONSOLE" not in log, log[-2000:]
    dom, log = open_in_browser(page, f"t={wanted}", tmp_path / "profile")
    assert body_state(dom)["scan-points"] == "0"  # off unless asked for
    assert "CONSOLE" not in log, log[-2000:]


def test_no_text_in_the_data_can_end_the_pages_script(
        run: tuple[RunResult, list[str]], tmp_path: Path) -> None:
    """An instruction's line with a comment such as ``# <!--<script>`` or ``</script>``
    (its text is shown on the timeline) does not end or hide the player: the page comes up
    and shows the text as text."""
    result, lines = run
    data = replay_data(result, lines)
    line = data["instructions"][-1]["line"]
    hostile = list(lines)
    hostile[line - 1] += " # <!--<script> & </script> \"'"
    page = tmp_path / "show.html"
    write_replay_html(result, str(page), hostile)
    assert "<!--<script>" not in page.read_text(encoding="utf-8")
    dom, log = open_in_browser(page, "t=0", tmp_path / "profile")
    assert body_state(dom)["ready"] == "1"
    assert "# &lt;!--&lt;script&gt; &amp; &lt;/script&gt;" in dom  # as text in the timeline
    assert "CONSOLE" not in log, log[-2000:]

"""dancebots run: the outputs of a run, and clear errors that leave nothing half-written."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pandas as pd
import pytest

from dancebots.cli import main
from dancebots.report.runlog import LOG_COLUMNS

Capture = pytest.CaptureFixture[str]


def test_run_writes_every_output(capsys: Capture, examples: Path, tmp_path: Path) -> None:
    out = tmp_path / "run"
    status = main(["run", str(examples / "thesis_7_3.dance"), "--out", str(out)])
    stdout = capsys.readouterr().out
    assert status == 0
    names = {p.name for p in out.iterdir()}
    assert {"metrics.json", "speeds_distances.png", "trajectories.png", "log.csv",
            "run.mcap", "show.html", "animation.gif"} <= names
    assert (out / "animation.gif").read_bytes()[:6] == b"GIF89a"
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["collisions"] == 0
    assert metrics["profile"] == "ideal"
    log = pd.read_csv(out / "log.csv")
    assert tuple(log.columns) == LOG_COLUMNS
    assert set(log["robot"]) == {"R1", "R2"}
    assert log["t"].max() >= metrics["show_duration_s"]
    assert "collisions: 0" in stdout
    assert not list(tmp_path.glob(".run.partial-*"))
    # what a spectator sees (issue 12): in the table, below it and in metrics.json
    for column in ("RMS slot", "max", "heading", "reverse %"):
        assert column in stdout
    assert "formation error (every two robots of a formation" in stdout
    assert "angular speed sign flips (chatter): R1 " in stdout
    assert ("driven against the slot's direction, longest way / all ways: R1 0.00 / 0.00 m, "
            "R2 ") in stdout
    for key in ("reverse_fraction", "max_heading_error_deg", "max_formation_error_m"):
        assert key in metrics
        assert key in metrics["per_robot"]["R1"]


def test_run_with_lidar_points_and_sound(capsys: Capture, examples: Path,
                                         tmp_path: Path) -> None:
    from dancebots.report.sound import espeak_available

    out = tmp_path / "crash"
    args = ["run", str(examples / "crash_7_2_2.dance"), "--out", str(out), "--show-lidar"]
    if espeak_available():  # scripts/dev.sh installs espeak-ng, so CI writes the WAV too
        args.append("--sound")
    assert main(args) == 0
    assert (out / "animation.gif").stat().st_size > 10_000
    if espeak_available():
        assert (out / "sound.wav").read_bytes()[:4] == b"RIFF"
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["stops"] >= 1
    assert metrics["per_robot"]["R1"]["stops"] >= 1
    assert "stops" in capsys.readouterr().out


def test_rerun_replaces_an_earlier_run(capsys: Capture, examples: Path, tmp_path: Path) -> None:
    out = tmp_path / "run"
    for profile in ("ideal", "realistic"):
        assert main(["run", str(examples / "thesis_7_3.dance"), "--out", str(out),
                     "--profile", profile, "--no-animation"]) == 0
    assert json.loads((out / "metrics.json").read_text())["profile"] == "realistic"
    assert not (out / "animation.gif").exists()
    capsys.readouterr()


@pytest.mark.parametrize(("args", "message"), [
    (["--world", "missing.toml"], "missing.toml: error: no such file"),
    (["--world", "bad.toml"], "bad.toml:1:6: error: invalid TOML"),
    # what run refuses, check reports first, with a position (issue 10, part 3)
    (["--world", "other.toml"], "thesis_7_3.dance:1:1: error: the world places R1 but not R2"),
    (["--world", "tiny.toml"], "thesis_7_3.dance:3:1: error: R1 starts outside the room of "
     "tiny.toml"),
    (["--out", "not_empty"], "dancebots run: error: --out not_empty holds files that "
     "dancebots did not write (no dancebots-manifest.json); choose a new or empty directory"),
    (["--out", "a_file"], "dancebots run: error: --out a_file exists and is not a directory; "
     "choose another --out"),
])
def test_bad_input_is_one_clear_line(capsys: Capture, examples: Path, tmp_path: Path,
                                     monkeypatch: pytest.MonkeyPatch, args: list[str],
                                     message: str) -> None:
    monkeypatch.chdir(tmp_path)
    Path("bad.toml").write_text("[room\nsize = 3\n")
    Path("other.toml").write_text('[[robots]]\nname = "R1"\nx = 1\ny = 1\n')
    Path("tiny.toml").write_text("[room]\nsize = 1.5\n")
    Path("not_empty").mkdir()
    Path("not_empty/keep.txt").write_text("mine")
    Path("a_file").write_text("mine")
    Path("show.dance").write_text((examples / "thesis_7_3.dance").read_text())
    before = sorted(p.name for p in tmp_path.rglob("*"))
    status = main(["run", "show.dance", *args])
    err = capsys.readouterr().err.replace("show.dance", "thesis_7_3.dance")
    assert status == 2
    assert err.startswith(message)
    assert "Traceback" not in err
    assert sorted(p.name for p in tmp_path.rglob("*")) == before  # nothing written
    assert Path("not_empty/keep.txt").read_text() == "mine"


def test_unwritable_output_directory(capsys: Capture, examples: Path, tmp_path: Path) -> None:
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        import os

        if os.access(locked, os.W_OK):  # root ignores permissions: use a path under a file
            target = tmp_path / "file" / "run"
            (tmp_path / "file").write_text("x")
        else:
            target = locked / "run"
        status = main(["run", str(examples / "thesis_7_3.dance"), "--out", str(target)])
        assert status == 2
        assert capsys.readouterr().err.startswith("dancebots run: error: ")
    finally:
        locked.chmod(0o700)


def test_invalid_scenario_exits_2(capsys: Capture, data: Path, tmp_path: Path) -> None:
    status = main(["run", str(data / "scenarios" / "invalid" / "unknown_robot.dance"),
                   "--out", str(tmp_path / "x")])
    assert status == 2
    assert "error: unknown robot 'R5'" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_mp4_animation_when_ffmpeg_is_present(examples: Path, tmp_path: Path) -> None:
    """scripts/dev.sh installs ffmpeg, so this runs in CI; without ffmpeg the run writes only
    the GIF, which test_run_writes_every_output covers."""
    from dancebots.plan.placement import place_show
    from dancebots.report.animation import animate_run
    from dancebots.report.frames import ffmpeg_available
    from dancebots.shows.formation import SimConfig, simulate
    from dancebots.sim import prepare_show
    from tests_support import plan_of

    if not ffmpeg_available():
        pytest.skip("ffmpeg is not installed (scripts/dev.sh installs it)")
    plan = plan_of((examples / "thesis_7_3.dance").read_text())
    arena, placement = prepare_show(place_show(plan, None))
    result = simulate(plan, arena, placement, SimConfig())
    target = tmp_path / "a.mp4"
    animate_run(result, str(target))
    assert target.read_bytes()[4:8] == b"ftyp"


def test_the_bundled_open_day_show(capsys: Capture, tmp_path: Path) -> None:
    """The main job: the open-day show with visitors, with the defaults (the path follower
    on the feasible timing), runs clean: no contact, every robot on its final slot, exit 0.
    With the thesis's follower and timing the verdict is honest: robots drive against their
    slots' direction and end far from their slots, so the run exits 1 and says why; the
    robots stop and speak for the visitors (issue 4's open-day example)."""
    out = tmp_path / "open_day"
    assert main(["run", "--no-animation", "--out", str(out)]) == 0
    metrics = json.loads((out / "metrics.json").read_text())
    assert (metrics["follower"], metrics["timing"]) == ("path", "feasible")
    assert metrics["collisions"] == 0
    assert metrics["verdict"] == {"clean": True, "failures": []}
    assert all(robot["final_error_m"] < 0.05 for robot in metrics["per_robot"].values())
    assert metrics["scenario"].endswith("open_day.dance")
    thesis = tmp_path / "open_day_thesis"
    assert main(["run", "--no-animation", "--follower", "thesis", "--timing", "thesis",
                 "--hold", "alone", "--out", str(thesis)]) == 1
    metrics = json.loads((thesis / "metrics.json").read_text())
    assert metrics["verdict"]["clean"] is False
    assert any(failure.startswith(("a robot ends away from the final slot (more than 0.5 m)",
                                   "robots end away from the final slot (more than 0.5 m)"))
               for failure in metrics["verdict"]["failures"])
    assert metrics["stops"] >= 5
    speech = [e for e in metrics["events"] if e["kind"] == "speech"]
    assert {e["text"] for e in speech} == {"Obstacle is too close, I have to stop"}
    capsys.readouterr()


def test_no_lidar_among_people_is_loud_and_the_verdict_says_what_went_wrong(
        capsys: Capture, tmp_path: Path) -> None:
    """The open-day hall with its three visitors, robots without LIDAR (and the thesis's
    follower, which swings them into the visitors' way): a warning before simulating, and a
    verdict (JSON on stdout, and in metrics.json) that fails the show."""
    out = tmp_path / "blind"
    assert main(["run", "--no-lidar", "--no-animation", "--json", "--follower", "thesis",
                 "--timing", "thesis", "--out", str(out)]) == 1
    captured = capsys.readouterr()
    assert ("WARNING: --no-lidar with 3 spectators in the world: the robots cannot see people "
            "and will drive into them") in captured.err
    summary = json.loads(captured.out)
    assert summary["output"] == str(out)
    verdict = summary["verdict"]
    assert verdict["clean"] is False
    # the contacts' line names the first, when, and how fast the robot and person came
    assert any(re.search(r" contacts? with (a person|people) \(first: R\d with .+ at t = "
                         r"[\d.]+ s: the robot closing at -?[\d.]+ m/s, the person at "
                         r"-?[\d.]+ m/s\)$", f) for f in verdict["failures"])
    assert json.loads((out / "metrics.json").read_text())["verdict"] == verdict


def test_check_warnings_are_repeated_before_simulating(capsys: Capture, examples: Path,
                                                       tmp_path: Path) -> None:
    main(["run", str(examples / "thesis_7_1.dance"), "--no-lidar", "--no-animation",
          "--timing", "thesis", "--out", str(tmp_path / "run")])
    err = capsys.readouterr().err
    assert "thesis_7_1.dance:4:1: warning: desired speed above the robot's maximum" in err


def test_a_robot_that_reverses_makes_the_show_not_clean(capsys: Capture, tmp_path: Path,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    """The verdict's new reasons reach the exit status, the printed verdict and metrics.json:
    R2's simulated run is replaced by one on its slot but turned round and reversing."""
    import numpy as np

    from dancebots.geometry import wrap_angles
    from dancebots.report import metrics as metrics_module
    from dancebots.shows.formation import RunResult

    original = metrics_module.run_metrics

    def reversing(result: RunResult) -> metrics_module.RunMetrics:
        poses, velocities = result.desired.copy(), result.velocities.copy()
        poses[1, :, 2] = wrap_angles(poses[1, :, 2] + np.pi)
        velocities[1, :, 0] = -result.reference[1, :, 3]
        return original(RunResult(**{
            **{f: getattr(result, f) for f in result.__dataclass_fields__},
            "poses": poses, "velocities": velocities}))

    monkeypatch.setattr(metrics_module, "run_metrics", reversing)
    show = tmp_path / "straight.dance"
    show.write_text("robots R1 R2\nrow R1,R2 0 1.2\nmove 2 0\n")
    out = tmp_path / "run"
    assert main(["run", str(show), "--no-lidar", "--no-animation", "--out", str(out)]) == 1
    stdout = capsys.readouterr().out
    failures = ["a robot drives against its desired direction (more than 5 % of the time the "
                "slot moves): R2 100.0 %",
                "a robot ends turned away from the final slot's heading (more than 30°): R2 "
                "180°"]
    assert stdout.endswith("verdict: NOT CLEAN\n" + "".join(f"  - {f}\n" for f in failures))
    written = json.loads((out / "metrics.json").read_text())
    assert written["verdict"] == {"clean": False, "failures": failures}
    assert written["per_robot"]["R2"]["reverse_fraction"] == 1.0

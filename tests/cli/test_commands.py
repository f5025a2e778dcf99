"""The dancebots command: exit statuses, output formats, and hostile inputs."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from dancebots.cli import main

Capture = pytest.CaptureFixture[str]


COMPILING = "compiling the simulator's "
"""The line check's simulation pass prints once per machine, while numba compiles its kernels
(on a fresh clone the first test that simulates sees it; tests/sim/test_kernels.py tests it)."""


def run(capsys: Capture, *args: str) -> tuple[int, str, str]:
    """dancebots ARGS: its exit status, stdout and stderr (without the one-off line that
    says the simulator's kernels are being compiled)."""
    status = main(list(args))
    out, err = capsys.readouterr()
    err = "".join(line for line in err.splitlines(keepends=True)
                  if not line.startswith(COMPILING))
    return status, out, err


def test_check_prints_the_timeline(capsys: Capture, tmp_path: Path) -> None:
    """--timeline: when each instruction runs, in show time, with its line's text and where
    the feasible timing slowed the leader, by how much; the same in the JSON. A formation
    instruction shows once; a split (newVL) gives each new formation its own lines."""
    path = tmp_path / "split.dance"
    path.write_text("robots R1 R2\ngroups\nleft R1\nright R2\nstart\n"
                    "row R1,R2 0 1.2\nmove 2 0\n"
                    "row R1 0 0\nrow R2 0 0\nnewVL\n"
                    "move 1 90 left\ncircle -1 90 0.3 right\n")
    status, out, _ = run(capsys, "check", "--rigid-only", "--timeline", str(path))
    assert status == 0
    table = out.splitlines()[out.splitlines().index(
        " line  start s    end s  speed  instruction"):-1]
    assert [row.split()[0] for row in table[1:]] == ["6", "7", "8", "9", "11", "12"]
    assert table[1].endswith("  row R1,R2 0 1.2")
    assert table[3].split()[1] == table[4].split()[1]  # both new formations start together
    status, out, _ = run(capsys, "check", "--rigid-only", "--timeline", "--json", str(path))
    timeline = json.loads(out)["timeline"]
    assert [(e["line"], e["kind"]) for e in timeline] == [
        (6, "formation"), (7, "move"), (8, "formation"), (9, "formation"), (11, "move"),
        (12, "circle")]
    assert all(e["start"] <= e["end"] for e in timeline)
    assert timeline[1]["end"] <= timeline[2]["start"] + 1e-9  # the split after the move
    for entry, row in zip(timeline, table[1:], strict=True):
        assert row.split()[1:3] == [f"{entry['start']:.1f}", f"{entry['end']:.1f}"]
        assert ("%" in row) == (entry["speed_fraction"] < 1.0)


def test_check_valid_prints_summary(capsys: Capture, tmp_path: Path) -> None:
    path = tmp_path / "straight.dance"
    path.write_text("robots R1 R2\nrow R1,R2 0 1.2\nmove 2 0\n")
    status, out, err = run(capsys, "check", str(path))
    assert status == 0
    assert out.splitlines() == [
        f"{path}: 2 robots (R1 R2)",
        "show duration 5.6 s, 1 formation, smallest gap between footprints 0.60 m",
        "robot      type     path m  max |v| m/s  max |w| rad/s",
        "R1         SIM        1.90         0.35           0.00",
        "R2         SIM        1.90         0.35           0.00",
        f"{path}: ok",
    ]
    assert err == ""


THESIS = ("--follower", "thesis", "--timing", "thesis", "--hold", "alone")
"""The thesis's follower (eq. 4.4) and timing, which the defaults (path, feasible) replace."""


def test_warnings_and_strict(capsys: Capture, examples: Path) -> None:
    path = str(examples / "thesis_7_1.dance")
    status, out, err = run(capsys, "check", *THESIS, "--rigid-only", path)
    assert status == 0
    assert "thesis_7_1.dance:4:1: warning: desired speed above the robot's maximum" in err
    assert "simulated" not in err
    assert out.rstrip().endswith("ok (2 warnings)")
    assert run(capsys, "check", *THESIS, "--strict", "--rigid-only", path)[0] == 1
    # the default feasible timing slows the leader instead: notes, no warning
    status, out, err = run(capsys, "check", "--strict", "--rigid-only", path)
    assert status == 0
    assert err.rstrip().endswith("0 errors, 0 warnings, 2 notes")


def test_check_runs_the_show_and_reports_at_the_instruction(capsys: Capture,
                                                             examples: Path) -> None:
    """The simulation pass: 7.1's thesis follower falls more than 0.5 m behind its place in
    the corner of line 4 (with the turn guard that only cuts the sweep it no longer holds R2
    mid-spin there, so R2 no longer turns round);
    --follower tracking --timing feasible and the defaults (path, feasible) leave nothing to
    report; the findings are warnings (exit 1 only with --strict)."""
    path = str(examples / "thesis_7_1.dance")
    status, out, err = run(capsys, "check", *THESIS, path)
    assert status == 0
    assert ("thesis_7_1.dance:4:1: warning: simulated (ideal profile, thesis follower): R1 "
            "is more than 0.5 m from its place from t = 8.0 s to 9.6 s (up to 0.57 m)") in err
    assert out.rstrip().endswith("ok (4 warnings)")
    # the tracking follower on the feasible timing: no speed above a robot's maximum, but with
    # LIDAR its rigid slots point the robots at each other in the corners (README: 49-50 cm):
    # the robot held there falls behind its slot (it waits for its slot rather than reverse
    # against it), and that is all check may find (0.51 m at most with the default guard)
    status, out, err = run(capsys, "check", "--follower", "tracking", "--timing", "feasible",
                           path)
    assert status == 0
    warnings = [line for line in err.splitlines() if ": warning: " in line]
    assert all("(ideal profile, tracking follower): R" in w and "is more than 0.5 m from its "
               "place" in w for w in warnings)
    count = f"{len(warnings)} warning{'' if len(warnings) == 1 else 's'}"
    assert err.rstrip().endswith(f"0 errors, {count}, 2 notes")  # notes: the leader slows
    assert out.rstrip().endswith("thesis_7_1.dance: ok" + (f" ({count})" if warnings else ""))
    status, out, err = run(capsys, "check", path)
    assert status == 0
    assert err.rstrip().endswith("0 errors, 0 warnings, 2 notes")
    report = json.loads(run(capsys, "check", *THESIS, "--json", path)[1])
    assert any(d["message"].startswith("simulated (ideal profile, thesis follower): R1 is more")
               for d in report["diagnostics"])


def test_json_report(capsys: Capture, examples: Path) -> None:
    status, out, _ = run(capsys, "check", *THESIS, "--json",
                         str(examples / "thesis_6_3.dance"))
    assert status == 0
    report = json.loads(out)
    assert report["valid"] is True
    assert report["report"]["robots"] == ["R1", "R2", "R3", "R4"]
    assert report["report"]["groups"] == {"group1": ["R1", "R3"], "group2": ["R2", "R4"]}
    assert set(report["report"]["per_robot"]["R1"]) == {
        "type", "path_length_m", "max_speed_mps", "max_angular_speed_radps", "speed_limit_mps"}
    assert {d["severity"] for d in report["diagnostics"]} == {"warning", "note"}
    # the only note: the right-angle corner of line 9 is too tight for the square
    assert [(d["line"], d["message"][:40]) for d in report["diagnostics"]
            if d["severity"] == "note"] == [(9, "the leader turns here too tightly for th")]


def test_json_errors(capsys: Capture, data: Path) -> None:
    path = data / "scenarios" / "invalid" / "unknown_robot.dance"
    status, out, _ = run(capsys, "check", "--json", str(path))
    assert status == 2
    report = json.loads(out)
    assert report["valid"] is False
    assert report["report"] is None
    assert report["diagnostics"][0]["line"] == 2
    assert report["diagnostics"][0]["col"] == 8
    assert report["diagnostics"][0]["hint"] == "the robots are R1 R2 R3 R4"


def test_demo_passes_strict_check(capsys: Capture, tmp_path: Path) -> None:
    status, out, _ = run(capsys, "demo")
    assert status == 0
    for keyword in ("robots", "groups", "start", "row", "column", "triangle", "square",
                    "move", "circle", "newVL", "tempo", "wait", " at beat ", " by beat "):
        assert keyword in out
    demo = tmp_path / "demo.dance"
    demo.write_text(out)
    # its plan is clean; simulated, the thesis follower turns robots round (issue 12) but the
    # tracking and path (default) followers on the feasible timing perform it without a
    # finding
    status, _, err = run(capsys, "check", *THESIS, "--strict", "--rigid-only", str(demo))
    assert (status, err) == (0, "")
    for follower in ("tracking", "path"):
        status, _, err = run(capsys, "check", "--strict", "--follower", follower, str(demo))
        assert status == 0
        assert ": warning: " not in err  # only notes of where the leader slows


def test_plan_png(capsys: Capture, examples: Path, tmp_path: Path) -> None:
    target = tmp_path / "plan.png"
    status, out, _ = run(capsys, "plan", str(examples / "thesis_6_3.dance"), "--png",
                         str(target))
    assert status == 0
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not (tmp_path / "plan.png.partial").exists()
    assert out == f"wrote {target}\n"


def test_plan_png_in_a_world(capsys: Capture, examples: Path, data: Path,
                             tmp_path: Path) -> None:
    target = tmp_path / "plan.png"
    status, _, _ = run(capsys, "plan", str(examples / "thesis_7_1.dance"), "--world",
                       str(data / "worlds" / "two_robots.toml"), "--png", str(target))
    assert status == 0
    assert target.stat().st_size > 10_000


def test_plan_unwritable_directory(capsys: Capture, examples: Path, tmp_path: Path) -> None:
    target = tmp_path / "missing" / "plan.png"
    status, _, err = run(capsys, "plan", str(examples / "thesis_7_1.dance"), "--png",
                         str(target))
    assert status == 2
    assert err == (f"dancebots plan: error: cannot write {target}: the directory "
                   f"{target.parent} does not exist\n")
    assert not target.parent.exists()


@pytest.mark.parametrize(("name", "content", "message"), [
    ("missing.dance", None, "missing.dance: error: no such file"),
    ("folder", "DIR", "folder: error: is a directory, not a file"),
    ("binary.dance", b"\x00\x01\x02\xff\xfe" * 100, "binary.dance:1:4: error: the file is not "
     "valid UTF-8 text (byte ff at byte offset 3)"),
    ("big.dance", b"move 1 0\n" * 1_200_000, "big.dance: error: the file is larger than 2 MiB"),
    ("nan.dance", b"robots R1\nrow R1 0 0\nmove NaN inf\n", "nan.dance:3:6: error: the move "
     "distance must be a finite number, not 'NaN'"),
    ("huge.dance", b"robots R1\nrow R1 0 0\nmove 1e308 1e308\n", "huge.dance:3:6: error: the "
     "move distance must be at most 1000, not 1e308"),
    ("empty.dance", b"", "empty.dance:1:1: error: the scenario is empty"),
])
def test_hostile_inputs(capsys: Capture, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                        name: str, content: bytes | str | None, message: str) -> None:
    monkeypatch.chdir(tmp_path)
    if content == "DIR":
        (tmp_path / name).mkdir()
    elif isinstance(content, bytes):
        (tmp_path / name).write_bytes(content)
    status, _, err = run(capsys, "check", name)
    assert status == 2
    assert err.splitlines()[0] == message
    assert "Traceback" not in err


def test_world_errors_reported_with_scenario_errors(capsys: Capture, data: Path,
                                                    examples: Path) -> None:
    status, _, err = run(capsys, "check", str(examples / "thesis_7_1.dance"), "--world",
                         str(data / "worlds" / "bad.toml"))
    assert status == 2
    assert "bad.toml:2:1: error: 'size' must be greater than 0" in err
    assert "8 errors, 0 warnings" in err


def test_bad_arguments_exit_2(capsys: Capture) -> None:
    with pytest.raises(SystemExit) as exit_info:
        main(["check", "x.dance", "--vmax", "nan"])
    assert exit_info.value.code == 2
    assert "must be a finite number > 0" in capsys.readouterr().err


def test_console_script_runs() -> None:
    out = subprocess.run([sys.executable, "-m", "dancebots.cli", "--version"], check=True,
                         capture_output=True, text=True)
    assert out.stdout.startswith("dancebots ")


@pytest.mark.parametrize("name", ["plan.jpg", "plan"])
def test_plan_needs_a_known_image_extension(capsys: Capture, examples: Path, tmp_path: Path,
                                            name: str) -> None:
    target = tmp_path / name
    status, _, err = run(capsys, "plan", str(examples / "thesis_7_3.dance"), "--out",
                         str(target))
    assert status == 2
    assert err == (f"dancebots plan: error: {target}: give a file name that ends in .png, "
                   ".svg or .pdf (the image's format)\n")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("command", ["run", "follow"])
def test_json_output_says_when_nothing_ran(capsys: Capture, tmp_path: Path,
                                           command: str) -> None:
    """Scripts reading --json get JSON on stdout even when the input is refused."""
    bad = tmp_path / "bad.toml"
    bad.write_text("[room\n")
    args = ["--world", str(bad)] if command == "follow" else [str(tmp_path / "none.dance")]
    status, out, err = run(capsys, command, *args, "--json", "--out", str(tmp_path / "o"))
    assert status == 2
    report = json.loads(out)
    assert report["ran"] is False
    assert report["diagnostics"][0]["severity"] == "error"
    assert err.startswith(str(tmp_path))
    status, out, _ = run(capsys, command, *([] if command == "follow" else [
        str(Path(__file__).parents[2] / "examples" / "thesis_7_3.dance")]), "--json",
        "--out", ".")
    assert status == 2
    assert json.loads(out)["error"].startswith("--out . is the working directory")


def test_a_missing_world_file_gets_a_world_hint(capsys: Capture, examples: Path) -> None:
    status, _, err = run(capsys, "check", str(examples / "thesis_7_1.dance"), "--world",
                         "nosuch.toml")
    assert status == 2
    assert err.splitlines()[:2] == [
        "nosuch.toml: error: no such file",
        "  hint: check the path; docs/worlds.md describes world files, and examples/worlds/ "
        "holds some"]
    status, _, err = run(capsys, "follow", "--world", "nosuch")
    assert status == 2
    assert err.splitlines()[1].endswith("; or name a bundled world: course, crossing")


def test_check_does_not_simulate_a_show_too_large_for_it(
        capsys: Capture, examples: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import dancebots.cli.check

    monkeypatch.setattr(dancebots.cli.check, "SIMULATION_LIMIT", 40)
    status, _, err = run(capsys, "check", *THESIS, str(examples / "thesis_7_1.dance"))
    assert status == 0
    assert ("thesis_7_1.dance:1:1: warning: not simulated: 2 robots for 23 s is 47 "
            "robot-seconds, more than check simulates (40)") in err
    assert "  hint: `--simulation-limit 47` simulates it too (about 1 s here)" in err
    assert "simulated (" not in err
    # the option raises the limit: the show is simulated (its findings, none here)
    status, _, err = run(capsys, "check", *THESIS, "--simulation-limit", "47",
                         str(examples / "thesis_7_1.dance"))
    assert status == 0
    assert "not simulated" not in err


def test_notes_are_counted_apart_and_do_not_fail_strict(capsys: Capture, examples: Path) -> None:
    path = str(examples / "thesis_7_1.dance")
    status, out, err = run(capsys, "check", "--rigid-only", "--strict", "--timing", "feasible",
                           path)
    assert status == 0
    assert "thesis_7_1.dance:4:1: note: the virtual leader slows to " in err
    assert err.rstrip().endswith("0 errors, 0 warnings, 2 notes")
    assert out.rstrip().endswith("thesis_7_1.dance: ok")


def test_a_bug_is_an_internal_error_with_its_own_exit_status(
        capsys: Capture, examples: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A crash inside dancebots exits 70 with the traceback and a line that says it is a
    bug, so that scripts tell it from a show that ran but not clean (1)."""
    import dancebots.report.findings

    def broken(*args: object, **kwargs: object) -> list[object]:
        raise ZeroDivisionError("boom")

    monkeypatch.setattr(dancebots.report.findings, "simulated_findings", broken)
    status, _, err = run(capsys, "check", str(examples / "thesis_7_3.dance"))
    assert status == 70
    assert "ZeroDivisionError: boom" in err
    assert err.rstrip().endswith("dancebots: internal error: this is a bug in dancebots, not "
                                 "in your input; please report it with the lines above")


def test_check_judges_the_places_its_follower_drives_to(capsys: Capture) -> None:
    """The bundled show: its columns' rigid slots swing into each other where the columns
    turn (line 23), which the tracking follower would drive; the places on the leaders'
    paths that the default path follower drives to keep apart, so check agrees with the
    clean run."""
    from dancebots.cli.common import bundled

    show, world = str(bundled("open_day.dance")), str(bundled("open_day.toml"))
    status, _, err = run(capsys, "check", "--rigid-only", show, "--world", world)
    assert status == 0
    assert err.rstrip().endswith("0 errors, 0 warnings, 11 notes")
    # one of them: the right-angle corner of line 15 makes R4's place wait (issue 12)
    assert ("open_day.dance:15:1: note: the leader turns here too tightly for the "
            "formation's width and depth" in err)
    status, _, err = run(capsys, "check", "--rigid-only", "--follower", "tracking", show,
                         "--world", world)
    assert status == 0
    assert "open_day.dance:23:1: warning: R1 and R2 come within 0.00 m of each other" in err


def test_the_physics_profile_says_how_to_install_mujoco_when_it_is_missing(
        capsys: Capture, examples: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Without MuJoCo, every command that simulates refuses --profile physics with the command
    that installs it (exit 2, nothing written); the other profiles do not need it."""
    monkeypatch.setitem(sys.modules, "mujoco", None)  # as if it were not installed
    hint = ("the physics profile runs on MuJoCo, which is not installed here: install it with "
            "`.venv/bin/pip install 'dancebots[physics]'` (or `pip install mujoco`), or use "
            "--profile ideal or realistic")
    from dancebots.cli.common import bundled

    show = str(examples / "thesis_7_1.dance")
    for command in (["run", show, "--out", str(tmp_path / "run")],
                    ["follow", "--out", str(tmp_path / "follow")],
                    ["certify", show, "--world", str(bundled("open_day_crowd.toml")), "--runs",
                     "1", "--out", str(tmp_path / "certify")]):
        status, _, err = run(capsys, *command, "--profile", "physics")
        assert status == 2, command
        assert err.strip() == f"dancebots {command[0]}: error: {hint}", command
    assert not any(tmp_path.iterdir())
    status, _, _ = run(capsys, "run", show, "--no-animation", "--out", str(tmp_path / "ideal"))
    assert status == 0

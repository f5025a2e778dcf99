"""The output writer never destroys a user's files (issue 10, part 1).

A user's files sit next to runs in every test; each test proves they survive, byte for byte.
"""

from __future__ import annotations

import contextlib
import json
import os
from pathlib import Path

import pytest

from dancebots import __version__
from dancebots.cli import main
from dancebots.cli.common import MANIFEST, OutputError, stage_output, write_file

Capture = pytest.CaptureFixture[str]
EXAMPLES = Path(__file__).parents[2] / "examples"
FAST = [str(EXAMPLES / "thesis_7_3.dance"), "--no-lidar", "--no-animation"]


def snapshot(root: Path) -> dict[str, bytes | None]:
    """Every path under root (directories as None, files with their bytes)."""
    return {str(p.relative_to(root)): (None if p.is_dir() else p.read_bytes())
            for p in sorted(root.rglob("*"))}


def user_files(directory: Path) -> None:
    directory.mkdir(parents=True, exist_ok=True)
    (directory / "precious.txt").write_text("mine\n")
    (directory / "sub").mkdir()
    (directory / "sub" / "notes.md").write_text("also mine\n")


@pytest.fixture
def no_simulation(monkeypatch: pytest.MonkeyPatch) -> None:
    """Refusals must come before the simulation: calling it fails the test."""
    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("simulated although the output was refused")

    monkeypatch.setattr("dancebots.shows.formation.simulate", refuse)


def fake_run(target: Path, files: dict[str, str]) -> list[str]:
    staged = stage_output(target, "test")
    for name, text in files.items():
        (staged.staging / name).write_text(text)
    staged.commit(list(files), __version__)
    return list(files)


# --- the reproducers of the issue ----------------------------------------------------------

@pytest.mark.usefixtures("no_simulation")
def test_a_directory_with_a_metrics_json_of_someone_else_is_refused(
        capsys: Capture, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    user_files(tmp_path / "b")
    (tmp_path / "b" / "metrics.json").write_text("{}")
    before = snapshot(tmp_path)
    assert main(["run", *FAST, "--out", "b"]) == 2
    assert capsys.readouterr().err == (
        f"dancebots run: error: --out b holds files that dancebots did not write (no "
        f"{MANIFEST}) (it looks like a run of an older dancebots: delete it if you no longer "
        "need it); choose a new or empty directory\n")
    assert snapshot(tmp_path) == before


@pytest.mark.usefixtures("no_simulation")
@pytest.mark.parametrize("out", [".", "..", "./", "sub/.."])
def test_the_working_directory_and_above_are_refused(
        capsys: Capture, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, out: str) -> None:
    work = tmp_path / "work"
    user_files(work)
    (work / "metrics.json").write_text("{}")
    (work / "show.dance").write_text((EXAMPLES / "thesis_7_3.dance").read_text())
    monkeypatch.chdir(work)
    before = snapshot(tmp_path)
    assert main(["run", "show.dance", "--no-lidar", "--out", out]) == 2
    assert capsys.readouterr().err == (
        f"dancebots run: error: --out {Path(out)} is the working directory or one above it; give "
        "a directory of its own, e.g. out/NAME\n")
    assert snapshot(tmp_path) == before


@pytest.mark.usefixtures("no_simulation")
def test_a_symbolic_link_is_refused_before_simulating(
        capsys: Capture, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    fake_run(tmp_path / "earlier", {"metrics.json": "{}\n"})
    user_files(tmp_path / "earlier")
    (tmp_path / "link").symlink_to("earlier")
    before = snapshot(tmp_path)
    assert main(["run", *FAST, "--out", "link"]) == 2
    assert capsys.readouterr().err == (
        "dancebots run: error: --out link is a symbolic link; give a real directory "
        "(dancebots does not write through links)\n")
    assert snapshot(tmp_path) == before


@pytest.mark.usefixtures("no_simulation")
def test_an_unwritable_place_is_refused_before_simulating(capsys: Capture) -> None:
    assert main(["run", *FAST, "--out", "/proc/x"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("dancebots run: error: cannot write /proc/x: ")
    assert err.endswith("; choose a writable --out\n")
    assert "partial" not in err
    assert "Traceback" not in err


@pytest.mark.usefixtures("no_simulation")
def test_a_file_is_refused(capsys: Capture, tmp_path: Path) -> None:
    (tmp_path / "a_file").write_text("mine")
    assert main(["run", *FAST, "--out", str(tmp_path / "a_file")]) == 2
    assert capsys.readouterr().err == (f"dancebots run: error: --out {tmp_path / 'a_file'} "
                                       "exists and is not a directory; choose another --out\n")
    assert (tmp_path / "a_file").read_text() == "mine"


@pytest.mark.usefixtures("no_simulation")
def test_a_run_whose_file_the_user_changed_is_refused(capsys: Capture, tmp_path: Path) -> None:
    fake_run(tmp_path / "run", {"metrics.json": "{}\n", "log.csv": "t\n"})
    (tmp_path / "run" / "log.csv").write_text("my edits\n")
    before = snapshot(tmp_path)
    assert main(["run", *FAST, "--out", str(tmp_path / "run")]) == 2
    assert capsys.readouterr().err == (
        f"dancebots run: error: {tmp_path / 'run' / 'log.csv'} was changed since dancebots "
        "wrote it; move it away (dancebots replaces only its own unchanged files) or choose "
        "another --out\n")
    assert snapshot(tmp_path) == before


@pytest.mark.usefixtures("no_simulation")
def test_an_unreadable_manifest_is_refused(capsys: Capture, tmp_path: Path) -> None:
    user_files(tmp_path / "run")
    (tmp_path / "run" / MANIFEST).write_text('{"files": {"../precious.txt": ["x"]}}')
    before = snapshot(tmp_path)
    assert main(["run", *FAST, "--out", str(tmp_path / "run")]) == 2
    assert "is not a manifest dancebots can read" in capsys.readouterr().err
    assert snapshot(tmp_path) == before


# --- runs into earlier runs ----------------------------------------------------------------

def test_a_rerun_replaces_only_its_own_files(capsys: Capture, tmp_path: Path) -> None:
    out = tmp_path / "run"
    assert main(["run", *FAST[:-1], "--out", str(out)]) == 0  # with the animation
    assert (out / "animation.gif").exists()
    user_files(out)
    (out / "extra.png").write_text("a picture of mine")
    mine = {k: v for k, v in snapshot(out).items()
            if k.startswith(("precious", "sub", "extra"))}
    assert main(["run", *FAST, "--out", str(out), "--profile", "realistic"]) == 0
    capsys.readouterr()
    assert json.loads((out / "metrics.json").read_text())["profile"] == "realistic"
    assert not (out / "animation.gif").exists()  # the earlier run's, not written this time
    after = snapshot(out)
    assert {k: after[k] for k in mine} == mine
    manifest = json.loads((out / MANIFEST).read_text())
    assert sorted(manifest["files"]) == ["log.csv", "metrics.json", "run.mcap", "show.html",
                                         "speeds_distances.png", "trajectories.png"]
    assert not [p for p in out.iterdir() if p.name.startswith(".")]  # no staging left


def test_an_empty_directory_is_used(capsys: Capture, tmp_path: Path) -> None:
    (tmp_path / "empty").mkdir()
    assert main(["run", *FAST, "--out", str(tmp_path / "empty")]) == 0
    capsys.readouterr()
    assert (tmp_path / "empty" / MANIFEST).exists()


def test_a_failed_run_leaves_the_earlier_run_intact(
        capsys: Capture, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    out = tmp_path / "run"
    fake_run(out, {"metrics.json": "{}\n"})
    user_files(out)
    before = snapshot(tmp_path)

    def broken(*args: object, **kwargs: object) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr("dancebots.report.runlog.write_log", broken)
    assert main(["run", *FAST, "--out", str(out)]) == 2
    assert capsys.readouterr().err.endswith(
        f"dancebots run: error: cannot write the outputs to {out}: No space left on device; "
        "nothing there was changed\n")
    assert snapshot(tmp_path) == before  # no staging directory left either


def test_a_user_file_with_an_output_name_is_refused_before_simulating(
        capsys: Capture, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    out = tmp_path / "run"
    fake_run(out, {"metrics.json": "{}\n"})
    (out / "animation.gif").write_text("MY OWN GIF")
    (tmp_path / "elsewhere.txt").write_text("mine")
    (out / "sound.wav").symlink_to(tmp_path / "elsewhere.txt")
    before = snapshot(tmp_path)
    monkeypatch.setattr("dancebots.shows.formation.simulate", None)  # must not be reached
    assert main(["run", *FAST, "--out", str(out)]) == 2
    assert capsys.readouterr().err == (
        f"dancebots run: error: {out / 'animation.gif'} is not a file of the earlier run (its "
        f"{MANIFEST} does not list it), and this run would write it; move it away or choose "
        "another --out\n")
    assert snapshot(tmp_path) == before


def test_a_file_changed_during_the_run_is_not_replaced(
        capsys: Capture, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The user edits the earlier run's log while the new run simulates: nothing is replaced,
    and the new run's files are kept beside, in a directory the message names."""
    from dancebots.report import metrics

    out = tmp_path / "run"
    fake_run(out, {"metrics.json": "{}\n", "log.csv": "t\n"})
    original = metrics.run_metrics

    def edit_meanwhile(result: object) -> object:
        (out / "log.csv").write_text("t\nmy edit\n")
        return original(result)  # type: ignore[arg-type]

    monkeypatch.setattr(metrics, "run_metrics", edit_meanwhile)
    assert main(["run", *FAST, "--out", str(out)]) == 2
    err = capsys.readouterr().err.splitlines()[-1]
    assert err.startswith(f"dancebots run: error: {out / 'log.csv'} was changed or made during "
                          f"the run, so nothing in {out} was replaced; the new run's files are "
                          f"in {out / 'unsaved-run-'}")
    assert (out / "log.csv").read_text() == "t\nmy edit\n"
    assert (out / "metrics.json").read_text() == "{}\n"
    kept = next(out.glob("unsaved-run-*"))
    assert {p.name for p in kept.iterdir()} >= {"log.csv", "metrics.json", MANIFEST}


def test_a_directory_made_by_someone_else_during_the_run_is_left_alone(
        capsys: Capture, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from dancebots.report import metrics

    out = tmp_path / "run"
    original = metrics.run_metrics

    def made_meanwhile(result: object) -> object:
        out.mkdir()
        (out / "theirs.txt").write_text("another run's")
        return original(result)  # type: ignore[arg-type]

    monkeypatch.setattr(metrics, "run_metrics", made_meanwhile)
    assert main(["run", *FAST, "--out", str(out)]) == 2
    err = capsys.readouterr().err.splitlines()[-1]
    assert err.startswith(f"dancebots run: error: {out} was made by someone else during the "
                          "run, so the new run was not moved there; its files are in "
                          f"{tmp_path / 'run.unsaved-'}")
    assert [p.name for p in out.iterdir()] == ["theirs.txt"]
    assert (next(tmp_path.glob("run.unsaved-*")) / "metrics.json").exists()


def test_the_manifest_is_never_written_through_a_link(capsys: Capture, tmp_path: Path) -> None:
    out = tmp_path / "run"
    fake_run(out, {"metrics.json": "{}\n"})
    (tmp_path / "victim.txt").write_text("precious")
    for name in (f".{MANIFEST}.tmp", f".{MANIFEST}.x.tmp"):
        (out / name).symlink_to(tmp_path / "victim.txt")
    assert main(["run", *FAST, "--out", str(out)]) == 0
    capsys.readouterr()
    assert (tmp_path / "victim.txt").read_text() == "precious"
    assert json.loads((out / MANIFEST).read_text())["command"] == "run"


def test_a_swallowed_ctrl_c_still_stops_the_run_before_it_replaces_anything(
        capsys: Capture, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A Ctrl-C that a library swallowed (it landed in a finalizer) is noted by the handler:
    the run stops at its next step, exits 130 and leaves the earlier run as it was."""
    from dancebots.cli import common
    from dancebots.report import metrics

    out = tmp_path / "run"
    fake_run(out, {"metrics.json": "{}\n"})
    before = snapshot(tmp_path)
    original = metrics.run_metrics

    def swallowed(result: object) -> object:
        with contextlib.suppress(KeyboardInterrupt):  # as a finalizer would lose it
            common.on_interrupt(2, None)
        return original(result)  # type: ignore[arg-type]

    monkeypatch.setattr(metrics, "run_metrics", swallowed)
    assert main(["run", *FAST, "--out", str(out)]) == 130
    assert capsys.readouterr().err.endswith("dancebots: interrupted\n")
    assert snapshot(tmp_path) == before


def test_a_failed_first_run_leaves_nothing(
        capsys: Capture, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def interrupted(*args: object, **kwargs: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr("dancebots.report.runlog.write_log", interrupted)
    assert main(["run", *FAST, "--out", str(tmp_path / "new" / "deeper" / "run")]) == 130
    assert "dancebots: interrupted" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []  # the parents it made are gone too


def test_commit_keeps_the_earlier_files_until_the_new_ones_are_complete(
        tmp_path: Path) -> None:
    out = tmp_path / "run"
    fake_run(out, {"a.txt": "old a\n", "b.txt": "old b\n"})
    user_files(out)
    staged = stage_output(out, "test")
    assert staged.staging.parent == out
    (staged.staging / "a.txt").write_text("new a\n")
    assert (out / "a.txt").read_text() == "old a\n"  # still the earlier run while writing
    staged.commit(["a.txt"], __version__)
    assert (out / "a.txt").read_text() == "new a\n"
    assert not (out / "b.txt").exists()
    assert (out / "precious.txt").read_text() == "mine\n"
    assert json.loads((out / MANIFEST).read_text())["files"] == {
        "a.txt": [__import__("hashlib").sha256(b"new a\n").hexdigest()]}


def test_a_file_the_earlier_run_wrote_and_the_user_replaced_by_a_link_is_refused(
        tmp_path: Path) -> None:
    out = tmp_path / "run"
    fake_run(out, {"a.txt": "a\n"})
    (out / "a.txt").unlink()
    (tmp_path / "elsewhere.txt").write_text("mine")
    (out / "a.txt").symlink_to(tmp_path / "elsewhere.txt")
    with pytest.raises(OutputError, match="was changed since dancebots wrote it"):
        stage_output(out, "test")
    assert (tmp_path / "elsewhere.txt").read_text() == "mine"


# --- single files: plan --png --------------------------------------------------------------

def test_plan_replaces_its_own_image_and_refuses_others(capsys: Capture, tmp_path: Path) -> None:
    scenario = str(EXAMPLES / "thesis_7_3.dance")
    image = tmp_path / "plan.png"
    assert main(["plan", scenario, "--png", str(image)]) == 0
    first = image.stat().st_mtime_ns
    assert main(["plan", scenario, "--png", str(image)]) == 0  # its own: replaced
    assert image.stat().st_mtime_ns >= first
    for name, kind in (("plan.svg", "svg"), ("plan.pdf", "pdf")):
        assert main(["plan", scenario, "--png", str(tmp_path / name)]) == 0, kind
        assert main(["plan", scenario, "--png", str(tmp_path / name)]) == 0, kind
    capsys.readouterr()
    for name, content in (("photo.png", b"\x89PNG\r\n\x1a\nsomeone else's"),
                          ("notes.svg", b"<svg><text>notes on dancebots plan</text></svg>")):
        (tmp_path / name).write_bytes(content)
        assert main(["plan", scenario, "--png", str(tmp_path / name)]) == 2
        assert capsys.readouterr().err == (
            f"dancebots plan: error: {tmp_path / name} exists and was not written by "
            "dancebots (or was changed since); remove it or choose another name\n")
        assert (tmp_path / name).read_bytes() == content
    with open(image, "ab") as handle:  # its own image, edited since: no longer its own
        handle.write(b"an edit")
    assert main(["plan", scenario, "--png", str(image)]) == 2
    assert capsys.readouterr().err.startswith(f"dancebots plan: error: {image} exists and was")
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == [
        ".dancebots-images.json"]


@pytest.mark.parametrize("kind", ["directory", "link"])
def test_plan_refuses_directories_and_links(capsys: Capture, tmp_path: Path, kind: str) -> None:
    target = tmp_path / "out.png"
    if kind == "directory":
        target.mkdir()
        message = f"{target} is a directory; give a file name, e.g. {target / 'plan.png'}"
    else:
        (tmp_path / "real.png").write_text("mine")
        target.symlink_to(tmp_path / "real.png")
        message = f"{target} is a symbolic link; give the path of a file"
    assert main(["plan", str(EXAMPLES / "thesis_7_3.dance"), "--png", str(target)]) == 2
    assert capsys.readouterr().err == f"dancebots plan: error: {message}\n"
    if kind == "link":
        assert (tmp_path / "real.png").read_text() == "mine"


def test_write_file_reports_without_its_temporary_name(tmp_path: Path) -> None:
    locked = tmp_path / "locked"
    locked.mkdir()

    def fail(path: Path) -> None:
        raise OSError(13, "Permission denied", str(path))

    with pytest.raises(OutputError) as error:
        write_file(locked / "plan.png", fail, __version__)
    assert str(error.value) == f"cannot write {locked / 'plan.png'}: Permission denied"
    assert os.listdir(locked) == []

"""The queue show end to end: the bundled course without collision, the seed's kidnapping
by a crossing person reproduced, and the tracking addition that prevents it."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from dancebots.cli import main
from dancebots.cli.common import bundled
from dancebots.report.queue_metrics import queue_metrics, surface_gaps
from dancebots.shows.queue import QueueConfig, simulate_queue
from dancebots.world import load_world, parse_world


@pytest.fixture(scope="module")
def course():  # type: ignore[no-untyped-def]
    return load_world(bundled("follow_course.toml"))


@pytest.fixture(scope="module")
def crossing():  # type: ignore[no-untyped-def]
    return load_world(bundled("follow_crossing.toml"))


def test_a1_pid_queue_runs_the_course_without_collision(course) -> None:  # type: ignore[no-untyped-def]
    result = simulate_queue(course, QueueConfig(detector="a1", controller="pid"))
    metrics = queue_metrics(result)
    assert result.collisions == ()
    assert metrics.intact
    assert all(f.kidnappings == 0 for f in metrics.followers)
    gaps = surface_gaps(result)[:, result.times > 5.0]
    assert gaps.min() > 0.2  # nobody drives into the one in front
    # the followers did walk the course: the last one ends beyond the second box
    assert result.poses[-1, -1, 0] > 8.5


def test_the_seeds_a2_b2_is_kidnapped_by_the_crossing_person(crossing) -> None:  # type: ignore[no-untyped-def]
    metrics = queue_metrics(simulate_queue(crossing, QueueConfig(detector="a2",
                                                                 controller="vo")))
    assert sum(f.kidnappings for f in metrics.followers) >= 1
    assert not metrics.intact


def test_tracking_the_target_keeps_the_queue_through_the_crossing(crossing) -> None:  # type: ignore[no-untyped-def]
    result = simulate_queue(crossing, QueueConfig(detector="a2-track", controller="vo"))
    metrics = queue_metrics(result)
    assert result.collisions == ()
    assert metrics.intact
    assert all(f.kidnappings == 0 for f in metrics.followers)
    assert not result.kidnapped.any()
    # the crosser did pass between F1 and F2 (within a metre of both)
    crosser = result.spectators[result.spectator_names.index("crosser")]
    between = np.hypot(*(crosser - result.poses[0, :, :2]).T) < 1.0
    assert (between & (np.hypot(*(crosser - result.poses[1, :, :2]).T) < 1.0)).any()


def test_follow_command_writes_its_outputs(tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "queue"
    assert main(["follow", "--robots", "2", "--detector", "a2-track", "--controller", "pid",
                 "--no-animation", "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["dancebots-manifest.json", "log.csv",
                                                     "metrics.json", "queue.png", "run.mcap",
                                                     "show.html"]
    metrics = json.loads((out / "metrics.json").read_text())
    assert [f["robot"] for f in metrics["followers"]] == ["F1", "F2"]
    assert metrics["queue_intact"] is True
    import pandas

    log = pandas.read_csv(out / "log.csv")
    assert set(log["robot"]) == {"F1", "F2"}
    assert "queue intact" in capsys.readouterr().out


def test_follow_needs_a_leader(tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    world = tmp_path / "empty.toml"
    world.write_text("[room]\nsize = 5.0\n")
    assert parse_world(world.read_text(), str(world))[0] is not None
    assert main(["follow", "--world", str(world), "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err == (
        f"dancebots follow: error: {world}: the queue show needs a spectator named 'leader' "
        "(the person the queue follows)\n")


def test_follow_reports_a_bad_world_with_its_position(tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    world = tmp_path / "bad.toml"
    world.write_text("[room]\nsize = -5.0\n")
    assert main(["follow", "--world", str(world)]) == 2
    assert f"{world}:2:" in capsys.readouterr().err


def test_a_queue_follows_a_robot_that_drives_the_path(course) -> None:  # type: ignore[no-untyped-def]
    result = simulate_queue(course, QueueConfig(detector="a2-track", controller="vo",
                                                leader="robot"))
    metrics = queue_metrics(result)
    assert result.robots == ("F1", "F2", "F3")
    assert "leader" not in result.spectator_names  # the robot took the person's place
    assert result.collisions == ()
    assert metrics.intact
    assert result.leader[-1, 0] > 10.5  # the leader robot drove to the path's end
    assert np.hypot(*(result.leader[-1] - (11.0, 3.0))) < 0.2


def test_a_short_queue_run_animates(tmp_path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    from PIL import Image

    from dancebots.report.queue_animation import animate_queue
    from dancebots.report.queue_plots import plot_queue

    world, _ = parse_world(
        "[room]\nsize = 6.0\n[[spectators]]\nname = \"leader\"\nspeed = 0.2\nradius = 0.2\n"
        "path = [[3.0, 3.0], [4.0, 3.0]]\n", "short.toml")
    assert world is not None
    result = simulate_queue(world, QueueConfig(robots=2, settle=1.0))
    frames = animate_queue(result, str(tmp_path / "queue.gif"))
    with Image.open(tmp_path / "queue.gif") as image:
        assert image.n_frames == frames > 5
    figure = plot_queue(result)
    assert len(figure.axes) == 2


def test_bundled_worlds_by_name(tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    assert main(["follow", "--world", "crossing", "--robots", "1", "--no-animation",
                 "--detector", "a2-track", "--out", str(tmp_path / "o")]) == 0
    assert "follow_crossing.toml" in capsys.readouterr().out


def test_the_stage_delivers_planar_scans_after_the_latency(course) -> None:  # type: ignore[no-untyped-def]
    """The queue's LIDAR is the stage's: a scan taken at t reaches the robots at t + 0.3 s,
    with the poses they had when it was taken."""
    from dancebots.shows.queue import queue_placement
    from dancebots.sim.kinematics import IDEAL
    from dancebots.sim.lidar import LidarConfig
    from dancebots.sim.stage import Stage

    arena, placement = queue_placement(course, QueueConfig(robots=2))
    stage = Stage(arena, placement, IDEAL, 0.05, None)
    lidar = LidarConfig(latency=0.3, period=0.1)
    arrived = {round(k * 0.05, 2): stage.planar_deliveries(k * 0.05, lidar) for k in range(9)}
    assert [t for t, scans in arrived.items() if scans] == [0.3, 0.4]
    stamp, ranges, poses = arrived[0.3][0]
    assert stamp == 0.0
    assert ranges.shape == (2, len(lidar.angles()))
    assert (poses == placement.starts).all()

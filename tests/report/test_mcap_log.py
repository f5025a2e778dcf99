"""The run's MCAP log (report/mcap_log.py): read back with the mcap reader, every topic with
one message per robot per tick, the values of the run, the standard ROS 1 types."""

from __future__ import annotations

import math
import sys
from collections import Counter
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_ros1.decoder import DecoderFactory

from dancebots.genpy_types import genpy_module
from dancebots.plan.compile import compile_scenario
from dancebots.plan.placement import place_show
from dancebots.report import mcap_log
from dancebots.report.mcap_log import write_queue_mcap, write_run_mcap
from dancebots.shows.formation import RobotEvent, RunResult, SimConfig, simulate
from dancebots.sim import prepare_show
from dancebots.world import parse_world

SHOW = "robots R1 R2\nrow R1,R2 0 1.2\nmove 3 0\n"
WORLD = """
[room]
polygon = [[-3.0, -3.0], [6.0, -3.0], [6.0, 3.0], [-3.0, 3.0]]

[[spectators]]
path = [[2.2, -0.6], [2.2, -0.6]]
speed = 0.5
"""
ROS_MD5 = {  # the sums ROS's generated classes carry (rosmsg md5)
    "geometry_msgs/PoseStamped": "d3812c3cbc69362b77dc0b19b345f8f5",
    "geometry_msgs/PoseArray": "916c28c5764443f268b296bb671b9d97",
    "geometry_msgs/Twist": "9f195f881246fdfa2798d1d3eebca84a",
    "geometry_msgs/TwistStamped": "98d34b0043a2093cf9d9345ab6eef12e",
    "tf2_msgs/TFMessage": "94810edda583a504dfda3829e70d7eec",
    "std_msgs/String": "992ce8a1687cec8c8bd883ec73ca41d1",
    "sensor_msgs/PointCloud2": "1158d486dd51d683ce2f1be655c3c181",
}


@pytest.fixture(scope="module")
def result() -> RunResult:
    _, plan, diagnostics = compile_scenario(SHOW, "t.dance")
    assert plan is not None, diagnostics
    world, problems = parse_world(WORLD, "w.toml")
    assert world is not None, problems
    arena, placement = prepare_show(place_show(plan, world))
    run = simulate(plan, arena, placement, SimConfig())
    assert not run.events  # the person stands clear: the events are set below
    return replace(run, events=(RobotEvent(1.25, "R2", "speech", "Obstacle is too close"),
                                RobotEvent(4.0, "R2", "beep", ""),
                                RobotEvent(float(run.times[-1]), "R1", "resume", "clear")))


def read(path: Path) -> list[tuple[str, str, int, Any]]:
    """(topic, schema name, log time ns, decoded message) of every message, in log order."""
    with open(path, "rb") as handle:
        reader = make_reader(handle, decoder_factories=[DecoderFactory()])
        return [(channel.topic, schema.name, message.log_time, decoded)
                for schema, channel, message, decoded in reader.iter_decoded_messages()]


def test_every_topic_has_a_message_per_tick_with_the_runs_values(result: RunResult,
                                                                  tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    count = write_run_mcap(result, str(path))
    messages = read(path)
    assert count == len(messages)
    ticks = len(result.times)
    counts = Counter((topic, schema) for topic, schema, _, _ in messages)
    expected = {("/tf", "tf2_msgs/TFMessage"): ticks,
                ("/spectators", "geometry_msgs/PoseArray"): ticks}
    for robot in ("R1", "R2"):
        expected |= {(f"/{robot}/pose", "geometry_msgs/PoseStamped"): ticks,
                     (f"/{robot}/desired", "geometry_msgs/PoseStamped"): ticks,
                     (f"/{robot}/virtual_leader", "geometry_msgs/PoseStamped"): ticks,
                     (f"/{robot}/cmd_vel", "geometry_msgs/Twist"): ticks,
                     (f"/{robot}/velocity", "geometry_msgs/TwistStamped"): ticks}
    expected[("/events", "std_msgs/String")] = 3
    assert dict(counts) == expected
    k = ticks // 2
    poses = [m for topic, _, _, m in messages if topic == "/R2/pose"]
    pose = poses[k].pose
    yaw = 2.0 * math.atan2(pose.orientation.z, pose.orientation.w)
    assert (pose.position.x, pose.position.y) == tuple(result.poses[1, k, :2])
    assert yaw == pytest.approx(result.poses[1, k, 2], abs=1e-12)
    assert poses[k].header.frame_id == "world"
    assert poses[k].header.stamp.to_sec() == pytest.approx(result.times[k], abs=1e-9)
    commands = [m for topic, _, _, m in messages if topic == "/R1/cmd_vel"]
    assert [[c.linear.x, c.angular.z] for c in commands] == result.commands[0].tolist()
    tf = [m for topic, _, _, m in messages if topic == "/tf"][k]
    assert [t.child_frame_id for t in tf.transforms] == ["R1/base_link", "R2/base_link"]
    assert tf.transforms[1].transform.translation.x == result.poses[1, k, 0]
    people = [m for topic, _, _, m in messages if topic == "/spectators"][k]
    assert [(p.position.x, p.position.y) for p in people.poses] == [
        tuple(result.spectators[0, k])]
    spoken = [(m.data, t) for topic, _, t, m in messages if topic == "/events"]
    assert spoken == [("R2 speech: Obstacle is too close", 1_250_000_000),
                      ("R2 beep", 4_000_000_000),
                      ("R1 resume: clear", round(result.times[-1] * 1e9))]
    times = [t for _, _, t, _ in messages]
    assert times == sorted(times)  # in time order, the events among the ticks
    assert times[-1] == round(result.times[-1] * 1e9)


def test_the_types_are_ross_and_the_log_the_same_without_ros(result: RunResult,
                                                             tmp_path: Path,
                                                             monkeypatch: pytest.MonkeyPatch,
                                                             ) -> None:
    """The definitions give ROS's MD5 sums; with ROS's genpy or the copy mcap-ros1-support
    carries (no ROS installed), and written twice (no clock read), the file is the same."""
    types = mcap_log._types()
    assert {name: types[name]._md5sum for name in ROS_MD5} == ROS_MD5
    first, again, without = (tmp_path / "a.mcap", tmp_path / "b.mcap", tmp_path / "c.mcap")
    write_run_mcap(result, str(first))
    write_run_mcap(result, str(again))
    monkeypatch.setitem(sys.modules, "genpy", None)  # import genpy raises ImportError
    mcap_log._types.cache_clear()
    try:
        assert "_vendor" in genpy_module().__name__
        write_run_mcap(result, str(without))
    finally:
        mcap_log._types.cache_clear()
    assert first.read_bytes() == again.read_bytes() == without.read_bytes()


def test_a_queue_logs_its_poses_commands_targets_and_leader(tmp_path: Path) -> None:
    """``follow``'s log: per follower a pose and a command at every tick and a target at
    every tick its detector has one (the NaN ticks have none), the leader at every tick."""
    from dancebots.cli.common import bundled
    from dancebots.shows.queue import QueueConfig, simulate_queue
    from dancebots.world import load_world

    world = load_world(bundled("follow_crossing.toml"))  # the crossing person hides F1
    result = simulate_queue(world, QueueConfig(robots=2, detector="a1", controller="pid"))
    path = tmp_path / "queue.mcap"
    assert write_queue_mcap(result, str(path)) == len(read(path))
    counts = Counter(topic for topic, _, _, _ in read(path))
    ticks = len(result.times)
    seen = np.isfinite(result.targets).all(axis=2).sum(axis=1)  # (R,) ticks with a target
    assert 0 < seen[1] < ticks or 0 < seen[0] < ticks  # some ticks without one, some with
    assert dict(counts) == {
        "/tf": ticks, "/leader": ticks, "/spectators": ticks,
        "/F1/pose": ticks, "/F1/cmd_vel": ticks, "/F1/target": int(seen[0]),
        "/F2/pose": ticks, "/F2/cmd_vel": ticks, "/F2/target": int(seen[1])}
    leader = [m for topic, _, _, m in read(path) if topic == "/leader"]
    assert (leader[-1].point.x, leader[-1].point.y) == tuple(result.leader[-1])


def test_the_ros_bridges_record_as_mcap(tmp_path: Path) -> None:
    """``ros simulate --record FILE.mcap``: the bridge's arrays (ROS times, poses, the
    commands obeyed, contacts) as /tf, poses, commands and /contacts at their times."""
    from dancebots.report.mcap_log import write_record_mcap

    times = 1_700_000_000.0 + np.arange(5) * 0.05  # ROS time, s
    poses = np.zeros((2, 5, 3))
    poses[0, :, 0] = np.arange(5) * 0.01
    poses[1, :, 1] = 1.0
    commands = np.zeros((2, 5, 2))
    commands[0, :, 0] = 0.2
    path = tmp_path / "record.mcap"
    count = write_record_mcap(str(path), ("R1", "R2"), times, poses, commands,
                              [(float(times[3]), "R2", "wall")])
    messages = read(path)
    assert count == len(messages) == 5 * 5 + 1
    counts = Counter(topic for topic, _, _, _ in messages)
    assert dict(counts) == {"/tf": 5, "/R1/pose": 5, "/R1/cmd_vel": 5, "/R2/pose": 5,
                            "/R2/cmd_vel": 5, "/contacts": 1}
    contact = next((t, m.data) for topic, _, t, m in messages if topic == "/contacts")
    assert contact == (round(times[3] * 1e9), "R2 touched wall")
    last = [m for topic, _, _, m in messages if topic == "/R1/pose"][-1]
    assert last.pose.position.x == poses[0, 4, 0]
    assert last.header.stamp.to_sec() == pytest.approx(times[4], abs=1e-6)



def test_recorded_scans_are_logged_as_point_clouds(tmp_path: Path) -> None:
    """With the scans recorded (run --show-lidar), each robot's hits of every scan are a
    PointCloud2 on /<robot>/scan at the time the scan reached it, the same points."""
    _, plan, diagnostics = compile_scenario(SHOW, "t.dance")
    assert plan is not None, diagnostics
    world, problems = parse_world(WORLD, "w.toml")
    assert world is not None, problems
    arena, placement = prepare_show(place_show(plan, world))
    result = simulate(plan, arena, placement, SimConfig(record_lidar=True))
    path = tmp_path / "scans.mcap"
    write_run_mcap(result, str(path))
    clouds = [(t, m) for topic, schema, t, m in read(path) if topic == "/R2/scan"]
    assert len(clouds) == len(result.lidar)
    when, hits = result.lidar[5]
    t, cloud = clouds[5]
    assert t == round(when * 1e9)  # logged when it reached the robot, stamped when scanned
    assert cloud.header.stamp.to_sec() == pytest.approx(when - result.config.lidar.latency,
                                                        abs=1e-6)
    assert (cloud.width, cloud.point_step, [f.name for f in cloud.fields]) == (
        len(hits[1]), 12, ["x", "y", "z"])
    xyz = np.frombuffer(cloud.data, dtype="<f4").reshape(-1, 3)
    np.testing.assert_array_equal(xyz[:, :2], np.asarray(hits[1], dtype=np.float32))
    assert not xyz[:, 2].any()

"""Several hosts: the ROS master and the simulator bridge in one network namespace, each
robot's nodes in a namespace of its own, linked by veth pairs (as robots on a network with
one master). The show runs across them; a robot whose cable is pulled is at zero command
within 0.3 s (the robots' 10 Hz rule at the bridge), and the others, which no longer hear its
hold messages, stop 1 s later and wait (the formation's shared show clock: a robot cut off
while it holds, or at any time, stops the show). Its formation_member, cut off from the
master, idles (no busy loop) and ends on SIGTERM. A robot whose cable is pulled while it
holds the show for a visitor keeps the show waiting: its silence holds as its message did."""

from __future__ import annotations

import os
import re
import signal
import time
from pathlib import Path

import numpy as np
import pytest
from tests.ros1.conftest import require_ros, start_master, stop
from tests.ros1.netns import hosts, namespace_processes, netns_missing
from tests.ros1.show import (
    SCENARIO_7_1,
    START_ALLOWANCE,
    Record,
    RosShow,
    plan_of,
    pure_run,
    wait_until,
)
from tests.ros1.test_ros_simulation import FINAL_TOLERANCE

pytestmark = pytest.mark.ros


def _require_ros_and_namespaces() -> None:
    """Skip without ROS or network namespaces; fail instead with DANCEBOTS_REQUIRE_ROS=1."""
    require_ros()
    reason = netns_missing()
    if reason is not None:
        if os.environ.get("DANCEBOTS_REQUIRE_ROS") == "1":
            pytest.fail(reason)
        pytest.skip(reason)


@pytest.mark.parametrize("pull_cable", [False, True], ids=["clean", "link-down"])
def test_show_across_network_namespaces(tmp_path: Path, pull_cable: bool) -> None:
    _require_ros_and_namespaces()
    duration = plan_of(SCENARIO_7_1).duration
    pure = pure_run(SCENARIO_7_1)
    with hosts(("R1", "R2")) as network:
        master, roscore = start_master(tmp_path, network.master_address, network.master)
        show = RosShow(master, tmp_path)
        pulled_at = None
        try:
            bridge_env = dict(master.env)
            show.launch("bridge", ["dancebots_ros", "sim_bridge.launch",
                                   f"scenario:={SCENARIO_7_1}",
                                   f"record:={tmp_path / 'record.npz'}",
                                   f"stop_after:={duration + START_ALLOWANCE}"],
                        network.master, bridge_env)
            for robot in ("R1", "R2"):
                env = dict(master.env, ROS_IP=network.addresses[robot])
                show.start_robot(SCENARIO_7_1, robot, network.robots[robot], env)
            wait_until(lambda: "R1: ok at show time" in show.log("R1"), 60, "R1's start")
            if pull_cable:
                time.sleep(10.0)
                pulled_at = time.time()
                network.take_down("R1")
            show.wait_bridge(duration + START_ALLOWANCE + 30)
            if pull_cable:
                check_cut_off_member_idles_and_ends(network.robots["R1"])
        finally:
            show.stop_all()
            stop(roscore)
    record = Record.load(tmp_path / "record.npz")
    r1, r2 = record.index("R1"), record.index("R2")
    assert len(record.contacts) == 0
    gap = np.hypot(*(record.poses[:, -1, :2] - pure.poses[:, -1, :2]).T)
    if pulled_at is None:
        assert gap[r1] <= FINAL_TOLERANCE  # both finish when nothing goes wrong
        assert gap[r2] <= FINAL_TOLERANCE
        assert "every robot answered" in show.log("R1")
    else:
        late = record.times > pulled_at + 0.3
        assert late.any()
        assert np.all(record.commands[r1, late] == 0.0)
        assert np.any(record.commands[r1, record.times < pulled_at] != 0.0)
        # the formation's shared show clock (the default --hold paced): R2 no longer
        # hears R1, so after the 1 s heartbeat timeout the show stops; R2 settles on its
        # place where the show stopped (its heading corrected, at most a few cm) and waits
        stood = record.times > pulled_at + 1.5
        drift = np.hypot(*(record.poses[r2, stood, :2] - record.poses[r2, stood.argmax(), :2]).T)
        assert drift.max() < 0.05
        assert gap[r2] > 0.5  # it did not drive on alone to the end of its part
        assert "not heard from R1" in show.log("R2")


VISITOR_WORLD = """\
# listing 7.1's row in a 12 m room; a visitor stands in R1's lane 2.8 m ahead for good
[room]
size = 12.0

[[robots]]
name = "R1"
x = 3.0
y = 6.6
yaw = 0.0

[[robots]]
name = "R2"
x = 3.0
y = 5.4
yaw = 0.0

[[spectators]]
name = "visitor"
path = [[5.8, 6.6]]
"""
WATCHED = 12.0
"""s the test watches the formation after R1's cable is pulled while it holds."""


def test_a_robot_cut_off_while_it_holds_keeps_the_show_waiting(tmp_path: Path) -> None:
    """R1 stops for a visitor in its lane and holds the show; R2 waits (its log says held by
    R1). Then R1's cable is pulled: R2 no longer hears R1, and a silent mate counts as a
    hold, so R2 keeps waiting where it stood (it must not take the silence for a release
    and drive on alone); R1, cut off from its clouds, stays at zero command."""
    _require_ros_and_namespaces()
    world = tmp_path / "visitor.toml"
    world.write_text(VISITOR_WORLD)
    with hosts(("R1", "R2")) as network:
        master, roscore = start_master(tmp_path, network.master_address, network.master)
        show = RosShow(master, tmp_path)
        try:
            show.launch("bridge", ["dancebots_ros", "sim_bridge.launch",
                                   f"scenario:={SCENARIO_7_1}", f"world:={world}",
                                   f"record:={tmp_path / 'record.npz'}",
                                   f"stop_after:={START_ALLOWANCE + 60}"],
                        network.master, dict(master.env))
            for robot in ("R1", "R2"):
                env = dict(master.env, ROS_IP=network.addresses[robot])
                show.start_robot(SCENARIO_7_1, robot, network.robots[robot], env,
                                 extra=(f"world:={world}",))
            wait_until(lambda: "(held by R1)" in show.log("R2"), START_ALLOWANCE + 30,
                       "R2 waiting for R1")
            time.sleep(2.0)
            pulled_at = time.time()
            network.take_down("R1")
            time.sleep(WATCHED)
            watched_until = time.time()
            r2_log = show.log("R2")
        finally:
            show.stop_all()
            stop(roscore)
    record = Record.load(tmp_path / "record.npz")
    r1, r2 = record.index("R1"), record.index("R2")
    assert len(record.contacts) == 0
    before = record.times < pulled_at
    assert np.any(record.commands[r1, before] != 0.0)  # it drove before it was held
    late = (record.times > pulled_at + 0.3) & (record.times < watched_until)
    assert late.sum() > 10 * (WATCHED - 1)  # the bridge recorded the whole watch (10 Hz)
    assert np.all(record.commands[r1, late] == 0.0)
    # R2 stood where the hold stopped it, through the cut and after it
    held = (record.times > pulled_at - 2.0) & (record.times < watched_until)
    drift = np.hypot(*(record.poses[r2, held, :2] - record.poses[r2, held.argmax(), :2]).T)
    assert drift.max() < 0.05
    assert not [line for line in r2_log.splitlines() if "the show goes on" in line
                and _logged_at(line) > pulled_at], r2_log


@pytest.mark.parametrize("r2_clock_offset", [0.0, 0.5], ids=["clocks-agree", "clock-off"])
def test_a_timecode_start_across_network_namespaces(tmp_path: Path,
                                                    r2_clock_offset: float) -> None:
    """`dancebots ros formation --start-at T` on each host: after the network test every
    robot agrees on T itself (not a proposal of its own), and the show starts then. With R2's
    clock 0.5 s off (injected in-process into its start agreement: the hosts here share one
    kernel clock) neither robot starts: each refuses and says why (two robots cannot tell
    whose clock is off), and the bridge records no motion."""
    _require_ros_and_namespaces()
    timecode = time.time() + START_ALLOWANCE + 10.0
    with hosts(("R1", "R2")) as network:
        master, roscore = start_master(tmp_path, network.master_address, network.master)
        show = RosShow(master, tmp_path)
        try:
            show.launch("bridge", ["dancebots_ros", "sim_bridge.launch",
                                   f"scenario:={SCENARIO_7_1}",
                                   f"record:={tmp_path / 'record.npz'}",
                                   f"stop_after:={START_ALLOWANCE + 30}"],
                        network.master, dict(master.env))
            for robot in ("R1", "R2"):
                env = dict(master.env, ROS_IP=network.addresses[robot])
                offset = r2_clock_offset if robot == "R2" else 0.0
                show.start_robot(SCENARIO_7_1, robot, network.robots[robot], env, extra=(
                    "start_strategy:=timecode", f"start_at:={timecode!r}",
                    f"clock_offset:={offset!r}"))
            if r2_clock_offset == 0.0:
                wait_until(lambda: all("start agreed at" in show.log(r) for r in ("R1", "R2")),
                           START_ALLOWANCE + 15, "the timecode start")
                wait_until(lambda: "R1: ok at show time" in show.log("R1"), 20,
                           "R1 driving")
            else:
                wait_until(lambda: all("refuses to start" in show.log(r) for r in ("R1", "R2")),
                           START_ALLOWANCE + 15, "both robots refusing")
                time.sleep(max(0.0, timecode + 3.0 - time.time()))  # past the start time
            logs = {robot: show.log(robot) for robot in ("R1", "R2")}
            show.wait_bridge(START_ALLOWANCE + 40)
        finally:
            show.stop_all()
            stop(roscore)
    record = Record.load(tmp_path / "record.npz")
    assert all("every robot answered" in log for log in logs.values())  # the network test
    if r2_clock_offset == 0.0:
        for robot, log in logs.items():
            match = re.search(rf"{robot}: start agreed at (\S+) \(timecode\)", log)
            assert match is not None, log
            assert float(match.group(1)) == timecode
        # before T the robots stand on their first slots (their followers hold them there,
        # a few mm); the show moves them only from T on
        before = (record.times > timecode - 15.0) & (record.times < timecode)
        assert before.sum() > 50  # agreed more than 30 s before T
        first = record.poses[:, before.argmax(), :2]
        drift = np.hypot(*(record.poses[:, before, :2] - first[:, None, :]).T)
        assert drift.max() < 0.03
        after = record.times > timecode + 8.0
        assert after.any()
        travelled = np.hypot(*(record.poses[:, after, :2][:, -1] - first).T)
        assert travelled.min() > 1.0
    else:
        # two robots cannot tell whose clock is off: each judges the other's, 0.5 s away
        for robot, side in (("R2", "ahead of"), ("R1", "behind")):
            # 0.5 s, less or more the transit of the least delayed message (sub-millisecond)
            assert re.search(rf"{robot}: refuses to start: this robot's clock is "
                             rf"0\.(49\d|50\d) s {side} the formation's", logs[robot]), logs[robot]
        assert not any("start agreed" in log for log in logs.values())
        assert np.all(record.commands == 0.0)


def _logged_at(line: str) -> float:
    """The wall-clock stamp (s) of a rospy log line ``[INFO] [1795719589.849273]: ...``."""
    match = re.search(r"\[(\d+\.\d+)\]", line)
    assert match is not None, line
    return float(match.group(1))


IDLE_CPU = 0.3
"""Share of a core a formation_member cut off from its master may use (its 20 Hz loop needs a
few per cent; the busy loop of issue 10 took 85-100 %)."""
TERM_WITHIN = 12.0
"""s from SIGTERM to the end of a cut-off formation_member: obstacle_detection's stop and
rospy's shutdown each give the unreachable master 3 s (common.SHUTDOWN_TIMEOUT)."""


def check_cut_off_member_idles_and_ends(namespace: str) -> None:
    """R1's formation_member, whose master has been unreachable for a while: its CPU use
    over 3 s is low, and SIGTERM ends it (with its obstacle_detection) within TERM_WITHIN s."""
    members = [pid for pid, command in namespace_processes(namespace)
               if "nodes/formation_member" in command]
    assert len(members) == 1, namespace_processes(namespace)
    member = members[0]
    ticks = os.sysconf("SC_CLK_TCK")

    def cpu_seconds() -> float:
        with open(f"/proc/{member}/stat") as stat:
            fields = stat.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / ticks  # utime + stime

    before, started = cpu_seconds(), time.monotonic()
    time.sleep(3.0)
    share = (cpu_seconds() - before) / (time.monotonic() - started)
    print(f"the cut-off formation_member used {share:.1%} of a core over 3 s")
    assert share < IDLE_CPU, f"the cut-off formation_member uses {share:.0%} of a core"
    detectors = [pid for pid, command in namespace_processes(namespace)
                 if "nodes/obstacle_detection" in command]
    os.kill(member, signal.SIGTERM)
    sent = time.monotonic()
    deadline = sent + TERM_WITHIN
    while time.monotonic() < deadline and any(
            pid in (member, *detectors) for pid, _ in namespace_processes(namespace)):
        time.sleep(0.1)
    print(f"it ended {time.monotonic() - sent:.1f} s after SIGTERM")
    left = [(pid, command) for pid, command in namespace_processes(namespace)
            if pid in (member, *detectors)]
    assert not left, f"still running {TERM_WITHIN:g} s after SIGTERM: {left}"

"""Starting a ROS show for the tests: the simulator bridge and each robot's formation.launch
as separate roslaunch processes (optionally each in its own network namespace), as on real
robots, and reading the bridge's record."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from tests.ros1.conftest import Master, stop, tagged

from dancebots.plan.compile import compile_scenario
from dancebots.plan.placement import place_show
from dancebots.plan.planner import Plan, PlanParameters
from dancebots.robot import BrainOptions
from dancebots.shows.formation import RunResult, SimConfig, simulate
from dancebots.sim import prepare_show

EXAMPLES = Path(__file__).parents[2] / "examples"
SCENARIO_7_1 = EXAMPLES / "thesis_7_1.dance"
START_ALLOWANCE = 30.0  # s for the nodes to start, test the network and agree (4 s delay)


def plan_of(path: Path) -> Plan:
    """The plan the ROS nodes make of ``path`` with their defaults (the feasible timing)."""
    _, plan, diagnostics = compile_scenario(path.read_text(), str(path),
                                            PlanParameters(timing="feasible"))
    assert plan is not None, diagnostics
    return plan


def pure_run(path: Path, profile: str = "ideal", world: Path | None = None) -> RunResult:
    """The pure simulation of ``path`` (in ``world``) with the ROS nodes' defaults (the path
    follower on the feasible timing) in the simulator's ``profile``, to compare a ROS run
    with."""
    from dancebots.sim import PROFILES
    from dancebots.world import load_world

    plan = plan_of(path)
    arena, placement = prepare_show(place_show(
        plan, None if world is None else load_world(str(world)), places="path"))
    return simulate(plan, arena, placement, SimConfig(profile=PROFILES[profile],
                                                      brain=BrainOptions(follower="path")))


@dataclass
class Record:
    """The bridge's record: times (T,) ROS time s, poses (R, T, 3) world, commands (R, T, 2)
    as applied (after the 10 Hz rule), contacts (K, 2) (time, robot index)."""

    robots: tuple[str, ...]
    times: np.ndarray
    poses: np.ndarray
    commands: np.ndarray
    contacts: np.ndarray

    @classmethod
    def load(cls, path: Path) -> Record:
        """The record the bridge wrote: NumPy's .npz, or an .mcap log (read back with the
        mcap reader: /<robot>/pose and /<robot>/cmd_vel per step, /contacts)."""
        if path.suffix == ".mcap":
            return cls._from_mcap(path)
        data = np.load(path)
        return cls(tuple(str(r) for r in data["robots"]), data["times"], data["poses"],
                   data["commands"], data["contacts"])

    @classmethod
    def _from_mcap(cls, path: Path) -> Record:
        import math

        from mcap.reader import make_reader
        from mcap_ros1.decoder import DecoderFactory

        poses: dict[str, list[tuple[float, float, float]]] = {}
        commands: dict[str, list[tuple[float, float]]] = {}
        times: list[float] = []
        contacts: list[tuple[float, str]] = []
        with open(path, "rb") as handle:
            reader = make_reader(handle, decoder_factories=[DecoderFactory()])
            for _, channel, message, decoded in reader.iter_decoded_messages(log_time_order=True):
                topic = channel.topic
                if topic == "/contacts":
                    contacts.append((message.log_time / 1e9, decoded.data.split(" ")[0]))
                elif topic == "/tf":
                    times.append(decoded.transforms[0].header.stamp.to_sec())
                elif topic.endswith("/pose"):
                    p = decoded.pose
                    poses.setdefault(topic.split("/")[1], []).append(
                        (p.position.x, p.position.y,
                         2.0 * math.atan2(p.orientation.z, p.orientation.w)))
                elif topic.endswith("/cmd_vel"):
                    commands.setdefault(topic.split("/")[1], []).append(
                        (decoded.linear.x, decoded.angular.z))
        robots = tuple(poses)
        return cls(robots, np.array(times), np.array([poses[r] for r in robots]),
                   np.array([commands[r] for r in robots]),
                   np.array([(t, robots.index(r)) for t, r in contacts]).reshape(-1, 2))

    def index(self, robot: str) -> int:
        return self.robots.index(robot)


@dataclass
class RosShow:
    """A running show: the bridge and each robot's nodes as roslaunch processes."""

    master: Master
    folder: Path
    processes: dict[str, subprocess.Popen[bytes]] = field(default_factory=dict)

    def launch(self, key: str, arguments: list[str], netns: str | None = None,
               env: dict[str, str] | None = None) -> None:
        command = ["roslaunch", "--wait", *arguments]
        if netns is not None:
            command = ["ip", "netns", "exec", netns, *command]
        with open(self.folder / f"{key}.log", "wb") as log:
            self.processes[key] = subprocess.Popen(
                command, env=tagged(env or self.master.env), stdout=log, stderr=subprocess.STDOUT,
                start_new_session=True)

    def start_bridge(self, scenario: Path, stop_after: float, silence: str = "") -> Path:
        record = self.folder / "record.npz"
        self.launch("bridge", ["dancebots_ros", "sim_bridge.launch", f"scenario:={scenario}",
                               f"record:={record}", f"stop_after:={stop_after}",
                               f"silence:={silence}"])
        return record

    def start_robot(self, scenario: Path, role: str, netns: str | None = None,
                    env: dict[str, str] | None = None, extra: tuple[str, ...] = ()) -> None:
        self.launch(role, ["dancebots_ros", "formation.launch", f"scenario:={scenario}",
                           f"role:={role}", f"robot_name:={role}", "hostname:=simulator",
                           *extra], netns, env)

    def wait_bridge(self, timeout: float) -> None:
        self.processes["bridge"].wait(timeout)

    def log(self, key: str) -> str:
        return (self.folder / f"{key}.log").read_text(errors="replace")

    def stop_all(self) -> None:
        """SIGINT every roslaunch (each shuts its nodes down), SIGKILL those that do not end
        within 10 s; fails when roslaunch had to escalate to SIGTERM or SIGKILL: a node
        ignored SIGINT for 15 s."""
        for process in self.processes.values():
            stop(process)
        for key in self.processes:
            escalations = [line for line in self.log(key).splitlines()
                           if "escalating to SIG" in line]
            assert not escalations, f"{key}: a node did not end on SIGINT: {escalations}"


def kill_tree(pid: int) -> list[int]:
    """SIGKILL a process and all its descendants (roslaunch starts every node in a session
    of its own, so killing its process group would leave the nodes running). Returns the
    killed pids."""
    table = subprocess.run(["ps", "-eo", "pid=,ppid="], capture_output=True, text=True,
                           check=True).stdout.split()
    children: dict[int, list[int]] = {}
    for child, parent in zip(table[::2], table[1::2], strict=True):
        children.setdefault(int(parent), []).append(int(child))
    tree, frontier = [], [pid]
    while frontier:
        current = frontier.pop()
        tree.append(current)
        frontier.extend(children.get(current, []))
    for member in tree:
        with contextlib.suppress(ProcessLookupError):
            os.kill(member, signal.SIGKILL)
    return tree


def wait_until(condition: object, timeout: float, what: str) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if callable(condition) and condition():
            return
        time.sleep(0.2)
    raise TimeoutError(f"{what} did not happen within {timeout:g} s")

"""Fixtures of the ROS tests: a real ``roscore`` (Debian's ROS 1) on a free loopback port.

Without Debian's ROS packages these tests are skipped, unless DANCEBOTS_REQUIRE_ROS=1 (set
by ``.ci/run``, which installs them), where a missing ROS is a failure.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import time
import xmlrpc.client
from collections.abc import Iterator
from pathlib import Path

import pytest

from dancebots.ros1.launching import ros_environment


def ros_missing() -> str | None:
    """Why ROS cannot run here, or None."""
    if shutil.which("roscore") is None or shutil.which("roslaunch") is None:
        return "roscore/roslaunch not installed (Debian packages ros-core, python3-roslaunch)"
    try:
        import rospy  # noqa: F401
        import tf2_ros  # noqa: F401
    except ImportError as exc:
        return f"rospy/tf2_ros not importable ({exc}); use a venv with --system-site-packages"
    return None


def require_ros() -> None:
    reason = ros_missing()
    if reason is None:
        return
    if os.environ.get("DANCEBOTS_REQUIRE_ROS") == "1":
        pytest.fail(f"ROS is required here: {reason}")
    pytest.skip(reason)


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def wait_for_master(uri: str, timeout: float = 20.0) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            code, _, _ = xmlrpc.client.ServerProxy(uri).getPid("/dancebots_test")
            if code == 1:
                return
        except OSError:
            pass
        time.sleep(0.2)
    raise TimeoutError(f"no ROS master answered at {uri} within {timeout:g} s")


def stop(process: subprocess.Popen[bytes], grace: float = 10.0) -> None:
    """SIGINT the process group (roslaunch shuts its nodes down), then SIGKILL."""
    if process.poll() is not None:
        return
    try:
        os.killpg(process.pid, signal.SIGINT)
        process.wait(grace)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()
    except ProcessLookupError:
        pass


class Master:
    """A running roscore: its URI and the environment that points nodes at it."""

    def __init__(self, uri: str, env: dict[str, str]) -> None:
        self.uri, self.env = uri, env


def start_master(log_dir: Path, host: str = "127.0.0.1",
                 netns: str | None = None) -> tuple[Master, subprocess.Popen[bytes]]:
    port = free_port()
    uri = f"http://{host}:{port}/"
    env = ros_environment()
    env.update(ROS_MASTER_URI=uri, ROS_IP=host, ROS_LOG_DIR=str(log_dir), ROS_HOME=str(log_dir))
    env.pop("ROS_HOSTNAME", None)
    command = ["roscore", "-p", str(port)]
    if netns:
        command = ["ip", "netns", "exec", netns, *command]
    with open(log_dir / "roscore.log", "wb") as log:
        process = subprocess.Popen(command, env=env, stdout=log, stderr=subprocess.STDOUT,
                                   start_new_session=True)
    try:
        wait_for_master(uri) if netns is None else _wait_in_netns(netns, uri)
    except TimeoutError:
        stop(process)
        raise
    return Master(uri, env), process


def _wait_in_netns(netns: str, uri: str) -> None:
    probe = ("import time, xmlrpc.client\n"
             "for _ in range(100):\n"
             "    try:\n"
             f"        xmlrpc.client.ServerProxy({uri!r}).getPid('/t'); break\n"
             "    except OSError: time.sleep(0.2)\n"
             "else: raise SystemExit(1)\n")
    subprocess.run(["ip", "netns", "exec", netns, "python3", "-c", probe], check=True,
                   timeout=30)


@pytest.fixture(scope="module")
def roscore(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Master]:
    require_ros()
    log_dir = tmp_path_factory.mktemp("roslog")
    master, process = start_master(log_dir)
    yield master
    stop(process)

"""Fixtures of the ROS tests: a real ``roscore`` (Debian's ROS 1) on a free loopback port,
and the guarantee that no test leaves a process behind.

Without Debian's ROS packages these tests are skipped, unless DANCEBOTS_REQUIRE_ROS=1 (set
by ``.ci/run``, which installs them), where a missing ROS is a failure.

Every process a test starts carries the test's tag in its environment (``TAG_VARIABLE``:
set in ``os.environ`` and in :attr:`Master.env`), and so do its children and grandchildren
(roslaunch passes its environment to the nodes, ``ip netns exec`` keeps it), even when they
run in sessions of their own, in other network namespaces, or were re-parented to init. At
the end of each test (and of each module, for the module's roscore), a tagged process still
alive after ``LEFT_GRACE`` s fails the test and is killed.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import time
import uuid
import xmlrpc.client
from collections.abc import Iterator
from contextlib import contextmanager, suppress
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


TAG_VARIABLE = "DANCEBOTS_TEST_PROCESS_TAG"
LEFT_GRACE = 15.0
"""s a test's processes get to end after the test before they count as left behind."""


def tagged(env: dict[str, str]) -> dict[str, str]:
    """``env`` with the running test's process tag (see the module)."""
    tag = os.environ.get(TAG_VARIABLE)
    return env if tag is None else dict(env, **{TAG_VARIABLE: tag})


def tagged_processes(tag: str) -> list[tuple[int, str]]:
    """The live processes (pid, command line) whose environment carries ``tag``."""
    needle = f"{TAG_VARIABLE}={tag}".encode()
    found = []
    for entry in os.scandir("/proc"):
        if not entry.name.isdigit() or int(entry.name) == os.getpid():
            continue
        try:
            if needle not in Path(entry.path, "environ").read_bytes().split(b"\0"):
                continue
            state = Path(entry.path, "stat").read_text().rsplit(")", 1)[1].split()[0]
            command = Path(entry.path, "cmdline").read_bytes().replace(b"\0", b" ")
        except (OSError, IndexError):
            continue  # gone meanwhile, or not ours to read
        if state != "Z":  # a zombie has ended; its parent reaps it
            found.append((int(entry.name), command.decode(errors="replace").strip()))
    return found


@contextmanager
def no_process_left(what: str, grace: float = LEFT_GRACE) -> Iterator[str]:
    """Tag the processes started inside (os.environ and Master.env); afterwards wait up to
    ``grace`` s for them to end, then kill the rest and fail: ``what`` left them behind."""
    tag = f"{os.getpid()}-{uuid.uuid4().hex[:12]}"
    previous = os.environ.get(TAG_VARIABLE)
    os.environ[TAG_VARIABLE] = tag
    try:
        yield tag
    finally:
        if previous is None:
            os.environ.pop(TAG_VARIABLE, None)
        else:
            os.environ[TAG_VARIABLE] = previous
        deadline = time.monotonic() + grace
        left = tagged_processes(tag)
        while left and time.monotonic() < deadline:
            time.sleep(0.2)
            left = tagged_processes(tag)
        if left:
            for pid, _ in left:
                with suppress(ProcessLookupError):
                    os.kill(pid, signal.SIGKILL)
            deadline = time.monotonic() + 10.0
            while tagged_processes(tag) and time.monotonic() < deadline:
                time.sleep(0.1)
            listing = "\n".join(f"  {pid}: {command[:200]}" for pid, command in left)
            pytest.fail(f"{what} left {len(left)} process(es) running {grace:g} s after it "
                        f"ended (now killed):\n{listing}", pytrace=False)


@pytest.fixture(autouse=True)
def _no_process_left(request: pytest.FixtureRequest) -> Iterator[None]:
    with no_process_left(f"test {request.node.nodeid}"):
        yield


class Master:
    """A running roscore: its URI and the environment that points nodes at it (with the
    running test's process tag, read when :attr:`env` is)."""

    def __init__(self, uri: str, env: dict[str, str]) -> None:
        self.uri, self.base_env = uri, env

    @property
    def env(self) -> dict[str, str]:
        """The environment of a process that talks to this master."""
        return tagged(self.base_env)


def start_master(log_dir: Path, host: str = "127.0.0.1",
                 netns: str | None = None) -> tuple[Master, subprocess.Popen[bytes]]:
    port = free_port()
    uri = f"http://{host}:{port}/"
    env = tagged(ros_environment())
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
def roscore(tmp_path_factory: pytest.TempPathFactory,
            request: pytest.FixtureRequest) -> Iterator[Master]:
    require_ros()
    log_dir = tmp_path_factory.mktemp("roslog")
    with no_process_left(f"the roscore of {request.module.__name__}"):
        master, process = start_master(log_dir)
        try:
            yield master
        finally:
            stop(process)

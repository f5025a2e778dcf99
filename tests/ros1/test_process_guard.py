"""The ROS fixtures' guarantee that a test leaves no process behind (issue 10, part 6): a
process a test started, or a grandchild of it in a session of its own whose parent has
ended, or a process inside the test's network namespaces, still alive after the test fails
the test and is killed. No ROS needed; the namespace case needs root."""

from __future__ import annotations

import os
import subprocess
import time

import pytest
from tests.ros1.conftest import no_process_left, tagged_processes
from tests.ros1.netns import hosts, namespace_processes, netns_missing


def leave_an_orphan(tags: list[str]) -> None:
    """sh starts sleep in a new session and exits: sleep is re-parented to init, out of
    reach of the test's process group, and ignores SIGINT and SIGTERM."""
    with no_process_left("the probe", grace=0.5) as tag:
        tags.append(tag)
        subprocess.run(["sh", "-c", "trap '' INT TERM; setsid sleep 300 & exit 0"],
                       check=True, timeout=10)
        time.sleep(0.2)
        assert len(tagged_processes(tag)) == 1


def test_an_orphaned_grandchild_in_its_own_session_fails_the_test_and_is_killed() -> None:
    tags: list[str] = []
    with pytest.raises(pytest.fail.Exception, match=r"left 1 process\(es\)") as failure:
        leave_an_orphan(tags)
    assert "sleep 300" in str(failure.value)
    assert tagged_processes(tags[0]) == []  # killed


def test_processes_that_end_in_time_pass() -> None:
    with no_process_left("the probe", grace=10.0) as tag:
        subprocess.Popen(["sleep", "2"], start_new_session=True)
        deadline = time.monotonic() + 1.0  # /proc/PID/environ may read empty while it execs
        while not tagged_processes(tag) and time.monotonic() < deadline:
            time.sleep(0.01)
        assert len(tagged_processes(tag)) == 1
    assert tagged_processes(tag) == []


def leave_a_process_in_a_namespace(namespaces: list[str]) -> None:
    with hosts(("R1",), grace=0.5) as network:
        namespaces.append(network.robots["R1"])
        subprocess.Popen(["ip", "netns", "exec", namespaces[0], "sleep", "300"],
                         start_new_session=True)
        time.sleep(0.5)
        assert len(namespace_processes(namespaces[0])) == 1


def test_a_process_left_in_a_network_namespace_fails_the_test_and_is_killed() -> None:
    reason = netns_missing()
    if reason is not None:
        if os.environ.get("DANCEBOTS_REQUIRE_ROS") == "1":
            pytest.fail(reason)
        pytest.skip(reason)
    namespaces: list[str] = []
    with pytest.raises(AssertionError, match="still ran inside the test's network") as failure:
        leave_a_process_in_a_namespace(namespaces)
    assert "sleep 300" in str(failure.value)
    assert not namespace_processes(namespaces[0])

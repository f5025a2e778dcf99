"""Hosts for the multi-host tests: one network namespace per host, joined by veth pairs to
a Linux bridge inside the master's namespace. Addresses exist only inside the namespaces
(a private test range); nothing is configured in the machine's own namespace. A process
still running inside a namespace when the hosts are removed fails the test (and is killed):
deleting a namespace does not end its processes, it only hides them."""

from __future__ import annotations

import os
import signal
import subprocess
import time
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass

from tests.ros1.conftest import LEFT_GRACE

SUBNET = "10.231.{run}.{host}"


@dataclass(frozen=True)
class Hosts:
    """The namespaces: ``master`` (the ROS master and the simulator bridge) and one per
    robot, with their addresses; ``links`` names each robot's cable end at the bridge."""

    master: str
    master_address: str
    robots: dict[str, str]
    addresses: dict[str, str]
    links: dict[str, str]

    def take_down(self, robot: str) -> None:
        """Unplug a robot's cable (its veth end on the master's side goes down)."""
        _ip("netns", "exec", self.master, "ip", "link", "set", self.links[robot], "down")


def _ip(*arguments: str) -> None:
    subprocess.run(["ip", *arguments], check=True, capture_output=True, timeout=20)


def netns_missing() -> str | None:
    if os.geteuid() != 0:
        return "network namespaces need root"
    try:
        _ip("netns", "list")
    except (OSError, subprocess.CalledProcessError) as exc:
        return f"ip netns does not work here ({exc})"
    return None


def namespace_processes(namespace: str) -> list[tuple[int, str]]:
    """The processes (pid, command line) running inside ``namespace``."""
    listed = subprocess.run(["ip", "netns", "pids", namespace], capture_output=True,
                            text=True, check=False, timeout=20).stdout.split()
    found = []
    for pid in map(int, listed):
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as cmdline:
                found.append((pid, cmdline.read().replace(b"\0", b" ").decode(
                    errors="replace").strip()))
        except OSError:
            continue
    return found


def _empty(namespaces: list[str], grace: float) -> list[tuple[str, int, str]]:
    """Wait up to ``grace`` s for the namespaces' processes to end; kill the rest and return
    them (namespace, pid, command line)."""
    deadline = time.monotonic() + grace
    while True:
        left = [(namespace, pid, command) for namespace in namespaces
                for pid, command in namespace_processes(namespace)]
        if not left or time.monotonic() >= deadline:
            break
        time.sleep(0.2)
    for _, pid, _ in left:
        with suppress(ProcessLookupError):
            os.kill(pid, signal.SIGKILL)
    deadline = time.monotonic() + 10.0
    while time.monotonic() < deadline and any(namespace_processes(n) for n in namespaces):
        time.sleep(0.1)
    return left


@contextmanager
def hosts(robots: tuple[str, ...], grace: float = LEFT_GRACE) -> Iterator[Hosts]:
    """Create the namespaces and links for ``robots``; remove them afterwards, failing when
    a process still runs inside one ``grace`` s after the block ended."""
    run = os.getpid() % 200 + 20
    tag = f"db{os.getpid() % 100000}"
    master = f"{tag}-m"
    created: list[str] = []
    completed = False
    try:
        _ip("netns", "add", master)
        created.append(master)
        _ip("netns", "exec", master, "ip", "link", "set", "lo", "up")
        _ip("netns", "exec", master, "ip", "link", "add", "br0", "type", "bridge")
        master_address = SUBNET.format(run=run, host=1)
        _ip("netns", "exec", master, "ip", "addr", "add", f"{master_address}/24", "dev", "br0")
        _ip("netns", "exec", master, "ip", "link", "set", "br0", "up")
        namespaces, addresses, links = {}, {}, {}
        for k, robot in enumerate(robots):
            namespace = f"{tag}-{k}"
            _ip("netns", "add", namespace)
            created.append(namespace)
            near, far = f"{tag}h{k}", f"{tag}r{k}"
            _ip("link", "add", near, "type", "veth", "peer", "name", far)
            _ip("link", "set", near, "netns", master)
            _ip("link", "set", far, "netns", namespace)
            _ip("netns", "exec", master, "ip", "link", "set", near, "master", "br0")
            _ip("netns", "exec", master, "ip", "link", "set", near, "up")
            address = SUBNET.format(run=run, host=11 + k)
            _ip("netns", "exec", namespace, "ip", "addr", "add", f"{address}/24", "dev", far)
            _ip("netns", "exec", namespace, "ip", "link", "set", far, "up")
            _ip("netns", "exec", namespace, "ip", "link", "set", "lo", "up")
            namespaces[robot], addresses[robot], links[robot] = namespace, address, near
        yield Hosts(master, master_address, namespaces, addresses, links)
        completed = True
    finally:
        left = _empty(created, grace)
        for namespace in reversed(created):  # deleting a namespace deletes its veth ends
            subprocess.run(["ip", "netns", "delete", namespace], capture_output=True,
                           check=False)
        if left and completed:
            listing = "\n".join(f"  {ns} {pid}: {command[:200]}" for ns, pid, command in left)
            raise AssertionError(f"{len(left)} process(es) still ran inside the test's network "
                                 f"namespaces {grace:g} s after the test (now killed):\n"
                                 f"{listing}")

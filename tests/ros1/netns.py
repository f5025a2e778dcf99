"""Hosts for the multi-host tests: one network namespace per host, joined by veth pairs to
a Linux bridge inside the master's namespace. Addresses exist only inside the namespaces
(a private test range); nothing is configured in the machine's own namespace."""

from __future__ import annotations

import os
import subprocess
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

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


@contextmanager
def hosts(robots: tuple[str, ...]) -> Iterator[Hosts]:
    """Create the namespaces and links for ``robots``; remove them afterwards."""
    run = os.getpid() % 200 + 20
    tag = f"db{os.getpid() % 100000}"
    master = f"{tag}-m"
    created: list[str] = []
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
    finally:
        for namespace in reversed(created):  # deleting a namespace deletes its veth ends
            subprocess.run(["ip", "netns", "delete", namespace], capture_output=True,
                           check=False)

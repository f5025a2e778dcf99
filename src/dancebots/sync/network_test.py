"""The network test of thesis ch. 3 (the ``network_test`` node, fig. 3.2) as a pure machine.

Each robot publishes ``test ROLE`` at 10 Hz. A robot that hears another robot's ``test X``
appends its role and publishes it back (``test X ME``). When a robot hears its own message
come back echoed by Y, it knows the link to Y works in both directions and strikes Y off the
list of robots it waits for (the list comes from the scenario). When the list is empty the
robot is ready (``/all_ready`` is true). A robot keeps echoing the others after it is ready,
so robots that started later can finish their own test.
"""

from __future__ import annotations

from dataclasses import dataclass

from dancebots.sync.messages import EchoMessage

__all__ = ["NetworkTest", "network_test_receive", "start_network_test"]


@dataclass(frozen=True, slots=True)
class NetworkTest:
    """role: this robot's role; roles: the formation's (from the scenario); waiting: the
    roles not yet heard both ways."""

    role: str
    roles: frozenset[str]
    waiting: frozenset[str]

    @property
    def ready(self) -> bool:
        """Has every other robot echoed this robot's message (``/all_ready``)?"""
        return not self.waiting

    def beacon(self) -> EchoMessage:
        """The message to publish at 10 Hz."""
        return EchoMessage(self.role)


def start_network_test(role: str, roles: tuple[str, ...] | frozenset[str]) -> NetworkTest:
    """The test of robot ``role`` in a formation of ``roles`` (which include it)."""
    if role not in roles:
        raise ValueError(f"role {role!r} is not one of the scenario's robots "
                         f"({', '.join(sorted(roles))})")
    return NetworkTest(role, frozenset(roles), frozenset(roles) - {role})


def network_test_receive(test: NetworkTest, message: EchoMessage,
                         ) -> tuple[NetworkTest, EchoMessage | None]:
    """The test after hearing ``message``, and the echo to publish (or None).

    Messages of unknown roles are ignored (they may belong to another show on the network).
    """
    if message.echoed_by is None:
        if message.origin == test.role or message.origin not in test.roles:
            return test, None  # our own beacon, or a stranger's
        return test, EchoMessage(message.origin, test.role)
    if message.origin == test.role and message.echoed_by in test.waiting:
        return NetworkTest(test.role, test.roles, test.waiting - {message.echoed_by}), None
    return test, None

"""What the nodes share: loading the show, reading parameters, and the /sync transport
wrapper that injects delay and loss in-process (the test kernel has no netem)."""

from __future__ import annotations

import sys
import threading
import zlib
from typing import Any

import numpy as np

from dancebots.plan.planner import Plan
from dancebots.sync import EchoMessage, StartProposal, SyncMessageError, parse_message
from dancebots.world import World

__all__ = ["DelayedPublisher", "load_show", "parse_sync", "required_param", "sync_publisher"]


def load_show(scenario: str, world: str | None = None, vmax: float | None = None,
              ) -> tuple[Plan, World | None]:
    """The plan every robot computes identically (same scenario, world and vmax), or exit
    with the scenario's positioned diagnostics on stderr (exit status 2)."""
    from dancebots.cli.common import print_diagnostics
    from dancebots.loading import load_show as load

    show = load(scenario, world or None, vmax or None)
    if show.plan is None or not show.valid:
        print_diagnostics(show.diagnostics, show.sources)
        sys.exit(2)
    return show.plan, show.world


def required_param(name: str) -> Any:
    """A node's parameter that has no default; exits with a clear message when missing."""
    import rospy

    if not rospy.has_param(name):
        rospy.logfatal(f"missing parameter {rospy.resolve_name(name)} (set it in the launch "
                       f"file or with _{name.lstrip('~')}:=VALUE)")
        sys.exit(2)
    return rospy.get_param(name)


class DelayedPublisher:
    """A rospy publisher whose messages are each dropped with probability ``loss`` or sent
    after a uniform random delay in [0, max_delay] s (seeded), so they may overtake each
    other: delay, loss and reordering injected in-process for tests, as this kernel has no
    netem. With max_delay = loss = 0 it publishes at once."""

    def __init__(self, publisher: Any, max_delay: float = 0.0, loss: float = 0.0,
                 seed: int = 0) -> None:
        self.publisher, self.max_delay, self.loss = publisher, max_delay, loss
        self.rng = np.random.default_rng(seed)
        self.lock = threading.Lock()

    def publish(self, message: Any) -> None:
        with self.lock:
            lost = self.loss > 0 and self.rng.random() < self.loss
            delay = float(self.rng.uniform(0.0, self.max_delay)) if self.max_delay > 0 else 0.0
        if lost:
            return
        if delay <= 0.0:
            self.publisher.publish(message)
            return
        timer = threading.Timer(delay, self._late, (message,))
        timer.daemon = True
        timer.start()

    def _late(self, message: Any) -> None:
        import rospy

        if not rospy.is_shutdown():
            self.publisher.publish(message)


def sync_publisher(role: str, stream: int) -> DelayedPublisher:
    """The /sync publisher of a node, wrapped for the test-only ``~sync_delay`` and
    ``~sync_loss`` parameters; ``stream`` separates the random draws of a robot's nodes."""
    import rospy
    from std_msgs.msg import String

    from dancebots.ros1.naming import SYNC_TOPIC

    seed = int(rospy.get_param("~sync_seed", zlib.crc32(role.encode())))
    return DelayedPublisher(rospy.Publisher(SYNC_TOPIC, String, queue_size=100),
                            float(rospy.get_param("~sync_delay", 0.0)),
                            float(rospy.get_param("~sync_loss", 0.0)), seed + stream)


def parse_sync(text: str) -> EchoMessage | StartProposal | None:
    """A /sync message, or None (logged, at most every 5 s) for text that is none."""
    import rospy

    try:
        return parse_message(text)
    except SyncMessageError as exc:
        rospy.logwarn_throttle(5.0, str(exc))
        return None

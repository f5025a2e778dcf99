"""What the nodes share: loading the show, reading parameters, the /sync transport
wrapper that injects delay and loss in-process (the test kernel has no netem), and how a node
lives and ends (:class:`NodeLife`) and logs (:class:`QueuedLog`) whatever happens to its
master."""

from __future__ import annotations

import contextlib
import os
import queue
import signal
import sys
import threading
import time
import zlib
from collections.abc import Callable
from types import FrameType
from typing import Any, cast

import numpy as np

from dancebots.plan.planner import Plan, Timing
from dancebots.sync import (
    EchoMessage,
    ShowMessage,
    StartProposal,
    SyncMessageError,
    parse_message,
)
from dancebots.world import World

__all__ = ["EXIT_TIMEOUT", "SHUTDOWN_TIMEOUT", "DelayedPublisher", "NodeLife", "QueuedLog",
           "load_show", "parse_sync", "required_param", "sync_publisher"]

SHUTDOWN_TIMEOUT = 3.0
"""s a stopping node gives rospy to unregister from the master; a master that does not answer
by then (a pulled cable: TCP would retry for about 15 min per call) is given up."""
EXIT_TIMEOUT = 5.0
"""s the interpreter gets to exit after rospy has shut down (rospy's connection threads are
not daemons and may wait on dead peers); then the process ends with os._exit."""


def load_show(scenario: str, world: str | None = None, vmax: float | None = None,
              timing: str = "thesis") -> tuple[Plan, World | None]:
    """The plan every robot computes identically (same scenario, world, vmax and timing), or
    exit with the scenario's positioned diagnostics (or the unknown timing) on stderr (exit
    status 2)."""
    from dancebots.diagnostics import format_diagnostics
    from dancebots.loading import load_show as load

    try:  # PlanParameters refuses an unknown timing
        show = load(scenario, world or None, vmax or None,
                    timing=cast(Timing, timing))
    except ValueError as error:
        print(error, file=sys.stderr)
        sys.exit(2)
    if show.plan is None or not show.valid:
        print(format_diagnostics(show.diagnostics, dict(show.sources)), file=sys.stderr)
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


def sync_publisher(role: str, stream: int, topic: str | None = None) -> DelayedPublisher:
    """The /sync publisher of a node (or one of ``topic``, std_msgs/String: the formation's
    /hold), wrapped for the test-only ``~sync_delay`` and ``~sync_loss`` parameters;
    ``stream`` separates the random draws of a robot's nodes and topics."""
    import rospy
    from std_msgs.msg import String

    from dancebots.ros1.naming import SYNC_TOPIC

    seed = int(rospy.get_param("~sync_seed", zlib.crc32(role.encode())))
    return DelayedPublisher(rospy.Publisher(topic or SYNC_TOPIC, String, queue_size=100),
                            float(rospy.get_param("~sync_delay", 0.0)),
                            float(rospy.get_param("~sync_loss", 0.0)), seed + stream)


def parse_sync(text: str, log: QueuedLog) -> EchoMessage | StartProposal | ShowMessage | None:
    """A /sync message, or None (logged, at most every 5 s) for text that is none."""
    try:
        return parse_message(text)
    except SyncMessageError as exc:
        log.warn(str(exc), every=5.0, key="bad /sync message")
        return None


class QueuedLog:
    """rospy logging that never blocks its caller. rospy's /rosout handler asks the master
    for a parameter on every message (while ``/rosout_disable_topics_generation`` is unset),
    which hangs as long as TCP retries when the master cannot be reached; so a control loop
    that logs would stop ticking. Messages go through a bounded queue to a daemon thread
    (when it is full, they are dropped and counted)."""

    def __init__(self, size: int = 1000) -> None:
        self.queue: queue.Queue[tuple[str, str]] = queue.Queue(size)
        self.last: dict[str, float] = {}
        self.dropped = 0
        threading.Thread(target=self._run, name="queued-log", daemon=True).start()

    def info(self, text: str) -> None:
        """Log ``text`` at INFO."""
        self._put("info", text)

    def warn(self, text: str, every: float = 0.0, key: str | None = None) -> None:
        """Log ``text`` at WARN, at most once per ``every`` s (wall clock) per ``key``
        (default: the text itself)."""
        if every > 0.0:
            key = text if key is None else key
            now = time.monotonic()
            if now - self.last.get(key, -float("inf")) < every:
                return
            self.last[key] = now
        self._put("warn", text)

    def error(self, text: str) -> None:
        """Log ``text`` at ERROR."""
        self._put("err", text)

    def flush(self, timeout: float = 1.0) -> None:
        """Wait up to ``timeout`` s (wall clock) for the queued messages to be written."""
        deadline = time.monotonic() + timeout
        while self.queue.unfinished_tasks and time.monotonic() < deadline:
            time.sleep(0.02)

    def _put(self, level: str, text: str) -> None:
        try:
            self.queue.put_nowait((level, text))
        except queue.Full:
            self.dropped += 1

    def _run(self) -> None:
        import rospy

        writers: dict[str, Callable[[str], None]] = {
            "info": rospy.loginfo, "warn": rospy.logwarn, "err": rospy.logerr}
        while True:
            level, text = self.queue.get()
            try:
                writers[level](text)
            finally:
                self.queue.task_done()


class NodeLife:
    """How a node runs and ends, whatever happens to its master.

    rospy's own signal handling runs the whole shutdown inside the signal handler, including
    unregistering from the master with no timeout, and ignores every later signal: a node that
    has lost its master (a pulled cable) then never ends, whatever it is sent. So the nodes
    call ``rospy.init_node(..., disable_signals=True)`` and create a NodeLife: SIGINT, SIGTERM
    and SIGHUP only set :attr:`stopping`; the node's loop sleeps with :meth:`wait`, which
    returns at once when a signal arrives, and ends with :meth:`end`, which gives rospy
    :data:`SHUTDOWN_TIMEOUT` s to shut down and then ends the process anyway. A node whose
    parent process died (its roslaunch was killed) stops too.
    """

    def __init__(self) -> None:
        self.stopping = threading.Event()
        self.signal: int | None = None
        self.parent = os.getppid()
        self.take_signals()

    def take_signals(self) -> None:
        """Handle SIGINT, SIGTERM and SIGHUP here (again: roslaunch's process classes install
        handlers of their own when they are created). Main thread only."""
        for number in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
            signal.signal(number, self._signalled)

    def _signalled(self, number: int, frame: FrameType | None) -> None:
        self.signal = number
        self.stopping.set()

    @property
    def running(self) -> bool:
        """Should the node go on (no signal, rospy not shut down, its parent alive)?"""
        import rospy

        if os.getppid() != self.parent:
            self.stopping.set()
        return not self.stopping.is_set() and not rospy.is_shutdown()

    def wait(self, seconds: float) -> bool:
        """Sleep up to ``seconds`` (wall clock; less when a signal arrives), then say whether
        the node should go on."""
        if seconds > 0.0:
            self.stopping.wait(seconds)
        return self.running

    def reason(self) -> str:
        """Why the node stops, for the log and rospy's shutdown."""
        import rospy

        if self.signal is not None:
            return f"signal {signal.Signals(self.signal).name}"
        if os.getppid() != self.parent:
            return "its parent process ended"
        if rospy.is_shutdown():
            return "rospy shut down"
        return "the node is done"

    def end(self, reason: str | None = None) -> None:
        """Shut rospy down (unregister, close connections) within SHUTDOWN_TIMEOUT s, else
        end the process at once; and make sure the interpreter exits within EXIT_TIMEOUT s."""
        import rospy

        reason = reason or self.reason()
        shutdown = threading.Thread(target=rospy.signal_shutdown, args=(reason,),
                                    name="shutdown", daemon=True)
        shutdown.start()
        shutdown.join(SHUTDOWN_TIMEOUT)
        if shutdown.is_alive():
            sys.stderr.write(f"[{rospy.get_name()}] the ROS master did not answer within "
                             f"{SHUTDOWN_TIMEOUT:g} s; exiting without unregistering "
                             f"({reason})\n")
            _exit_now()
        threading.Thread(target=_exit_after, args=(EXIT_TIMEOUT,), name="exit-watchdog",
                         daemon=True).start()


def _exit_after(seconds: float) -> None:
    time.sleep(seconds)
    _exit_now()


def _exit_now() -> None:
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(OSError, ValueError):
            stream.flush()
    os._exit(0)

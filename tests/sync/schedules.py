"""A discrete-event network for the sync tests: robots that publish on a shared topic and
a transport that delays, drops, duplicates and so reorders each delivery at random.

The kernel here has no netem, so message delay and loss are injected in-process by this
transport wrapper (``Transport``), seeded, one random draw per delivery.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from dancebots.sync import (
    EchoMessage,
    NetworkTest,
    StartAgreement,
    StartProposal,
    SyncMessageError,
    agreement_ready,
    agreement_receive,
    format_message,
    network_test_receive,
    new_agreement,
    parse_message,
    start_network_test,
)

PERIOD = 0.1  # both nodes publish at 10 Hz


@dataclass(frozen=True)
class Transport:
    """Each delivery (sender -> receiver, the sender's own subscriber included) is lost with
    ``loss``, else delayed uniformly in [0, max_delay] s, and delivered once more with
    ``duplication`` (with a delay of its own): deliveries overtake each other freely."""

    max_delay: float
    loss: float
    duplication: float
    seed: int

    def __post_init__(self) -> None:
        object.__setattr__(self, "rng", np.random.default_rng(self.seed))

    def deliveries(self, now: float) -> list[float]:
        rng: np.random.Generator = self.rng  # type: ignore[attr-defined]
        if rng.random() < self.loss:
            return []
        times = [now + rng.uniform(0.0, self.max_delay)]
        if rng.random() < self.duplication:
            times.append(now + rng.uniform(0.0, self.max_delay))
        return times


@dataclass
class Robot:
    role: str
    launched: float  # when its nodes start, s
    test: NetworkTest
    agreement: StartAgreement
    ready_at: float | None = None
    started_at: float | None = None  # when it saw show time >= 0 first


@dataclass
class Outcome:
    robots: dict[str, Robot]
    sent: int = 0
    queue: list[tuple[float, int, str, str]] = field(default_factory=list)


def run_schedule(launches: dict[str, float], transport: Transport, strategy: str = "agreed",
                 horizon: float = 40.0, epoch: float = 0.0,
                 intruder: Callable[[float], list[str]] | None = None) -> Outcome:
    """Launch each robot's network_test + formation_member at ``launches[role]`` s and run
    the shared /sync topic until ``horizon`` s; messages go through ``transport`` as text.
    The robots' common clock reads ``epoch`` + the schedule's time (s), and every tick
    ``intruder(clock)`` (if given) publishes the texts it returns (hostile or stray
    messages, through the same transport). Times in the outcome are the schedule's."""
    roles = tuple(sorted(launches))
    robots = {role: Robot(role, t, start_network_test(role, roles),
                          new_agreement(role, roles, strategy))
              for role, t in launches.items()}
    outcome = Outcome(robots)
    counter = 0

    def publish(now: float, text: str) -> None:
        nonlocal counter
        for receiver, robot in robots.items():
            if robot.launched > now:
                continue  # a node that is not running hears nothing
            for at in transport.deliveries(now):
                counter += 1
                heapq.heappush(outcome.queue, (at, counter, receiver, text))
        outcome.sent += 1

    tick = 0
    while tick * PERIOD <= horizon:
        now = tick * PERIOD
        while outcome.queue and outcome.queue[0][0] <= now:
            _, _, receiver, text = heapq.heappop(outcome.queue)
            robot = robots[receiver]
            try:
                message = parse_message(text)
            except SyncMessageError:
                continue  # the nodes log and drop what is not a /sync message
            if isinstance(message, EchoMessage):
                robot.test, echo = network_test_receive(robot.test, message)
                if echo is not None:
                    publish(now, format_message(echo))
            else:
                robot.agreement = agreement_receive(robot.agreement, message, epoch + now)
        for text in intruder(epoch + now) if intruder is not None else ():
            publish(now, text)
        for robot in robots.values():
            if now < robot.launched:
                continue
            if robot.ready_at is None and robot.test.ready:
                robot.ready_at = now
                robot.agreement = agreement_ready(robot.agreement, epoch + now)
            if not robot.test.ready:
                publish(now, format_message(robot.test.beacon()))
            proposal = robot.agreement.message(epoch + now)
            if proposal is not None:
                publish(now, format_message(proposal))
            start = robot.agreement.start
            if robot.started_at is None and start is not None and epoch + now >= start:
                robot.started_at = now
        tick += 1
    return outcome


__all__ = ["PERIOD", "Outcome", "Robot", "StartProposal", "Transport", "run_schedule"]

"""The start agreement of thesis ch. 4.2 as a pure state machine, in two strategies.

Once its network test is done, each robot publishes ``sync ROLE T`` at 10 Hz, T being its
clock + 4 s ("to accommodate any transmission delay"). A robot that hears a role for the
first time strikes it off its waiting list and keeps its proposal; when the list is empty it
waits until the start time and the virtual leader starts to move. The clocks are shared (NTP).

``thesis``: as written, the proposal of every message is the sender's clock + 4 s at
    sending, and the start is "the last valid proposal": that of the role heard last. Two
    robots that hear the roles in different orders (delays, losses) start at different times.
``agreed`` (an addition): each robot fixes its proposal once, when it is ready, and repeats
    that same value; the start is the latest of all roles' proposals. Every robot then holds
    the same set of values once it has heard every role, whatever the order, delay, loss,
    duplication or reordering of messages, so all agree on one start; and as every proposal
    is made only when its robot is ready, nobody starts before every role is ready. A robot
    that hears the last proposal after the start time starts late and catches up: its virtual
    leader is computed from the same start.

Both strategies ignore implausible proposals (:func:`implausible`): a start more than
:data:`PLAUSIBLE_AHEAD` s after the receiver's clock or more than :data:`PLAUSIBLE_BEHIND` s
before it. Such a proposal neither strikes its role off nor moves the start, so one stray or
hostile ``sync R2 1e308`` cannot make the formation wait for ever; the receiver keeps waiting
for a plausible proposal of that role (which a robot whose clock is far off never sends:
then nobody starts, the safe failure of unsynchronised clocks).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Literal, get_args

from dancebots.sync.messages import StartProposal

__all__ = ["MAX_CLOCK_OFFSET", "PLAUSIBLE_AHEAD", "PLAUSIBLE_BEHIND", "START_DELAY",
           "START_STRATEGIES", "StartAgreement", "StartStrategy", "agreement_ready",
           "agreement_receive", "implausible", "new_agreement", "show_time"]

START_DELAY = 4.0
"""Seconds between a robot's clock when it proposes and the start it proposes (thesis 4.2)."""
StartStrategy = Literal["thesis", "agreed"]
START_STRATEGIES: tuple[StartStrategy, ...] = get_args(StartStrategy)
MAX_CLOCK_OFFSET = 1.0
"""s: the largest offset between two robots' clocks the agreement tolerates (NTP on the
robots' network keeps them within milliseconds; thesis 4.2)."""
PLAUSIBLE_AHEAD = START_DELAY + MAX_CLOCK_OFFSET
"""s: a proposal is at most this far after the receiver's clock. Every proposal is its
sender's clock + :data:`START_DELAY` at the latest, and transmission only makes the
receiver's clock later, so only a clock offset can add to the delay."""
PLAUSIBLE_BEHIND = 3600.0
"""s: a proposal is at most this far before the receiver's clock. Under ``agreed`` a robot
repeats the proposal it made when it became ready, so a robot whose sensors come up late
hears old proposals; an hour covers any start-up of a show, while a clock that was never
synchronised (1970, 0 s) or a number that is no time is refused."""


@dataclass(frozen=True, slots=True)
class StartAgreement:
    """One robot's view of the start agreement.

    strategy: ``thesis`` or ``agreed`` (see the module); role, roles: this robot's and the
    formation's; proposal: this robot's own fixed proposal once it is ready (``agreed``);
    ready: has its network test passed; heard: the roles heard so far; value: the last
    valid proposal (``thesis``) or the latest proposal heard (``agreed``), s.
    """

    strategy: StartStrategy
    role: str
    roles: frozenset[str]
    ready: bool = False
    proposal: float | None = None
    heard: frozenset[str] = frozenset()
    value: float | None = None

    @property
    def start(self) -> float | None:
        """The agreed start time (s, common clock) once every role is heard, else None."""
        return self.value if self.heard >= self.roles else None

    def message(self, now: float) -> StartProposal | None:
        """What to publish on /sync at ``now`` (10 Hz), None before the robot is ready."""
        if not self.ready:
            return None
        if self.strategy == "thesis":
            return StartProposal(self.role, now + START_DELAY)
        assert self.proposal is not None
        return StartProposal(self.role, self.proposal)


def new_agreement(role: str, roles: tuple[str, ...] | frozenset[str],
                  strategy: str = "agreed") -> StartAgreement:
    """The agreement of robot ``role`` in a formation of ``roles`` (which include it).
    ``strategy`` is a plain string because it comes from a node parameter: it is checked
    against :data:`START_STRATEGIES` here (a ``ValueError`` names the choices)."""
    if strategy not in START_STRATEGIES:
        raise ValueError(f"unknown start strategy {strategy!r}; use one of "
                         f"{', '.join(START_STRATEGIES)}")
    if role not in roles:
        raise ValueError(f"role {role!r} is not one of the scenario's robots "
                         f"({', '.join(sorted(roles))})")
    return StartAgreement(strategy, role, frozenset(roles))


def agreement_ready(agreement: StartAgreement, now: float) -> StartAgreement:
    """The network test passed at ``now`` (``/all_ready``): start proposing. Under
    ``agreed`` the robot fixes its proposal (now + 4 s) and counts it as heard."""
    if agreement.ready:
        return agreement
    if agreement.strategy == "thesis":  # its own role is struck off when its message returns
        return replace(agreement, ready=True)
    proposal = now + START_DELAY
    return _hear(replace(agreement, ready=True, proposal=proposal),
                 StartProposal(agreement.role, proposal))


def implausible(start: float, now: float) -> str | None:
    """Why a proposed ``start`` (s, common clock) is not plausible at the receiver's clock
    ``now`` (s), or None when it is: it must lie in [now - PLAUSIBLE_BEHIND,
    now + PLAUSIBLE_AHEAD]. NaN and infinities are never plausible."""
    if not (math.isfinite(start) and math.isfinite(now)):
        return f"{start!r} is not a finite time"
    if start > now + PLAUSIBLE_AHEAD:
        return (f"it is {_span(start - now)} after this robot's clock (at most "
                f"{PLAUSIBLE_AHEAD:g} s: the {START_DELAY:g} s start delay and "
                f"{MAX_CLOCK_OFFSET:g} s of clock offset); are the clocks synchronised?")
    if start < now - PLAUSIBLE_BEHIND:
        return (f"it is {_span(now - start)} before this robot's clock (at most "
                f"{PLAUSIBLE_BEHIND:g} s); are the clocks synchronised?")
    return None


def agreement_receive(agreement: StartAgreement, proposal: StartProposal, now: float,
                      ) -> StartAgreement:
    """The agreement after hearing ``proposal`` on /sync at the receiver's clock ``now`` (s)
    (any order, any number of times). Roles outside the formation and implausible
    proposals (:func:`implausible`) are ignored; a role's first plausible proposal is the
    one kept."""
    if proposal.role not in agreement.roles or proposal.role in agreement.heard:
        return agreement
    if implausible(proposal.start, now) is not None:
        return agreement
    if agreement.strategy == "agreed" and proposal.role == agreement.role:
        return agreement  # its own value was fixed when it became ready
    return _hear(agreement, proposal)


def show_time(agreement: StartAgreement, now: float) -> float | None:
    """Seconds since the agreed start at ``now`` (negative before it), None while the start
    is not agreed yet."""
    start = agreement.start
    return None if start is None else now - start


def _span(seconds: float) -> str:
    """A duration for a message: seconds, or years when it is absurd."""
    if seconds < 1e6:
        return f"{seconds:.1f} s"
    return f"{seconds / 3.15576e7:.3g} years"


def _hear(agreement: StartAgreement, proposal: StartProposal) -> StartAgreement:
    if agreement.strategy == "thesis":
        value = proposal.start  # "the proposed time is saved as the last valid proposal"
    else:
        value = proposal.start if agreement.value is None else max(agreement.value,
                                                                   proposal.start)
    return replace(agreement, heard=agreement.heard | {proposal.role}, value=value)


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

``timecode`` (an addition: shows synchronised to music and lights): the start is an
    absolute time given to every robot (``formation_member``'s ``~start_at``, ``dancebots ros
    formation --start-at``). Each robot still waits for its network test, then repeats that
    time with its own clock (``sync ROLE T SENT``); the start is agreed once every role
    proposed the same time. Each robot measures the offset of every other robot's clock from
    its own from those messages (the largest ``SENT - now`` over a role's messages: transit
    only makes it smaller, so it approaches the offset from below) and refuses to start and
    says why (it goes on sending, so that the others can measure its clock), when the median
    of the formation's clocks against its own (its own included; of two middle values the
    one further from its own) is off by more than :data:`TIMECODE_OFFSET` (its own clock
    is off: the music would be off by as much;
    two robots cannot tell whose clock is off, and both refuse), when another robot was
    given another time, or when the time has passed before it is ready and the clocks are
    measured.

Every strategy refuses a show that is not the same everywhere (an addition; thesis 7.2.2's
crash came from robots that ran different versions of the scenario): each robot says which
show it runs (``show ROLE S W P``: the digests of its scenario file, world file and motion
parameters, ``loading.show_digests``), agrees on a start only once it has heard every other
robot's, and refuses to start, naming what differs, when one is not its own
(:func:`agreement_show`).

All strategies ignore implausible proposals (:func:`implausible`): a start more than
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

from dancebots.sync.messages import ShowMessage, StartProposal

__all__ = ["MAX_CLOCK_OFFSET", "PLAUSIBLE_AHEAD", "PLAUSIBLE_BEHIND", "START_DELAY",
           "START_STRATEGIES", "TIMECODE_AHEAD", "TIMECODE_OFFSET", "StartAgreement",
           "StartStrategy", "agreement_ready", "agreement_receive", "agreement_show",
           "implausible", "new_agreement", "show_time"]

START_DELAY = 4.0
"""Seconds between a robot's clock when it proposes and the start it proposes (thesis 4.2)."""
StartStrategy = Literal["thesis", "agreed", "timecode"]
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
TIMECODE_AHEAD = 86400.0
"""s: a ``timecode`` start is at most a day after a robot's clock when it gets ready (the
show of tonight; more is a mistyped date)."""
TIMECODE_OFFSET = 0.1
"""s: the largest offset of a robot's clock from the formation's (the median of all the
robots' clocks against its own) with which it starts a ``timecode`` show: a tenth of a
second against the music."""
TIMECODE_SAMPLES = 10
"""Messages of every other robot (1 s of them at 10 Hz) a robot measures its clock against
before it judges the offset and agrees on a ``timecode`` start: the least delayed of them
bounds the offset."""


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
    timecode: float | None = None
    offsets: tuple[tuple[str, float, int], ...] = ()
    max_offset: float = TIMECODE_OFFSET
    refused: str | None = None
    show: tuple[str, str, str] | None = None
    shows_heard: frozenset[str] = frozenset()

    @property
    def start(self) -> float | None:
        """The agreed start time (s, common clock) once every role is heard (under
        ``timecode``: and the clocks measured, :data:`TIMECODE_SAMPLES`; with ``show``: and
        every other robot's show heard, the same), else None (and None for good once the
        robot refused to start: ``refused`` says why)."""
        if self.refused is not None or not self.heard >= self.roles:
            return None
        if self.show is not None and not self.shows_heard >= self.roles - {self.role}:
            return None
        if self.strategy == "timecode" and not self._clocks_measured():
            return None
        return self.value

    def _clocks_measured(self) -> bool:
        """Whether every other role's clock is measured from enough messages."""
        counts = {role: count for role, _, count in self.offsets}
        return all(counts.get(role, 0) >= TIMECODE_SAMPLES for role in self.roles
                   if role != self.role)

    def message(self, now: float) -> StartProposal | None:
        """What to publish on /sync at ``now`` (10 Hz), None before the robot is ready."""
        if not self.ready:
            return None
        if self.strategy == "thesis":
            return StartProposal(self.role, now + START_DELAY)
        assert self.proposal is not None
        if self.strategy == "timecode":
            # (also once it refused: the others measure its clock and judge for themselves)
            return StartProposal(self.role, self.proposal, now)
        return StartProposal(self.role, self.proposal)

    def offset(self, role: str) -> float | None:
        """The measured offset (s) of ``role``'s clock from this robot's (its clock less
        this one's; a lower bound), None before a message of it with its clock."""
        return next((offset for name, offset, _ in self.offsets if name == role), None)


def new_agreement(role: str, roles: tuple[str, ...] | frozenset[str],
                  strategy: str = "agreed", timecode: float | None = None,
                  max_offset: float = TIMECODE_OFFSET,
                  show: tuple[str, str, str] | None = None) -> StartAgreement:
    """The agreement of robot ``role`` in a formation of ``roles`` (which include it).
    ``strategy`` is a plain string because it comes from a node parameter: it is checked
    against :data:`START_STRATEGIES` here (a ``ValueError`` names the choices). ``timecode``
    (s, common clock; the ``timecode`` strategy only, which needs it) and ``max_offset``
    (s, at least 0): see the module. ``show``: the digests of the show this robot runs
    (scenario, world, parameters: ``loading.show_digests``; None: not compared)."""
    if strategy not in START_STRATEGIES:
        raise ValueError(f"unknown start strategy {strategy!r}; use one of "
                         f"{', '.join(START_STRATEGIES)}")
    if role not in roles:
        raise ValueError(f"role {role!r} is not one of the scenario's robots "
                         f"({', '.join(sorted(roles))})")
    if (strategy == "timecode") != (timecode is not None):
        raise ValueError("the timecode start needs a start time (start_at), and only it takes "
                         "one")
    if timecode is not None and not math.isfinite(timecode):
        raise ValueError(f"the start time {timecode!r} is not a finite time")
    if not max_offset >= 0.0:
        raise ValueError(f"the largest clock offset must be 0 s or more, not {max_offset!r}")
    return StartAgreement(strategy, role, frozenset(roles), timecode=timecode,
                          max_offset=max_offset, show=show)


def agreement_ready(agreement: StartAgreement, now: float) -> StartAgreement:
    """The network test passed at ``now`` (``/all_ready``): start proposing. Under
    ``agreed`` the robot fixes its proposal (now + 4 s) and counts it as heard."""
    if agreement.ready:
        return agreement
    if agreement.strategy == "thesis":  # its own role is struck off when its message returns
        return replace(agreement, ready=True)
    if agreement.strategy == "timecode":
        assert agreement.timecode is not None
        refused = None
        if agreement.timecode < now:
            refused = (f"the start time {_instant(agreement.timecode)} has passed: this robot "
                       f"was ready at {_instant(now)}; give a later --start-at")
        elif agreement.timecode > now + TIMECODE_AHEAD:
            refused = (f"the start time {_instant(agreement.timecode)} is "
                       f"{_span(agreement.timecode - now)} after this robot's clock (at most "
                       f"{TIMECODE_AHEAD / 3600:g} h); is the date or the clock wrong?")
        ready = replace(agreement, ready=True, proposal=agreement.timecode, refused=refused)
        # (the others' clocks may be measured already: then it is judged now)
        return _judged(agreement, _hear(ready, StartProposal(agreement.role,
                                                             agreement.timecode)), now)
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
    if proposal.role not in agreement.roles:
        return agreement
    if agreement.strategy == "timecode":
        return _hear_timecode(agreement, proposal, now)
    if proposal.role in agreement.heard:
        return agreement
    if implausible(proposal.start, now) is not None:
        return agreement
    if agreement.strategy == "agreed" and proposal.role == agreement.role:
        return agreement  # its own value was fixed when it became ready
    return _hear(agreement, proposal)


def _hear_timecode(agreement: StartAgreement, proposal: StartProposal,
                   now: float) -> StartAgreement:
    """The ``timecode`` agreement after ``proposal``: another start time refuses; a
    message with the sender's clock updates that role's offset (the largest ``sent - now``
    of its messages: the least delayed one bounds it best); when every other role's clock
    is first measured from :data:`TIMECODE_SAMPLES` messages, the agreement is judged once:
    a start time that has passed, or a median of all the robots' clocks against this one's
    (its own 0 included) beyond ``max_offset``, refuses; else the start stands (later
    messages do not stop a show that runs)."""
    if proposal.role == agreement.role or agreement.refused is not None:
        return agreement
    if not (math.isfinite(proposal.start) and math.isfinite(now)) or _complete(agreement):
        return agreement  # (judged: the start stands, whatever comes later)
    if proposal.start != agreement.timecode:
        assert agreement.timecode is not None
        return replace(agreement, refused=(
            f"{proposal.role} was given another start time ({_instant(proposal.start)}) "
            f"than this robot ({_instant(agreement.timecode)}): give every robot the same "
            "--start-at"))
    offsets = {role: (offset, count) for role, offset, count in agreement.offsets}
    if proposal.sent is not None and math.isfinite(proposal.sent):
        offset, count = offsets.get(proposal.role, (-math.inf, 0))
        offsets[proposal.role] = (max(proposal.sent - now, offset), count + 1)
    heard = replace(agreement, heard=agreement.heard | {proposal.role},
                    value=agreement.timecode,
                    offsets=tuple(sorted((role, o, c) for role, (o, c) in offsets.items())))
    return _judged(agreement, heard, now)


def _complete(agreement: StartAgreement) -> bool:
    """Every role heard (this robot's own once it is ready) and every other one's clock
    measured (``timecode``)."""
    return agreement.heard >= agreement.roles and agreement._clocks_measured()


def _judged(before: StartAgreement, after: StartAgreement, now: float) -> StartAgreement:
    """``after``, judged at ``now`` when it became complete (:func:`_complete`) since
    ``before``: judged once, when the last of the robot's readiness and the clocks'
    measurement comes, whichever that is; then the start stands."""
    if _complete(before) or not _complete(after) or after.refused is not None:
        return after
    assert after.timecode is not None
    if now > after.timecode:
        return replace(after, refused=(
            f"the start time {_instant(after.timecode)} passed before the clocks were "
            f"measured (at {_instant(now)}: 1 s of every robot's messages); give a later "
            "--start-at"))
    # the formation's clock against this one's: the middle of all of them (this one's 0
    # included), of two middle ones the one further from this one's (two robots, or two
    # halves, cannot tell whose clock is off: each judges the other's)
    values = sorted([0.0, *(offset for _, offset, _ in after.offsets)])
    middle = len(values) // 2
    median = values[middle] if len(values) % 2 else max(values[middle - 1], values[middle],
                                                        key=abs)
    if abs(median) <= after.max_offset:
        return after
    side = "behind" if median > 0 else "ahead of"
    return replace(after, refused=(
        f"this robot's clock is {abs(median):.3f} s {side} the formation's (the median of "
        f"the robots' clocks, {', '.join(sorted(after.roles))}, measured from their /sync "
        f"messages; at most {after.max_offset:g} s): the show would be off the music by as "
        "much; synchronise the clocks (NTP, chrony) and start again"))


SHOW_PARTS = ("scenario file", "world file", "motion parameters")
"""What each of a show's three digests covers (``ShowMessage``)."""


def agreement_show(agreement: StartAgreement, message: ShowMessage) -> StartAgreement:
    """The agreement after hearing which show ``message.role`` runs: the same as this
    robot's, it counts; another one refuses the start, naming what differs (without
    ``show``, or for roles outside the formation and its own echo: unchanged). A robot
    that already refused stays refused."""
    if (agreement.show is None or message.role not in agreement.roles
            or message.role == agreement.role or agreement.refused is not None
            or agreement.start is not None):  # (a start that stands is not taken back)
        return agreement
    differ = [f"{part} ({theirs} there, {ours} here)" for part, theirs, ours in zip(
        SHOW_PARTS, message.digests, agreement.show, strict=True) if theirs != ours]
    if differ:
        return replace(agreement, refused=(
            f"{message.role} runs another show: its {' and its '.join(differ)} differ from "
            "this robot's (SHA-256 digests); give every robot the same scenario and world "
            "files and the same options (vmax, timing, follower, hold, stop rule, LIDAR)"))
    return replace(agreement, shows_heard=agreement.shows_heard | {message.role})


def show_time(agreement: StartAgreement, now: float) -> float | None:
    """Seconds since the agreed start at ``now`` (negative before it), None while the start
    is not agreed yet."""
    start = agreement.start
    return None if start is None else now - start


def _instant(seconds: float) -> str:
    """A clock time for a message: UTC date and time to the millisecond (seconds since the
    epoch), or the number itself where it is no date."""
    import datetime

    try:
        moment = datetime.datetime.fromtimestamp(seconds, tz=datetime.UTC)
    except (OverflowError, OSError, ValueError):
        return f"{seconds:g} s"
    return moment.strftime("%Y-%m-%d %H:%M:%S.%f")[:-3] + " UTC"


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


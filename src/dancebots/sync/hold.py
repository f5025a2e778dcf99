"""The formation's shared show clock (an addition to thesis ch. 4.2, where every robot's
virtual leader runs on its own from the agreed start, so a robot held by a visitor falls
behind while the others drive on).

Every robot publishes a :class:`HoldMessage` at every control tick: its role, its clock when
sending (the robots' clocks are shared, NTP, as for the start agreement), its show time and
whether it holds the show (held by something that is not a formation mate on its place, or
in its error state). Each robot keeps a :class:`ShowClock`. Its show time advances with its
clock only while

* it does not hold the show itself,
* no mate's latest message holds it, and
* every mate's latest message is younger than ``heartbeat_timeout`` (a robot not heard from
  counts as a hold: a lost robot stops the show; the show never runs on without it);

and never beyond any mate's show time as extrapolated from its latest message (that show time
plus the time since it was sent at the mate's pace, unless that mate holds the show), nor
backwards. Under the ``paced`` strategy a robot that a stranger slows (the corner cap, the
approach limit) says so with a pace below 1 (the share of the plan's speed it can follow), and
every show time advances at the smallest pace said: the formation slows together instead of
stopping and starting at every other tick; under ``together`` every pace is 1. So every
robot's show time stops when one is held and all resume together. A mate that waits without
holding is extrapolated as if it ran, so where a holder's messages are lost a robot may run
ahead of the waiting mates, by at most the heartbeat timeout (then the holder's silence holds
it); a robot that ran ahead waits until the others catch up, so the clocks meet again within
one message delay once messages pass: the formation shares one show time. Pure functions;
times in s.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Literal, TypeVar, get_args

import numpy as np
from numpy.typing import NDArray

__all__ = ["ADVANCE_MIN", "HOLD_STRATEGIES", "FormationClocks", "HoldMessage", "HoldParams",
           "HoldStrategy", "ShowClock", "clock_rate", "clock_receive", "clock_tick",
           "default_hold_strategy", "formation_clocks", "formation_receive", "formation_tick",
           "heard_positions", "new_clock"]

HoldStrategy = Literal["together", "alone", "paced"]
ArrayOrFloat = TypeVar("ArrayOrFloat", float, NDArray[np.float64])
HOLD_STRATEGIES: tuple[HoldStrategy, ...] = get_args(HoldStrategy)
"""``together`` (an addition): the shared show clock of this module; ``alone`` (thesis 4.2):
every robot's show time is its clock since the start, whatever the others do; ``paced`` (an
addition, the default of the tracking and path followers): ``together`` with paces (module
docstring; docs/safety.md has both certified)."""


def default_hold_strategy(follower: str) -> HoldStrategy:
    """The hold strategy of a robot told none, for its ``follower``: ``alone`` for the thesis's
    (thesis 4.2 as written), ``paced`` for the others (the simulator, ``dancebots ros
    simulate`` and the formation_member node alike)."""
    return "alone" if follower == "thesis" else "paced"


ADVANCE_MIN = 1e-9
"""s: a show time advances by more than this or not at all (no creep by rounding)."""


@dataclass(frozen=True, slots=True)
class HoldMessage:
    """What a robot tells the formation at every tick: its ``role``, its clock when sending
    (``stamp``, s), its ``show_time`` then (s), whether it ``holds`` the show, and where it
    stands in the show frame (``position``, m; None: unknown), so that its mates do not take
    it for a person where it is off its place; ``pace``: the share (0-1] of the plan's speed
    it can follow (the ``paced`` strategy, at least ``robot.PACE_MIN`` times its margin: a
    robot that can follow less holds the show; 1 otherwise)."""

    role: str
    stamp: float
    show_time: float
    holds: bool
    position: tuple[float, float] | None = None
    pace: float = 1.0


@dataclass(frozen=True, slots=True)
class HoldParams:
    """heartbeat_timeout: s without a message from a mate after which it counts as a hold
    (10 ticks at 10 Hz: a few lost messages do not stop the show, a robot gone does)."""

    heartbeat_timeout: float = 1.0


@dataclass(frozen=True, slots=True)
class ShowClock:
    """One robot's view of the shared show clock: its ``role``, the ``mates`` it waits for,
    its show time (s) at its clock ``updated`` (s), and the latest message heard from each
    mate."""

    role: str
    mates: tuple[str, ...]
    show_time: float
    updated: float
    heard: Mapping[str, HoldMessage]


def new_clock(role: str, roles: tuple[str, ...], start: float) -> ShowClock:
    """The clock of ``role`` in a formation of ``roles`` at the agreed start (its clock
    ``start`` s, show time 0); it runs once it has heard every mate."""
    return ShowClock(role, tuple(r for r in roles if r != role), 0.0, start,
                     MappingProxyType({}))


def clock_receive(clock: ShowClock, *messages: HoldMessage) -> ShowClock:
    """``clock`` after hearing ``messages`` in order (its own echo, unknown roles and messages
    older than the latest of their role are ignored); ``clock`` itself when none counts."""
    heard: dict[str, HoldMessage] | None = None
    for message in messages:
        if message.role not in clock.mates or not (
                math.isfinite(message.stamp) and math.isfinite(message.show_time)):
            continue
        latest = (heard if heard is not None else clock.heard).get(message.role)
        if latest is not None and latest.stamp >= message.stamp:
            continue
        if heard is None:
            heard = dict(clock.heard)
        heard[message.role] = message
    if heard is None:
        return clock
    return ShowClock(clock.role, clock.mates, clock.show_time, clock.updated,
                     MappingProxyType(heard))


def clock_tick(clock: ShowClock, now: float, holds: bool,
               params: HoldParams = HoldParams(), pace: float = 1.0) -> ShowClock:
    """``clock`` at its clock ``now`` (s): its show time advanced by the time since its last
    tick times the smallest pace (its own ``pace`` and its mates' latest) unless it ``holds``
    the show itself, a mate's latest message holds it or a mate was not heard from for
    ``heartbeat_timeout``; never beyond a mate's extrapolated show time, never backwards
    (module docstring)."""
    elapsed = max(now - clock.updated, 0.0)
    waiting = holds
    ceiling = math.inf
    rate = pace
    for mate in clock.mates:
        message = clock.heard.get(mate)
        if message is None or now - message.stamp > params.heartbeat_timeout:
            waiting = True
            continue
        if message.holds:
            waiting = True
        rate = min(rate, message.pace)
        ceiling = min(ceiling, message.show_time + (
            0.0 if message.holds else message.pace * max(now - message.stamp, 0.0)))
    show_time = clock.show_time
    ahead = show_time + elapsed * rate
    if not waiting and min(ahead, ceiling) > show_time + ADVANCE_MIN:
        show_time = min(ahead, ceiling)
    return ShowClock(clock.role, clock.mates, show_time, now, clock.heard)


def clock_rate(advance: ArrayOrFloat, elapsed: ArrayOrFloat) -> ArrayOrFloat:
    """How fast a show clock ran (0-1) that advanced ``advance`` s of show time over
    ``elapsed`` s of its own clock (floats or arrays alike): what a paced brain follows its
    place at. A full tick's advance (its ratio rounds to 1 - 1e-16) and no time elapsed (the
    first tick) are 1 exactly, so that an unpaced show runs as without paces."""
    ratio = np.asarray(advance, dtype=float) / np.maximum(np.asarray(elapsed, dtype=float),
                                                          1e-9)
    rate = np.where((ratio >= 1.0 - 1e-9) | (np.asarray(elapsed) <= 0.0), 1.0,
                    np.clip(ratio, 0.0, 1.0))
    return float(rate) if rate.ndim == 0 else rate  # type: ignore[return-value]


def heard_positions(clock: ShowClock) -> tuple[tuple[float, float], ...]:
    """Where the mates said they stand (show frame, m) in their latest messages that say it:
    what the brain leaves out as no stranger (``RobotBrain.step``'s ``mates_heard``)."""
    return tuple(m.position for m in clock.heard.values() if m.position is not None)


@dataclass(frozen=True, slots=True, eq=False)
class FormationClocks:
    """Every robot's :class:`ShowClock` at once, for a formation whose robots all hear the
    same messages (the simulator's in-process network: a message reaches every robot or,
    lost, none): per robot r, ``show_time`` (R,) and ``updated`` (R,) s; per sender s, the
    latest message heard from it, ``stamp`` (R,) s (NaN: none yet), ``sent_show_time``
    (R,) s, ``holds`` (R,), ``position`` (R, 2) m, show frame (NaN: not said) and ``pace``
    (R,) (1 until heard). Robot r
    ignores its own messages. The same show times as a :class:`ShowClock` per robot fed the
    same messages (tested), in O(R) array operations per tick instead of O(R^2) calls."""

    show_time: NDArray[np.float64]
    updated: NDArray[np.float64]
    stamp: NDArray[np.float64]
    sent_show_time: NDArray[np.float64]
    holds: NDArray[np.bool_]
    position: NDArray[np.float64]
    pace: NDArray[np.float64]


def formation_clocks(count: int, start: float) -> FormationClocks:
    """The clocks of a formation of ``count`` robots at the agreed start (every clock
    ``start`` s, show time 0, nothing heard: :func:`new_clock` for each)."""
    return FormationClocks(np.zeros(count), np.full(count, float(start)),
                           np.full(count, np.nan), np.zeros(count), np.zeros(count, dtype=bool),
                           np.full((count, 2), np.nan), np.ones(count))


def formation_receive(clocks: FormationClocks, sent: NDArray[np.bool_],
                      stamp: NDArray[np.float64], show_time: NDArray[np.float64],
                      holds: NDArray[np.bool_], position: NDArray[np.float64],
                      pace: NDArray[np.float64] | None = None) -> FormationClocks:
    """``clocks`` after every robot hears one message from each sender where ``sent`` (R,):
    stamp, show time, holds (R,), position (R, 2) (NaN: unknown) and pace (R,) (None: 1)
    per sender. As
    :func:`clock_receive`: messages with a non-finite stamp or show time, and those not
    newer than the latest heard from their sender, are ignored."""
    new = (sent & np.isfinite(stamp) & np.isfinite(show_time)
           & ~(clocks.stamp >= stamp))  # NaN (nothing heard yet) compares False
    if not new.any():
        return clocks
    return FormationClocks(clocks.show_time, clocks.updated,
                           np.where(new, stamp, clocks.stamp),
                           np.where(new, show_time, clocks.sent_show_time),
                           np.where(new, holds, clocks.holds),
                           np.where(new[:, None], position, clocks.position),
                           clocks.pace if pace is None else np.where(new, pace, clocks.pace))


def formation_tick(clocks: FormationClocks, now: float, holds: NDArray[np.bool_],
                   params: HoldParams = HoldParams(),
                   pace: NDArray[np.float64] | None = None) -> FormationClocks:
    """Every robot's clock at ``now`` (s), each robot holding the show or not (``holds``
    (R,)) at its own ``pace`` (R,) (None: 1): :func:`clock_tick` of each, from the latest
    messages of its mates."""
    count = len(clocks.show_time)
    age = now - clocks.stamp
    heard = ~np.isnan(clocks.stamp) & ~(age > params.heartbeat_timeout)
    bad = ~heard | clocks.holds  # a mate that makes the others wait
    # where a heard mate's show time stands now: the show time it sent, run on unless it holds
    reach = np.where(heard, clocks.sent_show_time + np.where(
        clocks.holds, 0.0, clocks.pace * np.maximum(age, 0.0)), math.inf)
    others_bad = (np.count_nonzero(bad) - bad) > 0  # any mate but itself
    # the smallest reach of the others: the smallest of all unless that is its own
    order = np.argsort(reach, kind="stable")
    ceiling = np.full(count, reach[order[0]] if count else math.inf)
    if count > 1:
        ceiling[order[0]] = reach[order[1]]
    else:
        ceiling[:] = math.inf
    waiting = holds | others_bad
    # the smallest pace of the others heard (the same way: its own left out), and its own
    paces = np.where(heard, clocks.pace, 1.0)
    slow = np.argsort(paces, kind="stable")
    rate = np.full(count, paces[slow[0]] if count else 1.0)
    if count > 1:
        rate[slow[0]] = paces[slow[1]]
    else:
        rate[:] = 1.0
    if pace is not None:
        rate = np.minimum(rate, pace)
    elapsed = np.maximum(now - clocks.updated, 0.0)
    ahead = np.minimum(clocks.show_time + elapsed * rate, ceiling)
    runs = ~waiting & (ahead > clocks.show_time + ADVANCE_MIN)
    return FormationClocks(np.where(runs, ahead, clocks.show_time), np.full(count, now),
                           clocks.stamp, clocks.sent_show_time, clocks.holds, clocks.position,
                           clocks.pace)

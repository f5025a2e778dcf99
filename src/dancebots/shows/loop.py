"""The loop both shows run (a thin shell over the stage and the recorder).

Time advances in fixed steps of ``dt`` seconds. At each control tick the show's step
decides the robots' commands from what the :class:`~dancebots.sim.stage.Stage` holds and
delivers, and names the values to record; the loop records them through the
:class:`~dancebots.sim.recorder.Recorder`, reports progress, and stops at the end (or, for a
show with a settle phase, once everything has stood still for ``STILL`` s after the planned
show). Between ticks the stage moves everything by one step with the commands issued at the
last tick (10 Hz rule, actuation, contacts: ``sim/stage.py``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from dancebots.sim.recorder import Recorder
from dancebots.sim.stage import Stage

__all__ = ["STILL", "Clock", "Progress", "Step", "Tick", "robots_moving", "run_show",
           "settled_since"]

FloatArray = NDArray[np.float64]
Progress = Callable[[float, float], None]
"""``progress(show_time, end_time)``, called about once per second of show time and at the end."""

STILL = 1.0
"""s: a show with a settle phase ends once no robot has moved or been told to for this long."""
STILL_SPEED = 1e-3
"""A robot slower than this (m/s or rad/s) stands still ..."""
STILL_COMMAND = 1e-9
"""... unless it is commanded more than this."""
PROGRESS_PERIOD = 1.0
"""s of show time between progress reports."""


@dataclass(frozen=True, slots=True)
class Clock:
    """The timing of a show: dt the step, s; end: the last step is the first at or after this
    show time, s; steps_per_tick: steps per control tick; settle_from: show time from which
    the show ends early once everything has stood still for ``STILL`` s (None: never);
    max_pause: s by which the show's own show time (``Tick.show_time``) may fall behind the
    loop's time, each second of it moving the end one second later."""

    dt: float
    end: float
    steps_per_tick: int = 1
    settle_from: float | None = None
    max_pause: float = 0.0


@dataclass(frozen=True, slots=True, eq=False)
class Tick:
    """What a show decided at a control tick: commands (R, 2) (v, w) for every robot of the
    stage, issued at the tick; record: the values to record at the tick, by name (the same
    names at every tick; copied when recorded); show_time: the show's own time at the tick
    when it paused (a formation whose shared clock stops while a robot is held), s (None:
    the loop's time); waiting: a robot waits to move (for a person to leave after the
    show: ``BrainState.waiting``), so the show has not settled even where every robot
    stands."""

    commands: FloatArray
    record: Mapping[str, NDArray[Any]]
    show_time: float | None = None
    waiting: bool = False


Step = Callable[[float], Tick]
"""A show's decisions at a control tick: ``step(show_time) -> Tick``."""


def robots_moving(velocity: FloatArray, commands: FloatArray) -> bool:
    """Whether any robot moves (velocities (R, 2), v m/s and w rad/s, above
    :data:`STILL_SPEED`) or is told to (commands (R, 2) above :data:`STILL_COMMAND`); a speed
    that is not a number is no motion (the others still count)."""
    return bool(np.count_nonzero(np.abs(velocity) > STILL_SPEED)
                or np.count_nonzero(np.abs(commands) > STILL_COMMAND))


def settled_since(still_since: float | None, now: float, show_time: float,
                  settle_from: float, moving: bool) -> float | None:
    """Since when (s, the loop's time ``now``) a show has been settled: its show time at or
    past ``settle_from`` with nothing ``moving`` (a robot drives, is told to, or waits to);
    ``still_since``: the answer at the last tick. None: not settled. A show ends once it has
    been settled :data:`STILL` s (:func:`run_show`, and the ROS simulator's bridge)."""
    if show_time >= settle_from and not moving:
        return now if still_since is None else still_since
    return None


def run_show(stage: Stage, step: Step, clock: Clock,
             progress: Progress | None = None) -> Recorder:
    """Run ``step`` and ``stage`` over the show's time; returns what was recorded at each
    tick. ``stage`` is left where the show ended (its contacts, recorded scans)."""
    count = len(stage.pose)
    commands: FloatArray = np.zeros((count, 2))
    issued: FloatArray = np.full(count, -math.inf)
    recorder = Recorder()
    total_steps = math.ceil(clock.end / clock.dt)
    still_since: float | None = None
    last_report = -math.inf
    show_time = 0.0
    k = 0
    while True:
        now = k * clock.dt
        if k % clock.steps_per_tick == 0:
            tick = step(now)
            commands, issued = tick.commands, np.full(count, now)
            recorder.add(now, **tick.record)
            show_time = now if tick.show_time is None else tick.show_time
            # a paused show ends as much later, up to max_pause
            lag = min(max(now - show_time, 0.0), clock.max_pause)
            if lag > 1e-6:  # (not for rounding: an unpaused show ends where it did)
                total_steps = math.ceil((clock.end + lag) / clock.dt)
            if progress is not None and now - last_report >= PROGRESS_PERIOD:
                progress(min(show_time, clock.end), clock.end)
                last_report = now
            if clock.settle_from is not None:
                still_since = settled_since(
                    still_since, now, show_time, clock.settle_from,
                    robots_moving(stage.velocity, commands) or tick.waiting)
                if still_since is not None and now - still_since >= STILL:
                    break
        if k >= total_steps:
            break
        stage.advance(now, commands, issued)
        k += 1
    if progress is not None:
        progress(clock.end, clock.end)
    return recorder

"""The verdict on a simulated show: did it run clean, and if not, what went wrong.

A show runs clean when no robot touched another robot, a wall, an obstacle or a person, no
robot went into its error state, every robot ends near its final slot (a formation show
that ends out of formation did not look like one), no robot drives against the direction its
slot moves for more than a small part of the time (a robot that turned round and reverses),
every robot ends facing about the way its final slot faces, the formation's shared show clock
does not stand for long with nobody near the robots that hold it (robots waiting for each other,
for a wall, for a lost or failed mate: ``report.metrics.clock_waits``), and no robot leaves its
formation on the way (further from its place than the formation is deep plus its own length: a robot
left standing behind a corner, ``report.metrics.off_formation``). Pure functions of the metrics;
the shells turn a verdict into their exit status (0 clean, 1 not).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from dancebots.report.metrics import RunMetrics
    from dancebots.report.queue_metrics import QueueMetrics

__all__ = ["FINAL_HEADING_TOLERANCE", "FINAL_SLOT_TOLERANCE", "OFF_FORMATION_TOLERANCE",
           "REVERSE_TOLERANCE", "STALL_CAUSES", "STALL_TOLERANCE", "Verdict", "queue_verdict",
           "run_verdict"]

FINAL_SLOT_TOLERANCE = 0.5
"""m: a robot that ends further than this from its final slot fails the show (about a robot's
length: the audience sees it out of place)."""
REVERSE_TOLERANCE = 0.05
"""A robot that drives against the direction its slot moves for more than this fraction of the
time its slot moves (``RobotMetrics.reverse_fraction``) fails the show: 5 %, a second in a
20-second show, is a short correction; more is a robot the audience sees reversing."""
FINAL_HEADING_TOLERANCE = 30.0
"""deg: a robot that ends with its heading further than this from its final slot's heading
fails the show (the audience sees it end askew or facing the wrong way)."""

OFF_FORMATION_TOLERANCE = 1.0
"""s: a robot outside its formation's block (``RobotMetrics.off_formation_time``) this long in
one go fails the show: a moment is a robot swinging wide, a second is one left behind (the
findings of check's simulation pass report the same stretches)."""

STALL_TOLERANCE = 3.0
"""s: the formation's shared show clock standing this long or longer, over the show, with no
person within ``report.metrics.PERSON_NEAR`` of a robot that held it fails the show: waiting
for people is the stop rule's work, waiting for nothing near is a stall (the bundled examples
have 0 s of it, the certified crowds at most 0.1 s a run)."""

STALL_CAUSES = "robots waiting for each other, for a wall, or for a failed or silent mate"
"""What stands a formation's clock with nobody near (the stall lines of run and certify)."""

_KINDS = {"robot": ("collision between robots", "collisions between robots"),
          "spectator": ("contact with a person", "contacts with people"),
          "wall": ("collision with a wall", "collisions with walls"),
          "obstacle": ("collision with an obstacle", "collisions with obstacles")}


@dataclass(frozen=True, slots=True)
class Verdict:
    """failures: one line per kind of failure, empty when the show ran clean."""

    failures: tuple[str, ...]

    @property
    def clean(self) -> bool:
        return not self.failures

    def to_json(self) -> dict[str, object]:
        return {"clean": self.clean, "failures": list(self.failures)}


def _contacts(events: Sequence[dict[str, object]]) -> list[str]:
    failures = []
    for kind, (one, many) in _KINDS.items():
        found = [e for e in events if e.get("kind") == kind]
        if found:
            first = found[0]
            speeds = ""
            robot, person = first.get("robot_closing_mps"), first.get("person_approach_mps")
            if isinstance(robot, (int, float)) and isinstance(person, (int, float)):
                speeds = (f": the robot closing at {robot:.2f} m/s, the person at "
                          f"{person:.2f} m/s")
            failures.append(f"{len(found)} {one if len(found) == 1 else many} (first: "
                            f"{first['robot']} with {first['with']} at t = "
                            f"{float(str(first['t_s'])):.1f} s{speeds})")
    return failures


def run_verdict(metrics: RunMetrics, final_tolerance: float = FINAL_SLOT_TOLERANCE,
                reverse_tolerance: float = REVERSE_TOLERANCE,
                heading_tolerance: float = FINAL_HEADING_TOLERANCE,
                off_formation_tolerance: float = OFF_FORMATION_TOLERANCE,
                stall_tolerance: float = STALL_TOLERANCE) -> Verdict:
    """The verdict on a formation show; final_tolerance in m, reverse_tolerance a fraction,
    heading_tolerance in deg, off_formation_tolerance and stall_tolerance in s."""
    from dancebots.report.metrics import PERSON_NEAR

    failures = _contacts(metrics.collision_events)
    for robot in metrics.robots:
        if robot.error is not None:
            failures.append(f"{robot.robot} went into its error state: {robot.error}")
    far = [r for r in metrics.robots if r.final_error > final_tolerance]
    if far:
        listed = ", ".join(f"{r.robot} {r.final_error:.2f} m" for r in far)
        failures.append(f"{'robots end' if len(far) > 1 else 'a robot ends'} away from the "
                        f"final slot (more than {final_tolerance:g} m): {listed}")
    against = [r for r in metrics.robots if r.reverse_fraction > reverse_tolerance]
    if against:
        listed = ", ".join(f"{r.robot} {100 * r.reverse_fraction:.1f} %" for r in against)
        who = "robots drive against their" if len(against) > 1 else "a robot drives against its"
        failures.append(f"{who} desired direction (more than {100 * reverse_tolerance:g} % of the "
                        f"time the slot moves): {listed}")
    if metrics.final_show_time is not None and not metrics.finished:
        end = metrics.end_show_time
        failures.append(f"the show did not finish: the formation waited for a held robot until "
                        f"the run ended at show time {metrics.final_show_time:.1f} s of "
                        f"{end:.1f} s{_waits_text(metrics)}")
    if metrics.clock_stood_otherwise >= stall_tolerance - 1e-9:
        failures.append(f"the formation stood {metrics.clock_stood_otherwise:.1f} s with nobody "
                        f"within {PERSON_NEAR:g} m of the robots that held it ({STALL_CAUSES})")
    outside = [r for r in metrics.robots
               if r.off_formation_time >= off_formation_tolerance - 1e-9]
    if outside:
        listed = ", ".join(f"{r.robot} {r.off_formation_time:.1f} s, up to "
                           f"{r.max_off_formation:.2f} m" for r in outside)
        failures.append(f"{'robots leave their' if len(outside) > 1 else 'a robot leaves its'} "
                        f"formation on the way (further from "
                        f"{'their' if len(outside) > 1 else 'its'} place than the formation is "
                        f"deep plus a robot length, {off_formation_tolerance:g} s or more in one "
                        f"go): "
                        f"{listed}")
    askew = [r for r in metrics.robots if r.final_heading_error > heading_tolerance]
    if askew:
        listed = ", ".join(f"{r.robot} {r.final_heading_error:.0f}°" for r in askew)
        failures.append(f"{'robots end' if len(askew) > 1 else 'a robot ends'} turned away "
                        f"from the final slot's heading (more than {heading_tolerance:g}°): "
                        f"{listed}")
    return Verdict(tuple(failures))


def queue_verdict(metrics: QueueMetrics) -> Verdict:
    """The verdict on a leader-follower queue: contacts, and a queue broken at the end."""
    failures = []
    contacts = sum(f.collisions for f in metrics.followers)
    if contacts:
        who = ", ".join(f"{f.robot} {f.collisions}" for f in metrics.followers if f.collisions)
        failures.append(f"{contacts} contact{'s' if contacts > 1 else ''} ({who})")
    broken = [f.robot for f in metrics.followers if not f.intact]
    if broken:
        failures.append(f"the queue is broken: {' '.join(broken)} no longer follow"
                        + ("s" if len(broken) == 1 else "") + " the one in front")
    return Verdict(tuple(failures))


def _waits_text(metrics: RunMetrics) -> str:
    """How long the shared clock stood and how much of it people explain, for the line of a
    show that did not finish ("" without a stood clock)."""
    from dancebots.report.metrics import PERSON_NEAR

    if metrics.clock_stood <= 0.0:
        return ""
    share = 100.0 * metrics.clock_stood_for_people / metrics.clock_stood
    return (f" (the clock stood {metrics.clock_stood:.1f} s, {share:.0f} % of it with a person "
            f"within {PERSON_NEAR:g} m of a robot that held it)")

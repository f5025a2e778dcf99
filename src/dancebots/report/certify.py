"""Certifying a show among people: the same show run over many seeds (new crowds, new noise),
each run summarised by what matters to the people around it, the summaries gathered into a
certificate.

:func:`run_seed` is what one worker does (a process of a local pool, or a Ray task): it
loads the show once per process and simulates one seed. :func:`summarise` and
:func:`certificate` are pure functions of the results.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict, dataclass
from functools import cache
from typing import TYPE_CHECKING

import numpy as np

from dancebots.perception.ssm import SsmParams

if TYPE_CHECKING:
    from dancebots.loading import LoadedShow
    from dancebots.plan.planner import Plan
    from dancebots.report.metrics import RunMetrics
    from dancebots.shows.formation import RunResult
    from dancebots.sim.setup import Arena, Placement

__all__ = ["PEOPLE_KEPT_WAITING", "RUNNING_SPEED", "Certificate", "CertifyJob", "RunSummary",
           "certificate", "job_has_crowds", "load_job", "run_seed", "simulate_seed",
           "summarise"]

PEOPLE_KEPT_WAITING = 0.9
"""The share of the stood clock with a person near that says people, not the show, kept the
unfinished shows waiting (``Certificate.people_kept_waiting``: the certificate then says to
give the show room)."""
RUNNING_SPEED = SsmParams().walking_speed
"""m/s: the walking speed ISO 13855 takes a person to approach at, SSM's
(``perception.ssm.SsmParams.walking_speed``, 1.6); a contact whose person came at the robot
faster (a child running) is told apart in a certificate
(``RunSummary.contacts_moving_runners``)."""


@dataclass(frozen=True, slots=True)
class CertifyJob:
    """What every run of a certification shares: the choreography and world files, the
    slowest robot's speed (m/s, None: the world's), the profile's name, the follower, the
    timing, the robots' LIDAR (False: blind robots), the final-slot tolerance (m) and whether
    the formation waits for a held robot (``SimConfig.hold``) and the stop rule
    (``BrainOptions.stop_rule``)."""

    scenario: str
    world: str
    vmax: float | None = None
    profile: str = "realistic"
    follower: str = "path"
    timing: str = "feasible"
    lidar: bool = True
    final_tolerance: float = 0.5
    hold: str | None = None
    stop_rule: str = "predicted"


@dataclass(frozen=True, slots=True)
class RunSummary:
    """One seed's run, as the people around it saw it.

    contacts_moving: contacts of a robot that moved with a person (the robot's doing);
    contacts_standing: contacts with a person of a robot that stood still; robot_contacts:
    contacts of robots with robots, walls or obstacles; min_person_gap: the smallest gap
    between a robot and a person, m (None without people); held: robot-seconds held by the
    stop rule; stops: how often a robot was held; held_place_error: the largest distance of a
    robot from its place while some robot was held, m (None: none was); overrun: s from the
    planned end until the last robot came to rest; finished: whether the show reached its
    end, every place on its final slot (``RunMetrics.finished``; not: the formation waited for
    a held robot until the run's limit); max_final_error:
    m; clean: the run's verdict; failures: its lines; wall: s the run took; clock_stood: s the
    formation's shared show clock stood during the show, clock_stood_for_people: s of it with
    a person near a robot that held it (``report.metrics.clock_waits``); how the robots
    looked: angular_sign_flips, the sign changes of their commanded turn rates (chatter),
    summed over the robots, reverse_fraction, the share of the ticks in which some robot's
    slot moves that a robot drove against it, and clock_brief_runs, how often the formation
    lurched on (the shared clock ran 0.35 s or less between two stands:
    ``report.metrics.clock_restarts``), and max_excess_turn, the most any robot turned beyond
    what it tracks, deg (spins and wiggles: ``report.metrics.excess_turn``);
    show_reached: the share (0-1) of the show its shared clock reached by the run's end (1
    for a show that finished: ``RunMetrics.show_reached``); contacts_moving_away: of
    contacts_moving, those in which the robot's footprint moved away from the person or
    slid past (its speed towards them, ``CollisionEvent.closing``, 0 or less: ISO/TS 15066
    counts the speed towards the person), told apart for the reader, still counted as the
    robot's (``report.metrics.RunMetrics``); contacts_moving_runners: of contacts_moving,
    those in which the person had come at the robot faster than :data:`RUNNING_SPEED` (their
    run-up, ``CollisionEvent.approach``), also still the robot's.
    """

    seed: int
    contacts_moving: int
    contacts_standing: int
    robot_contacts: int
    min_person_gap: float | None
    held: float
    stops: int
    held_place_error: float | None
    overrun: float
    finished: bool
    max_final_error: float
    clean: bool
    failures: tuple[str, ...]
    wall: float
    clock_stood: float = 0.0
    clock_stood_for_people: float = 0.0
    angular_sign_flips: int = 0
    reverse_fraction: float = 0.0
    clock_brief_runs: int = 0
    max_excess_turn: float = 0.0
    show_reached: float = 1.0
    contacts_moving_away: int = 0
    contacts_moving_runners: int = 0

    @property
    def clock_stood_otherwise(self) -> float:
        """s the clock stood with nobody near the robots that held it."""
        from dancebots.report.metrics import ClockWaits

        return ClockWaits(self.clock_stood, self.clock_stood_for_people).otherwise

    @property
    def stalled(self) -> bool:
        """The clock stood ``report.verdict.STALL_TOLERANCE`` s or more with nobody near."""
        from dancebots.report.verdict import STALL_TOLERANCE

        return self.clock_stood_otherwise >= STALL_TOLERANCE - 1e-9


def load_job(job: CertifyJob) -> LoadedShow:
    """The job's show, compiled, checked and placed as ``dancebots run`` does (its
    diagnostics say what is wrong)."""
    from dancebots.check import CheckOptions
    from dancebots.loading import load_show
    from dancebots.plan.placement import places_followed

    return load_show(job.scenario, job.world, job.vmax, check=CheckOptions(
        places=places_followed(job.follower)), timing=job.timing)  # type: ignore[arg-type]


@cache
def _loaded(job: CertifyJob) -> tuple[Plan, Arena, Placement]:
    """The job's plan, arena and placement, loaded once per process (the shell refuses a
    show :func:`load_job` finds invalid before any worker starts; ValueError otherwise)."""
    from dancebots.sim.setup import prepare_show

    show = load_job(job)
    if not show.valid or show.report is None or show.report.placement is None:
        raise ValueError("; ".join(d.message for d in show.diagnostics))
    arena, placement = prepare_show(show.report.placement)
    assert show.plan is not None  # a valid show has one
    return show.plan, arena, placement


def job_has_crowds(job: CertifyJob) -> bool:
    """Whether the job's world declares crowds (their forces are numba kernels of their own:
    ``sim.kernels.kernel_modules``)."""
    return bool(_loaded(job)[1].crowds)


def simulate_seed(job: CertifyJob, seed: int) -> RunResult:
    """The run of ``job`` with ``seed`` (the profile's noise and every crowd's draw), as
    certification runs it (``benchmarks/trace_contact.py`` traces one; ValueError for a show
    :func:`load_job` finds invalid)."""
    from dancebots.robot import BrainOptions
    from dancebots.shows.formation import SimConfig, simulate
    from dancebots.sim.kinematics import PROFILES
    from dancebots.sim.lidar import LidarConfig

    plan, arena, placement = _loaded(job)
    config = SimConfig(profile=PROFILES[job.profile], seed=seed,
                       lidar=LidarConfig() if job.lidar else None,
                       brain=BrainOptions(follower=job.follower,  # type: ignore[arg-type]
                                          stop_rule=job.stop_rule),  # type: ignore[arg-type]
                       hold=job.hold,  # type: ignore[arg-type]
                       scan_ahead=False)  # (the processes fill the cores)
    return simulate(plan, arena, placement, config)


def run_seed(job: CertifyJob, seed: int) -> RunSummary:
    """Simulate ``job`` with ``seed`` (:func:`simulate_seed`) and summarise it
    (:func:`summarise`)."""
    import time

    from dancebots.report.metrics import run_metrics
    from dancebots.report.verdict import run_verdict

    _loaded(job)  # (loaded once per process, before the clock starts, as before)
    started = time.perf_counter()
    result = simulate_seed(job, seed)
    metrics = run_metrics(result)
    verdict = run_verdict(metrics, job.final_tolerance)
    return summarise(seed, metrics, verdict.failures, time.perf_counter() - started)


def summarise(seed: int, metrics: RunMetrics, failures: Sequence[str],
              wall: float) -> RunSummary:
    """A run's :class:`RunSummary` from its metrics and verdict lines."""
    events = metrics.collision_events
    people = [e for e in events if e["kind"] == "spectator"]
    return RunSummary(
        seed, sum(1 for e in people if e.get("robot_moving", True)),
        sum(1 for e in people if not e.get("robot_moving", True)), len(events) - len(people),
        metrics.min_person_gap, float(sum(r.stopped_time for r in metrics.robots)),
        int(sum(r.stops for r in metrics.robots)), metrics.held_place_error,
        max(metrics.run_duration - metrics.show_duration, 0.0),
        metrics.finished,
        metrics.max_final_error,
        not failures, tuple(failures), wall, metrics.clock_stood,
        metrics.clock_stood_for_people, metrics.angular_sign_flips, metrics.reverse_fraction,
        metrics.clock_brief_runs, metrics.max_excess_turn, metrics.show_reached,
        sum(1 for e in people if e.get("robot_moving", True)
            and _away(e.get("robot_closing_mps"))),
        sum(1 for e in people if e.get("robot_moving", True)
            and _running(e.get("person_approach_mps"))))


def _running(approach: object) -> bool:
    """Whether a contact's person came at the robot faster than :data:`RUNNING_SPEED` (m/s,
    None: not measured)."""
    return isinstance(approach, (int, float)) and approach > RUNNING_SPEED


def _away(closing: object) -> bool:
    """Whether a contact's closing speed (m/s, None: not measured) says the robot moved away
    from the person or slid past."""
    return isinstance(closing, (int, float)) and closing <= 0.0


@dataclass(frozen=True, slots=True)
class Certificate:
    """A certification's result: the job, the runs (one :class:`RunSummary` per seed, in seed
    order), the wall time (s) and how many processes ran them. ``passed``: no contact of a
    moving robot with a person, no contact of a robot with a robot, wall or obstacle, every
    show finished (a show that waits for people for ever is no show) and no formation stood
    for nothing (:attr:`RunSummary.stalled`) in every run."""

    job: CertifyJob
    runs: tuple[RunSummary, ...]
    wall: float
    processes: int

    @property
    def contacts_moving(self) -> int:
        return sum(r.contacts_moving for r in self.runs)

    @property
    def contacts_moving_away(self) -> int:
        return sum(r.contacts_moving_away for r in self.runs)

    @property
    def contacts_moving_runners(self) -> int:
        return sum(r.contacts_moving_runners for r in self.runs)

    @property
    def contacts_standing(self) -> int:
        return sum(r.contacts_standing for r in self.runs)

    @property
    def robot_contacts(self) -> int:
        return sum(r.robot_contacts for r in self.runs)

    @property
    def unfinished(self) -> int:
        return sum(1 for r in self.runs if not r.finished)

    @property
    def stalled(self) -> int:
        return sum(1 for r in self.runs if r.stalled)

    @property
    def passed(self) -> bool:
        return (self.contacts_moving == 0 and self.robot_contacts == 0 and self.unfinished == 0
                and self.stalled == 0)

    def unfinished_for_people(self) -> float | None:
        """The share (0-1) of the time the clock stood in the unfinished runs with a person
        near a robot that held it (None: no unfinished run with a stood clock)."""
        stood = sum(r.clock_stood for r in self.runs if not r.finished)
        people = sum(r.clock_stood_for_people for r in self.runs if not r.finished)
        return people / stood if stood > 0.0 else None

    @property
    def people_kept_waiting(self) -> bool:
        """Whether people kept the unfinished shows waiting: a person was near a robot that
        held the clock :data:`PEOPLE_KEPT_WAITING` of the time it stood or more."""
        share = self.unfinished_for_people()
        return share is not None and share >= PEOPLE_KEPT_WAITING

    def gaps(self) -> np.ndarray:
        """The smallest robot-person gap of every run that had people (m)."""
        return np.array([r.min_person_gap for r in self.runs if r.min_person_gap is not None])

    def to_json(self) -> dict[str, object]:
        def stats(values: np.ndarray) -> dict[str, float | None]:
            if values.size == 0:
                return {"min": None, "p1": None, "p5": None, "median": None, "max": None}
            return {"min": round(float(values.min()), 4),
                    "p1": round(float(np.percentile(values, 1)), 4),
                    "p5": round(float(np.percentile(values, 5)), 4),
                    "median": round(float(np.median(values)), 4),
                    "max": round(float(values.max()), 4)}

        return {
            "job": asdict(self.job),
            "runs": len(self.runs),
            "passed": self.passed,
            "contacts_moving": self.contacts_moving,
            "runs_with_contacts_moving": sum(1 for r in self.runs if r.contacts_moving),
            "contacts_moving_away": self.contacts_moving_away,
            "contacts_moving_runners": self.contacts_moving_runners,
            "contacts_standing": self.contacts_standing,
            "robot_contacts": self.robot_contacts,
            "runs_not_clean": sum(1 for r in self.runs if not r.clean),
            "runs_unfinished": self.unfinished,
            "runs_stalled": self.stalled,
            "clock_stood_s": stats(np.array([r.clock_stood for r in self.runs])),
            "clock_stood_otherwise_s": stats(np.array([r.clock_stood_otherwise
                                                       for r in self.runs])),
            "min_person_gap_m": stats(self.gaps()),
            "held_robot_s": stats(np.array([r.held for r in self.runs])),
            "stops": stats(np.array([r.stops for r in self.runs], dtype=float)),
            "held_place_error_m": stats(np.array([r.held_place_error for r in self.runs
                                                  if r.held_place_error is not None])),
            "overrun_s": stats(np.array([r.overrun for r in self.runs])),
            "angular_sign_flips": stats(np.array([r.angular_sign_flips for r in self.runs],
                                                 dtype=float)),
            "reverse_fraction": stats(np.array([r.reverse_fraction for r in self.runs])),
            "clock_brief_runs": stats(np.array([r.clock_brief_runs for r in self.runs],
                                               dtype=float)),
            "max_excess_turn_deg": stats(np.array([r.max_excess_turn for r in self.runs])),
            "wall_s": round(self.wall, 2),
            "processes": self.processes,
            "per_run": [{**asdict(r), "failures": list(r.failures),
                         "wall": round(r.wall, 3)} for r in self.runs],
        }


def certificate(job: CertifyJob, runs: Sequence[RunSummary], wall: float,
                processes: int) -> Certificate:
    """The :class:`Certificate` of ``runs`` (any order: sorted by seed)."""
    return Certificate(job, tuple(sorted(runs, key=lambda r: r.seed)), wall, processes)

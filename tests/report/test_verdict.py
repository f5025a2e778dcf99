"""The verdict on a show: every kind of failure is named, and a clean show is clean."""

from __future__ import annotations

from dancebots.report.metrics import RobotMetrics, RunMetrics
from dancebots.report.queue_metrics import FollowerMetrics, QueueMetrics
from dancebots.report.verdict import queue_verdict, run_verdict


def metrics(robots: tuple[RobotMetrics, ...], events: tuple[dict[str, object], ...] = (),
            ) -> RunMetrics:
    return RunMetrics("show.dance", "ideal", 0, 10.0, 12.0, robots, (), len(events), events,
                      0.3)


def robot(name: str, final: float = 0.1, error: str | None = None) -> RobotMetrics:
    return RobotMetrics(name, 0.1, 0.2, 0.1, 0.2, 0, 0.0, error, final)


def contact(kind: str, other: str, t: float) -> dict[str, object]:
    return {"t_s": t, "robot": "R1", "with": other, "kind": kind, "x_m": 0.0, "y_m": 0.0}


def test_a_clean_show() -> None:
    verdict = run_verdict(metrics((robot("R1"), robot("R2", final=0.5))))
    assert verdict.clean
    assert verdict.to_json() == {"clean": True, "failures": []}


def test_every_failure_is_named() -> None:
    verdict = run_verdict(metrics(
        (robot("R1", final=2.386), robot("R2", error="no LIDAR data for 0.3 s"),
         robot("R3", final=0.7)),
        (contact("spectator", "child", 71.74), contact("robot", "R2", 3.0),
         contact("robot", "R3", 4.0), contact("wall", "wall", 5.0))))
    assert not verdict.clean
    assert verdict.failures == (
        "2 collisions between robots (first: R1 with R2 at t = 3.0 s)",
        "1 contact with a person (first: R1 with child at t = 71.7 s)",
        "1 collision with a wall (first: R1 with wall at t = 5.0 s)",
        "R2 went into its error state: no LIDAR data for 0.3 s",
        "robots end away from the final slot (more than 0.5 m): R1 2.39 m, R3 0.70 m",
    )


def test_the_final_tolerance_is_a_parameter() -> None:
    assert run_verdict(metrics((robot("R1", final=0.7),)), final_tolerance=1.0).clean
    assert not run_verdict(metrics((robot("R1", final=0.7),)), final_tolerance=0.6).clean


def follower(name: str, collisions: int = 0, intact: bool = True) -> FollowerMetrics:
    return FollowerMetrics(name, 0.0, 0.0, 0.0, 0.0, 0, 0.0, collisions, 0.5, intact)


def test_queue_verdict() -> None:
    assert queue_verdict(QueueMetrics("a1", "pid", 0.5, 60.0, (follower("F1"),))).clean
    verdict = queue_verdict(QueueMetrics("a1", "pid", 0.5, 60.0, (
        follower("F1", collisions=1), follower("F2", intact=False),
        follower("F3", collisions=2, intact=False))))
    assert verdict.failures == (
        "3 contacts (F1 1, F3 2)",
        "the queue is broken: F2 F3 no longer follow the one in front",
    )

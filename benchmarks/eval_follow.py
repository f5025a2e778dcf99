"""The second seed's evaluation (MAGESys 2019, sec. 3), in simulation: the queue of three
TurtleBot3 robots behind a walking person, on the static obstacle course and with a person
crossing the queue, for every detector-controller pairing.

Run: ``.venv/bin/python benchmarks/eval_follow.py``. Prints, per pairing and course: the
median distance error of the followers, their time without a target, kidnappings, contacts,
and whether the queue was intact at the end (every follower within 1.5 m of the object in
front). Deterministic (ideal profile, seed 0). Results: docs/leader-follower.md.
"""

from __future__ import annotations

import argparse

from dancebots.cli.common import bundled
from dancebots.report.queue_metrics import queue_metrics
from dancebots.shows.queue import QueueConfig, simulate_queue
from dancebots.world import load_world

PAIRINGS = [("a1", "pid", "first"), ("a1", "pid", "tuned"), ("a1", "vo", "first"),
            ("a2", "pid", "first"), ("a2", "vo", "first"), ("a2-track", "pid", "first"),
            ("a2-track", "vo", "first")]


def main() -> None:
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    print("course    detector  controller  median error m (F1 F2 F3)   lost s   kidnappings  "
          "contacts  queue")
    for course in ("follow_course.toml", "follow_crossing.toml"):
        world = load_world(bundled(course))
        for detector, controller, gains in PAIRINGS:
            result = simulate_queue(world, QueueConfig(detector=detector,
                                                       controller=controller, gains=gains))
            metrics = queue_metrics(result)
            label = controller + (f" ({gains})" if controller == "pid" else "")
            errors = " ".join(f"{f.median_error:5.2f}" for f in metrics.followers)
            lost = sum(f.lost_time for f in metrics.followers)
            kidnappings = sum(f.kidnappings for f in metrics.followers)
            contacts = sum(f.collisions for f in metrics.followers)
            print(f"{'static' if course == 'follow_course.toml' else 'crossing':9s} "
                  f"{detector:9s} {label:13s} {errors:>26s}  {lost:6.1f}  {kidnappings:>11d}  "
                  f"{contacts:>8d}  {'intact' if metrics.intact else 'BROKEN'}")


if __name__ == "__main__":
    main()

"""A person standing in a robot's footprint (issue 13): no deadlock with a moving command; the
robot stays still, neither driving nor turning, until the person leaves, then the show goes on."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from tests.tests_support import plan_of

from dancebots.plan.placement import place_show
from dancebots.report.metrics import run_metrics
from dancebots.report.verdict import run_verdict
from dancebots.robot import BrainOptions
from dancebots.shows.formation import SimConfig, simulate
from dancebots.sim.setup import prepare_show
from dancebots.world import Spectator

ROW = "robots R1 R2\nrow R1,R2 0 1.2\nmove 4 0\n"


def _run(hold: str = "together"):  # type: ignore[no-untyped-def]
    plan = plan_of(ROW)
    arena, placement = prepare_show(place_show(plan))
    x, y, theta = (float(v) for v in placement.starts[0])
    ahead = np.array([np.cos(theta), np.sin(theta)])
    # a child standing 0.4 m ahead of R1's centre, its disc over R1's front half, who walks
    # off sideways after 6 s (the world loader refuses such a start; the simulator must not
    # depend on it: a child may step into a standing robot's footprint at an open day)
    stand = np.array([x, y]) + 0.4 * ahead
    away = stand + 3.0 * np.array([-ahead[1], ahead[0]])
    child = Spectator("child", 0.25, 1.2, 0.8, np.array([stand, away]), np.zeros(2), False,
                      6.0, 0)
    return simulate(plan, replace(arena, spectators=(child,)), placement,
                    SimConfig(brain=BrainOptions(follower="path"), hold=hold))  # type: ignore[arg-type]


def test_a_robot_with_a_person_in_its_footprint_stands_still_until_they_leave() -> None:
    result = _run()
    while_there = result.times < 6.0
    # R1 neither drives nor turns while the child stands in it (no moving command at all)
    assert np.all(result.commands[0, while_there] == 0.0)
    assert np.all(result.velocities[0, while_there] == 0.0)
    # no contact of a moving robot with the child (a contact of R1 standing still is counted
    # apart: the child stood in it)
    assert not [c for c in result.collisions if c.kind == "spectator" and c.moving]
    # the formation waited (R2 too), then the show went on: everyone ends on its slot
    metrics = run_metrics(result)
    assert metrics.held_place_error is not None
    assert metrics.held_place_error <= 0.10
    verdict = run_verdict(metrics)
    assert not [f for f in verdict.failures if "final slot" in f or "did not finish" in f]
    assert metrics.max_final_error <= 0.05


def test_robots_that_touch_by_design_do_not_freeze() -> None:
    """Two robots 5 mm apart (a mate on its place within the 1 cm of OVERLAP): not a person
    in the footprint; the show runs clean."""
    plan = plan_of("robots R1 R2\nrow R1,R2 0 0.605\nmove 4 0\n")
    result = simulate(plan, *prepare_show(place_show(plan)),
                      SimConfig(brain=BrainOptions(follower="path")))
    metrics = run_metrics(result)
    assert run_verdict(metrics).clean
    assert metrics.max_final_error <= 0.05
    assert result.holds is not None
    assert not result.holds.any()

"""Speed and separation monitoring in the simulator (issue 13): a robot with ``--stop-rule
ssm`` or ``closing`` is standing when a person walking or running towards it arrives, where
the thesis's fixed 0.55 m leaves it driving into them (realistic profile: the robot's speed
lags its command)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from tests.tests_support import plan_of

from dancebots.plan.placement import place_show
from dancebots.robot import BrainOptions, StopRule
from dancebots.shows.formation import RunResult, SimConfig, simulate
from dancebots.sim.kinematics import REALISTIC
from dancebots.sim.setup import prepare_show
from dancebots.world import Spectator


def _walker_run(rule: StopRule, speed: float, across: bool) -> RunResult:
    """One robot driving 6 m; a person walks at ``speed`` m/s towards it head-on (from 5 m
    ahead) or across its way (2 m ahead, from 2.5 m beside it to 2.5 m beyond)."""
    plan = plan_of("robots R1\nrow R1 0 0\nmove 6 0\n")
    arena, placement = prepare_show(place_show(plan))
    x, y, theta = (float(v) for v in placement.starts[0])
    ahead = np.array([np.cos(theta), np.sin(theta)])
    left = np.array([-ahead[1], ahead[0]])
    here = np.array([x, y])
    way = ([here + 2.0 * ahead + 2.5 * left, here + 2.0 * ahead - 2.5 * left] if across
           else [here + 5.0 * ahead, here - 3.0 * ahead])
    person = Spectator("visitor", 0.25, 1.7, speed, np.array(way), np.zeros(2), False, 1.0, 0)
    return simulate(plan, replace(arena, spectators=(person,)), placement,
                    SimConfig(profile=REALISTIC, brain=BrainOptions(follower="path",
                                                                    stop_rule=rule)))


def _moving_contacts(result: RunResult) -> list[float]:
    return [c.time for c in result.collisions if c.kind == "spectator" and c.moving]


@pytest.mark.parametrize("rule", ["ssm", "closing"])
@pytest.mark.parametrize(("speed", "across"), [(1.0, False), (1.6, False), (2.0, False),
                                               (1.0, True), (2.0, True)])
def test_a_robot_is_standing_when_a_walking_person_reaches_it(rule: StopRule, speed: float,
                                                              across: bool) -> None:
    result = _walker_run(rule, speed, across)
    assert _moving_contacts(result) == []
    assert np.any(result.status[0] == 1)  # it stopped for them (and spoke: thesis 5.2)


def test_the_thesis_fixed_distance_drives_into_a_person_walking_head_on() -> None:
    """The comparison the stop rules are for: the same walker at 1 and 2 m/s, the fixed
    0.55 m."""
    for speed in (1.0, 2.0):
        result = _walker_run("fixed", speed, False)
        assert _moving_contacts(result)
        # driving at the person, not only touched while it moved (``CollisionEvent.closing``)
        assert all(c.closing is not None and c.closing > 0.0 for c in result.collisions
                   if c.kind == "spectator" and c.moving)

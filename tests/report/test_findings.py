"""check's simulation pass: what a simulated show predicts, at the scenario's lines."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from dancebots.plan.placement import place_show
from dancebots.plan.planner import PlanParameters
from dancebots.report.findings import FindingLimits, simulated_findings
from dancebots.report.metrics import run_metrics
from dancebots.report.verdict import run_verdict
from dancebots.robot import BrainOptions
from dancebots.shows.formation import RunResult, SimConfig, simulate
from dancebots.sim.setup import prepare_show
from tests_support import plan_of


def simulated(text: str, config: SimConfig | None = None) -> RunResult:
    plan = plan_of(text, path="show.dance")
    return simulate(plan, *prepare_show(place_show(plan)), config or SimConfig())


def test_a_show_that_goes_well_has_no_findings() -> None:
    result = simulated("robots A B\nrow A,B 0 1.2\nmove 3 0\n")
    assert simulated_findings(result, "ideal profile") == []


def test_a_robot_behind_its_place_is_reported_at_the_corner(examples: Path) -> None:
    """7.1 with the thesis follower (LIDAR on): R1 falls more than 0.5 m behind its place in
    the first sharp corner (line 4), R2 in the second (line 5); both end on their slots (the
    turn guard no longer holds R2 mid-spin in the corner, where it used to turn round)."""
    result = simulated((examples / "thesis_7_1.dance").read_text())
    found = [f"{d.line}:{d.col}: {d.message}" for d in simulated_findings(result, "x")]
    assert found == [
        "4:1: simulated (x): R1 is more than 0.5 m from its place from t = 8.0 s to 9.6 s "
        "(up to 0.57 m)",
        "5:1: simulated (x): R2 is more than 0.5 m from its place from t = 14.1 s to 15.5 s "
        "(up to 0.57 m)"]


def test_crossing_paths_are_a_contact_at_the_instruction(examples: Path) -> None:
    """7.4 without LIDAR: after the split the two robots' paths cross (check's rigid pass
    warns of it), and the simulated robots touch during line 15's move."""
    result = simulated((examples / "thesis_7_4.dance").read_text(), SimConfig(lidar=None))
    contacts = [d for d in simulated_findings(result, "x") if "touches" in d.message]
    assert [(d.line, d.message) for d in contacts] == [
        (15, "simulated (x): R1 touches R2 at t = 7.9 s")]
    assert contacts[0].hint is not None
    assert "paths cross" in contacts[0].hint


def test_many_findings_of_a_kind_end_in_a_count(examples: Path) -> None:
    result = simulated((examples / "thesis_7_1.dance").read_text())
    everything = simulated_findings(result, "x", FindingLimits(slot_distance=0.05,
                                                                 min_duration=0.1))
    capped = simulated_findings(result, "x", FindingLimits(slot_distance=0.05,
                                                            min_duration=0.1, per_kind=2))
    off = [d.message for d in everything if "from its place" in d.message]
    messages = [d.message for d in capped]
    assert len(off) > 3
    assert off[0] in messages
    assert off[1] not in messages  # counted instead
    assert f"simulated (x): ... and {len(off) - 1} more like the ones above" in messages


def test_the_final_finding_uses_the_verdicts_tolerances(examples: Path) -> None:
    result = simulated((examples / "thesis_7_1.dance").read_text())
    lenient = replace(FindingLimits(), final_heading=180.0)
    assert not any("ends" in d.message for d in simulated_findings(result, "x", lenient))
    strict = replace(FindingLimits(), final_distance=0.05)
    assert any("R2 ends 0.10 m from its final slot" in d.message
               for d in simulated_findings(result, "x", strict))


def test_moving_over_to_a_new_formation_is_not_a_finding_but_staying_away_is() -> None:
    """A column that becomes a row: the rear robot drives 1.6 m to its new place, which is
    the formation change, not a robot off its place; a robot whose recorded poses then stay
    where it was is reported once driving over should have been done."""
    import numpy as np

    text = "robots A B\ncolumn A;B 1.5 0\nmove 2 0\nrow A,B 0 1.5\nmove 8 0\n"
    result = simulated(text, SimConfig(lidar=None, brain=BrainOptions(follower="path")))
    assert not [d for d in simulated_findings(result, "x") if "from its place" in d.message]
    change = int(np.flatnonzero(np.diff(result.formation[1]) != 0)[0]) + 1
    poses = result.poses.copy()
    poses[1, change:] = poses[1, change]  # B never moves after the change
    stuck = replace(result, poses=poses)
    off = [f"{d.line}: {d.message}" for d in simulated_findings(stuck, "x")
           if "from its place" in d.message]
    assert len(off) == 1
    assert off[0].startswith("5: simulated (x): B is more than 0.5 m")


def test_a_robot_that_ends_off_its_slot_and_turned_is_not_said_to_have_reached_it(
        examples: Path) -> None:
    """7.4 with SIM robots, defaults, LIDAR, with R2's recorded poses kept where R2 was 2 s
    after the split (it was held beside R1 there, 1.05 m off its final slot and turned,
    before robots made room for a turn: ``RobotBrain._make_room``): the heading finding's
    hint does not say it reached its place."""
    import numpy as np

    plan = plan_of((examples / "thesis_7_4.dance").read_text(),
                   PlanParameters(timing="feasible"), path="show.dance")
    result = simulate(plan, *prepare_show(place_show(plan)),
                      SimConfig(brain=BrainOptions(follower="path")))
    split = int(np.flatnonzero(np.diff(result.formation[1]) != 0)[0]) + 1
    held = split + 20
    poses = result.poses.copy()
    poses[1, held:] = poses[1, held]
    final = {d.message.split(" ends ")[1].split(" ")[0]: d for d in
             simulated_findings(replace(result, poses=poses), "x")
             if d.message.startswith("simulated (x): R2 ends")}
    assert set(final) == {f"{np.hypot(*(poses[1, -1, :2] - result.final_slot[1, :2])):.2f}",
                          "facing"}
    assert final["facing"].hint == ("it did not reach its place either: see the findings "
                                    "before this one for why")


def test_a_robot_left_behind_a_turn_leaves_its_formation(data: Path) -> None:
    """A square turned round within its own width (issue 12): the path follower's inner
    places wait behind the robots ahead, R3 and R4 stand clear of the formation's block (R3
    for 1.0 s, the finding's and the verdict's threshold; 0.9 s before a place that stands
    a moment was tracked as if the clock stood, 2026-11-28; R4 for 2.3 s), and the finding
    says so at the turn (it used to report nothing: every robot was at its place)."""
    text = (data / "scenarios" / "valid" / "u_turn_square.dance").read_text()
    plan = plan_of(text, PlanParameters(timing="feasible"), path="show.dance")
    config = SimConfig(brain=BrainOptions(follower="path"))  # run's and check's defaults
    result = simulate(plan, *prepare_show(place_show(plan)), config)
    found = [f"{d.line}:{d.col}: {d.message}" for d in simulated_findings(result, "x")]
    assert found == [
        "13:1: simulated (x): R3 leaves its formation from t = 82.5 s to 83.4 s (up to 3.24 m "
        "from where the formation puts it, more than the formation is deep plus a robot "
        "length)",
        "13:1: simulated (x): R4 leaves its formation from t = 85.6 s to 87.8 s (up to 3.69 m "
        "from where the formation puts it, more than the formation is deep plus a robot "
        "length)"]
    metrics = run_metrics(result)
    assert [(r.robot, round(r.max_off_formation, 2)) for r in metrics.robots
            if r.off_formation_time > 0] == [("R3", 3.24), ("R4", 3.69)]
    # R3 is out for 1.0 s; R4 for 2.3 s
    assert run_verdict(metrics).failures == (
        "robots leave their formation on the way (further from their place than the formation "
        "is deep plus a robot length, 1 s or more in one go): R3 1.0 s, up to 3.24 m, R4 2.3 "
        "s, up to 3.69 m",)

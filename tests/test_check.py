"""check_plan: the summary and each kind of warning, pointing at the right line."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from dancebots.check import (
    CheckOptions,
    CheckReport,
    Widening,
    check_plan,
    widening_that_keeps_apart,
)
from dancebots.diagnostics import Severity
from dancebots.geometry import Pose
from dancebots.plan.compile import compile_scenario
from dancebots.plan.placement import places_followed
from dancebots.plan.planner import PlanParameters
from dancebots.world import World, load_world, parse_world
from tests_support import plan_of


def check(text: str, world: World | None = None, **options: float) -> CheckReport:
    _, plan, diagnostics = compile_scenario(text, "show.dance")
    assert plan is not None, diagnostics
    return check_plan(plan, world, CheckOptions(**options))  # type: ignore[arg-type]


def messages(report: CheckReport) -> list[str]:
    return [f"{d.line}: {d.message}" for d in report.diagnostics]


def test_summary_of_a_straight_show() -> None:
    report = check("robots R1 R2\nrow R1,R2 0 1.2\nmove 2 0\n")
    assert report.robots == ("R1", "R2")
    assert report.duration == pytest.approx(5.61, abs=0.06)
    r1 = report.summaries[0]
    # the leader stops 0.1 m short of the waypoint: 1.9 m < path <= 2.0 m
    assert 1.9 < r1.path_length <= 2.0
    assert r1.max_speed == pytest.approx(0.35)
    assert r1.max_angular_speed == 0.0
    assert report.min_clearance == pytest.approx(0.6)
    assert report.diagnostics == ()


def test_footprints_too_close_in_a_formation() -> None:
    report = check("robots R1 R2\nrow R1,R2 0 0.7\nmove 1 0\n")
    assert messages(report) == ["2: R1 and R2 are 0.10 m apart in this formation (clearance "
                                "0.2 m)"]
    assert report.min_clearance == pytest.approx(0.1)
    assert check("robots R1 R2\nrow R1,R2 0 0.7\nmove 1 0\n", clearance=0.05).diagnostics == ()


def test_crossing_groups_are_reported_at_the_moving_instruction() -> None:
    text = ("robots R1 R2\ngroups\na R1\nb R2\nstart\nrow R1,R2 0 3\nrow R1 0 0\nrow R2 0 0\n"
            "newVL\nmove 3 -60 a\nmove 3 60 b\n")
    found = messages(check(text))
    assert len(found) == 1
    assert found[0].startswith("10: R1 and R2 come within 0.00 m of each other (clearance 0.2 m)")


def test_circle_tighter_than_the_formation() -> None:
    text = "robots R1 R2 R3\nrow R1,R2,R3 0 1.5\ncircle 1 90 0.1\n"
    found = messages(check(text))
    assert ("3: the circle's radius 1 m is smaller than R1's lateral offset 1.5 m from the "
            "virtual leader: the inner robots would have to reverse") in found


def test_speed_above_maximum_points_at_the_turn() -> None:
    found = messages(check("robots R1 R2\nrow R1,R2 0 1.2\nmove 2 0\nmove 2 -90\n"))
    assert len(found) == 1
    assert found[0].startswith("4: desired speed above the robot's maximum: R1 1.29 m/s (max "
                               "0.5), R2 0.79 m/s (max 0.5)")


def test_world_types_set_the_limits(data: Path) -> None:
    world = load_world(str(data / "worlds" / "two_robots.toml"))
    report = check("robots R1 R2\nrow R1,R2 0 1.2\nmove 2 0\nmove 2 -90\n", world)
    r1, r2 = report.summaries
    assert (r1.robot_type.name, r2.robot_type.name) == ("HUSKY", "TRADR")
    found = messages(report)
    # HUSKY may drive 1.0 m/s, TRADR 0.5 m/s: only their excess is reported
    assert found[0].startswith("4: desired speed above the robot's maximum: R1 1.29 m/s (max 1)"
                               ", R2 0.79 m/s (max 0.5)")
    transform = report.world_transform
    assert transform is not None
    assert (transform.x, transform.y, transform.theta) == pytest.approx((2.0, 3.0, 0.0))


def test_leaving_the_room_is_an_error_entering_an_obstacle_a_warning(data: Path) -> None:
    world, _ = parse_world((data / "worlds" / "two_robots.toml").read_text(), "two.toml")
    assert world is not None
    report = check("robots R1 R2\nrow R1,R2 0 1.2\nmove 2 0\nmove 3 45\nmove 9 0\n", world)
    found = [(d.severity.value, d.line, d.message, d.hint) for d in report.diagnostics
             if "room" in d.message or "pillar" in d.message]
    assert found == [
        ("warning", 5, "R1 enters pillar (two.toml:5) from t = 16.2 s to 23.0 s",
         "steer the formation around the obstacle"),
        ("error", 5, "R2 leaves the room from t = 30.9 s to 40.2 s",
         "move the show's start poses, use a bigger room, or shorten the moves"),
        ("error", 5, "R1 leaves the room from t = 33.8 s to 40.2 s",
         "move the show's start poses, use a bigger room, or shorten the moves"),
    ]


def test_robot_far_from_its_slot(data: Path) -> None:
    text = ('[[robots]]\nname = "R1"\nx = 1\ny = 1\n[[robots]]\nname = "R2"\nx = 1\ny = 5\n')
    world, _ = parse_world(text, "w.toml")
    assert world is not None
    found = messages(check("robots R1 R2\nrow R1,R2 0 1.2\nmove 1 0\n", world))
    # slots 1.2 m apart, left R1 (y + 0.6), but R1 starts 4 m to the right of R2: the best
    # fit puts the slots at y = 3.6 (R1) and 2.4 (R2): 2.6 m from each start.
    assert found == [
        "2: R1 starts 2.60 m and 0 deg away from its place in the first formation (w.toml:1)",
        "2: R2 starts 2.60 m and 0 deg away from its place in the first formation (w.toml:5)",
    ]


def test_world_without_some_robots_is_an_error() -> None:
    world, _ = parse_world('[room]\nsize = 5\n[[robots]]\nname = "R1"\nx = 1\ny = 1\n',
                           "w.toml")
    assert world is not None
    # at the scenario's robots line, naming the world's first robot entry
    report = check("# two robots\n  robots R1 R2\nrow R1,R2 0 1.2\nmove 1 0\n", world)
    assert [(d.headline(), d.hint) for d in report.diagnostics] == [
        ("show.dance:2:3: error: the world places R1 but not R2 (w.toml:3)",
         "give every robot of the scenario a [[robots]] entry in w.toml, or none to let the "
         "show be centred in the room")]


def test_world_without_robots_centres_the_show(examples: Path) -> None:
    world = load_world(str(examples / "worlds" / "thesis_room.toml"))
    report = check((examples / "thesis_7_1.dance").read_text(), world)
    assert report.world_transform is not None
    assert not any("leaves the room" in d.message for d in report.diagnostics)


def headlines(report: CheckReport) -> list[tuple[str, str | None]]:
    return [(d.headline(), d.hint) for d in report.diagnostics if d.is_error]


def test_robots_overlapping_in_the_first_formation_cannot_start() -> None:
    # SIM robots are 0.6 m wide: 0.3 m apart they overlap; 0.6 m apart they touch, which the
    # simulator allows (a zero gap is no overlap)
    report = check("robots R1 R2 R3\nrow R1,R2,R3 0 0.3\nmove 1 0\n")
    assert headlines(report) == [
        ("show.dance:2:1: error: R1 and R2 overlap at their start poses", OVERLAP_HINT),
        ("show.dance:2:1: error: R2 and R3 overlap at their start poses", OVERLAP_HINT),
    ]
    assert headlines(check("robots R1 R2\nrow R1,R2 0 0.6\nmove 1 0\n")) == []
    # only the start counts: robots that meet later are a warning, and a collision in the run
    later = check("robots R1 R2\nrow R1,R2 0 1.2\nmove 1 0\nrow R1,R2 0 0.3\nmove 1 0\n")
    assert headlines(later) == []


OVERLAP_HINT = ("place them further apart (in the first formation or the world): the simulator "
                "would hold both where they stand")
ROOM_HINT = ("its footprint must lie inside the room, clear of the walls, at the start: move the "
             "start poses or use a bigger room")


def test_a_centred_show_too_big_for_the_room_starts_outside_it() -> None:
    world, _ = parse_world("[room]\nsize = 1.5\n", "w.toml")
    assert world is not None
    report = check("robots R1 R2\nrow R1,R2 0 1.2\nmove 1 0\n", world)
    # the starts are reported once, not again as leaving the room from t = 0
    assert headlines(report) == [
        ("show.dance:2:1: error: R1 starts outside the room of w.toml or against its wall",
         ROOM_HINT),
        ("show.dance:2:1: error: R2 starts outside the room of w.toml or against its wall",
         ROOM_HINT),
    ]


def test_a_centred_show_starting_on_an_obstacle_or_a_visitor() -> None:
    # the show is centred in the 10 m room: R1's slot at (5, 5.6), R2's at (5, 4.4)
    world, _ = parse_world(
        '[room]\nsize = 10\n[[obstacles]]\nname = "pillar"\n'
        'polygon = [[4.5, 5.4], [5.5, 5.4], [5.5, 6.4]]\n[[spectators]]\nname = "child"\n'
        'path = [[5, 4.4], [9, 4.4]]\n', "w.toml")
    assert world is not None
    report = check("robots R1 R2\nrow R1,R2 0 1.2\nmove 1 0\n", world)
    assert headlines(report) == [
        ("show.dance:2:1: error: R1 starts in or against obstacle 'pillar' (w.toml:3)",
         "move its start off the obstacle (the world's start poses, or the show's first "
         "formation)"),
        ("show.dance:2:1: error: R2 starts where spectator 'child' stands (w.toml:6)",
         "move the show's start or the spectator's first waypoint"),
    ]
    # the start in the pillar is not repeated as a warning from t = 0
    assert not any(d.message.startswith("R1 enters pillar") for d in report.diagnostics)


def test_a_world_that_places_the_robots_is_checked_where_it_places_them() -> None:
    """A World built without the loader's checks (as a test or a tool may) still gets them
    from check, positioned at the robot's [[robots]] entry."""
    text = '[[robots]]\nname = "R1"\nx = 5\ny = 5\n[[robots]]\nname = "R2"\nx = 5\ny = 5.3\n'
    world, diagnostics = parse_world(text, "w.toml")
    assert world is None
    assert [d.headline() for d in diagnostics] == [
        "w.toml:7:1: error: robots 'R1' and 'R2' overlap at their start poses"]
    valid, _ = parse_world(text.replace("5.3", "3.8"), "w.toml")
    assert valid is not None
    overlapping = World(valid.path, valid.room, valid.wall_height, (), (
        valid.robots[0], dataclasses.replace(valid.robots[1], start=Pose(5.0, 5.3, 0.0))))
    report = check("robots R1 R2\nrow R1,R2 0 1.2\nmove 1 0\n", overlapping)
    assert headlines(report) == [
        ("w.toml:5:1: error: R1 and R2 overlap at their start poses", OVERLAP_HINT)]


def test_a_world_robot_the_scenario_lacks_is_left_out_with_a_warning() -> None:
    world, _ = parse_world('[[robots]]\nname = "R1"\nx = 2\ny = 5.6\n[[robots]]\nname = "R2"\n'
                           'x = 2\ny = 4.4\n[[robots]]\nname = "X"\nx = 5\ny = 2\n', "w.toml")
    assert world is not None
    report = check("robots R1 R2\nrow R1,R2 0 1.2\nmove 1 0\n", world)
    assert [(d.headline(), d.hint) for d in report.diagnostics] == [
        ("w.toml:9:1: warning: the world's robot X is not in the scenario: it is left out of "
         "the show", "remove its [[robots]] entry, or add it to the scenario's robots line")]


def test_robots_piled_in_a_formation_are_named_twenty_times_then_counted() -> None:
    names = [f"R{i}" for i in range(30)]
    report = check("robots " + " ".join(names) + "\nrow " + ",".join(names) + " 0 0\n")
    mine = [m for m in messages(report) if "overlap at their start" not in m]
    assert len(mine) == 21
    assert mine[0] == "2: R0 and R1 are 0.00 m apart in this formation (clearance 0.2 m)"
    assert mine[-1] == ("2: in all, 435 pairs of robots of this formation are closer than the "
                        "clearance and 0 follow each other nearer than the stop distance (the "
                        "first 20 of each are listed)")


def test_a_long_show_of_many_robots_is_sampled_more_coarsely_and_says_so() -> None:
    names = [f"R{i}" for i in range(1000)]
    report = check("robots " + " ".join(names) + "\nrow " + ",".join(names) + " 0 1.2\n"
                   "move 100 0\n")
    warning, error = sorted(report.diagnostics, key=lambda d: d.is_error)
    assert (error.line, error.col) == (1, 1)  # simulating it would take about 2 GB
    assert error.message == ("the show is too large to simulate: 1000 robots for 286 s is "
                             "285,600 robot-seconds (at most 200,000; the simulator keeps "
                             "about 6 kB per robot-second)")
    assert (warning.line, warning.col) == (1, 1)
    assert warning.message == ("1000 robots over 286 s: check samples their places every "
                               "0.21 s instead of every 0.1 s")
    assert warning.hint == ("a brief contact between samples may go unreported: shorten the "
                            "show or check parts of it with fewer robots")


CROSSING = """robots A B C D
groups
g1 A C
g2 B D
start
square A,B;C,D 1 1
column A;C 1 0
column B;D 1 0
newVL
move 3 -60 g1
move 3 60 g2
move 2 0 g1
move 2 0 g2
"""


def test_the_sweep_across_formations_finds_what_comparing_every_pair_finds(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The spatial search used for many robots gives the very report of the pair loop."""
    import dancebots.check as check_module

    every_pair = check(CROSSING)
    monkeypatch.setattr(check_module, "_PAIR_LOOP_LIMIT", -1)
    swept = check(CROSSING)
    assert swept.diagnostics == every_pair.diagnostics
    assert swept.min_clearance == every_pair.min_clearance
    assert any(m.startswith("10: A and B come within 0.00 m") for m in messages(swept))


def test_a_search_cut_short_says_so(monkeypatch: pytest.MonkeyPatch) -> None:
    import dancebots.check as check_module

    monkeypatch.setattr(check_module, "_PAIR_LOOP_LIMIT", -1)
    monkeypatch.setattr(check_module, "_MAX_SWEEP", 1)
    report = check(CROSSING)
    [cut] = [d for d in report.diagnostics if "piled" in d.message]
    assert (cut.line, cut.col) == (1, 1)
    assert cut.message == ("so many robots are piled on each other that check compared only "
                           "some of the robots of different formations")
    assert cut.hint == "spread the robots out: give the formations spacings and row distances"


CORPUS_ROOT = Path(__file__).resolve().parent.parent
CORPUS_WORLDS = sorted([*CORPUS_ROOT.glob("examples/worlds/*.toml"),
                        *CORPUS_ROOT.glob("tests/data/worlds/*.toml"),
                        *CORPUS_ROOT.glob("src/dancebots/data/*.toml")])


@pytest.mark.parametrize("world_path", [None, *CORPUS_WORLDS],
                         ids=lambda p: "no world" if p is None else p.name)
def test_every_diagnostic_of_the_corpus_has_a_real_position(world_path: Path | None) -> None:
    """Each choreography of the corpus, alone and in each corpus world: every diagnostic of
    the compiler, the world loader and check points at line >= 1, column >= 1 of its file."""
    from dancebots.diagnostics import DiagnosticError, source_lines

    sources = sorted([*CORPUS_ROOT.glob("examples/*.dance"),
                      *CORPUS_ROOT.glob("tests/data/scenarios/*/*.dance"),
                      *CORPUS_ROOT.glob("src/dancebots/data/*.dance")])
    texts = {str(p): p.read_bytes().decode("utf-8", errors="replace") for p in sources}
    world = None
    if world_path is not None:
        texts[str(world_path)] = world_path.read_text(encoding="utf-8")
        try:
            world = load_world(str(world_path))
        except DiagnosticError as exc:
            found = list(exc.diagnostics)
        else:
            found = []
    else:
        found = []
    for source in sources:
        _, plan, diagnostics = compile_scenario(texts[str(source)], str(source))
        found += diagnostics
        if plan is not None and (world_path is None or world is not None):
            found += check_plan(plan, world).diagnostics
    for d in found:
        assert 1 <= d.line <= max(1, len(source_lines(texts[d.path]))), d.headline()
        assert d.col >= 1, d.headline()


@pytest.mark.parametrize(("spacing", "row_distance"), [("0.7", "1.5"), ("1.2", "1.25"),
                                                       ("0.85", "3"), ("2", "2")])
def test_the_index_in_a_large_formation_finds_what_comparing_every_pair_finds(
        monkeypatch: pytest.MonkeyPatch, spacing: str, row_distance: str) -> None:
    """70 robots (2,415 pairs, past the pair-loop limit): the STRtree gives the very warnings,
    in the same order, and the same smallest gap as comparing every pair."""
    import dancebots.check as check_module

    names = [f"R{i}" for i in range(70)]
    rows = ";".join(",".join(names[r * 10:(r + 1) * 10]) for r in range(7))
    text = f"robots {' '.join(names)}\nsquare {rows} {row_distance} {spacing}\nmove 1 0\n"
    indexed = check(text)
    monkeypatch.setattr(check_module, "_PAIR_LOOP_LIMIT", 10**9)
    every_pair = check(text)
    assert indexed.diagnostics == every_pair.diagnostics
    assert indexed.min_clearance == every_pair.min_clearance


def test_a_world_of_other_robots_centres_the_show(data: Path) -> None:
    """The world places R1 and R2, the show has A and B: the show is centred in the room and
    the world's robots are reported as left out (this raised a KeyError)."""
    _, plan, problems = compile_scenario("robots A B\nrow A,B 0 1.2\nmove 1 0\n", "s.dance")
    assert plan is not None
    assert problems == []
    world = load_world(str(data / "worlds" / "two_robots.toml"))
    report = check_plan(plan, world)
    assert [d.message for d in report.diagnostics if d.is_error] == []
    left_out = [d for d in report.diagnostics if "is not in the scenario" in d.message]
    assert [d.message for d in left_out] == [
        "the world's robot R1 is not in the scenario: it is left out of the show",
        "the world's robot R2 is not in the scenario: it is left out of the show"]
    assert all(d.line >= 1 and d.col >= 1 for d in report.diagnostics)


def test_a_pile_of_robots_names_twenty_overlaps_and_counts_the_rest() -> None:
    names = [f"R{i}" for i in range(30)]
    text = f"robots {' '.join(names)}\nrow {','.join(names)} 0 0\nmove 1 0\n"
    _, plan, _ = compile_scenario(text, "pile.dance")
    assert plan is not None
    errors = [d for d in check_plan(plan).diagnostics if d.is_error]
    overlaps = [d for d in errors if d.message.endswith("overlap at their start poses")]
    assert len(overlaps) == 21
    assert overlaps[0].message == ("... and 415 more pairs of robots overlap at their start "
                                   "poses")  # 30 * 29 / 2 = 435 pairs, 20 named
    assert all((d.line, d.col) == (2, 1) for d in errors)


def test_a_show_too_large_to_simulate_is_an_error_of_check_and_refused_by_setup() -> None:
    """1,000 robots driving 1 km would need about 18 GB in the simulator (the review's
    reproducer ran out of memory after 64 s): check says so at the robots line, and the
    simulator's setup refuses it with the same error."""
    from dancebots.plan.placement import place_show
    from dancebots.sim.setup import SetupError, prepare_show

    names = [f"R{i}" for i in range(1000)]
    text = "robots " + " ".join(names) + "\nrow " + ",".join(names) + " 0 1.2\nmove 1000 0\n"
    _, plan, _ = compile_scenario(text, "k1.dance")
    assert plan is not None
    errors = [d for d in check_plan(plan).diagnostics if d.is_error]
    assert [(d.line, d.col) for d in errors] == [(1, 1)]
    assert errors[0].message.startswith("the show is too large to simulate: 1000 robots for ")
    with pytest.raises(SetupError, match="too large to simulate"):
        prepare_show(place_show(plan, None))


def test_a_show_in_a_world_without_robots_is_centred_as_recorded(examples: Path) -> None:
    """Golden: 7.3 in the thesis's room (no [[robots]]) is centred on the extent of its
    desired positions at the placement's 0.1 s samples; a change of that sampling moves it."""
    plan = plan_of((examples / "thesis_7_3.dance").read_text())
    report = check_plan(plan, load_world(str(examples / "worlds" / "thesis_room.toml")))
    assert report.world_transform == Pose(4.317989750195567, 5.588761409272698, 0.0)


def test_ways_that_meet_at_a_formation_change_and_the_assignment_that_avoids_it() -> None:
    """A row that mirrors itself: R1 and R3 change sides through R2. The shortest assignment
    (Hungarian method) keeps every robot where it is, so check says to swap R1 and R3."""
    report = check("robots R1 R2 R3\nrow R1,R2,R3 0 1.5\nmove 2 0\nrow R3,R2,R1 0 1.5\n"
                   "move 2 0\n")
    [warning] = [d for d in report.diagnostics if "formation change" in d.message]
    assert (warning.line, warning.col) == (4, 1)
    assert warning.message == ("the ways of R1 and R2, R1 and R3, R2 and R3 to their new "
                               "slots meet at this formation change")
    assert warning.hint == ("swap R1 and R3 in this line: their ways then stay apart (the "
                            "shortest assignment)")


def test_a_half_turn_of_the_slots_is_undone_by_swaps() -> None:
    """Four robots in a square whose names move to the opposite corner: every way crosses
    the square's centre at the same time; the shortest assignment keeps every robot where it
    is, which check says as two swaps."""
    report = check("robots A B C D\nsquare A,B;C,D 1.5 1.5\nmove 2 0\n"
                   "square D,C;B,A 1.5 1.5\nmove 2 0\n")
    [warning] = [d for d in report.diagnostics if "formation change" in d.message]
    assert warning.line == 4
    assert warning.hint == ("swap A and D; swap B and C in this line: their ways then stay "
                            "apart (the shortest assignment)")


def test_slots_that_move_one_corner_round_together_do_not_meet() -> None:
    """Four robots whose names move one corner round the square: their ways are the square's
    sides, and moving along them together the robots stay 1.06 m apart (the square of the
    sides' midpoints), so no way meets another (the fixed segments touch at the corners)."""
    report = check("robots A B C D\nsquare A,B;C,D 1.5 1.5\nmove 2 0\n"
                   "square C,A;D,B 1.5 1.5\nmove 2 0\n")
    assert not any("formation change" in d.message for d in report.diagnostics)


def test_ways_that_stay_apart_are_not_reported() -> None:
    report = check("robots R1 R2\nrow R1,R2 0 1.5\nmove 2 0\nrow R1,R2 0 3\nmove 2 0\n")
    assert not any("formation change" in d.message for d in report.diagnostics)


def test_feasible_timing_notes_where_the_leader_slows() -> None:
    """Under --timing feasible, check says where and how much the leader slows (a note, not
    a warning: nothing to fix); under the thesis's timing, nothing."""
    text = "robots R1 R2\nrow R1,R2 0 1.2\nmove 2 0\nmove 2 -90\n"
    _, plan, _ = compile_scenario(text, "show.dance", PlanParameters(timing="feasible"))
    assert plan is not None
    notes = [d for d in check_plan(plan).diagnostics if d.severity is Severity.NOTE]
    assert [(d.line, d.col) for d in notes] == [(4, 1)]
    assert notes[0].message.startswith("the virtual leader slows to ")
    assert notes[0].message.endswith(" % of its speed here, so that no robot's slot or place "
                                     "on the path moves faster than 0.40 m/s "
                                     "(--timing feasible)")
    assert not any(d.severity is Severity.NOTE for d in check(text).diagnostics)


def test_a_meeting_no_departure_delay_removes_is_named_so(examples: Path) -> None:
    """Listing 7.4 with SIM robots 0.2 m apart: the robots' places meet whichever formation
    waits (R2's tail swings into R1 beside it), so the hint says that waiting does not help
    and asks for room; crossing_groups' meeting is removed by B waiting (a note) and the
    rigid pass has nothing to say about it."""
    def feasible(name: str) -> CheckReport:
        text = (examples / name).read_text()
        _, plan, diagnostics = compile_scenario(text, name, PlanParameters(timing="feasible"))
        assert plan is not None, diagnostics
        return check_plan(plan)

    report = feasible("thesis_7_4.dance")
    meeting = [d for d in report.diagnostics if d.message.startswith("R1 and R2 come within")]
    assert [(d.line, d.hint) for d in meeting] == [(15, (
        "no departure delay keeps them apart (the feasible timing tried 1, 3 and 8 s for "
        "either formation): make the formation at line 8 1.5 times as wide (R1 and R2 1.20 m "
        "apart there instead of 0.80 m: every spacing and row distance times 1.5) and the "
        "timing keeps them apart, or change one's path"))]
    crossing = feasible("crossing_groups.dance").diagnostics
    assert not any("come within" in d.message for d in crossing)
    assert any(d.severity is Severity.NOTE and d.message.startswith("B waits 8 s here")
               for d in crossing)


def test_the_widening_check_suggests_is_enough(examples: Path) -> None:
    """Listing 7.4 with SIM robots: widening the row the two robots shared (line 8) by 1.25
    is not enough, by 1.5 (1.2 m between them) it is, and the widened show checks without a
    meeting; before any formation they shared (line 8 itself) there is nothing to widen."""
    text = (examples / "thesis_7_4.dance").read_text()
    _, plan, _ = compile_scenario(text, "7_4.dance", PlanParameters(timing="feasible"))
    assert plan is not None
    assert plan.apart_by_no_delay == (("R1", "R2"),)
    widening = widening_that_keeps_apart(plan, ("R1", "R2"), 15)
    assert widening == Widening(8, 1.5, pytest.approx(0.8), pytest.approx(1.2))
    assert widening_that_keeps_apart(plan, ("R1", "R2"), 8) is None  # nothing before line 8
    wider = text.replace("row R1,R2 0 0.8", "row R1,R2 0 1.2")
    _, plan, _ = compile_scenario(wider, "7_4.dance", PlanParameters(timing="feasible"))
    assert plan is not None
    assert plan.apart_by_no_delay == ()
    options = CheckOptions(places=places_followed("path"))  # as check judges the defaults
    diagnostics = check_plan(plan, None, options).diagnostics
    assert not any("come within" in d.message for d in diagnostics)


def test_a_turn_tighter_than_the_formation_is_noted_where_the_places_wait(data: Path) -> None:
    """Where the leader turns too tightly for the formation, the path follower's inner places
    wait behind the robots ahead and the formation loses its shape (issue 12): a note at each
    instruction where a wait grows (line 11's corner, line 13's turn round), with a circle that
    keeps the shape; none for the rigid slots, which do not wait."""
    text = (data / "scenarios" / "valid" / "u_turn_square.dance").read_text()
    _, plan, _ = compile_scenario(text, "show.dance", PlanParameters(timing="feasible"))
    assert plan is not None
    notes = [d for d in check_plan(plan, None, CheckOptions(places="path")).diagnostics
             if "too tightly" in d.message]
    lead = ("the leader turns here too tightly for the formation's width and depth: places on "
            "its path wait behind the robots ahead and the formation loses its shape (along "
            "the leader's path: ")
    assert [(d.line, d.severity, d.message) for d in notes] == [
        (11, Severity.NOTE, lead + "R3 up to 3.3 m for 4 s)"),
        (13, Severity.NOTE, lead + "R3 up to 5.5 m for 30 s, R4 up to 3.9 m for 10 s)")]
    assert notes[0].hint == ("turn on a circle of radius 2.3 m or more to keep the shape (on a "
                             "circle of radius r the inner places wait about 2 m x 0.75 m / "
                             "(r - 0.75 m))")
    rigid = check_plan(plan, None, CheckOptions(places="rigid")).diagnostics
    assert not [d for d in rigid if "too tightly" in d.message]
    # the circle the hint gives: no wait long enough to note
    rounded = text.replace("move 2 90 by beat 89", "circle 2.3 90 0.1 by beat 89").replace(
        "move 2 180 at beat 97", "circle 2.3 180 0.1 at beat 97")
    _, plan, _ = compile_scenario(rounded, "show.dance", PlanParameters(timing="feasible"))
    assert plan is not None
    assert not [d for d in check_plan(plan, None, CheckOptions(places="path")).diagnostics
                if "too tightly" in d.message]


def test_a_column_turned_round_is_told_to_turn_on_a_circle() -> None:
    """A column (every lateral offset 0) folds onto itself where its leader turns round within
    its length: the note says so instead of a circle of radius 0 m (which the width alone
    gave)."""
    text = "robots A B C\ncolumn A;B;C 1.5 0\nmove 4 0\nmove 4 180\n"
    _, plan, _ = compile_scenario(text, "show.dance", PlanParameters(timing="feasible"))
    assert plan is not None
    notes = [d for d in check_plan(plan, None, CheckOptions(places="path")).diagnostics
             if "too tightly" in d.message]
    assert [d.line for d in notes] == [4]
    assert notes[0].hint is not None
    assert notes[0].hint == ("a column folds onto itself where its leader turns round within "
                             "the column's length: turn on a circle instead of on the spot")

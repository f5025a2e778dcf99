"""Places on the leader's path (plan/places.py): distance kept in a file, rows abeam, and a
smooth way to the rigid slot after the leader's end."""

from __future__ import annotations

import math
import os

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from dancebots.plan import PlanParameters
from dancebots.plan.places import FILE_MARGIN, catch_up_speed, path_places, places_end
from tests_support import plan_of

HUSKY = (0.99, 0.67)
SQUARE_CORNER = ("robots R1 R2 R3 R4\nsquare R1,R2;R3,R4 1.6 1;1\nmove 2 0\nmove 4 -90\n"
                 "move 2 0\n")


def _places(text: str, params: PlanParameters, step: float = 0.05,
            ) -> tuple[np.ndarray, dict[str, tuple[np.ndarray, ...]]]:
    plan = plan_of(text, params)
    times = np.arange(0.0, places_end(plan) + 1.0, step)
    return times, {robot: path_places(plan, robot, times) for robot in plan.robots}


def test_the_rear_robot_of_the_inner_file_keeps_its_distance_round_a_sharp_corner() -> None:
    """The open-day square's 90 deg corner: on the leader's timing the rear robot of the
    inner file came 1 m nearer to the front one (2 |oy| tan 45 deg); now every place keeps at
    least min(1.6 m, the diagonal + margin) from the place of the robot ahead of it."""
    for timing in ("thesis", "feasible"):
        _, places = _places(SQUARE_CORNER, PlanParameters(timing=timing, footprint=HUSKY))
        keep = min(1.6, math.hypot(*HUSKY) + FILE_MARGIN)
        for front, rear in (("R1", "R3"), ("R2", "R4")):
            gap = np.hypot(*(places[front][0] - places[rear][0]).T)
            assert gap.min() >= keep - 0.002, (timing, front, rear, gap.min())  # interpolated
        inner = np.hypot(*(places["R2"][0] - places["R4"][0]).T)
        assert inner.min() < 1.6 - 0.05  # the corner did bring them nearer than the rows


def test_robots_side_by_side_keep_the_leaders_timing() -> None:
    """A row is not a file: thesis 7.1's two robots are placed abeam the same point of the
    leader's path at every instant (its inner robot backs up round the corners' loops), so
    they stay exactly 1.2 m apart, in the corners too."""
    text = "robots R1 R2\nrow R1,R2 0 1.2\nmove 2 0\nmove 2 -90\nmove 4 90\n"
    _, places = _places(text, PlanParameters(timing="feasible"))
    distance = np.hypot(*(places["R1"][0] - places["R2"][0]).T)
    assert np.abs(distance - 1.2).max() < 1e-3  # chords between the leader's 0.05 s samples
    assert (places["R2"][2] != places["R2"][1]).any()  # R2 backs up somewhere


def test_places_go_smoothly_to_the_rigid_slots_after_a_show_that_ends_on_an_arc() -> None:
    """After a circle the places behind the leader are on the arc, not on the rigid slots;
    they drive there at ``catch_up_speed`` at most (no jump), and stand on the slots by
    ``places_end``."""
    text = "robots R1 R2 R3 R4\nsquare R1,R2;R3,R4 1.6 1.4;1.4\ncircle -3 120 0.1\n"
    params = PlanParameters(timing="feasible", footprint=HUSKY)
    plan = plan_of(text, params)
    step = 0.05
    times = np.arange(0.0, places_end(plan) + 1.0, step)
    for robot in plan.robots:
        points, heading, _, speed = path_places(plan, robot, times)
        moves = np.hypot(*np.diff(points, axis=0).T)
        assert moves.max() <= catch_up_speed(plan) * step * 1.05 + 1e-9, robot
        slot = plan.desired_poses(robot, times[-1:])[0]
        assert np.hypot(*(points[-1] - slot[:2])) < 1e-6, robot
        assert speed[-1] == 0.0
        assert abs(math.remainder(heading[-1] - slot[2], 2 * math.pi)) < 1e-9
    rear = path_places(plan, "R4", np.array([plan.duration]))[0][0]
    slot = plan.desired_poses("R4", np.array([plan.duration]))[0]
    assert np.hypot(*(rear - slot[:2])) > 0.2  # the arc did leave it off its rigid slot


SHAPES = ["row A,B,C 0 {s}", "column A;B;C {s} 0", "triangle A;B,C {s} {s}"]


@settings(max_examples=int(os.environ.get('PLACES_EXAMPLES', '40')), deadline=None)
@given(st.sampled_from(SHAPES), st.floats(0.3, 3.0),
       st.lists(st.tuples(st.floats(0.0, 4.0), st.floats(-180.0, 180.0)), max_size=4),
       st.none() | st.sampled_from(SHAPES), st.sampled_from(["thesis", "feasible"]))
@example("column A;B;C {s} 0", 0.375, [(0.25, -84.0), (1.0, -116.0)], None, "thesis")
def test_places_are_finite_and_end_on_the_rigid_slots(
        shape: str, spacing: float, moves: list[tuple[float, float]], then: str | None,
        timing: str) -> None:
    """Any formation of three on any moves (none too), maybe ending in a formation change:
    the places, their headings and speeds are finite, speeds are >= 0, a place keeps its
    distance from the robots ahead of it until the leader's end, and every place stands on
    its rigid slot at ``places_end``."""
    text = ("robots A B C\n" + shape.format(s=f"{spacing:.3f}") + "\n"
            + "".join(f"move {d:.3f} {a:.1f}\n" for d, a in moves)
            + ("" if then is None else then.format(s=f"{spacing:.3f}") + "\n"))
    plan = plan_of(text, PlanParameters(timing=timing, footprint=HUSKY))  # type: ignore[arg-type]
    end = places_end(plan)
    assert end >= plan.duration
    times = np.concatenate([np.arange(0.0, end, 0.25), [end, end + 1.0]])
    placed = {}
    for robot in plan.robots:
        points, heading, motion, speed = path_places(plan, robot, times)
        for array in (points, heading, motion, speed):
            assert np.isfinite(array).all()
        assert (speed >= 0.0).all()
        slot = plan.desired_poses(robot, times[-1:])[0]
        assert np.hypot(*(points[-1] - slot[:2])) < 1e-6
        placed[robot] = points
    # until the leader's end a place keeps min(rigid distance, diagonal + FILE_MARGIN) from
    # the place of every robot ahead of it (to 2 cm: interpolated between the leader's
    # samples); robots side by side are not held apart from each other, and on the way to
    # the slots after the end the places do not look at each other (a column that ends
    # with a U-turn crosses itself: check's simulation pass reports that)
    during = times <= plan.duration
    offsets = plan.formations[0].offsets
    reach = math.hypot(*HUSKY) + FILE_MARGIN
    for a, b in (("A", "B"), ("A", "C"), ("B", "C")):
        (ax, ay), (bx, by) = offsets[a], offsets[b]
        first = during & (plan.formation_indices(a, times) == 0) & (
            plan.formation_indices(b, times) == 0)
        if abs(ax - bx) < 1e-9 or not first.any():
            continue
        keep = min(math.hypot(ax - bx, ay - by), reach)
        assert np.hypot(*(placed[a] - placed[b]).T)[first].min() > keep - 0.02, (a, b)


def _held_back_loops(abeam: np.ndarray, room: np.ndarray) -> np.ndarray:
    """The two passes of ``places._held_back`` as plain loops over every sample."""
    values, rooms = abeam.tolist(), room.tolist()
    for k in range(len(values) - 2, -1, -1):
        values[k] = min(values[k], values[k + 1] + rooms[k])
    for k in range(1, len(values)):
        values[k] = min(values[k], values[k - 1] + rooms[k - 1])
    return np.array(values, dtype=float)


@settings(max_examples=300, deadline=None)
@given(steps=st.lists(st.floats(-2.0, 3.0) | st.sampled_from([math.nan, 1e300, -1e-300]),
                      min_size=1, max_size=60),
       rooms=st.lists(st.floats(0.0, 0.5) | st.sampled_from([math.inf, 0.0, 1e-300]),
                      min_size=60, max_size=60))
def test_holding_back_only_where_the_bound_binds_is_the_loops(steps: list[float],
                                                              rooms: list[float]) -> None:
    """``_held_back`` runs its passes only from where the rate bound binds: the same
    numbers as the loops over every sample, bit for bit, waits (drops) and NaNs among
    them."""
    from dancebots.plan.places import _held_back

    abeam = np.cumsum(np.array(steps))
    room = np.array(rooms[: len(steps) - 1], dtype=float)
    assert _held_back(abeam, room).tobytes() == _held_back_loops(abeam, room).tobytes()


@settings(max_examples=200, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), samples=st.integers(1, 30), queries=st.integers(0, 20))
def test_the_points_and_stretch_alone_are_those_of_the_whole_look_up(
        seed: int, samples: int, queries: int) -> None:
    """``OffsetPath.points_at`` and ``stretch_at`` (what the file table and the rate bound
    ask for) are ``at``'s points and stretch, bit for bit: before the path, on steps that do
    not move, after it, at lengths that are not numbers."""
    from dancebots.plan.places import OffsetPath

    rng = np.random.default_rng(seed)
    driven = np.cumsum(np.where(rng.random(samples) < 0.2, 0.0, rng.uniform(0, 1, samples)))
    path = OffsetPath(driven - driven[0], rng.normal(size=(samples, 2)),
                      np.cumsum(rng.normal(size=samples)), rng.normal(size=samples))
    lengths = rng.uniform(-2.0, float(path.driven[-1]) + 2.0, queries)
    if queries:
        lengths[0] = math.nan
    points, heading, stretch = path.at(lengths)
    assert path.points_at(lengths).tobytes() == points.tobytes()
    assert path.stretch_at(lengths).tobytes() == stretch.tobytes()
    # ``at`` as it was before it kept the steps' differences
    before = _at_before(path, lengths)
    for new, old in zip((points, heading, stretch), before, strict=True):
        assert new.tobytes() == old.tobytes()


def _at_before(path: object, driven: np.ndarray) -> tuple[np.ndarray, ...]:
    """``OffsetPath.at`` as written before 2026-11-27 (the differences taken per call)."""
    p_driven, p_points = path.driven, path.points  # type: ignore[attr-defined]
    p_heading, p_stretch = path.heading, path.stretch  # type: ignore[attr-defined]
    count = len(driven)
    if len(p_driven) < 2:
        points = np.broadcast_to(p_points[0], (count, 2)).copy()
        heading = np.full(count, p_heading[0])
        stretch = np.ones(count)
    else:
        j = np.clip(np.searchsorted(p_driven, driven, side="right") - 1, 0, len(p_driven) - 2)
        step = p_driven[j + 1] - p_driven[j]
        fraction = np.clip(np.where(step > 0.0, (driven - p_driven[j])
                                    / np.where(step > 0.0, step, 1.0), 0.0), 0.0, 1.0)
        points = p_points[j] + fraction[:, None] * (p_points[j + 1] - p_points[j])
        heading = p_heading[j] + fraction * (p_heading[j + 1] - p_heading[j])
        stretch = p_stretch[j].copy()
    behind = driven < 0.0
    if behind.any():
        first = p_heading[0]
        points[behind] = p_points[0] + driven[behind][:, None] * np.array(
            [np.cos(first), np.sin(first)])
        heading[behind] = first
        stretch[behind] = 1.0
    return points, heading, stretch

"""The shows' animations: robots with a heading mark and their name, the legend outside the
room, the clock above it, the title without directories, leader paths broken at newVL."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
from numpy.typing import NDArray

from dancebots.plan.placement import place_show
from dancebots.report.animation import render_frames
from dancebots.report.frames import Clock, RobotMarks, frame_ticks
from dancebots.report.queue_animation import render_queue_frames
from dancebots.report.run_plots import broken_at_changes, plot_trajectories
from dancebots.shows.formation import RunResult, SimConfig, simulate
from dancebots.shows.queue import QueueConfig, QueueResult, simulate_queue
from dancebots.sim import prepare_show
from dancebots.world import parse_world
from tests_support import plan_of

# two robots side by side split into one column each with its own virtual leader (newVL):
# at the split each leader jumps 0.6 m, from the middle of the row to its robot's column
SPLIT = ("robots R1 R2\ngroups\nleft R1\nright R2\n\nstart\nrow R1,R2 0 1.2\nmove 1.5 0\n"
         "column R1 0 0\ncolumn R2 0 0\nnewVL\nmove 1.5 0 left\nmove 1.5 0 right\n")
DARK, LIGHT = 3 * 80, 3 * 200
"""Sums of a pixel's RGB: ink (the marks are black) and the white room."""


@pytest.fixture(scope="module")
def split() -> RunResult:
    """The split show, its scenario file deep in a directory."""
    plan = plan_of(SPLIT, path="/some/where/deep/split.dance")
    arena, placement = prepare_show(place_show(plan, None))
    return simulate(plan, arena, placement, SimConfig())


@pytest.fixture(scope="module")
def queue() -> QueueResult:
    world, _ = parse_world(
        "[room]\nsize = 6.0\n[[spectators]]\nname = \"leader\"\nspeed = 0.2\nradius = 0.2\n"
        "path = [[3.0, 3.0], [4.0, 3.0]]\n", "short.toml")
    assert world is not None
    return simulate_queue(world, QueueConfig(robots=2, settle=1.0))


def first_frame(frames: tuple[int, Iterator[NDArray[np.uint8]]],
                ) -> tuple[NDArray[np.uint8], Any]:
    """The first frame of a render and its figure (drawn, so its transforms are final);
    the rest of the frames are dropped, which closes the figure."""
    figure = plt.gcf()  # render_* made it the current figure
    _, iterator = frames
    frame = next(iterator)
    return frame, figure


def pixel(figure: Any, frame: NDArray[np.uint8], x: float, y: float) -> NDArray[np.int64]:
    """The RGB of the frame at room point (x, y) m."""
    column, row = figure.axes[0].transData.transform((x, y))
    colour: NDArray[np.int64] = frame[round(frame.shape[0] - row), round(column)].astype(
        np.int64)
    return colour


def still(result: Any, poses: list[tuple[float, float, float]]) -> Any:
    """The result with every robot standing at poses (R, 3) all the time."""
    return replace(result, poses=np.broadcast_to(np.array(poses)[:, None, :],
                                                 result.poses.shape).copy())


def test_broken_at_changes_puts_a_nan_row_before_each_new_formation() -> None:
    points = np.arange(12.0).reshape(6, 2)
    broken = broken_at_changes(points, np.array([0, 0, 1, 1, 1, 3]))
    assert broken.shape == (8, 2)
    assert np.isnan(broken[[2, 6]]).all()
    np.testing.assert_array_equal(broken[~np.isnan(broken[:, 0])], points)
    np.testing.assert_array_equal(broken_at_changes(points, np.zeros(6, dtype=int)), points)


def test_the_leaders_paths_break_at_the_newvl_jump(split: RunResult) -> None:
    change = int(np.flatnonzero(np.diff(split.formation[0]))[0]) + 1
    jump = np.hypot(*(split.leader[0, change, :2] - split.leader[0, change - 1, :2]))
    assert jump > 0.5  # the leader jumps here: no line may join its two positions
    _, figure = first_frame(render_frames(split))
    paths = [line.get_xydata() for line in figure.axes[0].lines
             if np.isnan(line.get_xydata()).any()]
    plt.close(figure)
    assert len(paths) == len(split.robots)
    for path in paths:
        assert np.flatnonzero(np.isnan(path[:, 0])).tolist() == [change]
    figure = plot_trajectories(split)
    leaders = [line.get_xydata() for line in figure.axes[0].lines
               if line.get_color() == "black"]
    plt.close(figure)
    assert len(leaders) == len(split.robots)
    assert all(np.isnan(path[change, 0]) for path in leaders)


def test_frame_count_title_clock_and_legend(split: RunResult) -> None:
    count, frames = render_frames(split)
    figure = plt.gcf()
    first = next(frames)  # drawn: the layout is final
    axes = figure.axes[0]
    assert axes.get_title(loc="left") == "split.dance (ideal, x5)"  # no directory
    room = axes.get_window_extent()
    legend = axes.get_legend().get_window_extent()
    assert legend.y1 < room.y0  # below the room, not on it
    assert all(legend.y1 < label.get_window_extent().y0  # nor on the tick labels
               for label in axes.get_xticklabels() if label.get_text())
    assert legend.y0 > 0  # in the frame
    assert {text.get_text() for text in axes.get_legend().get_texts()} == {"virtual leader"}
    rendered = [first, *frames]
    assert count == len(rendered) == len(frame_ticks(split.times, 5.0, 10))
    # the clock: above the room, inside the frame, changing from frame to frame
    height = rendered[0].shape[0]
    strip = slice(0, int(height - room.y1))  # the rows above the axes
    assert not np.array_equal(rendered[0][strip], rendered[-1][strip])


def test_a_robot_facing_backwards_shows_its_heading_mark_behind(split: RunResult) -> None:
    """R1 stands at (0, 2) facing +x, then -x: the arrowhead is just beyond the front edge."""
    length = split.placement.types[0].length
    ahead, behind = (length / 2 + 0.1, 2.0), (-length / 2 - 0.1, 2.0)
    marks = []
    for theta in (0.0, np.pi):
        frame, figure = first_frame(render_frames(still(split, [(0.0, 2.0, theta),
                                                                (0.0, -2.0, 0.0)])))
        marks.append((pixel(figure, frame, *ahead).sum(), pixel(figure, frame, *behind).sum()))
        plt.close(figure)
    (facing_ahead, facing_behind) = marks
    assert facing_ahead[0] < DARK  # facing +x: the black arrowhead right of the front edge
    assert facing_ahead[1] > LIGHT
    assert facing_behind[0] > LIGHT  # facing -x: it is on the other side
    assert facing_behind[1] < DARK


def test_the_names_are_drawn_beside_their_robots(split: RunResult) -> None:
    frame, figure = first_frame(render_frames(still(split, [(0.0, 2.0, 0.0),
                                                             (0.0, -2.0, 0.0)])))
    axes = figure.axes[0]
    names = [c for c in axes.collections if c.get_label() == "robot names"]
    assert len(names) == 1
    kind = split.placement.types[0]
    reach = np.hypot(kind.length, kind.width) / 2
    offsets = names[0].get_offsets()
    np.testing.assert_allclose(np.hypot(*(offsets - [[0.0, 2.0], [0.0, -2.0]]).T),
                               [reach, reach])
    # ink up and to the right of each robot's circumscribed circle: its name
    for y in (2.0, -2.0):
        left, bottom = axes.transData.transform((reach / np.sqrt(2), y + reach / np.sqrt(2)))
        box = frame[int(frame.shape[0] - bottom) - 12:int(frame.shape[0] - bottom),
                    int(left):int(left) + 16]
        assert (box.sum(axis=2) < DARK).sum() > 5
    plt.close(figure)


def test_robot_marks_follow_the_poses() -> None:
    figure, axes = plt.subplots()
    axes.set_aspect("equal")
    axes.set_xlim(-5, 5)
    axes.set_ylim(-5, 5)
    marks = RobotMarks(axes, ["A", "B"], np.array([1.0, 0.5]), np.array([0.5, 0.5]),
                       ["tab:blue", "tab:red"])
    artists = marks.move(np.array([[1.0, 1.0, 0.0], [-2.0, 0.0, np.pi / 2]]))
    assert artists == [marks.bodies, marks.headings, marks.arrows, marks.names]
    np.testing.assert_allclose(marks.arrows.get_offsets(), [[1.5, 1.0], [-2.0, 0.25]],
                               atol=1e-12)
    segments = marks.headings.get_segments()
    np.testing.assert_allclose(segments[1], [[-2.0, 0.0], [-2.0, 0.25]], atol=1e-12)
    tips = np.array([path.vertices[np.argmax(np.abs(path.vertices).sum(axis=1))]
                     for path in marks.arrows.get_paths()])  # the vertex farthest out
    np.testing.assert_allclose(tips / np.hypot(*tips.T)[:, None], [[1.0, 0.0], [0.0, 1.0]],
                               atol=1e-12)  # pointing along each heading
    assert marks.labels == ("A", "B")
    plt.close(figure)


def test_the_clock_sits_in_the_title_row() -> None:
    figure, axes = plt.subplots(figsize=(4, 3), dpi=80, layout="constrained")
    axes.set_title("show.dance", loc="left")
    clock = Clock(axes)
    clock.set_text("t = 123.4 s")
    figure.canvas.draw()
    anchors = clock.artist.get_offset_transform().transform(clock.artist.get_offsets())
    room = axes.get_window_extent()
    assert len(anchors) == len("t = 123.4 s")
    assert np.all(anchors[:, 1] > room.y1)  # above the room
    assert np.all(anchors[:, 1] < figure.bbox.y1 - 8)  # a line of text fits above
    assert anchors[0, 0] > figure.bbox.x0
    assert anchors[-1, 0] < room.x1  # right-aligned at the room's right edge
    plt.close(figure)


def test_the_queue_draws_headings_names_and_the_legend_outside(queue: QueueResult) -> None:
    count, _ = render_queue_frames(queue)
    plt.close(plt.gcf())
    assert count == len(frame_ticks(queue.times, 5.0, 10))
    length = queue.config.robot_type.length
    ahead, behind = (2.0 + length / 2 + 0.05, 4.0), (2.0 - length / 2 - 0.05, 4.0)
    marks = []
    for theta in (0.0, np.pi):
        frame, figure = first_frame(render_queue_frames(
            still(queue, [(2.0, 4.0, theta), (2.0, 2.0, 0.0)])))
        marks.append((pixel(figure, frame, *ahead).sum(), pixel(figure, frame, *behind).sum()))
        axes = figure.axes[0]
        names = [c for c in axes.collections if c.get_label() == "robot names"]
        assert len(names) == 1
        assert len(names[0].get_paths()) == 2
        assert figure.legends[0].get_window_extent().y1 < axes.get_window_extent().y0
        assert "targets" in {t.get_text() for t in figure.legends[0].get_texts()}
        plt.close(figure)
    (facing_ahead, facing_behind) = marks
    assert facing_ahead[0] < DARK
    assert facing_ahead[1] > LIGHT
    assert facing_behind[0] > LIGHT
    assert facing_behind[1] < DARK

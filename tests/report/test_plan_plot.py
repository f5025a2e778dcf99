"""plot_plan's timeline strip: a bar per instruction, a line per beat, a marker per cue
coloured by whether it is met."""

from __future__ import annotations

import matplotlib.pyplot as plt  # the Agg backend: tests/conftest.py
from matplotlib.colors import to_rgba

from dancebots.plan.planner import PlanParameters, instruction_timeline
from dancebots.report.plan_plot import MAX_BEAT_LINES, plot_plan, plot_timeline
from tests_support import plan_of

SHOW = ("robots A B\ntempo 120\nstart\nrow A,B 0 1.2\nmove 1 0 by beat 21\nwait 2\n"
        "move 6 0 by 14\n")


def test_the_timeline_has_a_bar_per_instruction_beats_and_cues_met_and_missed() -> None:
    plan = plan_of(SHOW, PlanParameters(timing="feasible"))
    entries = instruction_timeline(plan)
    missed = [e for e in entries if e.cue_missed_by]
    met = [e for e in entries if e.cue is not None and not e.cue_missed_by]
    assert len(missed) == 1  # 6 m in 1.5 s cannot be
    assert len(met) == 1
    figure, ax = plt.subplots()
    try:
        plot_timeline(plan, ax)
        assert len(ax.patches) == len(entries)
        markers = [line for line in ax.lines if line.get_marker() == "v"]
        assert sorted(to_rgba(m.get_color()) for m in markers) == sorted(
            [to_rgba("tab:green"), to_rgba("tab:red")])
        end = max(plan.duration, max(e.end for e in entries))
        beat_lines = sum(len(c.get_segments()) for c in ax.collections)
        assert beat_lines == int(end / 0.5) + 1  # a line per beat at 120 bpm from 0 s
        assert "120 beats per minute (a line per beat" in ax.get_title()
        [met_marker] = [m for m in markers if to_rgba(m.get_color()) == to_rgba("tab:green")]
        assert met_marker.get_xdata()[0] == 10.0  # at its cue (beat 21), not its end
    finally:
        plt.close(figure)


def test_a_long_fast_show_gets_fewer_beat_lines() -> None:
    plan = plan_of("robots A B\ntempo 600\nstart\nrow A,B 0 1.2\nwait 600\n")
    figure, ax = plt.subplots()
    try:
        plot_timeline(plan, ax)
        assert sum(len(c.get_segments()) for c in ax.collections) <= MAX_BEAT_LINES
        assert "a line every 16 beats" in ax.get_title()
    finally:
        plt.close(figure)


def test_the_plan_figure_has_the_map_and_the_timeline() -> None:
    figure = plot_plan(plan_of(SHOW))
    try:
        assert len(figure.axes) == 2
        assert figure.axes[1].get_xlabel() == "show time [s]"
    finally:
        plt.close(figure)

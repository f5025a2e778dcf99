"""``show.html``: a formation run as one self-contained web page that replays it (issue 14).

No server and no network: the run's samples and the player (``replay.html``, plain
JavaScript on a canvas) are inlined in the file, which opens from the output directory in any
browser. The player draws the room and obstacles, every robot's footprint with its heading
and name, where it believes its desired pose (dashed) and its virtual leader (+) are, trails,
and the people; it plays and pauses, at 1-20x, and scrubs on a timeline that marks each
choreography instruction (its line and text) while its formation's leader executes it and
each event (speech, beep, resume, error: click one to jump to it). ``show.html#t=12.5`` opens
at show time 12.5 s.

The samples are float32 arrays (poses to well under a millimetre in a 100 m room; the times
float64, which the page compares with the times it is asked for), base64 in a JSON block:
100 robots for 10 minutes are about 30 MB, and a frame draws only the robots, their trails
and the people of one tick. The page keeps its state in ``document.body``'s data
attributes (``data-time``, ``data-tick``, ``data-instruction``, ``data-playing``,
``data-robots``, ``data-people``, ``data-ready``, and ``data-load-ms`` and ``data-draw-ms``:
ms to unpack the data and to draw the latest frame) and in ``window.dancebotsReplay``
(``seek(t)``, ``state()``): what the tests and ``benchmarks/bench_replay.py`` read from a real
browser (100 robots for 10 minutes: a frame in 6 ms).
"""

from __future__ import annotations

import base64
import json
from collections.abc import Sequence
from importlib import resources
from typing import Any

import numpy as np

from dancebots.plan.planner import instruction_timeline
from dancebots.shows.formation import STATUS, RunResult
from dancebots.shows.queue import QueueResult
from dancebots.sim.setup import Arena

__all__ = ["queue_replay_data", "replay_data", "replay_page", "write_queue_replay_html",
           "write_replay_html"]

PLACEHOLDER = "/*DANCEBOTS_DATA*/null"
"""Where the template takes the run's data (a JSON object literal)."""


def _packed(array: np.ndarray[Any, Any], dtype: str = "<f4") -> str:
    """``array`` as little-endian ``dtype`` bytes in base64 (a JavaScript typed array)."""
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).tobytes()).decode()


def replay_data(result: RunResult, source_lines: Sequence[str] | None = None,
                ) -> dict[str, Any]:
    """What the page draws, as JSON-ready values: times (T,) s; per robot its name, footprint
    (m) and colour; poses, desired poses and leaders (R, T, 3) world frame and status codes
    (R, T) packed; people (C, T, 2) with radii; the room and obstacle polygons; the
    instructions (line, text from ``source_lines`` or the instruction's kind, start and end
    s of each formation change and of each move or circle as its leader ran it, and the
    formation's index: its lane on the timeline) and the events; with the scans recorded
    (``SimConfig.record_lidar``, ``run --show-lidar``) every robot's delivered scans."""
    plan, placement, arena = result.plan, result.placement, result.arena

    def text(line: int, fallback: str) -> str:
        if source_lines is not None and 0 < line <= len(source_lines):
            return source_lines[line - 1].strip()
        return fallback

    instructions = [{"line": entry.line, "start": entry.start, "end": entry.end,
                     "lane": entry.formation, "text": text(entry.line, entry.kind)}
                    for entry in instruction_timeline(plan)]  # a lane per formation
    return {
        **({"scans": _scans(result.lidar, len(result.robots))} if result.lidar else {}),
        **_scene(placement.robots, [(k.length, k.width) for k in placement.types], arena),
        "title": plan.scenario.path,
        "profile": result.config.profile.name,
        "duration": plan.duration,
        "count": len(result.times),
        "times": _packed(result.times, "<f8"),
        "poses": _packed(result.poses),
        "desired": _packed(result.desired),
        "leaders": _packed(result.leader),
        "status": _packed(result.status, "u1"),
        "status_names": list(STATUS),
        "people": _packed(result.spectators),
        "radii": result.spectator_radii.tolist(),
        "instructions": instructions,
        "events": [{"t": e.time, "robot": e.robot, "kind": e.kind, "text": e.text}
                   for e in sorted(result.events, key=lambda e: e.time)],
    }


def _scene(robots: Sequence[str], sizes: Sequence[tuple[float, float]],
           arena: Arena) -> dict[str, Any]:
    """What both pages draw the same way: the robots (name, footprint length and width m,
    colour) and the room and obstacle polygons (world frame, m)."""
    from matplotlib.colors import to_hex

    from dancebots.report.run_plots import robot_colours

    colours = robot_colours(len(robots))
    return {"robots": [{"name": name, "length": length, "width": width,
                        "colour": to_hex(colours[i])}
                       for i, (name, (length, width)) in enumerate(zip(robots, sizes,
                                                                         strict=True))],
            "room": np.asarray(arena.room).tolist(),
            "obstacles": [np.asarray(o.polygon).tolist() for o in arena.obstacles]}


def _scans(lidar: Sequence[tuple[float, Sequence[np.ndarray[Any, Any]]]],
           robots: int) -> dict[str, str]:
    """The recorded scans (``RunResult.lidar``: per scan the time it reached the robots and
    per robot its hits (M, 2), world frame) packed: times (S,), offsets (S * R + 1,) int32
    into points (N, 2): scan s's hits of robot r are points[offsets[s R + r]:offsets[s R +
    r + 1]]."""
    parts = [np.asarray(hits, dtype=np.float64).reshape(-1, 2)
             for _, per_robot in lidar for hits in per_robot]
    assert len(parts) == len(lidar) * robots
    offsets = np.concatenate([[0], np.cumsum([len(p) for p in parts])])
    return {"times": _packed(np.array([t for t, _ in lidar])),
            "offsets": _packed(offsets, "<i4"),
            "points": _packed(np.concatenate(parts) if parts else np.zeros((0, 2)))}


def queue_replay_data(result: QueueResult) -> dict[str, Any]:
    """What the page draws of a leader-follower queue (``dancebots follow``): the followers
    (poses, footprints of their type, colours), the detector's target of each (R, T, 2)
    where it has one (NaN where not: not drawn), the leader's path (T, 2), the people, the
    room; no instructions; as events, each time a follower loses its target or has it
    kidnapped (``QueueResult.kidnapped``) and when it has it back."""
    kind = result.config.robot_type
    count, robots = len(result.times), len(result.robots)
    lost = np.logical_not(np.isfinite(result.targets).all(axis=2))  # (R, T)
    kidnapped = result.kidnapped
    events: list[dict[str, Any]] = []
    for i, robot in enumerate(result.robots):
        for flags, kind_name, text in ((lost[i], "lost", "no target"),
                                       (kidnapped[i], "kidnapped", "follows something else")):
            changes = np.flatnonzero(np.diff(flags.astype(np.int8)))
            starts = [k + 1 for k in changes if flags[k + 1]] + ([0] if flags[0] else [])
            ends = [k + 1 for k in changes if not flags[k + 1]]
            events += [{"t": float(result.times[k]), "robot": robot, "kind": kind_name,
                        "text": text} for k in starts]
            events += [{"t": float(result.times[k]), "robot": robot, "kind": "resume",
                        "text": f"{kind_name} no more"} for k in ends]
    events.sort(key=lambda e: (e["t"], e["robot"]))
    status = np.where(lost | kidnapped, STATUS.index("stopped"), STATUS.index("ok"))
    return {
        **_scene(result.robots, [(kind.length, kind.width)] * robots, result.arena),
        "title": "leader-follower queue", "profile": result.config.profile.name,
        "duration": float(result.times[-1]), "count": count,
        "times": _packed(result.times, "<f8"), "poses": _packed(result.poses),
        "status": _packed(status, "u1"),
        "status_names": list(STATUS), "targets": _packed(result.targets),
        "head": _packed(result.leader), "people": _packed(result.spectators),
        "radii": result.spectator_radii.tolist(), "instructions": [], "events": events,
    }


def write_queue_replay_html(result: QueueResult, path: str) -> None:
    """Write the queue's replay page to ``path`` (:func:`queue_replay_data`)."""
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(replay_page(queue_replay_data(result)))


def write_replay_html(result: RunResult, path: str,
                      source_lines: Sequence[str] | None = None) -> None:
    """Write the run's replay page to ``path`` (module docstring)."""
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(replay_page(replay_data(result, source_lines)))


def replay_page(data: dict[str, Any]) -> str:
    """The page (``replay.html``) with ``data`` (:func:`replay_data`'s form) in it."""
    template = resources.files("dancebots.report").joinpath("replay.html").read_text(
        encoding="utf-8")
    assert template.count(PLACEHOLDER) == 1, "the replay template lost its data slot"
    # no "<" inside the script block (JSON's \u003c instead): "</script>" or "<!--" in a
    # text (a comment on an instruction's line) would otherwise end it or hide the player
    text = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("<", "\\u003c")
    return template.replace(PLACEHOLDER, text)

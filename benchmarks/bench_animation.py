"""Time to write a show's animations (GIF and MP4), as ``dancebots run`` and ``dancebots
follow`` do, against the way they were written before (issue 14: a quarter of that time).

For the bundled open-day run (ideal profile) and the bundled ``follow`` course: the median of
N repetitions of

* before: each file rendered on its own, the GIF's frames each quantised to their own
  64-colour palette (Pillow's median cut), as ``frames.write_frames`` did until this
  benchmark was written (reproduced here as the baseline);
* now: every frame rendered once and written to both files, the GIF on one palette
  (``frames.write_animation``);

and the ratio. Without ffmpeg only the GIFs are timed. Run:
``.venv/bin/python benchmarks/bench_animation.py [--repeat N]``.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

from PIL import Image

from dancebots.report.frames import GIF_COLOURS, ffmpeg_available, write_frames


def before(render: Callable[[], tuple[int, Iterator[Any]]], directory: Path, fps: int = 10,
           ) -> None:
    """The baseline: the GIF rendered and quantised frame by frame, the MP4 rendered again."""
    _, frames = render()
    images = [Image.fromarray(frame).quantize(colors=GIF_COLOURS) for frame in frames]
    images[0].save(directory / "before.gif", save_all=True, append_images=images[1:],
                   duration=1000 // fps, loop=0, optimize=False)
    if ffmpeg_available():
        count, frames = render()
        write_frames(frames, str(directory / "before.mp4"), fps=fps, count=count)


def median_time(action: Callable[[], object], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        started = time.perf_counter()
        action()
        times.append(time.perf_counter() - started)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    from dancebots.check import CheckOptions
    from dancebots.cli.common import bundled
    from dancebots.loading import load_show
    from dancebots.plan.placement import places_followed
    from dancebots.report.animation import animate_run, render_frames
    from dancebots.report.queue_animation import animate_queue, render_queue_frames
    from dancebots.robot import BrainOptions
    from dancebots.shows.formation import SimConfig, simulate
    from dancebots.shows.queue import QueueConfig, simulate_queue
    from dancebots.sim.setup import prepare_show
    from dancebots.world import load_world

    show = load_show(bundled("open_day.dance"), bundled("open_day.toml"), None,
                     check=CheckOptions(places=places_followed("path")), timing="feasible")
    assert show.report is not None
    assert show.report.placement is not None
    arena, placement = prepare_show(show.report.placement)
    run = simulate(show.report.placement.plan, arena, placement,
                   SimConfig(brain=BrainOptions(follower="path")))
    queue = simulate_queue(load_world(bundled("follow_course.toml")), QueueConfig())
    kinds = ["gif"] + (["mp4"] if ffmpeg_available() else [])
    print(f"GIF and MP4 ({' and '.join(kinds)}), median of {args.repeat}:")
    with tempfile.TemporaryDirectory() as name:
        directory = Path(name)
        for label, render, animate in (
                ("open-day run", lambda: render_frames(run),
                 lambda paths: animate_run(run, paths)),
                ("follow course", lambda: render_queue_frames(queue),
                 lambda paths: animate_queue(queue, paths))):
            count, frames = render()
            sum(1 for _ in frames)
            then = median_time(lambda render=render: before(render, directory), args.repeat)
            now = median_time(lambda animate=animate: animate(
                [str(directory / f"now.{kind}") for kind in kinds]), args.repeat)
            print(f"  {label:<14} {count:4d} frames: before {then:6.2f} s, now {now:6.2f} s, "
                  f"{now / then:.2f} of before")


if __name__ == "__main__":
    main()

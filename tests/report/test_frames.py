"""The reports' frame engine: frame times, blitted RGB frames, GIF and MP4 files."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
from PIL import Image

from dancebots.report.frames import (
    blit_frames,
    ffmpeg_available,
    frame_ticks,
    write_animation,
    write_frames,
)

TIMES = np.arange(201) * 0.05  # 10 s sampled at 20 Hz


def moving_dot(size: tuple[float, float] = (3.0, 2.0), dpi: int = 50,
               ) -> tuple[Any, Any, Any]:
    """A figure with a static line (the background) and a dot that moves with the key."""
    figure, axes = plt.subplots(figsize=size, dpi=dpi)
    axes.plot([0, 10], [0, 1], color="0.5")
    axes.set_xlim(0, 10)
    axes.set_ylim(0, 1)
    dot = axes.plot([], [], "o", color="tab:red", markersize=8)[0]

    def update(k: int) -> list[Any]:
        dot.set_data([TIMES[k]], [0.5])
        return [dot]

    return figure, dot, update


@pytest.mark.parametrize(("speedup", "fps"), [(5.0, 10), (1.0, 10), (2.0, 25), (10.0, 5)])
def test_one_frame_per_speedup_over_fps_show_seconds(speedup: float, fps: int) -> None:
    ticks = frame_ticks(TIMES, speedup, fps)
    assert len(ticks) == int(10.0 * fps / speedup) + 1
    assert ticks[0] == 0
    np.testing.assert_allclose(TIMES[ticks], np.arange(len(ticks)) * speedup / fps,
                               atol=0.05)


def test_a_speedup_between_samples_takes_the_next_sample() -> None:
    ticks = frame_ticks(TIMES, 2.5, 10)  # a frame every 0.25 s, samples every 0.05 s
    assert len(ticks) == 41
    assert np.all(TIMES[ticks] >= np.arange(41) * 0.25 - 1e-9)
    assert np.all(TIMES[ticks] < np.arange(41) * 0.25 + 0.05)


def test_frames_are_rgb_of_the_figure_size_and_the_figure_is_closed() -> None:
    figure, _, update = moving_dot()
    frames = list(blit_frames(figure, update, [0, 100, 200]))
    assert len(frames) == 3
    for frame in frames:
        assert frame.dtype == np.uint8
        assert frame.shape == (100, 150, 3)  # 2 x 3 in at 50 dpi
    assert not np.array_equal(frames[0], frames[1])
    assert not plt.fignum_exists(figure.number)


def test_a_blitted_frame_is_the_full_drawing_of_that_state() -> None:
    """The moving artist is not in the background: each frame shows it once, where the
    update put it, as a full redraw of the figure in that state would."""
    figure, _, update = moving_dot()
    blitted = list(blit_frames(figure, update, [0, 120]))[1]
    reference_figure, _, reference_update = moving_dot()
    reference_update(120)
    reference_figure.canvas.draw()
    reference = np.asarray(reference_figure.canvas.buffer_rgba())[..., :3]
    plt.close(reference_figure)
    np.testing.assert_array_equal(blitted, reference)


def test_gif_is_written_with_every_frame_and_the_progress(tmp_path: Path) -> None:
    figure, _, update = moving_dot()
    keys = frame_ticks(TIMES, 5.0, 10).tolist()
    seen: list[tuple[int, int]] = []
    path = tmp_path / "dot.gif"
    written = write_frames(blit_frames(figure, update, keys), str(path), fps=10,
                           count=len(keys), progress=lambda done, total: seen.append(
                               (done, total)))
    assert written == len(keys) == 21
    assert seen == [(k, 21) for k in range(1, 22)]
    with Image.open(path) as image:
        assert image.n_frames == 21
        assert image.size == (150, 100)
        assert image.info["duration"] == 100


def test_mp4_through_ffmpeg(tmp_path: Path) -> None:
    if not ffmpeg_available():
        pytest.skip("ffmpeg is not installed (scripts/dev.sh installs it)")
    figure, _, update = moving_dot(size=(3.02, 2.0))  # 151 x 100 px: padded to even
    path = tmp_path / "dot.mp4"
    assert write_frames(blit_frames(figure, update, [0, 50, 100, 150]), str(path), fps=10,
                        count=4) == 4
    assert path.read_bytes()[4:8] == b"ftyp"


def test_no_frames_is_an_error(tmp_path: Path) -> None:
    figure, _, update = moving_dot()
    with pytest.raises(ValueError, match="no frames"):
        write_frames(blit_frames(figure, update, []), str(tmp_path / "none.gif"), fps=10,
                     count=0)
    assert not plt.fignum_exists(figure.number)


def test_one_rendering_goes_to_the_gif_and_the_mp4(tmp_path: Path) -> None:
    """Every frame is drawn once however many files it goes to; the GIF has every frame with
    one palette, and a colour that only a later frame shows (a person, here a purple square
    from frame 3 on) keeps its colour: the palette holds the accent colours too."""
    figure, _, update = moving_dot()
    square = figure.axes[0].plot([], [], "s", color="purple", markersize=12)[0]
    drawn: list[int] = []

    def counted(k: int) -> list[Any]:
        drawn.append(k)
        square.set_data(([8.0], [0.8]) if k >= 30 else ([], []))
        return [*update(k), square]

    keys = [0, 10, 20, 30, 40]
    paths = [str(tmp_path / "dot.gif")] + (
        [str(tmp_path / "dot.mp4")] if ffmpeg_available() else [])
    assert write_animation(blit_frames(figure, counted, keys), paths, fps=10, count=5) == 5
    assert drawn == [0, *keys]  # the background once, then each frame once
    with Image.open(paths[0]) as image:
        assert image.n_frames == 5
        image.seek(4)
        rgb = np.asarray(image.convert("RGB"))
    purple = np.all(np.abs(rgb.astype(int) - [128, 0, 128]) <= 12, axis=-1)
    assert np.count_nonzero(purple) > 20  # the square, still purple
    if len(paths) > 1:
        assert Path(paths[1]).read_bytes()[4:8] == b"ftyp"


def test_no_file_to_write_is_an_error() -> None:
    figure, _, update = moving_dot()
    with pytest.raises(ValueError, match="no file"):
        write_animation(blit_frames(figure, update, [0]), [], fps=10, count=1)
    plt.close(figure)

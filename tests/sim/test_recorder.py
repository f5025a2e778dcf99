"""The show loops' recorder: named samples, copied when recorded, stacked over time."""

from __future__ import annotations

import numpy as np
import pytest

from dancebots.sim.recorder import Recorder


def test_samples_are_copied_and_stacked_along_time() -> None:
    recorder = Recorder()
    poses = np.zeros((2, 3))
    leader = np.zeros(2)
    for t in (0.0, 0.1, 0.2):
        poses[:, 0] = t  # the loop reuses its arrays: the recorder must copy
        leader[:] = (t, -t)
        recorder.add(t, poses=poses, leader=leader)
    assert recorder.times.tolist() == [0.0, 0.1, 0.2]
    stacked = recorder.series("poses")
    assert stacked.shape == (2, 3, 3)  # (R, T, 3)
    assert stacked[:, :, 0].tolist() == [[0.0, 0.1, 0.2]] * 2
    assert recorder.series("leader", axis=0).tolist() == [[0.0, 0.0], [0.1, -0.1],
                                                          [0.2, -0.2]]


def test_every_tick_records_the_same_names() -> None:
    recorder = Recorder()
    recorder.add(0.0, poses=np.zeros(3))
    with pytest.raises(ValueError, match="recorded"):
        recorder.add(0.1, poses=np.zeros(3), commands=np.zeros(2))

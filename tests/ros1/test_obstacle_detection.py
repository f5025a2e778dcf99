"""The obstacle_detection node against a real roscore: one cloud in, the thesis's outputs
out (stop flags at 55 cm, the cropped, height-filtered and flattened /obstacles)."""

from __future__ import annotations

import json
import subprocess
import sys
import xmlrpc.client
from pathlib import Path

import numpy as np
import pytest
from tests.ros1.conftest import Master, stop

from dancebots.ros1.launching import PACKAGE_DIR

pytestmark = pytest.mark.ros
PROBE = Path(__file__).with_name("probe_obstacle_detection.py")
NODES = PACKAGE_DIR / "dancebots_ros" / "nodes"


def detect(master: Master, tmp_path: Path, points: list[list[float]]) -> dict[str, object]:
    parameters = xmlrpc.client.ServerProxy(master.uri)
    parameters.setParam("/test", "/T/length", 1.0)
    parameters.setParam("/test", "/T/width", 0.5)
    with open(tmp_path / "node.log", "wb") as log:
        node = subprocess.Popen(
            [sys.executable, str(NODES / "obstacle_detection"), "__ns:=/T", "_robot_name:=T"],
            env=master.env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    try:
        probe = subprocess.run([sys.executable, str(PROBE), json.dumps(points)],
                               env=master.env, capture_output=True, text=True, timeout=60,
                               cwd=Path(__file__).parents[2], check=True)
    finally:
        stop(node)
    result: dict[str, object] = json.loads(probe.stdout.strip().splitlines()[-1])
    return result


def test_obstacle_in_front_stops_and_is_flattened(roscore: Master, tmp_path: Path) -> None:
    answers = detect(roscore, tmp_path, [
        [0.9, 0.0, 0.5],    # 0.4 m before the front edge (0.5 m from the centre): stop
        [0.9, 0.0, 1.7],    # above 1.5 m: ignored
        [-1.5, 0.3, 0.05],  # below 0.1 m: ignored
        [3.0, 0.0, 0.5],    # outside the 4 x 4 m crop: ignored
        [-1.4, 1.0, 0.5]])  # kept, but beside the rear corridor
    assert answers["front"] is True
    assert answers["rear"] is False
    obstacles = answers["obstacles"]
    assert isinstance(obstacles, dict)
    np.testing.assert_allclose(sorted(obstacles["points"]), [[-1.4, 1.0, 0.0], [0.9, 0.0, 0.0]],
                               atol=1e-6)  # float32 on the wire
    assert obstacles["stamp"] == pytest.approx(1234.5)  # the scan's stamp is kept
    assert obstacles["frame"] == "T/base_link"


def test_obstacle_behind_stops_backwards_only(roscore: Master, tmp_path: Path) -> None:
    answers = detect(roscore, tmp_path, [[-0.95, 0.1, 0.4]])
    assert answers["front"] is False
    assert answers["rear"] is True

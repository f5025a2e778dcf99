"""The core and the simulator run on a machine without ROS: nothing outside the node modules
imports rospy (checked in a fresh interpreter in which every ROS module fails to import)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).parents[1]

NO_ROS = """
import sys
for name in ("rospy", "roslaunch", "tf2_ros", "genpy", "std_msgs", "sensor_msgs",
             "geometry_msgs", "rosgraph"):
    sys.modules[name] = None  # any import of them raises ImportError
from dancebots.cli import main
import dancebots.ros1, dancebots.ros1.naming, dancebots.sync, dancebots.ros1.launching
import dancebots.cli.ros
assert main(["check", "examples/thesis_7_1.dance"]) == 0
# it runs (0: clean, 1: not clean; 7.1's thesis follower drives a robot backwards)
assert main(["run", "examples/thesis_7_1.dance", "--no-animation", "--out", sys.argv[1]]) in (0, 1)
assert main(["ros", "simulate", "examples/thesis_7_1.dance", "--print-command"]) == 0
print("fine without ROS")
"""


def test_core_cli_and_simulator_need_no_ros(tmp_path: Path) -> None:
    result = subprocess.run([sys.executable, "-c", NO_ROS, str(tmp_path / "out")], cwd=ROOT,
                            capture_output=True, text=True, timeout=300, check=False)
    assert result.returncode == 0, result.stderr[-2000:]
    assert "fine without ROS" in result.stdout
    assert (tmp_path / "out" / "metrics.json").exists()
    # the MCAP log too: its ROS 1 types come from the genpy that mcap-ros1-support carries
    assert (tmp_path / "out" / "run.mcap").read_bytes()[:8] == b"\x89MCAP0\r\n"

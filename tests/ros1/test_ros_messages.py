"""Message conversion, the sound_play request, and the launch files as roslaunch reads them
(Debian's ROS packages, no master needed)."""

from __future__ import annotations

import numpy as np
import pytest
from tests.ros1.conftest import require_ros

from dancebots.perception.obstacles import DetectorParams, obstacle_points_from_columns
from dancebots.ros1.launching import PACKAGE_DIR, simulation_launch
from dancebots.world import BUILTIN_ROBOT_TYPES

LAUNCH = PACKAGE_DIR / "dancebots_ros" / "launch"


@pytest.fixture(autouse=True)
def _ros() -> None:
    require_ros()


def test_clouds_round_trip_through_pointcloud2() -> None:
    from std_msgs.msg import Header

    from dancebots.ros1.convert import cloud_message, cloud_points

    points = np.random.default_rng(1).uniform(-5, 5, (300, 3))
    message = cloud_message(points, Header(frame_id="R1/base_link"))
    assert message.width == 300
    assert message.header.frame_id == "R1/base_link"
    np.testing.assert_allclose(cloud_points(message), points, atol=1e-5)  # float32


def test_clouds_with_other_fields_and_nan_points_are_read() -> None:
    from sensor_msgs.msg import PointCloud2, PointField
    from std_msgs.msg import Header

    from dancebots.ros1.convert import cloud_points

    layout = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("pad", "<f4"),
                       ("intensity", "<f4")])
    data = np.zeros(3, dtype=layout)
    data["x"], data["y"], data["z"] = [1, 2, np.nan], [4, 5, 6], [7, 8, 9]
    fields = [PointField(name, 4 * k, PointField.FLOAT32, 1) for k, name in
              enumerate(["x", "y", "z"])] + [PointField("intensity", 16, PointField.FLOAT32, 1)]
    message = PointCloud2(header=Header(), height=1, width=3, fields=fields,
                          is_bigendian=False, point_step=20, row_step=60,
                          data=data.tobytes(), is_dense=False)
    np.testing.assert_allclose(cloud_points(message), [[1, 4, 7], [2, 5, 8]])


def test_a_cloud_without_xyz_is_refused() -> None:
    from sensor_msgs.msg import PointCloud2, PointField

    from dancebots.ros1.convert import cloud_points

    message = PointCloud2(fields=[PointField("intensity", 0, PointField.FLOAT32, 1)],
                          height=1, width=0, point_step=4)
    with pytest.raises(ValueError, match="no float32 x, y and z fields"):
        cloud_points(message)


def test_obstacle_points_reach_the_brain_unfiltered() -> None:
    from dancebots.ros1.convert import obstacle_cloud

    points = np.array([[0.8, 0.1], [-1.5, 1.9], [0.0, -0.7]])
    cloud = obstacle_cloud(2.5, points)
    assert cloud.stamp == 2.5
    kept = obstacle_points_from_columns(cloud.columns, cloud.height_step, DetectorParams())
    np.testing.assert_array_equal(kept, points)


def test_speech_and_beep_requests_serialise() -> None:
    from io import BytesIO

    from dancebots.ros1.sound import SoundRequest, beep_request, say_request

    request = say_request("Obstacle is too close, I have to stop")
    buffer = BytesIO()
    request.serialize(buffer)
    decoded = SoundRequest().deserialize(buffer.getvalue())
    assert decoded.sound == SoundRequest.SAY == -3
    assert decoded.command == SoundRequest.PLAY_ONCE
    assert decoded.arg == "Obstacle is too close, I have to stop"
    assert beep_request().sound == SoundRequest.BACKINGUP
    assert SoundRequest._type == "sound_play/SoundRequest"


def _load(path: str, argv: list[str]) -> dict[str, object]:
    import roslaunch.config
    import roslaunch.xmlloader

    config = roslaunch.config.ROSLaunchConfig()
    roslaunch.xmlloader.XmlLoader().load(path, config, argv=argv, verbose=False)
    return {name: param.value for name, param in config.params.items()} | {
        "nodes": sorted(f"{n.namespace}{n.name}" for n in config.nodes)}


@pytest.mark.parametrize(("hostname", "kind"), [("ctu-robot", "TRADR"),
                                                ("husky-robot", "HUSKY"), ("vm", "SIM")])
def test_formation_launch_sets_the_size_from_the_host_name(hostname: str, kind: str) -> None:
    loaded = _load(str(LAUNCH / "formation.launch"),
                   ["scenario:=/x.dance", "role:=R1", f"hostname:={hostname}"])
    robot = BUILTIN_ROBOT_TYPES[kind]
    assert loaded["/length"] == robot.length
    assert loaded["/width"] == robot.width
    assert loaded["/formation_member/max_speed"] == robot.max_speed
    assert loaded["nodes"] == ["/formation_member", "/network_test"]
    assert loaded["/formation_member/role"] == "R1"


def test_a_robot_name_puts_its_nodes_and_parameters_under_it() -> None:
    loaded = _load(str(LAUNCH / "formation.launch"),
                   ["scenario:=/x.dance", "role:=R2", "robot_name:=R2", "hostname:=vm"])
    assert loaded["/R2/length"] == 1.2
    assert loaded["nodes"] == ["/R2/formation_member", "/R2/network_test"]
    assert loaded["/R2/network_test/robot_name"] == "R2"


def test_the_generated_simulation_launch_loads(tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    from dancebots.ros1.launching import ros_environment

    for key, value in ros_environment().items():
        monkeypatch.setenv(key, value)
    path = tmp_path / "simulation.launch"
    path.write_text(simulation_launch("/s.dance", ("R1", "R2"), stop_after=50.0,
                                      types=((0.99, 0.67, 1.0), (0.73, 0.6, 0.5))))
    loaded = _load(str(path), [])
    assert loaded["nodes"] == ["/R1/formation_member", "/R1/network_test",
                               "/R2/formation_member", "/R2/network_test", "/sim_bridge"]
    assert loaded["/R1/length"] == 0.99  # the simulated robot's, not this host's
    assert loaded["/R2/formation_member/max_speed"] == 0.5
    assert loaded["/sim_bridge/stop_after"] == 50.0

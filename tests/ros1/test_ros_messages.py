"""Message conversion, the sound_play request, and the launch files as roslaunch reads them
(Debian's ROS packages, no master needed)."""

from __future__ import annotations

import contextlib

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


def _xyz_fields(datatype: int | None = None, offsets: tuple[int, int, int] = (0, 4, 8),
                names: str = "xyz") -> list[object]:
    from sensor_msgs.msg import PointField

    return [PointField(name, offset, PointField.FLOAT32 if datatype is None else datatype, 1)
            for name, offset in zip(names, offsets, strict=True)]


def _malformed_clouds() -> dict[str, object]:
    """PointCloud2 messages whose fields, sizes and data do not fit (issue 10, part 6)."""
    from sensor_msgs.msg import PointCloud2, PointField
    from std_msgs.msg import Header

    good = np.arange(12, dtype="<f4").tobytes()  # one point of 12 bytes

    def cloud(**changes: object) -> object:
        values: dict[str, object] = {"header": Header(), "height": 1, "width": 1,
                                         "fields": _xyz_fields(), "is_bigendian": False,
                                         "point_step": 12, "row_step": 12, "data": good[:12],
                                         "is_dense": True}
        values.update(changes)
        return PointCloud2(**values)

    return {
        "empty data": cloud(data=b""),
        "empty data, 1000 points": cloud(width=1000, row_step=12000, data=b""),
        "data shorter than the points": cloud(width=2, row_step=24),
        "huge width and height": cloud(width=2**32 - 1, height=2**32 - 1),
        "point step 0": cloud(point_step=0),
        "point step shorter than the fields": cloud(point_step=8),
        "field beyond the point": cloud(fields=_xyz_fields(offsets=(0, 4, 100))),
        "negative offset": cloud(fields=_xyz_fields(offsets=(-4, 4, 8))),
        "float64 fields": cloud(fields=_xyz_fields(PointField.FLOAT64)),
        "no fields": cloud(fields=[]),
        "x, y, w fields": cloud(fields=_xyz_fields(names="xyw")),
        "rows shorter than a row of points": cloud(height=2, width=1, row_step=4,
                                                   data=good + good),
        "negative width": cloud(width=-1),
        "data that is no bytes": cloud(data=None),
        "fields that are no fields": cloud(fields=[1, 2, 3]),
        "not a PointCloud2": Header(),
    }


@pytest.mark.parametrize("case", [
    "empty data", "empty data, 1000 points", "data shorter than the points",
    "huge width and height", "point step 0", "point step shorter than the fields",
    "field beyond the point", "negative offset", "float64 fields", "no fields",
    "x, y, w fields", "rows shorter than a row of points", "negative width",
    "data that is no bytes", "fields that are no fields", "not a PointCloud2"])
def test_a_malformed_cloud_is_the_malformed_cloud_error(case: str) -> None:
    from dancebots.ros1.convert import MalformedCloudError, cloud_points

    with pytest.raises(MalformedCloudError):
        cloud_points(_malformed_clouds()[case])


def test_malformed_clouds_from_the_wire_are_the_malformed_cloud_error() -> None:
    """Clouds as rospy hands them over: serialised and deserialised, with sizes that
    disagree with the data; and random bytes deserialised as a PointCloud2."""
    import io

    import genpy
    from sensor_msgs.msg import PointCloud2
    from std_msgs.msg import Header

    from dancebots.ros1.convert import MalformedCloudError, cloud_points

    rng = np.random.default_rng(7)
    read = 0
    for width, height, step, size in [(5, 1, 12, 0), (1, 7, 12, 12), (3, 1, 4, 12),
                                      (100, 100, 12, 1200), (0, 1, 12, 0), (1, 1, 16, 12)]:
        message = PointCloud2(header=Header(), height=height, width=width,
                              fields=_xyz_fields(), point_step=step, row_step=step * width,
                              data=rng.bytes(size))
        buffer = io.BytesIO()
        message.serialize(buffer)
        received = PointCloud2().deserialize(buffer.getvalue())
        try:
            points = cloud_points(received)
        except MalformedCloudError:
            continue
        read += 1
        assert points.shape[1] == 3
        assert np.isfinite(points).all()
    assert read == 1  # only the empty cloud (0 x 1 points) is well formed
    for _ in range(300):  # random bytes: genpy refuses them or the cloud is refused or read
        try:
            received = PointCloud2().deserialize(rng.bytes(int(rng.integers(0, 200))))
        except (genpy.DeserializationError, ValueError, UnicodeDecodeError):
            continue
        with contextlib.suppress(MalformedCloudError):
            cloud_points(received)


def test_padded_rows_and_big_endian_clouds_are_read() -> None:
    from sensor_msgs.msg import PointCloud2
    from std_msgs.msg import Header

    from dancebots.ros1.convert import cloud_points

    rows = np.zeros((2, 5), dtype=">f4")  # 2 rows of 1 point (12 bytes) + 8 bytes padding
    rows[:, :3] = [[1, 2, 3], [4, 5, 6]]
    message = PointCloud2(header=Header(), height=2, width=1, fields=_xyz_fields(),
                          is_bigendian=True, point_step=12, row_step=20, data=rows.tobytes())
    np.testing.assert_allclose(cloud_points(message), [[1, 2, 3], [4, 5, 6]])
    inf = np.array([[np.inf, 0, 0], [1, 1, 1]], dtype="<f4")
    message = PointCloud2(header=Header(), height=1, width=2, fields=_xyz_fields(),
                          point_step=12, row_step=24, data=inf.tobytes())
    np.testing.assert_allclose(cloud_points(message), [[1, 1, 1]])  # infinite points dropped


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
                                      types=((0.99, 0.67, 1.0), (0.73, 0.6, 0.5)),
                                      stop_rule="closing", show_end=19.5))
    loaded = _load(str(path), [])
    assert loaded["nodes"] == ["/R1/formation_member", "/R1/network_test",
                               "/R2/formation_member", "/R2/network_test", "/sim_bridge"]
    assert loaded["/R1/length"] == 0.99  # the simulated robot's, not this host's
    assert loaded["/R2/formation_member/max_speed"] == 0.5
    assert loaded["/R1/formation_member/stop_rule"] == "closing"
    assert loaded["/sim_bridge/stop_after"] == 50.0
    assert loaded["/sim_bridge/show_end"] == 19.5


def test_the_formations_wait_is_logged_once_however_late_the_ticks() -> None:
    """formation_member logs once when the shared show clock has stood for a second (why:
    the mate not heard from), however late its ticks come (a loaded machine), and once when
    it runs again."""
    from dancebots.ros1.formation_member_node import _report_wait
    from dancebots.sync.hold import HoldMessage, clock_receive, clock_tick, new_clock

    class Lines:
        def __init__(self) -> None:
            self.lines: list[str] = []

        def info(self, text: str) -> None:
            self.lines.append(text)

    log = Lines()
    clock = clock_tick(clock_receive(new_clock("R2", ("R1", "R2"), 0.0),
                                     HoldMessage("R1", 0.0, 0.0, False)), 0.1, False)
    waiting = None
    for now in (0.2, 1.35, 2.9, 4.0):  # R1 silent from 0 s: the clock stops (1 s timeout)
        before, clock = clock, clock_tick(clock, now, False)
        waiting = _report_wait(log, "R2", clock, before, waiting, now)  # type: ignore[arg-type]
    assert log.lines == ["R2: the show waits at show time 0.2 s (not heard from R1)"]
    before, clock = clock, clock_tick(clock_receive(clock, HoldMessage("R1", 4.1, 1.0, False)),
                                      4.2, False)
    assert _report_wait(log, "R2", clock, before, waiting, 4.2) is None  # type: ignore[arg-type]
    assert log.lines[1:] == ["R2: the show goes on at show time 0.4 s (it waited 2.9 s)"]

"""A show as an MCAP log with ROS 1 message types: what Foxglove, PlotJuggler and the ROS
tools open (docs/run-outputs.md, docs/leader-follower.md).

One message per robot per control tick on each of its topics, stamped with the time since
the start (s, as nanoseconds from the epoch: the log starts on 1 January 1970; nothing here
reads a clock, so a run's log is the same every time). A formation show
(:func:`write_run_mcap`):

* ``/tf`` (``tf2_msgs/TFMessage``): ``world`` -> ``<robot>/base_link`` for every robot;
* ``/<robot>/pose``, ``/<robot>/desired``, ``/<robot>/virtual_leader``
  (``geometry_msgs/PoseStamped``, frame ``world``): where it is, where it believes its
  desired pose and its virtual leader are;
* ``/<robot>/cmd_vel`` (``geometry_msgs/Twist``): its command; ``/<robot>/velocity``
  (``geometry_msgs/TwistStamped``, frame ``<robot>/base_link``): its actual speeds;
* ``/spectators`` (``geometry_msgs/PoseArray``, frame ``world``): the people, when there are;
* ``/events`` (``std_msgs/String``): "ROBOT KIND: TEXT" at the time of each event (speech,
  beep, resume, error; "ROBOT KIND" for one without text, a beep);
* with the scans recorded (``run --show-lidar``), ``/<robot>/scan``
  (``sensor_msgs/PointCloud2``, frame ``world``, x y z float32): each scan's hits where they
  were when scanned, stamped with the scan's time and logged when it reached the robot (the
  LIDAR's latency later; a scan due after the run's last tick too).

The ROS simulator bridge's record (``dancebots ros simulate --record FILE.mcap``,
:class:`RecordLog`, written as the run goes): ``/tf``, ``/<robot>/pose`` and
``/<robot>/cmd_vel`` (the command the robot obeyed at that step) at every step, stamped with
ROS time, and ``/contacts`` (``std_msgs/String``: "ROBOT touched OTHER") at each contact.

A leader-follower queue (:func:`write_queue_mcap`): ``/tf``, ``/<robot>/pose`` and
``/<robot>/cmd_vel`` as above, ``/<robot>/target`` (``geometry_msgs/PointStamped``, frame
``world``: what its detector follows; no message at a tick without one), ``/leader``
(``geometry_msgs/PointStamped``: the person or robot at the head) and ``/spectators``.

The messages are built from their standard definitions (:data:`DEFINITIONS`, comments left
out: the same MD5 sums as ROS's) by genpy's dynamic types (ROS's own ``genpy`` where it is
installed, else the copy ``mcap-ros1-support`` carries) and written by ``mcap-ros1-support``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from functools import cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

from dancebots.genpy_types import genpy_module, message_classes
from dancebots.shows.formation import RunResult
from dancebots.shows.queue import QueueResult

FloatArray = NDArray[np.float64]

__all__ = ["DEFINITIONS", "RecordLog", "write_queue_mcap", "write_record_mcap", "write_run_mcap"]

_HEADER = "uint32 seq\ntime stamp\nstring frame_id"
_POINT = "float64 x\nfloat64 y\nfloat64 z"
_QUATERNION = "float64 x\nfloat64 y\nfloat64 z\nfloat64 w"
_POSE = "Point position\nQuaternion orientation"
_TWIST = "Vector3 linear\nVector3 angular"
_TRANSFORM = "Vector3 translation\nQuaternion rotation"


def _full(main: str, *parts: tuple[str, str]) -> str:
    """A message definition with the definitions it uses, as ROS concatenates them."""
    rule = "=" * 80
    return main + "".join(f"\n{rule}\nMSG: {name}\n{text}" for name, text in parts)


DEFINITIONS: dict[str, str] = {
    "geometry_msgs/PoseStamped": _full(
        "std_msgs/Header header\ngeometry_msgs/Pose pose", ("std_msgs/Header", _HEADER),
        ("geometry_msgs/Pose", _POSE), ("geometry_msgs/Point", _POINT),
        ("geometry_msgs/Quaternion", _QUATERNION)),
    "geometry_msgs/PoseArray": _full(
        "std_msgs/Header header\ngeometry_msgs/Pose[] poses", ("std_msgs/Header", _HEADER),
        ("geometry_msgs/Pose", _POSE), ("geometry_msgs/Point", _POINT),
        ("geometry_msgs/Quaternion", _QUATERNION)),
    "geometry_msgs/PointStamped": _full(
        "std_msgs/Header header\ngeometry_msgs/Point point", ("std_msgs/Header", _HEADER),
        ("geometry_msgs/Point", _POINT)),
    "geometry_msgs/Twist": _full(_TWIST, ("geometry_msgs/Vector3", _POINT)),
    "geometry_msgs/TwistStamped": _full(
        "std_msgs/Header header\ngeometry_msgs/Twist twist", ("std_msgs/Header", _HEADER),
        ("geometry_msgs/Twist", _TWIST), ("geometry_msgs/Vector3", _POINT)),
    "tf2_msgs/TFMessage": _full(
        "geometry_msgs/TransformStamped[] transforms",
        ("geometry_msgs/TransformStamped",
         "std_msgs/Header header\nstring child_frame_id\nTransform transform"),
        ("std_msgs/Header", _HEADER), ("geometry_msgs/Transform", _TRANSFORM),
        ("geometry_msgs/Vector3", _POINT), ("geometry_msgs/Quaternion", _QUATERNION)),
    "sensor_msgs/PointCloud2": _full(
        "std_msgs/Header header\nuint32 height\nuint32 width\n"
        "sensor_msgs/PointField[] fields\nbool is_bigendian\nuint32 point_step\n"
        "uint32 row_step\nuint8[] data\nbool is_dense", ("std_msgs/Header", _HEADER),
        ("sensor_msgs/PointField",
         "uint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\nuint8 INT32=5\n"
         "uint8 UINT32=6\nuint8 FLOAT32=7\nuint8 FLOAT64=8\nstring name\nuint32 offset\n"
         "uint8 datatype\nuint32 count")),
    "std_msgs/String": "string data",
}
"""The ROS 1 definitions of the message types the log uses (``.msg`` text, as in ROS's
``_full_text`` without the comments)."""


@cache
def _types() -> dict[str, Any]:
    """The message classes of :data:`DEFINITIONS` by type name (and their sub-types)."""
    return message_classes(DEFINITIONS)


class _Log:
    """Message constructors of one log (poses, twists, points in ``world``) and the MCAP
    writer they go to; ``count`` messages written."""

    def __init__(self, writer: Any) -> None:
        self.writer, self.count = writer, 0
        types = _types()
        self.types = types
        self.time = genpy_module().Time
        self._header, self._point = types["std_msgs/Header"], types["geometry_msgs/Point"]
        self._pose = types["geometry_msgs/Pose"]
        self._quaternion = types["geometry_msgs/Quaternion"]
        self._vector = types["geometry_msgs/Vector3"]

    def write(self, topic: str, message: Any, t: float, sequence: int) -> None:
        self.writer.write_message(topic, message, log_time=round(max(t, 0.0) * 1e9),
                                  sequence=sequence)
        self.count += 1

    def header(self, k: int, t: float, frame: str) -> Any:
        return self._header(k, self.time.from_sec(max(t, 0.0)), frame)

    def pose(self, x: float, y: float, theta: float) -> Any:
        return self._pose(self._point(x, y, 0.0), self._quaternion(
            0.0, 0.0, math.sin(0.5 * theta), math.cos(0.5 * theta)))

    def pose_stamped(self, header: Any, x: float, y: float, theta: float) -> Any:
        return self.types["geometry_msgs/PoseStamped"](header, self.pose(x, y, theta))

    def point_stamped(self, header: Any, x: float, y: float) -> Any:
        return self.types["geometry_msgs/PointStamped"](header, self._point(x, y, 0.0))

    def twist(self, linear: float, angular: float) -> Any:
        return self.types["geometry_msgs/Twist"](self._vector(linear, 0.0, 0.0),
                                                 self._vector(0.0, 0.0, angular))

    def frames(self, header: Any, robots: tuple[str, ...],
               poses: Sequence[Sequence[float]]) -> Any:
        """``/tf``: ``world`` -> ``<robot>/base_link`` at ``poses`` (x, y, theta)."""
        transform = self.types["geometry_msgs/Transform"]
        stamped = self.types["geometry_msgs/TransformStamped"]
        return self.types["tf2_msgs/TFMessage"]([stamped(
            header, f"{robot}/base_link", transform(self._vector(x, y, 0.0),
                                                    self.pose(x, y, theta).orientation))
            for robot, (x, y, theta) in zip(robots, poses, strict=True)])

    def robots_at(self, world: Any, robots: Sequence[str], poses: Sequence[Sequence[float]],
                  commands: Sequence[Sequence[float]], t: float, k: int) -> None:
        """What every show logs at tick ``k`` (time ``t``): each robot's ``pose`` (x, y,
        theta) and ``cmd_vel`` (v, w), and ``/tf`` with all of them; ``world``: the tick's
        header."""
        for robot, pose, command in zip(robots, poses, commands, strict=True):
            self.write(f"/{robot}/pose", self.pose_stamped(world, *pose), t, k)
            self.write(f"/{robot}/cmd_vel", self.twist(*command), t, k)
        self.write("/tf", self.frames(world, tuple(robots), poses), t, k)

    def cloud(self, header: Any, points: FloatArray) -> Any:
        """A ``sensor_msgs/PointCloud2`` of ``points`` (N, 2) at z = 0: x, y, z float32."""
        field = self.types["sensor_msgs/PointField"]
        xyz = np.zeros((len(points), 3), dtype="<f4")
        xyz[:, :2] = points
        return self.types["sensor_msgs/PointCloud2"](
            header, 1, len(points), [field(name, 4 * i, 7, 1) for i, name in enumerate("xyz")],
            False, 12, 12 * len(points), xyz.tobytes(), True)

    def people(self, header: Any, spectators: list[list[list[float]]], k: int) -> Any:
        """``/spectators``: where the people (C, T, 2) are at tick ``k``."""
        return self.types["geometry_msgs/PoseArray"](
            header, [self.pose(p[k][0], p[k][1], 0.0) for p in spectators])


def write_run_mcap(result: RunResult, path: str,
                   progress: Callable[[int, int], None] | None = None) -> int:
    """Write the formation run ``result`` as an MCAP file at ``path`` (module docstring);
    returns the number of messages. ``progress(done, total)`` is called once per tick."""
    from mcap_ros1.writer import Writer  # type: ignore[import-untyped,unused-ignore]

    robots, times = result.robots, result.times.tolist()
    poses, desired, leader = result.poses.tolist(), result.desired.tolist(), result.leader.tolist()
    velocities, commands = result.velocities.tolist(), result.commands.tolist()
    spectators = result.spectators.tolist()
    events = sorted(result.events, key=lambda e: e.time)
    with open(path, "wb") as handle, Writer(handle) as writer:
        log = _Log(writer)
        string, twist_stamped = (log.types["std_msgs/String"],
                                 log.types["geometry_msgs/TwistStamped"])

        def say(index: int) -> None:
            event = events[index]
            words = f"{event.robot} {event.kind}" + (f": {event.text}" if event.text else "")
            log.write("/events", string(words), event.time, index)

        scans: list[Any] = list(result.lidar or [])

        latency = result.config.lidar.latency if result.config.lidar is not None else 0.0

        def scan(index: int) -> None:  # stamped when scanned, logged when it reached them
            when, hits = scans[index]
            header = log.header(index, when - latency, "world")
            for robot, points in zip(robots, hits, strict=True):
                log.write(f"/{robot}/scan", log.cloud(header, np.asarray(points).reshape(-1, 2)),
                          when, index)

        said = scanned = 0
        for k, t in enumerate(times):
            while said < len(events) and events[said].time <= t + 1e-9:
                say(said)
                said += 1
            while scanned < len(scans) and scans[scanned][0] <= t + 1e-9:
                scan(scanned)
                scanned += 1
            world = log.header(k, t, "world")
            log.robots_at(world, robots, [p[k] for p in poses], [c[k] for c in commands], t, k)
            for i, robot in enumerate(robots):
                log.write(f"/{robot}/desired", log.pose_stamped(world, *desired[i][k]), t, k)
                log.write(f"/{robot}/virtual_leader", log.pose_stamped(world, *leader[i][k]),
                          t, k)
                log.write(f"/{robot}/velocity", twist_stamped(
                    log.header(k, t, f"{robot}/base_link"), log.twist(*velocities[i][k])),
                    t, k)
            if spectators:
                log.write("/spectators", log.people(world, spectators, k), t, k)
            if progress is not None:
                progress(k + 1, len(times))
        for index in range(said, len(events)):  # after the last tick (none: it records them)
            say(index)
        for index in range(scanned, len(scans)):  # delivered after the last tick
            scan(index)
    return log.count


def write_queue_mcap(result: QueueResult, path: str,
                     progress: Callable[[int, int], None] | None = None) -> int:
    """Write the leader-follower queue ``result`` as an MCAP file at ``path`` (module
    docstring); returns the number of messages. ``progress(done, total)``: once per tick."""
    from mcap_ros1.writer import Writer  # type: ignore[import-untyped,unused-ignore]

    robots, times = result.robots, result.times.tolist()
    poses, commands = result.poses.tolist(), result.commands.tolist()
    targets, leader = result.targets.tolist(), result.leader.tolist()
    spectators = result.spectators.tolist()
    with open(path, "wb") as handle, Writer(handle) as writer:
        log = _Log(writer)
        for k, t in enumerate(times):
            world = log.header(k, t, "world")
            log.robots_at(world, robots, [p[k] for p in poses], [c[k] for c in commands], t, k)
            for i, robot in enumerate(robots):
                if all(map(math.isfinite, targets[i][k])):
                    log.write(f"/{robot}/target", log.point_stamped(world, *targets[i][k]),
                              t, k)
            log.write("/leader", log.point_stamped(world, *leader[k]), t, k)
            if spectators:
                log.write("/spectators", log.people(world, spectators, k), t, k)
            if progress is not None:
                progress(k + 1, len(times))
    return log.count


class RecordLog:
    """The ROS simulator bridge's record as an MCAP log written as the run goes (module
    docstring): :meth:`step` appends one step (O(1), whatever the run's length; the MCAP
    writer flushes its chunks as they fill), :meth:`contact` one contact, :meth:`close`
    finishes the file (its index and summary). A run killed before ``close`` leaves the
    chunks written so far, which MCAP's readers can recover."""

    def __init__(self, path: str, robots: Sequence[str]) -> None:
        from mcap_ros1.writer import Writer  # type: ignore[import-untyped,unused-ignore]

        self.robots = tuple(robots)
        self._handle = open(path, "wb")  # noqa: SIM115 (closed by close())
        try:
            self._writer: Any = Writer(self._handle)
            self._log = _Log(self._writer)
        except BaseException:
            self._handle.close()
            raise
        self._steps = self._contacts = 0

    @property
    def count(self) -> int:
        """Messages written so far."""
        return self._log.count

    def step(self, t: float, poses: FloatArray, commands: FloatArray) -> None:
        """One step at ROS time ``t`` (s): poses (R, 3) world, the commands obeyed (R, 2)."""
        log, k = self._log, self._steps
        log.robots_at(log.header(k, t, "world"), self.robots, poses.tolist(), commands.tolist(),
                      t, k)
        self._steps += 1

    def contact(self, t: float, robot: str, other: str) -> None:
        """A contact of ``robot`` with ``other`` at ROS time ``t`` (s)."""
        self._log.write("/contacts", self._log.types["std_msgs/String"](
            f"{robot} touched {other}"), t, self._contacts)
        self._contacts += 1

    def close(self) -> None:
        """Finish the file (idempotent)."""
        if not self._handle.closed:
            try:
                self._writer.finish()
            finally:
                self._handle.close()


def write_record_mcap(path: str, robots: Sequence[str], times: FloatArray, poses: FloatArray,
                      commands: FloatArray,
                      contacts: Sequence[tuple[float, str, str]] = ()) -> int:
    """A whole record at once (:class:`RecordLog`): times (T,) ROS time, s; poses (R, T, 3)
    world; the commands obeyed (R, T, 2); contacts (time s, robot, what it touched), each
    logged before the first step after it; returns the number of messages."""
    record = RecordLog(path, robots)
    pending = sorted(contacts)
    told = 0
    try:
        for k, t in enumerate(times.tolist()):
            while told < len(pending) and pending[told][0] <= t + 1e-9:
                record.contact(*pending[told])
                told += 1
            record.step(t, poses[:, k], commands[:, k])
        for contact in pending[told:]:
            record.contact(*contact)
    finally:
        record.close()
    return record.count

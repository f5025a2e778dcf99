"""The run as an MCAP log with ROS 1 message types: what Foxglove, PlotJuggler and the ROS
tools open (docs/run-outputs.md).

One message per robot per control tick on each of its topics, stamped with the time since
the start (s, as nanoseconds from the epoch: the log starts on 1 January 1970; nothing here
reads a clock, so a run's log is the same every time):

* ``/tf`` (``tf2_msgs/TFMessage``): ``world`` -> ``<robot>/base_link`` for every robot;
* ``/<robot>/pose``, ``/<robot>/desired``, ``/<robot>/virtual_leader``
  (``geometry_msgs/PoseStamped``, frame ``world``): where it is, where it believes its
  desired pose and its virtual leader are;
* ``/<robot>/cmd_vel`` (``geometry_msgs/Twist``): its command; ``/<robot>/velocity``
  (``geometry_msgs/TwistStamped``, frame ``<robot>/base_link``): its actual speeds;
* ``/spectators`` (``geometry_msgs/PoseArray``, frame ``world``): the people, when there are;
* ``/events`` (``std_msgs/String``): "ROBOT KIND: TEXT" at the time of each event (speech,
  beep, resume, error).

The messages are built from their standard definitions (:data:`DEFINITIONS`, comments left
out: the same MD5 sums as ROS's) by genpy's dynamic types (ROS's own ``genpy`` where it is
installed, else the copy ``mcap-ros1-support`` carries) and written by ``mcap-ros1-support``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import cache
from typing import Any

from dancebots.shows.formation import RunResult

__all__ = ["DEFINITIONS", "write_run_mcap"]

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
    "std_msgs/String": "string data",
}
"""The ROS 1 definitions of the message types the log uses (``.msg`` text, as in ROS's
``_full_text`` without the comments)."""


def _genpy() -> Any:
    """ROS's own genpy where ROS is installed (messages that are ``genpy.Message``), else the
    copy mcap-ros1-support carries (as its decoder does)."""
    try:
        import genpy  # type: ignore[import-not-found,unused-ignore]
    except ImportError:
        from mcap_ros1._vendor import genpy  # type: ignore[import-untyped,unused-ignore]
    return genpy


@cache
def _types() -> dict[str, Any]:
    """The message classes of :data:`DEFINITIONS` by type name (and their sub-types)."""
    from importlib import import_module

    dynamic = import_module(_genpy().__name__ + ".dynamic")
    classes: dict[str, Any] = {}
    for name, text in DEFINITIONS.items():
        classes.update(dynamic.generate_dynamic(name, text))
    return classes


def write_run_mcap(result: RunResult, path: str,
                   progress: Callable[[int, int], None] | None = None) -> int:
    """Write the run ``result`` as an MCAP file at ``path`` (module docstring); returns the
    number of messages. ``progress(done, total)`` is called once per control tick."""
    from mcap_ros1.writer import Writer  # type: ignore[import-untyped,unused-ignore]

    types = _types()
    pose_stamped, pose_array = types["geometry_msgs/PoseStamped"], types["geometry_msgs/PoseArray"]
    twist, twist_stamped = types["geometry_msgs/Twist"], types["geometry_msgs/TwistStamped"]
    tf_message, transform = types["tf2_msgs/TFMessage"], types["geometry_msgs/TransformStamped"]
    string, header = types["std_msgs/String"], types["std_msgs/Header"]
    pose_type, point, quaternion = (types["geometry_msgs/Pose"], types["geometry_msgs/Point"],
                                    types["geometry_msgs/Quaternion"])
    vector = types["geometry_msgs/Vector3"]

    time_type = _genpy().Time

    def stamp(t: float) -> Any:
        return time_type.from_sec(max(t, 0.0))

    def pose_of(x: float, y: float, theta: float) -> Any:
        return pose_type(point(x, y, 0.0),
                         quaternion(0.0, 0.0, math.sin(0.5 * theta), math.cos(0.5 * theta)))

    robots, times = result.robots, result.times.tolist()
    poses, desired, leader = result.poses.tolist(), result.desired.tolist(), result.leader.tolist()
    velocities, commands = result.velocities.tolist(), result.commands.tolist()
    spectators = result.spectators.tolist()
    events = sorted(result.events, key=lambda e: e.time)
    count = 0
    with open(path, "wb") as handle, Writer(handle) as writer:
        def write(topic: str, message: Any, t: float, sequence: int) -> None:
            nonlocal count
            writer.write_message(topic, message, log_time=round(max(t, 0.0) * 1e9),
                                 sequence=sequence)
            count += 1

        next_event = 0
        for k, t in enumerate(times):
            while next_event < len(events) and events[next_event].time <= t + 1e-9:
                event = events[next_event]
                write("/events", string(f"{event.robot} {event.kind}: {event.text}".strip()),
                      event.time, next_event)
                next_event += 1
            when = stamp(t)
            world = header(k, when, "world")
            frames = []
            for i, robot in enumerate(robots):
                x, y, theta = poses[i][k]
                frames.append(transform(world, f"{robot}/base_link", types[
                    "geometry_msgs/Transform"](vector(x, y, 0.0), pose_of(x, y, theta)
                                               .orientation)))
                write(f"/{robot}/pose", pose_stamped(world, pose_of(x, y, theta)), t, k)
                write(f"/{robot}/desired", pose_stamped(world, pose_of(*desired[i][k])), t, k)
                write(f"/{robot}/virtual_leader", pose_stamped(world, pose_of(*leader[i][k])),
                      t, k)
                v, w = commands[i][k]
                write(f"/{robot}/cmd_vel", twist(vector(v, 0.0, 0.0), vector(0.0, 0.0, w)), t, k)
                v, w = velocities[i][k]
                write(f"/{robot}/velocity", twist_stamped(
                    header(k, when, f"{robot}/base_link"),
                    twist(vector(v, 0.0, 0.0), vector(0.0, 0.0, w))), t, k)
            write("/tf", tf_message(frames), t, k)
            if spectators:
                write("/spectators", pose_array(world, [pose_of(p[k][0], p[k][1], 0.0)
                                                        for p in spectators]), t, k)
            if progress is not None:
                progress(k + 1, len(times))
        for event in events[next_event:]:  # after the last tick (none, as the loop records)
            write("/events", string(f"{event.robot} {event.kind}: {event.text}".strip()),
                  event.time, next_event)
            next_event += 1
    return count

"""The simulator bridge (the thesis's turtle_bridge, ch. 7.1): each simulated robot looks
like a real one over ROS, so unmodified formation_member nodes drive it.

Parameters: ``~scenario`` (required), ``~world``, ``~vmax`` (as for formation_member),
``~profile`` (ideal | realistic | physics | physics-geometric), ``~seed``, ``~lidar`` (default
true), ``~rate`` (simulation steps per second, default 20), ``~record`` (optional path: the
run's times, poses, applied commands and contacts, written every 5 s and at shutdown;
``.mcap``: an MCAP log with ROS 1 types, ``report.mcap_log.write_record_mcap``, else NumPy's
.npz), ``~stop_after`` (s; shut down after this long, which ends a launch whose bridge is
required; 0: run until stopped), ``~show_end`` (s of show time; when above 0, the bridge
listens to the formation's ``/hold`` messages and shuts down once every robot's shared show
clock is there, no robot holds the show and every robot has stood still for ``STILL`` s, or
the clocks are ``~settle`` s (default 20) past it: the run ends when the show does however
long the formation waited for people, as ``dancebots run`` ends it; a formation whose robots
send no hold messages, ``--hold alone``, ends at ``~stop_after``), ``~silence`` (fault
injection: "R1@12.5" stops publishing R1's clouds from 12.5 s on).
Per robot R of the scenario (its name prefixes everything, as all share one master):
subscribes ``/R/nav/cmd_vel`` (geometry_msgs/Twist; a command older than 0.1 s stops the
robot, the robots' 10 Hz rule); publishes TF ``R/map`` -> ``R/base_link`` (the map's origin
is the robot's start pose) every step and ``/R/points_filtered`` (PointCloud2 in
``R/base_link``, 10 Hz, stamped with the scan time and delivered the LIDAR's 0.3 s later).
The stage's clock is ROS time since the bridge started; spectators walk from then. Ends on
SIGINT/SIGTERM (writing the record first) even without its master
(:class:`dancebots.ros1.common.NodeLife`).
"""

from __future__ import annotations

import math
import threading
from pathlib import Path

import numpy as np
import rospy
import tf2_ros
from geometry_msgs.msg import Twist
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import Header, String

from dancebots.plan.placement import place_show
from dancebots.ros1.common import NodeLife, QueuedLog, load_show, required_param
from dancebots.ros1.convert import cloud_message, transform_message
from dancebots.ros1.naming import HOLD_TOPIC, RobotNames
from dancebots.shows.loop import STILL, robots_moving, settled_since
from dancebots.sim.kinematics import PROFILES, fresh_commands
from dancebots.sim.lidar import LidarConfig
from dancebots.sim.setup import SetupError, prepare_show
from dancebots.sim.stage import Stage
from dancebots.sync.messages import HoldMessageError, parse_hold

RECORD_EVERY = 5.0  # s between writes of the record


def main() -> None:
    rospy.init_node("sim_bridge", disable_signals=True)
    life = NodeLife()
    log = QueuedLog()
    world_file = str(rospy.get_param("~world", "")) or None
    plan, world = load_show(str(required_param("~scenario")), world_file,
                            float(rospy.get_param("~vmax", 0.0)) or None,
                            str(rospy.get_param("~timing", "feasible")))
    profile = str(rospy.get_param("~profile", "ideal"))
    if profile not in PROFILES:
        rospy.logfatal(f"unknown profile {profile!r}; use one of {', '.join(PROFILES)}")
        raise SystemExit(2)
    try:
        arena, placement = prepare_show(place_show(plan, world))
    except SetupError as exc:
        rospy.logfatal(str(exc))
        raise SystemExit(2) from None
    dt = 1.0 / float(rospy.get_param("~rate", 20.0))
    lidar = LidarConfig() if rospy.get_param("~lidar", True) else None
    stage = Stage(arena, placement, PROFILES[profile], dt, lidar,
                  seed=int(rospy.get_param("~seed", 0)))
    robots = placement.robots
    names = [RobotNames(robot) for robot in robots]
    count = len(robots)
    lock = threading.Lock()
    command = np.zeros((count, 2))
    issued = np.full(count, -math.inf)
    start = rospy.get_time()

    def commanded(message: Twist, robot: int) -> None:
        with lock:
            command[robot] = (message.linear.x, message.angular.z)
            issued[robot] = rospy.get_time() - start

    for i, name in enumerate(names):
        rospy.Subscriber(name.topic("nav/cmd_vel"), Twist, commanded, callback_args=i,
                         queue_size=1)
    clouds = [rospy.Publisher(name.topic("points_filtered"), PointCloud2, queue_size=1)
              for name in names]
    broadcaster = tf2_ros.TransformBroadcaster()
    record_path = str(rospy.get_param("~record", "")) or None
    times: list[float] = []
    poses: list[np.ndarray] = []
    applied: list[np.ndarray] = []
    streamed = None  # an .mcap record: written step by step as the run goes (opened below)
    told = 0  # contacts streamed so far

    def write_record() -> None:
        if record_path is None or not times or streamed is not None:
            return
        partial = Path(record_path).with_suffix(".partial.npz")
        np.savez(partial, robots=np.array(robots), times=np.array(times),
                 poses=np.stack(poses, axis=1), commands=np.stack(applied, axis=1),
                 lengths=np.array([t.length for t in placement.types]),
                 widths=np.array([t.width for t in placement.types]),
                 contacts=np.array([(c.time, robots.index(c.robot)) for c in stage.collisions]
                                   ).reshape(-1, 2))
        partial.replace(record_path)

    log.info(f"sim_bridge: {count} robots, {1 / dt:g} steps/s, LIDAR "
             f"{'on' if lidar else 'off'}")
    stop_after = float(rospy.get_param("~stop_after", 0.0))
    show_end = float(rospy.get_param("~show_end", 0.0))
    settle = float(rospy.get_param("~settle", 20.0))
    silenced = _silences(str(rospy.get_param("~silence", "")), robots)
    clocks: dict[str, tuple[float, bool]] = {}  # each robot's last show time and hold heard

    def hold_heard(message: String) -> None:
        try:
            heard = parse_hold(message.data)
        except HoldMessageError:
            return  # (the formation_member nodes log bad messages)
        if heard.role in robots:
            with lock:
                clocks[heard.role] = (heard.show_time, heard.holds)

    if show_end > 0.0:
        rospy.Subscriber(HOLD_TOPIC, String, hold_heard, queue_size=100)

    def advance(now: float) -> np.ndarray:
        """Publish the clouds and poses at stage time ``now`` (s), record, and step; returns
        the commands (R, 2) the robots obeyed."""
        nonlocal told
        stamp = rospy.Time.from_sec(start + now)
        for i, cloud in enumerate(stage.deliveries(now)):
            if cloud is not None and now < silenced.get(i, math.inf):
                header = Header(stamp=rospy.Time.from_sec(start + cloud.stamp),
                                frame_id=names[i].frame("base_link"))
                clouds[i].publish(cloud_message(cloud.points(), header))
        broadcaster.sendTransform([
            transform_message(stamp, name.frame("map"), name.frame("base_link"), pose)
            for name, pose in zip(names, stage.own_poses().tolist(), strict=True)])
        with lock:
            current, sent = command.copy(), issued.copy()
        obeyed = fresh_commands(current, sent, now, stage.command_timeout)
        if streamed is not None:
            streamed.step(start + now, stage.pose, obeyed)
            for contact in stage.collisions[told:]:
                streamed.contact(start + contact.time, contact.robot, contact.other)
            told = len(stage.collisions)
        else:
            times.append(start + now)
            poses.append(stage.pose.copy())
            applied.append(obeyed)
        stage.advance(now, current, sent)
        return obeyed

    step = 0
    still_since: float | None = None
    formation_time: float | None = None  # the show time every robot's clock has reached
    last_write = 0.0
    reason = None
    if record_path is not None and record_path.endswith(".mcap"):
        from dancebots.report.mcap_log import RecordLog

        streamed = RecordLog(record_path, robots)  # closed in the finally below
    try:
        while life.running:
            now = step * dt
            if 0 < stop_after <= now:
                reason = "the show is over"
                unfinished = ("" if formation_time is None or formation_time >= show_end
                              else f"; the show had not finished: show time "
                              f"{formation_time:.1f} s of {show_end:.1f} s (the formation "
                              f"waited for a held or silent robot)")
                log.info(f"sim_bridge: {stop_after:g} s are over; {len(stage.collisions)} "
                         f"contacts{unfinished}")
                break
            if not life.wait(start + now - rospy.get_time()):
                break
            obeyed = advance(now)
            if show_end > 0.0:
                with lock:
                    heard = list(clocks.values()) if len(clocks) == count else []
                if heard:
                    formation_time = min(time for time, _ in heard)
                    still_since = settled_since(
                        still_since, now, formation_time, show_end,
                        any(holds for _, holds in heard)
                        or robots_moving(stage.velocity, obeyed))
                    if (still_since is not None and now - still_since >= STILL) or (
                            formation_time >= show_end + settle):
                        reason = "the show is over"
                        log.info(f"sim_bridge: the show is over at show time "
                                 f"{formation_time:.1f} s, {now:.1f} s are over; "
                                 f"{len(stage.collisions)} contacts")
                        break
            if now - last_write >= RECORD_EVERY:
                write_record()
                last_write = now
            step += 1
    finally:
        write_record()
        if streamed is not None:
            for contact in stage.collisions[told:]:
                streamed.contact(start + contact.time, contact.robot, contact.other)
            streamed.close()
        log.flush()
        life.end(reason)


def _silences(text: str, robots: tuple[str, ...]) -> dict[int, float]:
    """Parse "R1@12.5,R2@20" into {robot index: time}; exits on a malformed entry."""
    result = {}
    for entry in filter(None, (part.strip() for part in text.split(","))):
        robot, _, when = entry.partition("@")
        try:
            result[robots.index(robot)] = float(when)
        except ValueError:
            rospy.logfatal(f"~silence: {entry!r} is not ROBOT@SECONDS with a robot of "
                           f"the scenario ({', '.join(robots)})")
            raise SystemExit(2) from None
    return result


if __name__ == "__main__":
    main()

"""The ``formation_member`` node (thesis ch. 3, 4): agrees on the start over ``/sync``, then
drives the robot with the RobotBrain of the simulator. A thin rospy shell: ROS time, TF and
messages in; Twist, /sync proposals and speech out.

Parameters: ``~scenario``, ``~role`` (required); ``~world`` and ``~vmax`` (optional, the same
on every robot: they set the plan's vmax); ``~robot_name`` (optional prefix of topics and
frames); ``~start_strategy`` ("agreed", or "thesis" as written); ``~lidar`` (default true:
read ``obstacles`` and stop for them); ``~max_speed`` and ``~max_angular_speed`` (default:
the robot type of this host, thesis ch. 3); ``~launch_detector`` (default true: start the
``obstacle_detection`` node through the roslaunch API, as the thesis does);
``~sync_delay``/``~sync_loss``/``~sync_seed`` (test only, see network_test). Robot size from
``[/robot_name]/length`` and ``/width``.

It proposes a start once ``all_ready`` is true and its pose and (with LIDAR) obstacle
clouds arrive. Subscribes ``[/robot_name]/all_ready``, ``/sync``,
``[/robot_name]/obstacles``; TF
``map`` -> ``base_link`` (a transform older than 0.3 s counts as a failed look-up).
Publishes ``[/robot_name]/nav/cmd_vel`` (geometry_msgs/Twist) at 20 Hz (the brain ticks at
10 Hz; the robots ignore commands slower than 10 Hz), ``/sync`` proposals at 10 Hz,
``[/robot_name]/robotsound`` (sound_play/SoundRequest: the stop sentence, beeps) and
``[/robot_name]/events`` (std_msgs/String: every safety event as "kind: text").
"""

from __future__ import annotations

import math
import socket
import threading
from typing import Any

import rospy
import tf2_ros
from geometry_msgs.msg import Twist
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import Bool, String

from dancebots.control.follower import FollowerParams
from dancebots.geometry import wrap_angle
from dancebots.perception.cloud import PointCloud
from dancebots.robot import BrainState, RobotBrain, SensingConfig
from dancebots.ros1.common import load_show, parse_sync, required_param, sync_publisher
from dancebots.ros1.convert import cloud_points, obstacle_cloud
from dancebots.ros1.naming import SYNC_TOPIC, RobotNames, robot_type_for_host
from dancebots.ros1.sound import SoundRequest, beep_request, say_request
from dancebots.sync import (
    StartProposal,
    agreement_ready,
    agreement_receive,
    format_message,
    new_agreement,
    show_time,
)

CONTROL_HZ = 10.0
PUBLISH_HZ = 20.0
POSE_MAX_AGE = 0.3
"""s: a map -> base_link transform older than this is a failed look-up (thesis 5.1)."""


def main() -> None:
    rospy.init_node("formation_member")
    scenario = str(required_param("~scenario"))
    role = str(required_param("~role"))
    world_file = str(rospy.get_param("~world", "")) or None
    plan, _ = load_show(scenario, world_file, float(rospy.get_param("~vmax", 0.0)) or None)
    names = RobotNames(str(rospy.get_param("~robot_name", "")))
    kind = robot_type_for_host(socket.gethostname())
    length = float(rospy.get_param(names.param("length"), kind.length))
    width = float(rospy.get_param(names.param("width"), kind.width))
    use_lidar = bool(rospy.get_param("~lidar", True))
    try:
        agreement = new_agreement(role, plan.robots,
                                  str(rospy.get_param("~start_strategy", "agreed")))
        brain = RobotBrain(plan, role, FollowerParams(
            vmax=plan.parameters.vmax,
            max_linear=float(rospy.get_param("~max_speed", kind.max_speed)),
            max_angular=float(rospy.get_param("~max_angular_speed", kind.max_angular_speed))),
            sensing=SensingConfig(length, width, lidar=use_lidar))
    except ValueError as exc:
        rospy.logfatal(str(exc))
        raise SystemExit(2) from None
    if use_lidar and rospy.get_param("~launch_detector", True):
        _launch_detector(names)

    lock = threading.Lock()
    latest_cloud: list[Any] = []
    sync = sync_publisher(role, 1)
    cmd_vel = rospy.Publisher(names.topic("nav/cmd_vel"), Twist, queue_size=1)
    sound = rospy.Publisher(names.topic("robotsound"), SoundRequest, queue_size=10)
    events_out = rospy.Publisher(names.topic("events"), String, queue_size=10)

    network_ready = threading.Event()
    cloud_seen = threading.Event()

    def all_ready(message: Bool) -> None:
        if message.data:
            network_ready.set()

    def heard(message: String) -> None:
        nonlocal agreement
        parsed = parse_sync(message.data)
        if isinstance(parsed, StartProposal):
            with lock:
                agreement = agreement_receive(agreement, parsed)

    def obstacles(message: PointCloud2) -> None:
        with lock:
            latest_cloud[:] = [message]
        cloud_seen.set()

    rospy.Subscriber(names.topic("all_ready"), Bool, all_ready, queue_size=1)
    rospy.Subscriber(SYNC_TOPIC, String, heard, queue_size=100)
    if use_lidar:
        rospy.Subscriber(names.topic("obstacles"), PointCloud2, obstacles, queue_size=1)
    buffer = tf2_ros.Buffer()
    tf2_ros.TransformListener(buffer)
    map_frame, base_frame = names.frame("map"), names.frame("base_link")

    def look_up_pose(now: float) -> tuple[float, float, float] | None:
        try:
            transform = buffer.lookup_transform(map_frame, base_frame, rospy.Time(0))
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                tf2_ros.ExtrapolationException):
            return None
        if now - transform.header.stamp.to_sec() > POSE_MAX_AGE:
            return None
        t, q = transform.transform.translation, transform.transform.rotation
        yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
        return t.x, t.y, wrap_angle(yaw)

    state: BrainState = brain.initial_state()
    command = Twist()
    status = "waiting"
    start_logged = False
    rate = rospy.Rate(PUBLISH_HZ)
    tick = 0
    while not rospy.is_shutdown():
        now = rospy.get_time()
        if tick % round(PUBLISH_HZ / CONTROL_HZ) == 0:
            with lock:
                if (not agreement.ready and network_ready.is_set()
                        and (cloud_seen.is_set() or not use_lidar)
                        and look_up_pose(now) is not None):
                    # ready when the network test passed and the sensors deliver: only
                    # then does the robot propose a start (and its safety watch begin)
                    agreement = agreement_ready(agreement, now)
                current = agreement
                message = latest_cloud.pop() if latest_cloud else None
            proposal = current.message(now)
            if proposal is not None:
                sync.publish(String(format_message(proposal)))
            elapsed = show_time(current, now)
            if elapsed is not None and not start_logged:
                rospy.loginfo(f"{role}: start agreed at {current.start!r} "
                              f"({current.strategy}), show time now {elapsed:.2f} s")
                start_logged = True
            command = Twist()
            if elapsed is not None:
                cloud: PointCloud | None = None
                if message is not None:
                    stamp = message.header.stamp.to_sec() - (now - elapsed)
                    cloud = obstacle_cloud(stamp, cloud_points(message))
                state, cmd, happened = brain.step(state, elapsed, look_up_pose(now), cloud)
                command.linear.x, command.angular.z = cmd.linear, cmd.angular
                for event in happened:
                    events_out.publish(String(f"{event.kind}: {event.text}"))
                    if event.kind == "speech":
                        sound.publish(say_request(event.text))
                    elif event.kind == "beep":
                        sound.publish(beep_request())
                    elif event.kind == "error":
                        rospy.logerr(f"{role}: {event.text}; stopped for good")
                if state.status != status:
                    rospy.loginfo(f"{role}: {state.status} at show time {elapsed:.1f} s")
                    status = state.status
        cmd_vel.publish(command)
        tick += 1
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break
    cmd_vel.publish(Twist())


def _launch_detector(names: RobotNames) -> None:
    """Start obstacle_detection beside this node through the roslaunch API (thesis ch. 3)."""
    import roslaunch

    node = roslaunch.core.Node(
        "dancebots_ros", "obstacle_detection", name="obstacle_detection",
        namespace=rospy.get_namespace(), output="log",
        args=f"_robot_name:={names.prefix}" if names.prefix else "")
    launch = roslaunch.scriptapi.ROSLaunch()
    launch.start()
    process = launch.launch(node)
    rospy.on_shutdown(process.stop)
    rospy.on_shutdown(launch.stop)


if __name__ == "__main__":
    main()

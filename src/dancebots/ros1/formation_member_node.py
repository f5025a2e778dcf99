"""The ``formation_member`` node (thesis ch. 3, 4): agrees on the start over ``/sync``, then
drives the robot with the RobotBrain of the simulator. A thin rospy shell: ROS time, TF and
messages in; Twist, /sync proposals and speech out.

Parameters: ``~scenario``, ``~role`` (required); ``~world`` and ``~vmax`` (optional, the same
on every robot: they set the plan's vmax); ``~robot_name`` (optional prefix of topics and
frames); ``~start_strategy`` ("agreed", or "thesis" as written); ``~follower`` ("path", the
default, "tracking" or "thesis"; docs/control.md) and ``~timing`` ("feasible", the default,
or "thesis"; the same on every robot: it sets the plan's timing); ``~actuator_lag`` (s,
default 0: the time constant with which the robot's speeds follow its commands; the
tracking and path followers lead their feedforward by it); ``~lidar`` (default true:
read ``obstacles`` and stop for them); ``~hold`` ("paced", the default, "together", or
"alone", the default with the thesis follower: whether the formation shares one show clock,
below);
``~stop_rule`` ("predicted", the default, "fixed", the default with the thesis follower,
"closing" or "ssm": when the robot stops for what it sees; docs/safety.md); ``~max_speed``
and ``~max_angular_speed`` (default: the robot type of this host, thesis ch. 3);
``~launch_detector`` (default true: start the ``obstacle_detection`` node through the
roslaunch API, as the thesis does);
``~sync_delay``/``~sync_loss``/``~sync_seed`` (test only, see network_test). Robot size from
``[/robot_name]/length`` and ``/width``.

It proposes a start once ``all_ready`` is true and its pose and (with LIDAR) obstacle
clouds arrive. Subscribes ``[/robot_name]/all_ready``, ``/sync``,
``[/robot_name]/obstacles``; TF
``map`` -> ``base_link`` (a transform older than 0.3 s counts as a failed look-up).
Publishes ``[/robot_name]/nav/cmd_vel`` (geometry_msgs/Twist) at 20 Hz (the brain ticks at
10 Hz; the robots ignore commands slower than 10 Hz), ``/sync`` proposals at 10 Hz,
``[/robot_name]/robotsound`` (sound_play/SoundRequest: the stop sentence, beeps) and
``[/robot_name]/events`` (std_msgs/String: every safety event as "kind: text"), and from the
agreed start, with each command, the thesis's virtual-leader frames on TF (ch. 4.1):
``map`` -> ``vl_map`` (the show frame in the robot's map frame, from its first slot) ->
``virtual_leader`` (the leader it follows at its show time), each prefixed like the others, so
that RViz shows every robot's virtual leader.

The formation waits together (``~hold`` paced or together, ``sync.hold``): from the agreed
start every formation_member publishes a hold message on ``/hold`` at 10 Hz (std_msgs/String,
``hold ROLE STAMP SHOW_TIME HOLDS X Y [pace P]``: its clock, its show time, whether it holds
the show, where it stands in the show frame and, with ``paced``, the share of the plan's
speeds it can follow, at which every show time then runs) and keeps the shared show clock
from the others': its show time stops while any robot holds the show or has not been heard
from for 1 s (a robot that is lost, or whose link is cut, stops the show: safe, not the
other way round), and all resume together. With ``alone`` (thesis 4.2) its show time is
the time since the start. Bad /hold texts are logged at most every 5 s and ignored;
``~sync_delay``/``~sync_loss`` act on /hold too.

Faults: a malformed cloud on ``obstacles`` counts as a scan that did not arrive (after 0.3 s
without a readable one the robot stops for good, thesis 5.1), and is logged at most every
5 s; ``/sync`` proposals outside the plausibility window are ignored and logged. The loop
ticks on the wall clock and never waits for the master: a robot that lost its master keeps
publishing its (zero) command at 20 Hz and ends on SIGINT/SIGTERM within a few seconds
(see :class:`dancebots.ros1.common.NodeLife`), stopping its obstacle_detection first.
"""

from __future__ import annotations

import math
import socket
import threading
import time
from typing import Any, cast

import numpy as np
import rospy
import tf2_ros
from geometry_msgs.msg import Twist
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import Bool, String

from dancebots.geometry import wrap_angle
from dancebots.loading import show_digests
from dancebots.perception.cloud import PointCloud
from dancebots.plan.placement import robot_types
from dancebots.plan.planner import virtual_leader_pose
from dancebots.robot import (
    BrainOptions,
    BrainState,
    Follower,
    RobotBrain,
    brain_for,
    default_stop_rule,
)
from dancebots.ros1.common import (
    NodeLife,
    QueuedLog,
    load_show,
    parse_sync,
    required_param,
    sync_publisher,
)
from dancebots.ros1.convert import (
    MalformedCloudError,
    cloud_points,
    obstacle_cloud,
    transform_message,
)
from dancebots.ros1.naming import HOLD_TOPIC, SYNC_TOPIC, RobotNames, robot_type_for_host
from dancebots.ros1.sound import SoundRequest, beep_request, say_request
from dancebots.sync import (
    TIMECODE_OFFSET,
    ShowMessage,
    StartAgreement,
    StartProposal,
    agreement_ready,
    agreement_receive,
    agreement_show,
    format_message,
    implausible,
    new_agreement,
    show_time,
)
from dancebots.sync.hold import (
    HOLD_STRATEGIES,
    HoldMessage,
    ShowClock,
    clock_rate,
    clock_receive,
    clock_tick,
    default_hold_strategy,
    heard_positions,
    new_clock,
)
from dancebots.sync.messages import HoldMessageError, format_hold, parse_hold
from dancebots.world import RobotType

CONTROL_HZ = 10.0
PUBLISH_HZ = 20.0
POSE_MAX_AGE = 0.3
"""s: a map -> base_link transform older than this is a failed look-up (thesis 5.1)."""
DETECTOR_SIGINT_TIMEOUT = 5.0
"""s obstacle_detection gets to end after SIGINT before SIGTERM, then 1 s before SIGKILL."""


def main() -> None:
    rospy.init_node("formation_member", disable_signals=True)
    life = NodeLife()
    log = QueuedLog()
    scenario = str(required_param("~scenario"))
    role = str(required_param("~role"))
    world_file = str(rospy.get_param("~world", "")) or None
    plan, world = load_show(scenario, world_file,
                            float(rospy.get_param("~vmax", 0.0)) or None,
                            str(rospy.get_param("~timing", "feasible")))
    names = RobotNames(str(rospy.get_param("~robot_name", "")))
    kind = robot_type_for_host(socket.gethostname())
    length = float(rospy.get_param(names.param("length"), kind.length))
    width = float(rospy.get_param(names.param("width"), kind.width))
    use_lidar = bool(rospy.get_param("~lidar", True))
    try:
        strategy = str(rospy.get_param("~start_strategy", "agreed"))
        start_at = float(rospy.get_param("~start_at", 0.0)) or None
        clock_offset = float(rospy.get_param("~clock_offset", 0.0))  # tests only
        this_robot = RobotType(
            kind.name, length, width, float(rospy.get_param("~max_speed", kind.max_speed)),
            float(rospy.get_param("~max_angular_speed", kind.max_angular_speed)))
        follower = cast(Follower, str(rospy.get_param("~follower", "path")))
        hold = str(rospy.get_param("~hold", "")) or default_hold_strategy(follower)
        if hold not in HOLD_STRATEGIES:
            raise ValueError(f"unknown ~hold {hold!r}; choose from {', '.join(HOLD_STRATEGIES)}")
        stop_rule = default_stop_rule(follower, str(rospy.get_param("~stop_rule", "")))
        # the mates' footprints as the world gives them (else the default robot's), as the
        # simulator's bridge places them (``robot.MATE_BODY_MARGIN``)
        mate_types = [kind for name, kind in zip(plan.robots, robot_types(plan, world),
                                                 strict=True) if name != role]
        brain = brain_for(plan, role, this_robot, BrainOptions(  # RobotBrain checks both
            follower=follower, lidar=use_lidar, stop_rule=stop_rule,
            actuator_lag=float(rospy.get_param("~actuator_lag", 0.0)),
            paced=hold == "paced"), mate_types)
        # the show every robot must run alike: its files and what changes the motion (each
        # robot's own size and speed limits may differ: they come from its host)
        show = show_digests(scenario, world_file, {
            "vmax": plan.parameters.vmax, "timing": plan.parameters.timing,
            "follower": follower, "hold": hold, "stop_rule": stop_rule, "lidar": use_lidar})
        agreement = new_agreement(
            role, plan.robots, strategy, start_at if strategy == "timecode" else None,
            float(rospy.get_param("~max_clock_offset", TIMECODE_OFFSET)), show)
    except (ValueError, OSError) as exc:
        rospy.logfatal(str(exc))
        raise SystemExit(2) from None
    detector = None
    if use_lidar and rospy.get_param("~launch_detector", True):
        detector = _launch_detector(names)
        life.take_signals()  # roslaunch's process class installed handlers of its own
    try:
        _run(life, log, role, names, agreement, brain, use_lidar, hold != "alone",
             clock_offset)
    finally:
        if detector is not None:
            detector.stop([])  # SIGINT, then SIGTERM, then SIGKILL: bounded
        log.info(f"{role}: stopping ({life.reason()})")
        log.flush()
        life.end()


def _run(life: NodeLife, log: QueuedLog, role: str, names: RobotNames,
         agreement: StartAgreement, brain: RobotBrain, use_lidar: bool,
         together: bool, clock_offset: float = 0.0) -> None:
    """The node's loop: subscriptions, then a 20 Hz wall-clock loop until ``life`` ends; the
    robot's last command is zero. ``together``: the formation's shared show clock;
    ``clock_offset`` (tests only, s): the start agreement's clock is off by this much (a
    robot whose clock is not synchronised, injected in-process)."""
    lock = threading.Lock()
    latest_cloud: list[tuple[float, Any]] = []
    inbox: list[HoldMessage] = []  # hold messages heard since the last tick
    sync = sync_publisher(role, 1)
    hold_out = sync_publisher(role, 2, HOLD_TOPIC)
    cmd_vel = rospy.Publisher(names.topic("nav/cmd_vel"), Twist, queue_size=1)
    leader_frames = tf2_ros.TransformBroadcaster()
    vl_map, leader_frame = names.frame("vl_map"), names.frame("virtual_leader")
    show_frame = brain.show_frame
    sound = rospy.Publisher(names.topic("robotsound"), SoundRequest, queue_size=10)
    events_out = rospy.Publisher(names.topic("events"), String, queue_size=10)
    obstacles_topic = names.topic("obstacles")

    network_ready = threading.Event()
    cloud_seen = threading.Event()

    def all_ready(message: Bool) -> None:
        if message.data:
            network_ready.set()

    def heard(message: String) -> None:
        nonlocal agreement
        parsed = parse_sync(message.data, log)
        if isinstance(parsed, ShowMessage):
            with lock:
                agreement = agreement_show(agreement, parsed)
            return
        if not isinstance(parsed, StartProposal):
            return
        now = rospy.get_time() + clock_offset
        with lock:
            waiting = parsed.role in agreement.roles and parsed.role not in agreement.heard
            agreement = agreement_receive(agreement, parsed, now)
        reason = implausible(parsed.start, now) if (
            waiting and agreement.strategy != "timecode") else None
        if reason is not None:
            log.warn(f"{role}: ignoring the start proposed by {parsed.role}: {reason}",
                     every=5.0, key=f"implausible {parsed.role}")

    def obstacles(message: PointCloud2) -> None:
        try:  # a malformed cloud is a scan that did not arrive
            points = cloud_points(message)
        except MalformedCloudError as exc:
            log.warn(f"{role}: {obstacles_topic}: {exc}; counted as a missing scan",
                     every=5.0, key="malformed cloud")
            return
        with lock:
            latest_cloud[:] = [(message.header.stamp.to_sec(), points)]
        cloud_seen.set()

    def hold_heard(message: String) -> None:
        try:
            parsed = parse_hold(message.data)
        except HoldMessageError as exc:
            log.warn(f"{role}: {exc}", every=5.0, key="bad /hold message")
            return
        with lock:
            if len(inbox) < 1000:  # bounded: a flood cannot grow it
                inbox.append(parsed)

    rospy.Subscriber(names.topic("all_ready"), Bool, all_ready, queue_size=1)
    if together:
        rospy.Subscriber(HOLD_TOPIC, String, hold_heard, queue_size=100)
    rospy.Subscriber(SYNC_TOPIC, String, heard, queue_size=100)
    if use_lidar:
        rospy.Subscriber(obstacles_topic, PointCloud2, obstacles, queue_size=1)
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
    clock: ShowClock | None = None
    rate = 1.0  # how fast the shared clock ran since the last tick (``~hold`` paced)
    waiting: tuple[float, bool] | None = None
    command = Twist()
    status = "waiting"
    start_logged = refusal_logged = False
    period = 1.0 / PUBLISH_HZ
    next_tick = time.monotonic()
    tick = 0
    while life.running:
        now = rospy.get_time()
        if tick % round(PUBLISH_HZ / CONTROL_HZ) == 0:
            with lock:
                if (not agreement.ready and network_ready.is_set()
                        and (cloud_seen.is_set() or not use_lidar)
                        and look_up_pose(now) is not None):
                    # ready when the network test passed and the sensors deliver: only
                    # then does the robot propose a start (and its safety watch begin)
                    agreement = agreement_ready(agreement, now + clock_offset)
                current = agreement
                arrived = latest_cloud.pop() if latest_cloud else None
            if current.show is not None:  # which show it runs, from the start on
                sync.publish(String(format_message(ShowMessage(role, *current.show))))
            proposal = current.message(now + clock_offset)
            if proposal is not None:
                sync.publish(String(format_message(proposal)))
            if current.refused is not None and not refusal_logged:
                log.error(f"{role}: refuses to start: {current.refused}")
                refusal_logged = True
            elapsed = show_time(current, now + clock_offset)
            if elapsed is not None and not start_logged:
                log.info(f"{role}: start agreed at {current.start!r} "
                         f"({current.strategy}), show time now {elapsed:.2f} s")
                start_logged = True
            command = Twist()
            if elapsed is not None:
                cloud: PointCloud | None = None
                if arrived is not None:  # stamps on the time since the start, as the brain's
                    cloud = obstacle_cloud(arrived[0] - (now - elapsed), arrived[1])
                shown, mates_heard = elapsed, None
                if together and elapsed >= 0.0:  # (the shared clock runs from the start)
                    with lock:
                        received, inbox[:] = list(inbox), []
                    before = clock
                    clock = clock_tick(clock_receive(
                        before or new_clock(role, brain.plan.robots, now - elapsed),
                        *received), now, state.holding_the_show, pace=state.pace)
                    rate = 1.0 if before is None else clock_rate(  # (paced brains)
                        clock.show_time - before.show_time, now - before.updated)
                    shown = clock.show_time
                    mates_heard = np.array(heard_positions(clock), dtype=float).reshape(-1, 2)
                    waiting = _report_wait(log, role, clock, before, waiting, now)
                pose = look_up_pose(now)
                leader = virtual_leader_pose(brain.plan, role, max(shown, 0.0))
                stamp = rospy.Time.from_sec(now)
                leader_frames.sendTransform([
                    transform_message(stamp, map_frame, vl_map,
                                      (show_frame.x, show_frame.y, show_frame.theta)),
                    transform_message(stamp, vl_map, leader_frame,
                                      (leader.x, leader.y, leader.theta))])
                state, cmd, happened = brain.step(state, shown, pose, cloud, clock=elapsed,
                                                  mates_heard=mates_heard, rate=rate)
                command.linear.x, command.angular.z = cmd.linear, cmd.angular
                if together:  # (from the agreement on: at the start every mate is heard)
                    hold_out.publish(String(format_hold(HoldMessage(
                        role, now, max(shown, 0.0), state.holding_the_show,
                        None if pose is None else brain.show_position(pose), state.pace))))
                for event in happened:
                    events_out.publish(String(f"{event.kind}: {event.text}"))
                    if event.kind == "speech":
                        sound.publish(say_request(event.text))
                    elif event.kind == "beep":
                        sound.publish(beep_request())
                    elif event.kind == "error":
                        log.error(f"{role}: {event.text}; stopped for good")
                if state.status != status:
                    log.info(f"{role}: {state.status} at show time {elapsed:.1f} s")
                    status = state.status
        cmd_vel.publish(command)
        tick += 1
        next_tick += period
        if next_tick < time.monotonic() - period:  # after a stall: no burst of ticks
            next_tick = time.monotonic()
        life.wait(next_tick - time.monotonic())
    cmd_vel.publish(Twist())


def _report_wait(log: QueuedLog, role: str, clock: ShowClock, before: ShowClock | None,
                 waiting: tuple[float, bool] | None, now: float) -> tuple[float, bool] | None:
    """Log once when the shared show clock has stood for a second, and when it runs again;
    ``waiting``: since when (s, the robot's clock) it stands and whether that was logged,
    None while it runs (returned updated)."""
    if before is None or clock.show_time > before.show_time:
        if waiting is not None and waiting[1]:
            log.info(f"{role}: the show goes on at show time {clock.show_time:.1f} s "
                     f"(it waited {now - waiting[0]:.1f} s)")
        return None
    since, told = (now, False) if waiting is None else waiting
    if not told and now - since >= 1.0:
        why = [m for m in clock.mates if m not in clock.heard
               or now - clock.heard[m].stamp > 1.0]
        held = [m for m, message in clock.heard.items() if message.holds]
        log.info(f"{role}: the show waits at show time {clock.show_time:.1f} s"
                 + (f" (not heard from {', '.join(why)})" if why else "")
                 + (f" (held by {', '.join(held)})" if held else ""))
        told = True
    return since, told


def _launch_detector(names: RobotNames) -> Any:
    """Start obstacle_detection beside this node through the roslaunch API (thesis ch. 3):
    the node's process alone (roslaunch.nodeprocess), not a whole ROSLaunch parent, whose
    XML-RPC server thread spins on its closed socket after ``stop()`` (the busy loop of
    issue 10). The process runs in a session of its own; it is stopped by the caller and
    ends by itself when this process dies (it watches its parent)."""
    import rosgraph
    import roslaunch.core
    import roslaunch.nodeprocess

    node = roslaunch.core.Node(
        "dancebots_ros", "obstacle_detection", name="obstacle_detection",
        namespace=rospy.get_namespace(), output="log",
        args=f"_robot_name:={names.prefix}" if names.prefix else "")
    node.machine = roslaunch.core.local_machine()
    process = roslaunch.nodeprocess.create_node_process(
        str(rospy.get_param("/run_id", "")), node, rosgraph.get_master_uri(),
        sigint_timeout=DETECTOR_SIGINT_TIMEOUT, sigterm_timeout=1.0)
    process.start()
    return process


if __name__ == "__main__":
    main()

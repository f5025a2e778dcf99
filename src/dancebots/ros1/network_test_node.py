"""The ``network_test`` node (thesis ch. 3, fig. 3.2): echo test on ``/sync``, then
``all_ready``. A thin rospy shell around ``sync.network_test``.

Parameters: ``~scenario`` (the show's file, for its list of robots), ``~role`` (this robot's
name in the scenario), ``~robot_name`` (optional prefix of its topics), ``~sync_delay`` and
``~sync_loss`` (test only: delay up to s / drop probability of every /sync message it sends,
injected in-process), ``~sync_seed`` (default: from the role).
Publishes ``/sync`` (std_msgs/String) at 10 Hz and ``[/robot_name]/all_ready``
(std_msgs/Bool, latched) once every robot has echoed it.
"""

from __future__ import annotations

import threading
import zlib

import rospy
from std_msgs.msg import Bool, String

from dancebots.ros1.common import DelayedPublisher, load_show, required_param
from dancebots.ros1.naming import SYNC_TOPIC, RobotNames
from dancebots.sync import (
    EchoMessage,
    SyncMessageError,
    format_message,
    network_test_receive,
    parse_message,
    start_network_test,
)

RATE_HZ = 10.0


def main() -> None:
    rospy.init_node("network_test")
    plan, _ = load_show(required_param("~scenario"))
    role = str(required_param("~role"))
    names = RobotNames(str(rospy.get_param("~robot_name", "")))
    try:
        test = start_network_test(role, plan.robots)
    except ValueError as exc:
        rospy.logfatal(str(exc))
        raise SystemExit(2) from None
    lock = threading.Lock()
    sync = DelayedPublisher(rospy.Publisher(SYNC_TOPIC, String, queue_size=100),
                            float(rospy.get_param("~sync_delay", 0.0)),
                            float(rospy.get_param("~sync_loss", 0.0)),
                            int(rospy.get_param("~sync_seed", zlib.crc32(role.encode()))))
    ready = rospy.Publisher(names.topic("all_ready"), Bool, queue_size=1, latch=True)
    ready.publish(Bool(False))

    def heard(message: String) -> None:
        nonlocal test
        try:
            parsed = parse_message(message.data)
        except SyncMessageError as exc:
            rospy.logwarn_throttle(5.0, str(exc))
            return
        if not isinstance(parsed, EchoMessage):
            return
        with lock:
            test, echo = network_test_receive(test, parsed)
        if echo is not None:
            sync.publish(String(format_message(echo)))

    rospy.Subscriber(SYNC_TOPIC, String, heard, queue_size=100)
    announced = False
    rate = rospy.Rate(RATE_HZ)
    while not rospy.is_shutdown():
        with lock:
            current = test
        if not current.ready:
            sync.publish(String(format_message(current.beacon())))
        elif not announced:
            rospy.loginfo(f"{role}: every robot answered; all ready")
            ready.publish(Bool(True))
            announced = True
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break


if __name__ == "__main__":
    main()

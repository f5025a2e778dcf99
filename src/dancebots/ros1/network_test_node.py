"""The ``network_test`` node (thesis ch. 3, fig. 3.2): echo test on ``/sync``, then
``all_ready``. A thin rospy shell around ``sync.network_test``.

Parameters: ``~scenario`` (the show's file, for its list of robots), ``~role`` (this robot's
name in the scenario), ``~robot_name`` (optional prefix of its topics), ``~sync_delay`` and
``~sync_loss`` (test only: delay up to s / drop probability of every /sync message it sends,
injected in-process), ``~sync_seed`` (default: from the role).
Publishes ``/sync`` (std_msgs/String) at 10 Hz and ``[/robot_name]/all_ready``
(std_msgs/Bool, latched) once every robot has echoed it. Ticks on the wall clock and ends on
SIGINT/SIGTERM even without its master (:class:`dancebots.ros1.common.NodeLife`).
"""

from __future__ import annotations

import threading

import rospy
from std_msgs.msg import Bool, String

from dancebots.ros1.common import (
    NodeLife,
    QueuedLog,
    load_show,
    parse_sync,
    required_param,
    sync_publisher,
)
from dancebots.ros1.naming import SYNC_TOPIC, RobotNames
from dancebots.sync import (
    EchoMessage,
    format_message,
    network_test_receive,
    start_network_test,
)

RATE_HZ = 10.0


def main() -> None:
    rospy.init_node("network_test", disable_signals=True)
    life = NodeLife()
    log = QueuedLog()
    plan, _ = load_show(required_param("~scenario"))
    role = str(required_param("~role"))
    names = RobotNames(str(rospy.get_param("~robot_name", "")))
    try:
        test = start_network_test(role, plan.robots)
    except ValueError as exc:
        rospy.logfatal(str(exc))
        raise SystemExit(2) from None
    lock = threading.Lock()
    sync = sync_publisher(role, 0)
    ready = rospy.Publisher(names.topic("all_ready"), Bool, queue_size=1, latch=True)
    ready.publish(Bool(False))

    def heard(message: String) -> None:
        nonlocal test
        parsed = parse_sync(message.data, log)
        if not isinstance(parsed, EchoMessage):
            return
        with lock:
            test, echo = network_test_receive(test, parsed)
        if echo is not None:
            sync.publish(String(format_message(echo)))

    rospy.Subscriber(SYNC_TOPIC, String, heard, queue_size=100)
    announced = False
    try:
        while life.wait(1.0 / RATE_HZ):
            with lock:
                current = test
            if not current.ready:
                sync.publish(String(format_message(current.beacon())))
            elif not announced:
                log.info(f"{role}: every robot answered; all ready")
                ready.publish(Bool(True))
                announced = True
    finally:
        log.flush()
        life.end()


if __name__ == "__main__":
    main()

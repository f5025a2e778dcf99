"""The ``obstacle_detection`` node (thesis 5.2): LIDAR cloud in, stop flags and flattened
obstacle points out. A thin rospy shell around ``perception.obstacles``.

Parameter ``~robot_name`` (optional prefix); robot size from ``[/robot_name]/length`` and
``/width`` (thesis ch. 3; default: the robot type of this host).
Subscribes ``[/robot_name]/points_filtered`` (sensor_msgs/PointCloud2 in ``base_link``).
Publishes, for every cloud: ``[/robot_name]/stop_front`` and ``/stop_rear`` (std_msgs/Bool:
an obstacle nearer than 55 cm to the front / rear) and ``[/robot_name]/obstacles``
(PointCloud2: the points cropped to 4 x 4 m, 0.1 m < z < 1.5 m, flattened to z = 0, with the
input's stamp and frame, so consumers can compensate the LIDAR's lag). A malformed cloud is
logged (at most every 5 s) and skipped. Ends on SIGINT/SIGTERM even without its master, and
when its parent process (formation_member, which starts it) dies.
"""

from __future__ import annotations

import socket

import numpy as np
import rospy
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import Bool

from dancebots.perception.obstacles import obstacle_points, stop_flags
from dancebots.ros1.common import NodeLife, QueuedLog
from dancebots.ros1.convert import MalformedCloudError, cloud_message, cloud_points
from dancebots.ros1.naming import RobotNames, robot_type_for_host


def main() -> None:
    rospy.init_node("obstacle_detection", disable_signals=True)
    life = NodeLife()
    log = QueuedLog()
    names = RobotNames(str(rospy.get_param("~robot_name", "")))
    kind = robot_type_for_host(socket.gethostname())
    length = float(rospy.get_param(names.param("length"), kind.length))
    width = float(rospy.get_param(names.param("width"), kind.width))
    front = rospy.Publisher(names.topic("stop_front"), Bool, queue_size=1)
    rear = rospy.Publisher(names.topic("stop_rear"), Bool, queue_size=1)
    flat = rospy.Publisher(names.topic("obstacles"), PointCloud2, queue_size=1)

    def detect(message: PointCloud2) -> None:
        try:
            points = obstacle_points(cloud_points(message))
        except MalformedCloudError as exc:
            log.warn(f"{names.topic('points_filtered')}: {exc}; skipped", every=5.0,
                     key="malformed cloud")
            return
        flags = stop_flags(points, length, width)
        front.publish(Bool(flags.front))
        rear.publish(Bool(flags.rear))
        flat.publish(cloud_message(np.column_stack([points, np.zeros(len(points))]),
                                   message.header))

    rospy.Subscriber(names.topic("points_filtered"), PointCloud2, detect, queue_size=1,
                     buff_size=2**22)
    try:
        while life.wait(0.2):
            pass
    finally:
        log.flush()
        life.end()


if __name__ == "__main__":
    main()

"""Run as a script by test_obstacle_detection.py: publishes one cloud on /T/points_filtered
and prints what obstacle_detection answers on /T/stop_front, /T/stop_rear, /T/obstacles."""

from __future__ import annotations

import json
import sys

import numpy as np
import rospy
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import Bool, Header

from dancebots.ros1.convert import cloud_message, cloud_points

answers: dict[str, object] = {}


def main() -> None:
    rospy.init_node("probe", disable_signals=True)
    points = np.array(json.loads(sys.argv[1]), dtype=float)
    rospy.Subscriber("/T/stop_front", Bool, lambda m: answers.setdefault("front", m.data))
    rospy.Subscriber("/T/stop_rear", Bool, lambda m: answers.setdefault("rear", m.data))
    rospy.Subscriber("/T/obstacles", PointCloud2, lambda m: answers.setdefault(
        "obstacles", {"points": cloud_points(m).tolist(), "stamp": m.header.stamp.to_sec(),
                      "frame": m.header.frame_id}))
    publisher = rospy.Publisher("/T/points_filtered", PointCloud2, queue_size=1, latch=True)
    header = Header(stamp=rospy.Time.from_sec(1234.5), frame_id="T/base_link")
    deadline = rospy.get_time() + 20.0
    while len(answers) < 3 and rospy.get_time() < deadline:
        publisher.publish(cloud_message(points, header))
        rospy.sleep(0.2)
    print(json.dumps(answers))


if __name__ == "__main__":
    main()

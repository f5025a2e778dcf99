"""Run as a script by test_ros_simulation.py: once a robot's ``points_filtered`` carries
clouds, publishes malformed PointCloud2 messages on its ``obstacles`` at 20 Hz (beside the
good ones of obstacle_detection) until SIGINT, as a broken second driver would; prints
"flooding T" (T: wall clock, s) when it starts. Argument: the robot's name (topic prefix)."""

from __future__ import annotations

import sys
import time

import rospy
from sensor_msgs.msg import PointCloud2, PointField
from std_msgs.msg import Header


def malformed(stamp: rospy.Time, frame: str) -> list[PointCloud2]:
    """Clouds whose sizes, fields or data do not fit (the cases of test_ros_messages)."""
    xyz = [PointField(name, 4 * k, PointField.FLOAT32, 1) for k, name in enumerate("xyz")]
    header = Header(stamp=stamp, frame_id=frame)
    return [
        PointCloud2(header=header, height=1, width=5, fields=xyz, point_step=12,
                    row_step=60, data=b""),
        PointCloud2(header=header, height=1, width=1, fields=xyz, point_step=4,
                    row_step=4, data=bytes(4)),
        PointCloud2(header=header, height=1, width=1, fields=xyz[:2], point_step=12,
                    row_step=12, data=bytes(12)),
        PointCloud2(header=header, height=4000, width=4000, fields=xyz, point_step=12,
                    row_step=48000, data=bytes(100)),
    ]


def main() -> None:
    robot = sys.argv[1]
    rospy.init_node("flood_malformed_clouds")
    seen = [False]
    rospy.Subscriber(f"/{robot}/points_filtered", PointCloud2,
                     lambda _: seen.__setitem__(0, True))
    flood = rospy.Publisher(f"/{robot}/obstacles", PointCloud2, queue_size=10)
    while not rospy.is_shutdown() and not seen[0]:
        time.sleep(0.05)
    print(f"flooding {time.time():.3f}", flush=True)
    rate = rospy.Rate(20.0)
    k = 0
    while not rospy.is_shutdown():
        clouds = malformed(rospy.Time.now(), f"{robot}/base_link")
        flood.publish(clouds[k % len(clouds)])
        k += 1
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break


if __name__ == "__main__":
    main()

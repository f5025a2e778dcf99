"""Run as a script by test_ros_simulation.py while a show runs: listens to /tf for the
virtual-leader frames of formation_member (R1/map -> R1/vl_map -> R1/virtual_leader) until
it is sent SIGTERM (or for at most argv[1] s), then prints, as JSON, each frame's parent and
the planar poses (x, y, theta) heard."""

from __future__ import annotations

import json
import math
import signal
import sys
import threading

import rospy
from tf2_msgs.msg import TFMessage

heard: dict[str, dict[str, object]] = {}
lock = threading.Lock()


def listen(message: TFMessage) -> None:
    for transform in message.transforms:
        child = transform.child_frame_id
        if child.endswith(("/vl_map", "/virtual_leader")):
            t, q = transform.transform.translation, transform.transform.rotation
            with lock:
                entry = heard.setdefault(child, {"parent": transform.header.frame_id,
                                                 "poses": []})
                poses = entry["poses"]
                assert isinstance(poses, list)
                poses.append((t.x, t.y, 2.0 * math.atan2(q.z, q.w)))


def main() -> None:
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    rospy.init_node("leader_frames_probe", disable_signals=True)
    subscriber = rospy.Subscriber("/tf", TFMessage, listen, queue_size=100)
    print("listening", flush=True)
    stop.wait(float(sys.argv[1]))
    subscriber.unregister()
    with lock:
        print(json.dumps(heard), flush=True)


if __name__ == "__main__":
    main()

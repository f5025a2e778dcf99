"""ROS 1 shells (thesis ch. 3): the ``network_test``, ``formation_member`` and
``obstacle_detection`` nodes, the simulator bridge, their launch files and message
conversion. Everything here only moves data between rospy and the pure core; importing this
package does not import rospy (the nodes do), so the core installs and runs without ROS.

The ROS package ``dancebots_ros`` (launch files, node executables) lives in
``ros1/package``; ``dancebots ros`` puts it on ``ROS_PACKAGE_PATH`` and runs ``roslaunch``.
"""

from dancebots.ros1.naming import RobotNames, robot_type_for_host

__all__ = ["RobotNames", "robot_type_for_host"]

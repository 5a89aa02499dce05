#!/usr/bin/env python3
"""rostest: the shipped launch files start, load their config files and publish."""
import sys
import time
import unittest

import rospy
import rostest
from sensor_msgs.msg import Imu
from tf2_msgs.msg import TFMessage


class LaunchFiles(unittest.TestCase):
    def collect(self, topic, n, timeout_s=60.0):  # a hang guard, not a speed limit
        msgs = []
        sub = rospy.Subscriber(topic, Imu, msgs.append)
        end = time.time() + timeout_s
        while len(msgs) < n and time.time() < end and not rospy.is_shutdown():
            time.sleep(0.05)
        sub.unregister()
        return msgs

    def test_standalone_node_from_imu_sim_launch(self):
        msgs = self.collect("/standalone/imu/data_raw", 200)
        self.assertGreaterEqual(len(msgs), 200)
        self.assertEqual(msgs[0].header.frame_id, "imu")
        self.assertEqual(msgs[0].orientation_covariance[0], -1.0)
        # crista_sim turns at 0.3 rad/s about z; config/imu_driver.yaml's sigma is on the diagonal.
        self.assertAlmostEqual(sum(m.angular_velocity.z for m in msgs) / len(msgs), 0.3, delta=0.02)
        self.assertAlmostEqual(msgs[0].angular_velocity_covariance[0], 0.005 ** 2, places=12)
        span = msgs[-1].header.stamp.to_sec() - msgs[0].header.stamp.to_sec()
        self.assertAlmostEqual((len(msgs) - 1) / span, 100.0, delta=5.0)

    def test_nodelet_in_manager_in_camera_frame(self):
        msgs = self.collect("/in_manager/imu/data_raw", 50)
        self.assertGreaterEqual(len(msgs), 50)
        self.assertEqual(msgs[0].header.frame_id, "camera_optical")  # identity rotation from config

    def test_camera_imu_static_tf(self):
        got = []
        sub = rospy.Subscriber("/tf_static", TFMessage, lambda m: got.extend(m.transforms))
        end = time.time() + 60.0
        while not any(t.child_frame_id == "imu" for t in got) and time.time() < end:
            time.sleep(0.05)
        sub.unregister()
        t = next(t for t in got if t.child_frame_id == "imu")
        self.assertEqual(t.header.frame_id, "camera_optical")
        self.assertAlmostEqual(t.transform.rotation.w, 1.0)


if __name__ == "__main__":
    rospy.init_node("test_launch_files")
    rostest.rosrun("imu_driver", "launch_files", LaunchFiles, sys.argv)

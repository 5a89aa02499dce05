#!/usr/bin/env python3
"""rostest: imu_driver's scripts as a user runs them, on bad input: a non-zero exit status and one
stderr line naming the file (or parameter) and what was wrong; a truncated bag is called truncated,
with `rosbag reindex` suggested. The bags are written here and cut."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rospkg
import rospy
import rostest
from sensor_msgs.msg import Imu

SCRIPTS = os.path.join(rospkg.RosPack().get_path("imu_driver"), "scripts")


def run(*args):
    p = subprocess.run([sys.executable] + list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       universal_newlines=True, timeout=120)  # a hang guard
    return p.returncode, p.stderr


class ScriptsCli(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="imu_driver_scripts_cli_")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def write_bag(self, name, n=300):
        path = os.path.join(self.dir, name)
        with rosbag.Bag(path, "w") as bag:
            for k in range(n):
                m = Imu()
                m.header.stamp = rospy.Time(1.0 + 0.01 * k)
                m.linear_acceleration.z = 9.81
                bag.write("imu/data_raw", m, m.header.stamp)
        return path

    def test_gyro_bias_report_on_a_truncated_bag(self):
        whole = self.write_bag("whole.bag")
        cut = os.path.join(self.dir, "cut.bag")
        with open(whole, "rb") as f:
            data = f.read()
        with open(cut, "wb") as f:
            f.write(data[:len(data) * 6 // 10])
        code, err = run(os.path.join(SCRIPTS, "gyro_bias_report.py"), cut, "--png", "")
        self.assertEqual(code, 1, err)
        self.assertEqual(err.count("\n"), 1, err)
        self.assertIn("gyro_bias_report: cannot read %s: the bag is truncated" % cut, err)
        self.assertIn("rosbag reindex %s" % cut, err)
        # The whole bag reads: still data, one static segment.
        code, err = run(os.path.join(SCRIPTS, "gyro_bias_report.py"), whole, "--png", "")
        self.assertEqual(code, 0, err)

    def test_gyro_bias_report_on_missing_and_malformed_files(self):
        missing = os.path.join(self.dir, "missing.bag")
        code, err = run(os.path.join(SCRIPTS, "gyro_bias_report.py"), missing, "--png", "")
        self.assertEqual(code, 1, err)
        self.assertIn("gyro_bias_report: cannot read %s" % missing, err)
        self.assertNotIn("Traceback", err)
        csv = os.path.join(self.dir, "short.csv")
        with open(csv, "w") as f:
            f.write("0.0,1,2,3\n0.01,1,2,3\n")
        code, err = run(os.path.join(SCRIPTS, "gyro_bias_report.py"), csv, "--png", "")
        self.assertEqual(code, 1, err)
        self.assertIn("%s: need 7 columns" % csv, err)
        self.assertNotIn("Traceback", err)

    def test_camera_imu_static_tf_refuses_a_bad_quaternion_with_exit_1(self):
        bad = os.path.join(self.dir, "camera_imu.yaml")
        with open(bad, "w") as f:
            f.write("camera_imu:\n  rotation_xyzw: [1.0, 1.0, 0.0, 0.0]\n")
        code, err = run(os.path.join(SCRIPTS, "camera_imu_static_tf.py"), bad)
        self.assertEqual(code, 1, err)
        self.assertIn(bad, err)
        code, err = run(os.path.join(SCRIPTS, "camera_imu_static_tf.py"), os.path.join(self.dir, "missing.yaml"))
        self.assertEqual(code, 1, err)
        self.assertNotIn("Traceback", err)
        code, err = run(os.path.join(SCRIPTS, "camera_imu_static_tf.py"))
        self.assertEqual(code, 2, err)  # no file given: usage

if __name__ == "__main__":
    rospy.init_node("test_scripts_cli", anonymous=True)
    rostest.rosrun("imu_driver", "scripts_cli", ScriptsCli, sys.argv)

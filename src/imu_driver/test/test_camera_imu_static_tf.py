#!/usr/bin/env python3
"""rostest: a camera-IMU calibration that cannot be used stops the launch with the file's name.

The node is run as roslaunch runs it; a zero quaternion, random bytes or a misspelt key give a message
naming the file (and the line and nearest key), exit status 1, and camera_imu_tf.launch (required node)
shuts down instead of running on without the IMU.
"""
import os
import subprocess
import sys
import tempfile
import unittest

import rospkg
import rostest
from rig_model.strict_yaml import FileError, check_keys, load_yaml_file

SCRIPT = os.path.join(rospkg.RosPack().get_path("imu_driver"), "scripts", "camera_imu_static_tf.py")
TMP = tempfile.mkdtemp(prefix="imu_driver_camera_imu_tf_")


def write(name, data):
    path = os.path.join(TMP, name)
    with open(path, "wb") as f:
        f.write(data)
    return path


def check(path):
    return subprocess.run([sys.executable, SCRIPT, "--check", path], capture_output=True, text=True)


class CameraImuStaticTf(unittest.TestCase):
    def refused(self, path, *expected):
        r = check(path)
        self.assertEqual(r.returncode, 1, r.stderr)
        for e in expected:
            self.assertIn(e, r.stderr)
        return r.stderr

    def test_shipped_files_load(self):
        # (ar_bringup's check_launch_files.py checks the files the launch files name.)
        r = check(os.path.join(rospkg.RosPack().get_path("imu_driver"), "config", "camera_imu.yaml"))
        self.assertEqual(r.returncode, 0, r.stderr)

    def test_zero_quaternion(self):
        path = write("zero.yaml", b"camera_imu:\n  parent_frame: camera_optical\n  rotation_xyzw: [0, 0, 0, 0]\n")
        self.refused(path, path + ":3: camera_imu.rotation_xyzw: must be a unit quaternion")

    def test_non_finite_quaternion(self):
        path = write("nan.yaml", b"camera_imu:\n  rotation_xyzw: [.nan, 0, 0, 1]\n")
        self.refused(path, path + ":2: camera_imu.rotation_xyzw: must be a list of 4 finite numbers")

    def test_absurd_lever_arm(self):
        path = write("lever.yaml", b"camera_imu:\n  rotation_xyzw: [0, 0, 0, 1]\n  translation_m: [2, 8, -6]\n")
        self.refused(path, path + ":3: camera_imu.translation_m: is the IMU's origin", "more than 1 m")

    def test_random_bytes(self):
        path = write("random.yaml", bytes([0xfe, 0xff, 0x00, 0x13, 0x80]) + b"garbage")
        err = self.refused(path, path + ": not a text file (invalid UTF-8 at byte 0); expected YAML")
        self.assertNotIn("codec", err)

    def test_misspelt_key(self):
        path = write("misspelt.yaml", b"camera_imu:\n  parent_frame: camera_optical\n  rotaton_xyzw: [0, 0, 0, 1]\n")
        self.refused(path, path + ":3: unknown key 'camera_imu.rotaton_xyzw' (did you mean 'rotation_xyzw'?)")

    def test_missing_file(self):
        self.refused(os.path.join(TMP, "absent.yaml"), os.path.join(TMP, "absent.yaml") + ": cannot open the file")

    def test_the_launch_stops(self):
        """camera_imu_tf.launch's node is required: its exit ends roslaunch, with the file named."""
        path = write("launch_zero.yaml", b"camera_imu:\n  rotation_xyzw: [0, 0, 0, 0]\n")
        # Returns once roslaunch has shut down (the test's time-limit bounds a launch that would not).
        r = subprocess.run(["roslaunch", "imu_driver", "camera_imu_tf.launch", "camera_imu:=" + path],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.assertIn(path + ":2: camera_imu.rotation_xyzw: must be a unit quaternion", r.stdout)
        self.assertIn("REQUIRED process [camera_imu_static_tf", r.stdout)

    def test_gyro_calibration(self):
        """The 3.2.1 file the driver reads is checked by the same required node."""
        good = write("good.yaml", b"camera_imu:\n  rotation_xyzw: [0, 0, 0, 1]\n")
        gyro = write("gyro.yaml", b"# bias\ngyro_bias_rad_s: [0.01, 0, 0]\ngyro_nose_sigma_rad_s: [0.001, 0, 0]\n")
        r = subprocess.run([sys.executable, SCRIPT, "--check", good, gyro], capture_output=True, text=True)
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertIn(gyro + ":3: unknown key 'gyro_nose_sigma_rad_s' (did you mean 'gyro_noise_sigma_rad_s'?)",
                      r.stderr)
        shipped = os.path.join(rospkg.RosPack().get_path("imu_driver"), "config", "gyro_calibration.yaml")
        r = subprocess.run([sys.executable, SCRIPT, "--check", good, shipped], capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stderr)
        # A broken gyro calibration stops the launch too.
        rnd = write("gyro_random.yaml", bytes([0xfe, 0x00, 0x81]))
        r = subprocess.run(["roslaunch", "imu_driver", "camera_imu_tf.launch", "camera_imu:=" + good,
                            "gyro_calibration:=" + rnd], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.assertIn(rnd + ": not a text file (invalid UTF-8 at byte 0); expected YAML", r.stdout)
        self.assertIn("REQUIRED process [camera_imu_static_tf", r.stdout)

    def test_python_helper(self):
        path = write("helper.yaml", b"top:\n  height_m: 1\n  hieght_m: 2\n")
        data = load_yaml_file(path)
        with self.assertRaises(FileError) as e:
            check_keys(path, data["top"], ["height_m", "radius_m"], "top")
        self.assertEqual(str(e.exception), path + ":3: unknown key 'top.hieght_m' (did you mean 'height_m'?)")
        with self.assertRaises(FileError) as e:
            check_keys(path, data, ["cones"])
        self.assertEqual(str(e.exception), path + ":1: unknown key 'top'; known keys: cones")
        with self.assertRaises(FileError) as e:
            load_yaml_file(write("broken.yaml", b"a: [1\n"))
        self.assertIn("broken.yaml:2: not valid YAML", str(e.exception))


if __name__ == "__main__":
    rostest.rosrun("imu_driver", "camera_imu_static_tf", CameraImuStaticTf, sys.argv)

#!/usr/bin/env python3
"""Publishes the camera-IMU rotation (thesis 3.2.2) and lever arm as a static tf.

Usage: camera_imu_static_tf.py [--check] CAMERA_IMU_YAML [GYRO_CALIBRATION_YAML]
The first file is calibrate_camera_imu's output (camera_imu: {parent_frame, child_frame,
translation_m, rotation_xyzw, ...}); the optional second is the 3.2.1 gyro calibration the driver
reads (gyro_bias_rad_s, gyro_noise_sigma_rad_s), checked here too because this node is the one the
launch files mark required. A file that cannot be used (unreadable, not YAML, an unknown key, a
rotation that is not a unit quaternion, a value that is not 3 finite numbers) is refused with a
message naming the file, and the node exits with status 1, so roslaunch stops instead of running
without the IMU. With --check it only checks the files (exit 0 or 1) and needs no ROS master.
"""
import math
import sys

import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped
from rig_model.strict_yaml import FileError, check_keys, fail, load_yaml_file, numbers, string

# calibrate_camera_imu writes the first four; the others are its report, read by people.
CAMERA_IMU_KEYS = ["parent_frame", "child_frame", "translation_m", "rotation_xyzw", "method", "rms_residual_deg",
                   "euler_minimisation_rotation_xyzw", "euler_minimisation_rms_residual_deg", "svd_vs_euler_deg",
                   "poses"]


# A lever arm longer than this is a broken calibration (pose_ekf refuses it too).
MAX_LEVER_ARM_M = 1.0


def read_camera_imu(path):
    """(parent_frame, child_frame, translation_m, rotation_xyzw) from the file; raises FileError."""
    root = load_yaml_file(path)
    check_keys(path, root, ["camera_imu"])
    if "camera_imu" not in root:
        fail(path, root, "camera_imu", "is missing")
    c = root["camera_imu"]
    check_keys(path, c, CAMERA_IMU_KEYS, "camera_imu")
    parent = string(path, c, "camera_imu", "parent_frame", "camera_optical")
    child = string(path, c, "camera_imu", "child_frame", "imu")
    t = numbers(path, c, "camera_imu", "translation_m", 3, [0.0, 0.0, 0.0])
    length = math.sqrt(sum(v * v for v in t))
    if length > MAX_LEVER_ARM_M:  # pose_ekf's kMaxLeverArmM
        fail(path, c, "camera_imu.translation_m",
             "is the IMU's origin in %s in metres; %s is %.3g m long, more than %g m: not a rig (centimetres?)"
             % ("camera_optical", t, length, MAX_LEVER_ARM_M), "translation_m")
    q = numbers(path, c, "camera_imu", "rotation_xyzw", 4)
    norm = math.sqrt(sum(v * v for v in q))
    if abs(norm - 1.0) > 1e-3:
        fail(path, c, "camera_imu.rotation_xyzw",
             "must be a unit quaternion [x, y, z, w], got %s (norm %.6g)" % (q, norm), "rotation_xyzw")
    return parent, child, t, [v / norm for v in q]


# imu_driver's calibration_files.cpp reads the same keys (GyroCalibrationKeys()).
GYRO_CALIBRATION_KEYS = ["gyro_bias_rad_s", "gyro_noise_sigma_rad_s", "gyro_calibration_source"]


def check_gyro_calibration(path):
    """Raises FileError unless the 3.2.1 gyro calibration file is usable."""
    root = load_yaml_file(path)
    if root is None:
        return  # comments only: the driver runs uncalibrated and says so
    check_keys(path, root, GYRO_CALIBRATION_KEYS)
    numbers(path, root, "", "gyro_bias_rad_s", 3, [0.0, 0.0, 0.0])
    sigma = numbers(path, root, "", "gyro_noise_sigma_rad_s", 3, [0.0, 0.0, 0.0])
    if min(sigma) < 0.0:
        fail(path, root, "gyro_noise_sigma_rad_s", "must be 3 finite numbers >= 0", "gyro_noise_sigma_rad_s")


def main(argv):
    check_only = len(argv) > 1 and argv[1] == "--check"
    files = argv[2:] if check_only else argv[1:]
    if len(files) not in (1, 2):
        sys.stderr.write("usage: camera_imu_static_tf.py [--check] CAMERA_IMU_YAML [GYRO_CALIBRATION_YAML]\n")
        return 2
    path = files[0]
    try:
        parent, child, t, q = read_camera_imu(path)
        if len(files) == 2:
            check_gyro_calibration(files[1])
    except FileError as e:
        sys.stderr.write("camera_imu_static_tf: a calibration cannot be used: %s\n" % e)
        return 1  # before init_node: a refused file needs no ROS master to say so
    if check_only:
        return 0

    rospy.init_node("camera_imu_static_tf")
    msg = TransformStamped()
    msg.header.stamp = rospy.Time.now()
    msg.header.frame_id = parent
    msg.child_frame_id = child
    msg.transform.translation.x, msg.transform.translation.y, msg.transform.translation.z = t
    r = msg.transform.rotation
    r.x, r.y, r.z, r.w = q
    broadcaster = tf2_ros.StaticTransformBroadcaster()
    broadcaster.sendTransform(msg)
    rospy.loginfo("static tf %s -> %s from %s: rotation %s, translation %s m", parent, child, path, q, t)
    rospy.spin()
    return 0


if __name__ == "__main__":
    sys.exit(main(rospy.myargv(sys.argv)))

#!/usr/bin/env python3
"""Publishes the camera-IMU rotation (thesis 3.2.2) as a static tf.

Reads ~camera_imu/{parent_frame, child_frame, translation_m, rotation_xyzw}, i.e. the YAML
written by calibrate_camera_imu loaded into this node's private namespace.
"""
import sys

import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped


def main():
    rospy.init_node("camera_imu_static_tf")
    c = rospy.get_param("~camera_imu", None)
    if not isinstance(c, dict) or "rotation_xyzw" not in c:
        rospy.logfatal("%s: ~camera_imu/rotation_xyzw is not set (load config/camera_imu.yaml into ~camera_imu)",
                       rospy.get_name())
        sys.exit(1)
    q = c["rotation_xyzw"]
    t = c.get("translation_m", [0.0, 0.0, 0.0])
    if len(q) != 4 or abs(sum(v * v for v in q) - 1.0) > 1e-3:
        rospy.logfatal("~camera_imu/rotation_xyzw must be a unit quaternion [x, y, z, w], got %s", q)
        sys.exit(1)
    if len(t) != 3:
        rospy.logfatal("~camera_imu/translation_m must be [x, y, z] in metres, got %s", t)
        sys.exit(1)
    msg = TransformStamped()
    msg.header.stamp = rospy.Time.now()
    msg.header.frame_id = c.get("parent_frame", "camera_optical")
    msg.child_frame_id = c.get("child_frame", "imu")
    msg.transform.translation.x, msg.transform.translation.y, msg.transform.translation.z = t
    r = msg.transform.rotation
    r.x, r.y, r.z, r.w = q
    broadcaster = tf2_ros.StaticTransformBroadcaster()
    broadcaster.sendTransform(msg)
    rospy.loginfo("static tf %s -> %s: rotation %s", msg.header.frame_id, msg.child_frame_id, q)
    rospy.spin()


if __name__ == "__main__":
    main()

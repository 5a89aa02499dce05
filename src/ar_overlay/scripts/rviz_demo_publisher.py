#!/usr/bin/env python3
"""Stands in for the rig while the other packages are not there: the camera circling three cones
(tf cones -> camera_optical), a grey camera image + camera_info for the overlay nodelet, the cones
as markers, a noisy single-frame camera pose and a smoother EKF pose, both with covariance, and
the EKF odometry. For the rviz config and its screenshot (rviz_screenshot.sh); not the real
pipeline's numbers."""
import math

import numpy as np
import rospy
import tf2_ros
from geometry_msgs.msg import PoseWithCovarianceStamped, TransformStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import CameraInfo, Image
from visualization_msgs.msg import Marker, MarkerArray

W, H, F = 640, 480, 520.0
CONES = [(0.6, 0.0), (-0.3, 0.52), (-0.3, -0.52)]  # x toward cone 1, origin at the centroid


def look_at(eye, target):
    """T_cones_camera (rotation matrix, translation) for an optical frame at eye looking at target."""
    z = np.subtract(target, eye)
    z = z / np.linalg.norm(z)
    x = np.cross(z, [0, 0, 1.0])
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z]), np.asarray(eye, float)


def quat(R):
    w = math.sqrt(max(1e-12, 1 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    return ((R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w), w)


def set_pose(p, t, q):
    p.position.x, p.position.y, p.position.z = t
    p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w = q


def covariance(sigma_m, sigma_rad):
    c = np.zeros((6, 6))
    c[:3, :3] = np.diag([sigma_m ** 2, (0.6 * sigma_m) ** 2, (1.5 * sigma_m) ** 2])
    c[3:, 3:] = np.eye(3) * sigma_rad ** 2
    return c.flatten().tolist()


def cone_markers():
    arr = MarkerArray()
    for i, (x, y) in enumerate(CONES):
        m = Marker(type=Marker.CYLINDER, action=Marker.ADD, id=i, ns="cones")
        m.header.frame_id = "cones"
        m.pose.position.x, m.pose.position.y, m.pose.position.z = x, y, 0.23
        m.pose.orientation.w = 1.0
        m.scale.x = m.scale.y = 0.2
        m.scale.z = 0.46
        m.color.r, m.color.g, m.color.b, m.color.a = 1.0, 0.45, 0.0, 1.0
        arr.markers.append(m)
    return arr


def main():
    rospy.init_node("rviz_demo_publisher")
    tf = tf2_ros.TransformBroadcaster()
    pubs = {
        "image": rospy.Publisher("camera/image_raw", Image, queue_size=2),
        "info": rospy.Publisher("camera/camera_info", CameraInfo, queue_size=2),
        "cones": rospy.Publisher("rig_sim/cones", MarkerArray, queue_size=1, latch=True),
        "meas": rospy.Publisher("cone_tracker/pose", PoseWithCovarianceStamped, queue_size=5),
        "ekf": rospy.Publisher("pose_ekf/pose", PoseWithCovarianceStamped, queue_size=5),
        "odom": rospy.Publisher("pose_ekf/odometry", Odometry, queue_size=5),
    }
    pubs["cones"].publish(cone_markers())
    rng = np.random.default_rng(1)
    rows = np.linspace(70, 150, H, dtype=np.uint8)[:, None, None]
    pixels = np.broadcast_to(rows, (H, W, 3)).astype(np.uint8).tobytes()
    rate = rospy.Rate(20)
    t0 = rospy.Time.now()
    while not rospy.is_shutdown():
        now = rospy.Time.now()
        a = 0.25 * (now - t0).to_sec()
        R, t = look_at((1.6 * math.cos(a), 1.6 * math.sin(a), 0.9 + 0.15 * math.sin(2 * a)), (0, 0, 0.25))
        q = quat(R)
        ts = TransformStamped()
        ts.header.stamp, ts.header.frame_id, ts.child_frame_id = now, "cones", "camera_optical"
        ts.transform.translation.x, ts.transform.translation.y, ts.transform.translation.z = t
        ts.transform.rotation.x, ts.transform.rotation.y, ts.transform.rotation.z, ts.transform.rotation.w = q
        tf.sendTransform(ts)
        img = Image(height=H, width=W, encoding="rgb8", step=3 * W, data=pixels)
        img.header.stamp, img.header.frame_id = now, "camera_optical"
        info = CameraInfo(height=H, width=W, distortion_model="plumb_bob", D=[0.0] * 5,
                          K=[F, 0, W / 2 - 0.5, 0, F, H / 2 - 0.5, 0, 0, 1])
        info.header = img.header
        pubs["image"].publish(img)
        pubs["info"].publish(info)
        for key, sigma, noise in (("meas", 0.05, 0.04), ("ekf", 0.02, 0.005)):
            m = PoseWithCovarianceStamped()
            m.header.stamp, m.header.frame_id = now, "cones"
            set_pose(m.pose.pose, t + rng.normal(0, noise, 3), q)
            m.pose.covariance = covariance(sigma, 0.05)
            pubs[key].publish(m)
        odom = Odometry()
        odom.header.stamp, odom.header.frame_id, odom.child_frame_id = now, "cones", "camera_optical"
        set_pose(odom.pose.pose, t, q)
        pubs["odom"].publish(odom)
        rate.sleep()


if __name__ == "__main__":
    main()

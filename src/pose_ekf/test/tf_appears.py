#!/usr/bin/python3
"""rostest: feed pose_ekf a few camera poses and IMU samples; tf and topics must appear."""
import math
import unittest

import dynamic_reconfigure.client
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import PoseWithCovarianceStamped, TransformStamped
from diagnostic_msgs.msg import DiagnosticArray
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu


class TfAppears(unittest.TestCase):
    def setUp(self):
        self.odom = None
        self.pose = None
        self.diagnostics = {}
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics)
        rospy.Subscriber("pose_ekf/odometry", Odometry, lambda m: setattr(self, "odom", m))
        rospy.Subscriber("pose_ekf/pose", PoseWithCovarianceStamped, lambda m: setattr(self, "pose", m))
        self.cam_pub = rospy.Publisher("cone_tracker/pose", PoseWithCovarianceStamped, queue_size=10)
        self.imu_pub = rospy.Publisher("imu/data_raw", Imu, queue_size=100)
        # The camera-IMU rotation (3.2.2) as a static transform: IMU x = camera z.
        self.static = tf2_ros.StaticTransformBroadcaster()
        t = TransformStamped()
        t.header.stamp = rospy.Time.now()
        t.header.frame_id = "camera_optical"
        t.child_frame_id = "imu"
        t.transform.rotation.w = math.sqrt(0.5)
        t.transform.rotation.y = -math.sqrt(0.5)
        self.static.sendTransform(t)
        self.buffer = tf2_ros.Buffer()
        self.listener = tf2_ros.TransformListener(self.buffer)

    def on_diagnostics(self, msg):
        for status in msg.status:
            self.diagnostics[status.name] = {kv.key: kv.value for kv in status.values}

    def camera(self, stamp):
        m = PoseWithCovarianceStamped()
        m.header.stamp = stamp
        m.header.frame_id = "cones"
        m.pose.pose.position.x, m.pose.pose.position.y, m.pose.pose.position.z = 0.2, -2.0, 1.2
        m.pose.pose.orientation.w = 1.0
        for i in range(6):
            m.pose.covariance[7 * i] = 1e-4
        return m

    def imu(self, stamp):
        m = Imu()
        m.header.stamp = stamp
        m.header.frame_id = "imu"
        m.orientation_covariance[0] = -1.0
        m.linear_acceleration.z = 9.80665  # in the imu frame; rotated into the camera by tf
        return m

    def test_tf_and_topics_appear(self):
        # Until the nodelet has subscribed (a condition; 60 s is a hang guard).
        deadline = rospy.Time.now() + rospy.Duration(60.0)
        while (self.cam_pub.get_num_connections() == 0 or self.imu_pub.get_num_connections() == 0) and \
                rospy.Time.now() < deadline and not rospy.is_shutdown():
            rospy.sleep(0.05)
        rate = rospy.Rate(100)
        for i in range(200):
            now = rospy.Time.now()
            if i % 3 == 0:
                self.cam_pub.publish(self.camera(now))
            self.imu_pub.publish(self.imu(now))
            rate.sleep()
        tf = self.buffer.lookup_transform("cones", "camera_optical", rospy.Time(0), rospy.Duration(60.0))
        self.assertAlmostEqual(tf.transform.translation.y, -2.0, delta=0.05)
        deadline = rospy.Time.now() + rospy.Duration(60.0)  # hang guards, not speed limits
        while (self.odom is None or self.pose is None) and rospy.Time.now() < deadline:
            rospy.sleep(0.05)
        self.assertIsNotNone(self.pose, "no pose_ekf/pose")
        self.assertIsNotNone(self.odom, "no pose_ekf/odometry")
        self.assertEqual(self.odom.child_frame_id, "camera_optical")
        self.assertEqual(self.pose.header.frame_id, "cones")
        # Until the filter's diagnostics count the camera updates: a status published while the nodelet
        # still worked through its queue counts fewer.
        deadline = rospy.Time.now() + rospy.Duration(60.0)
        filter_status = None
        while rospy.Time.now() < deadline:
            filter_status = next((v for k, v in self.diagnostics.items() if k.endswith("filter")), None)
            if filter_status is not None and int(filter_status["camera updates"]) > 10:
                break
            rospy.sleep(0.1)
        self.assertIsNotNone(filter_status, "no pose_ekf filter diagnostics; got %s" % list(self.diagnostics))
        self.assertGreater(int(filter_status["camera updates"]), 10)
        self.assertEqual(filter_status["camera poses rejected (chi2 gate)"], "0")  # good poses pass the gate
        self.assertEqual(filter_status["re-initialisations (chi2 gate)"], "0")
        self.assertEqual(int(filter_status["NaN rejected"]), 0)

    def test_reconfigure_switches_and_noise(self):
        client = dynamic_reconfigure.client.Client("pose_ekf", timeout=10)
        self.assertAlmostEqual(client.get_configuration(timeout=5)["sigma_gyro_rad_s"], 0.01)  # from the yaml
        applied = client.update_configuration({"sigma_gyro_rad_s": 0.02, "use_accel": False})
        self.assertAlmostEqual(applied["sigma_gyro_rad_s"], 0.02)
        self.assertFalse(applied["use_accel"])


if __name__ == "__main__":
    rospy.init_node("pose_ekf_tf_test")
    rostest.rosrun("pose_ekf", "tf_appears", TfAppears)

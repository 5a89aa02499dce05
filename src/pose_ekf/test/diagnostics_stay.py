#!/usr/bin/python3
"""rostest: a refused pose_ekf config and a dead IMU path (no camera-IMU tf) show as ERROR on /diagnostics."""
import threading
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from sensor_msgs.msg import Imu


class DiagnosticsStay(unittest.TestCase):
    def setUp(self):
        self.lock = threading.Lock()
        self.last = {}   # status name -> DiagnosticStatus
        self.count = {}  # status name -> messages seen
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics)
        self.imu_pub = rospy.Publisher("no_tf/imu", Imu, queue_size=100)

    def on_diagnostics(self, msg):
        with self.lock:
            for s in msg.status:
                self.last[s.name] = s
                self.count[s.name] = self.count.get(s.name, 0) + 1

    def wait_for(self, predicate, iterations=3000, each=None):
        """Polls predicate every 20 ms, at most `iterations` times (a bound, not a timing assertion)."""
        for _ in range(iterations):
            if rospy.is_shutdown():
                break
            if each:
                each()
            with self.lock:
                if predicate():
                    return True
            rospy.sleep(0.02)
        with self.lock:
            return predicate()

    def test_refused_config_is_an_error_naming_the_parameter(self):
        name = "pose_ekf_refused: filter"
        self.assertTrue(self.wait_for(lambda: self.count.get(name, 0) >= 3), "no repeated %s status" % name)
        with self.lock:
            s = self.last[name]
            names = [n for n in self.count if n.startswith("pose_ekf_refused:")]
        self.assertEqual(s.level, DiagnosticStatus.ERROR, s.message)
        self.assertIn("sigma_gyro_rad_s", s.message)
        self.assertIn("not started", s.message)
        self.assertNotIn("; ;", s.message)
        self.assertFalse(s.message.rstrip().endswith(";"), s.message)
        self.assertEqual(names, [name], "a refused component publishes only its refusal")

    def test_imu_without_tf_is_an_error(self):
        name = "pose_ekf_no_tf: filter"
        stamp = [rospy.Time.now()]

        def feed():
            m = Imu()
            stamp[0] += rospy.Duration(0.01)
            m.header.stamp, m.header.frame_id = stamp[0], "imu_without_tf"
            m.orientation_covariance[0] = -1
            m.linear_acceleration.z = 9.81
            self.imu_pub.publish(m)

        def dropped():
            s = self.last.get(name)
            return s is not None and s.level == DiagnosticStatus.ERROR and "dropped" in s.message
        self.assertTrue(self.wait_for(dropped, each=feed), "IMU samples dropped without an ERROR on %s" % name)
        with self.lock:
            s = self.last[name]
        self.assertIn("imu_without_tf", s.message)
        values = {kv.key: kv.value for kv in s.values}
        self.assertGreater(int(values["IMU without camera-IMU tf"]), 0)


if __name__ == "__main__":
    rospy.init_node("pose_ekf_diagnostics_stay")
    rostest.rosrun("pose_ekf", "diagnostics_stay", DiagnosticsStay)

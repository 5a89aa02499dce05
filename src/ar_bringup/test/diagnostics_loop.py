#!/usr/bin/python3
"""rostest (test/diagnostics_loop.test): /diagnostics survive rosbag play's loop jumps.

Counts the loops by the IMU stamps jumping back (rosbag play's /clock lags far behind on a loaded
machine, as the player only publishes it while it waits, so the clock may barely jump); after the first one, every nodelet's main status must arrive again several
times, the jump must be counted, and the EKF's IMU rate (of stamps) must be the bag's rate. The wait is
bounded by the number of loops played (max_loops), so a slow machine only makes it slower.
"""
import threading
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import Imu

STATUSES = ["cone_tracker: tracker", "pose_ekf: filter", "ar_overlay: overlay", "pose_ekf: imu input"]
AFTER_JUMP = 3  # statuses of each name required after the first jump


class DiagnosticsLoop(unittest.TestCase):
    def setUp(self):
        self.lock = threading.Condition()
        self.max_loops = rospy.get_param("~max_loops", 5)
        self.jumps = 0
        self.last_stamp = None
        self.after_jump = {}  # status name -> count received after the first jump
        self.last = {}        # status name -> {key: value}, with level and message
        rospy.Subscriber("imu/data_raw", Imu, self.on_imu, queue_size=200)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics)

    def on_imu(self, msg):
        with self.lock:
            t = msg.header.stamp.to_sec()
            if self.last_stamp is not None and t < self.last_stamp - 1.0:
                self.jumps += 1
            self.last_stamp = t

    def on_diagnostics(self, msg):
        with self.lock:
            for s in msg.status:
                values = {kv.key: kv.value for kv in s.values}
                values["level"], values["message"] = s.level, s.message
                self.last[s.name] = values
                if self.jumps >= 1:
                    self.after_jump[s.name] = self.after_jump.get(s.name, 0) + 1
            self.lock.notify_all()

    def done(self):
        if self.jumps < 1 or any(self.after_jump.get(n, 0) < AFTER_JUMP for n in STATUSES):
            return False
        return (int(self.last["pose_ekf: filter"].get("time jumps back", 0)) >= 1 and
                int(self.last["cone_tracker: tracker"].get("time jumps back", 0)) >= 1)

    def test_diagnostics_survive_the_loop(self):
        # Bounded by loops of the bag, not by seconds (rospy.sleep would raise at each jump of sim time);
        # the condition is woken by every /diagnostics message.
        with self.lock:
            while not rospy.is_shutdown() and not self.done() and self.jumps < self.max_loops:
                self.lock.wait(0.5)
        with self.lock:
            jumps, after, last = self.jumps, dict(self.after_jump), dict(self.last)
        self.assertGreaterEqual(jumps, 1, "the bag never looped (no IMU stamp jumped back)")
        for name in STATUSES:
            self.assertGreaterEqual(after.get(name, 0), AFTER_JUMP,
                                    "%s: %d statuses after the first jump (in %d loops)" % (name, after.get(name, 0), jumps))
        self.assertGreaterEqual(int(last["pose_ekf: filter"]["time jumps back"]), 1, last["pose_ekf: filter"])
        self.assertGreaterEqual(int(last["cone_tracker: tracker"]["time jumps back"]), 1, last["cone_tracker: tracker"])
        imu = last["pose_ekf: imu input"]
        self.assertEqual(imu["rate measured"], "True", imu)
        self.assertAlmostEqual(float(imu["rate of stamps (Hz)"]), 100.0, delta=20.0, msg=imu)
        self.assertGreaterEqual(int(imu["stamp jumps back"]), 1, imu)


if __name__ == "__main__":
    rospy.init_node("diagnostics_loop_test")
    rostest.rosrun("ar_bringup", "diagnostics_loop", DiagnosticsLoop)

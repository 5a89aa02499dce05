#!/usr/bin/env python3
"""rig_check's checks and the master-URI warning on synthetic inputs (no pipeline, no timing)."""
import os
import subprocess
import unittest

from ar_bringup import master_uri
from ar_bringup import rig_check as rc


def stamps(rate_hz, n, t0=100.0):
    return [t0 + i / rate_hz for i in range(n)]


class RateTest(unittest.TestCase):
    def test_rate_from_stamps(self):
        self.assertAlmostEqual(rc.rate_from_stamps(stamps(30.0, 31)), 30.0)
        self.assertIsNone(rc.rate_from_stamps([1.0]))
        self.assertIsNone(rc.rate_from_stamps([1.0, 1.0]))

    def test_camera_rate_within_10_percent(self):
        self.assertEqual(rc.check_rate("r", "t", stamps(28.0, 100), 30.0, 0.10, "fix").level, rc.PASS)
        r = rc.check_rate("r", "camera/image_raw", stamps(25.0, 100), 30.0, 0.10, "fix")
        self.assertEqual(r.level, rc.FAIL)
        self.assertIn("25.0 Hz", r.detail)
        self.assertEqual(r.fix, "fix")

    def test_dropped_frames_lower_the_rate(self):
        s = stamps(100.0, 1000)
        del s[::5]  # every 5th sample lost: 80 Hz
        self.assertEqual(rc.check_rate("IMU rate", "imu", s, 100.0, 0.05, "f").level, rc.FAIL)
        self.assertEqual(rc.check_rate("IMU rate", "imu", stamps(96.0, 500), 100.0, 0.05, "f").level, rc.PASS)

    def test_no_messages(self):
        r = rc.check_rate("IMU rate", "imu/data_raw", [], 100.0, 0.05, "f")
        self.assertEqual(r.level, rc.FAIL)
        self.assertIn("0 message(s) on imu/data_raw", r.detail)
        self.assertEqual(rc.check_camera_found(0, "camera/image_raw").level, rc.FAIL)
        self.assertEqual(rc.check_camera_found(3, "camera/image_raw").level, rc.PASS)


class CalibrationTest(unittest.TestCase):
    def info(self, K, model="plumb_bob"):
        return {"K": K, "D": [0.0] * 5, "distortion_model": model, "width": 640, "height": 480}

    def test_default_camera_info_fails(self):
        r = rc.check_camera_info(self.info([0.0] * 9, ""))
        self.assertEqual(r.level, rc.FAIL)
        self.assertIn("default", r.detail)
        self.assertIn("camera_info_url", r.fix)
        self.assertEqual(rc.check_camera_info(None).level, rc.FAIL)

    def test_calibrated(self):
        self.assertEqual(rc.check_camera_info(self.info([500, 0, 320, 0, 500, 240, 0, 0, 1])).level, rc.PASS)
        r = rc.check_camera_info(self.info([500, 0, 900, 0, 500, 240, 0, 0, 1]))
        self.assertEqual(r.level, rc.FAIL)
        self.assertIn("principal point", r.detail)

    def test_gyro(self):
        self.assertEqual(rc.check_gyro_calibrated(True).level, rc.PASS)
        self.assertEqual(rc.check_gyro_calibrated(False).level, rc.FAIL)
        r = rc.check_gyro_calibrated(None)
        self.assertEqual(r.level, rc.FAIL)
        self.assertIn("imu/calibrate", r.fix)


class CounterTest(unittest.TestCase):
    def test_growing_counter_fails(self):
        d = [{"missing packets": "3"}, {"missing packets": "3"}, {"missing packets": "10"}]
        r = rc.check_counter("camera packets", d, "missing packets", "missing packets", "cable")
        self.assertEqual(r.level, rc.FAIL)
        self.assertIn("7 missing packets", r.detail)

    def test_steady_counter_passes(self):
        d = [{"rejected: bad CRC": "2"}, {"rejected: bad CRC": "2"}]
        self.assertEqual(rc.check_counter("crc", d, "rejected: bad CRC", "bad CRC", "f").level, rc.PASS)

    def test_missing_diagnostics(self):
        r = rc.check_counter("camera packets", [], "missing packets", "x", "f", missing_detail="no driver")
        self.assertEqual((r.level, r.detail), (rc.WARN, "no driver"))
        self.assertEqual(rc.check_counter("c", [{"other": "1"}], "missing packets", "x", "f").level, rc.WARN)


class SceneTest(unittest.TestCase):
    def test_tf(self):
        self.assertEqual(rc.check_tf(True, "camera_optical", "imu").level, rc.PASS)
        r = rc.check_tf(False, "camera_optical", "imu", "frame imu does not exist")
        self.assertEqual(r.level, rc.FAIL)
        self.assertIn("imu does not exist", r.detail)

    def test_layout_and_cones(self):
        self.assertEqual(rc.check_layout(None).level, rc.FAIL)
        self.assertEqual(rc.check_layout(2).level, rc.FAIL)
        self.assertEqual(rc.check_layout(4).level, rc.PASS)
        self.assertEqual(rc.check_cones_detected([]).level, rc.FAIL)
        self.assertEqual(rc.check_cones_detected([4, 3]).level, rc.PASS)
        self.assertEqual(rc.check_cones_detected([2] * 20 + [4, 3, 4, 4, 1, 4, 4, 3, 4, 4]).level, rc.PASS)  # one miss
        r = rc.check_cones_detected([4] * 30 + [2] * 10)  # "now": the last 10 frames count, not the window
        self.assertEqual(r.level, rc.FAIL)
        self.assertIn("2 cones", r.detail)

    def test_ekf(self):
        base = {"message": "tracking", "camera updates": "120"}
        self.assertEqual(rc.check_ekf(dict(base, **{"camera NIS mean": "5.8"})).level, rc.PASS)
        self.assertEqual(rc.check_ekf(dict(base, **{"camera NIS mean": "2.3"})).level, rc.PASS)
        self.assertEqual(rc.check_ekf(dict(base, **{"camera NIS mean": "40"})).level, rc.FAIL)
        self.assertEqual(rc.check_ekf(dict(base, **{"camera NIS mean": "nan"})).level, rc.FAIL)
        self.assertEqual(rc.check_ekf(dict(base, **{"camera NIS mean": "0.2"})).level, rc.WARN)
        self.assertEqual(rc.check_ekf(dict(base, **{"camera NIS mean": "15"})).level, rc.WARN)
        self.assertEqual(rc.check_ekf(base).level, rc.WARN)  # no NIS published
        waiting = {"message": "waiting for the first camera pose", "camera updates": "0", "camera NIS mean": "0"}
        self.assertEqual(rc.check_ekf(waiting).level, rc.FAIL)
        self.assertEqual(rc.check_ekf(None).level, rc.FAIL)
        # camera_update cones: the cones' NIS per dof decides, not the pose NIS of the few poses fused.
        cones = dict(base, **{"camera update path": "cones", "cone frames fused": "300", "camera NIS mean": "27"})
        self.assertEqual(rc.check_ekf(dict(cones, **{"cone NIS mean per dof": "0.9"})).level, rc.PASS)
        self.assertEqual(rc.check_ekf(dict(cones, **{"cone NIS mean per dof": "3"})).level, rc.WARN)
        self.assertEqual(rc.check_ekf(dict(cones, **{"cone NIS mean per dof": "5"})).level, rc.FAIL)
        self.assertIn("cone NIS mean per dof 0.90", rc.check_ekf(dict(cones, **{"cone NIS mean per dof": "0.9"})).detail)
        # No cone frame fused yet (only the initialising pose): the pose NIS, as in pose mode.
        no_cones = dict(cones, **{"cone frames fused": "0", "camera NIS mean": "5.8"})
        self.assertEqual(rc.check_ekf(no_cones).level, rc.PASS)


class ClockTest(unittest.TestCase):
    def test_closest_offset_decides(self):
        # Transport delays vary with load; the closest stamp bounds the clock offset.
        self.assertEqual(rc.check_clock("IMU clock", [0.050, 0.003, 0.200]).level, rc.PASS)
        r = rc.check_clock("camera clock", [0.35, 0.31, 0.4])  # stamps 310+ ms behind: a clock offset
        self.assertEqual(r.level, rc.FAIL)
        self.assertIn("-310.0 ms", r.detail)
        self.assertEqual(rc.check_clock("camera clock", [-0.5, -0.45]).level, rc.FAIL)  # stamps in the future
        self.assertEqual(rc.check_clock("camera clock", []).level, rc.FAIL)
        self.assertEqual(rc.check_clock("IMU clock", [0.0257], limit_s=0.25).level, rc.PASS)
        self.assertEqual(rc.check_clock("IMU clock", [0.0257]).level, rc.FAIL)


class MasterTest(unittest.TestCase):
    def test_master(self):
        self.assertEqual(rc.check_master("192.168.1.5", "192.168.1.2:11311", True).level, rc.PASS)
        self.assertEqual(rc.check_master(None, "192.168.1.2:11311", True).level, rc.WARN)
        r = rc.check_master("192.168.1.5", "192.168.1.2:11311", False, "Connection refused")
        self.assertEqual(r.level, rc.FAIL)
        self.assertIn("Connection refused", r.detail)

    def test_local_addresses(self):
        for a in ["127.0.0.1", "127.0.0.3", "10.1.2.3", "172.16.0.1", "172.31.255.1", "192.168.0.7",
                  "169.254.3.4", "::1", "fe80::1", "fd00::5"]:
            self.assertTrue(rc.is_local_address(a), a)
        for a in ["8.8.8.8", "172.32.0.1", "100.64.0.1", "2001:db8::1", "11.0.0.1", "0.0.0.0"]:
            self.assertFalse(rc.is_local_address(a), a)
        self.assertIsNone(rc.is_local_address("rig.local"))

    def test_master_uri_warning(self):
        self.assertIsNone(master_uri.warning("http://127.0.0.1:11311"))
        self.assertIsNone(master_uri.warning("http://192.168.8.1:11311/"))
        w = master_uri.warning("http://52.1.2.3:11311")
        self.assertIn("52.1.2.3", w)
        self.assertIn("outside the local network", w)
        # Host names are resolved (injected resolver: no DNS in tests).
        self.assertIsNone(master_uri.warning("http://rig:11311", resolve=lambda h: "10.0.0.2"))
        w = master_uri.warning("http://cloud.example.org:11311", resolve=lambda h: "93.184.216.34")
        self.assertIn("cloud.example.org (93.184.216.34)", w)

        def fail(host):
            raise OSError("Name or service not known")
        self.assertIn("does not resolve", master_uri.warning("http://nowhere:11311", resolve=fail))
        self.assertIn("not set", master_uri.warning(""))

    def test_exit_codes_and_format(self):
        results = [rc.ok("a", "fine"), rc.Result(rc.WARN, "b", "hm", "do x")]
        self.assertEqual(rc.exit_code(results), 0)
        self.assertEqual(rc.exit_code(results + [rc.Result(rc.FAIL, "c", "bad", "do y")]), 1)
        line = rc.format_line(rc.Result(rc.FAIL, "IMU rate", "0 Hz", "plug it in"))
        self.assertTrue(line.startswith("FAIL IMU rate"))
        self.assertIn("fix: plug it in", line)


class NoMasterTest(unittest.TestCase):
    def test_no_master_exit_2(self):
        # A port nothing listens on (this test's own): one line, exit code 2.
        env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:11399")
        p = subprocess.run(["rosrun", "ar_bringup", "rig_check", "--window", "0"], env=env, capture_output=True,
                           text=True)
        self.assertEqual(p.returncode, 2, p.stdout + p.stderr)
        self.assertEqual(len(p.stdout.strip().splitlines()), 1, p.stdout)
        self.assertIn("no ROS master at http://127.0.0.1:11399", p.stdout)

    def test_no_pipeline_exit_2(self):
        # rostest's own master runs no pipeline: one line, exit code 2.
        p = subprocess.run(["rosrun", "ar_bringup", "rig_check", "--window", "0"], capture_output=True, text=True)
        self.assertEqual(p.returncode, 2, p.stdout + p.stderr)
        self.assertEqual(len(p.stdout.strip().splitlines()), 1, p.stdout)
        self.assertIn("runs no pipeline", p.stdout)

    def test_check_master_uri_script(self):
        env = dict(os.environ, ROS_MASTER_URI="http://8.8.4.4:11311")
        p = subprocess.run(["rosrun", "ar_bringup", "check_master_uri"], env=env, capture_output=True, text=True)
        self.assertEqual(p.returncode, 0)
        self.assertIn("outside the local network ranges", p.stderr)
        env["ROS_MASTER_URI"] = "http://127.0.0.2:11311"
        p = subprocess.run(["rosrun", "ar_bringup", "check_master_uri"], env=env, capture_output=True, text=True)
        self.assertNotIn("WARN", p.stderr)


class AllTests(unittest.TestSuite):
    def __init__(self):
        loader = unittest.defaultTestLoader
        super().__init__([loader.loadTestsFromTestCase(c) for c in (RateTest, CalibrationTest, CounterTest, SceneTest,
                                                                     ClockTest, MasterTest, NoMasterTest)])


if __name__ == "__main__":
    import rostest
    rostest.rosrun("ar_bringup", "rig_check", "test_rig_check.AllTests")

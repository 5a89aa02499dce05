#!/usr/bin/env python3
"""rostest: imu_driver_node on a pseudo-terminal written by this script.

The frames are built here with an independent encoder (bitwise CRC-16/ARC), so
the test also cross-checks the C++ encoder/decoder pair against the format.
"""
import math
import os
import pty
import random
import struct
import sys
import time
import tty
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import Imu
from std_msgs.msg import Bool
from std_srvs.srv import Trigger

GYRO_RAD_PER_COUNT = 600.0 / 65536.0 * math.pi / 180.0
ACCEL_PER_COUNT = 196.1 / 65536.0
BIAS = (0.01, -0.02, 0.03)


def crc16_arc(data):
    crc = 0
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def frame(msg_type, payload):
    body = bytes([0x55, 0xAA, msg_type, len(payload)]) + bytes(payload)
    return body + struct.pack(">H", crc16_arc(body))


def hs_frame(gyro, accel, seq):
    return frame(0xFF, struct.pack(">6hIBB", *gyro, *accel, 1234, 0, seq))


def has_inner_sync(f):
    return any(f[k] == 0x55 and f[k + 1] == 0xAA for k in range(1, len(f) - 1))


class Pty:
    def __init__(self, link):
        self.link = link
        self.master = None

    def plug(self):
        self.master, slave = pty.openpty()
        tty.setraw(slave)
        name = os.ttyname(slave)
        os.close(slave)
        tmp = self.link + ".new"
        if os.path.lexists(tmp):
            os.unlink(tmp)
        os.symlink(name, tmp)
        os.rename(tmp, self.link)

    def unplug(self):
        # The link goes first (like udev on unplug): the pty number is reused by the
        # next openpty on the machine, and the driver must not reopen someone else's.
        os.unlink(self.link)
        os.close(self.master)
        self.master = None

    def write_paced(self, chunks, period_s=0.01):
        # On an absolute schedule: the driver's clock model expects the IMU's steady rate.
        start = time.time()
        for k, c in enumerate(chunks):
            os.write(self.master, c)
            time.sleep(max(0.0, start + (k + 1) * period_s - time.time()))


class ImuDriverPtyTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_imu_driver_pty")
        cls.dir = rospy.get_param("~dir")
        os.makedirs(cls.dir, exist_ok=True)
        cls.link = os.path.join(cls.dir, "tty")
        for stale in (cls.link, os.path.join(cls.dir, "gyro_calibration.yaml")):
            if os.path.lexists(stale):
                os.unlink(stale)
        cls.msgs = []
        cls.received_s = []  # wall time each message arrived here
        cls.diag = None
        cls.calibrated = []
        rospy.Subscriber("imu/data_raw", Imu, cls.on_imu, queue_size=1000)
        rospy.Subscriber("/diagnostics", DiagnosticArray, cls.on_diag)
        rospy.Subscriber("imu/is_calibrated", Bool, lambda m: cls.calibrated.append(m.data))
        cls.rng = random.Random(5)

    @classmethod
    def on_imu(cls, msg):
        cls.received_s.append(time.time())
        cls.msgs.append(msg)

    @classmethod
    def tearDownClass(cls):
        for name in ("tty", "tty.new", "gyro_calibration.yaml"):
            path = os.path.join(cls.dir, name)
            if os.path.lexists(path):
                os.unlink(path)
        try:
            os.rmdir(cls.dir)
        except OSError:
            pass

    @classmethod
    def on_diag(cls, msg):
        for s in msg.status:
            if s.name.endswith("Crista IMU"):
                cls.diag = (s.level, s.message, {kv.key: kv.value for kv in s.values})

    def wait_for(self, cond, what, timeout_s=60.0):  # a hang guard, not a speed limit
        end = time.time() + timeout_s
        while time.time() < end and not rospy.is_shutdown():
            if cond():
                return
            time.sleep(0.02)
        self.fail("timed out waiting for " + what)

    def valid_frames(self, n, first_seq, gyro=None, accel=None):
        out = []
        while len(out) < n:
            seq = (first_seq + len(out)) % 256
            g = gyro() if gyro else [self.rng.randint(-32768, 32767) for _ in range(3)]
            a = accel() if accel else [self.rng.randint(-32768, 32767) for _ in range(3)]
            f = hs_frame(g, a, seq)
            if not has_inner_sync(f):
                out.append((f, g, a))
        return out

    def wait_for_driver_counts(self, samples, rejected=None):
        """Until the driver's own diagnostics count exactly these samples (and rejects): then every
        byte written has been parsed, and the count of messages is final, whatever the load."""
        def done():
            d = self.diag[2]
            return (int(d.get("samples", -1)) == samples and
                    all(int(d.get("rejected: " + k, -1)) == n for k, n in (rejected or {}).items()))
        self.wait_for(done, "the driver's diagnostics to count %d samples and %s (last: %s)"
                      % (samples, rejected, self.diag[2]))
        self.wait_for(lambda: len(self.msgs) >= samples, "%d messages" % samples)

    def check_values(self, msgs, sent, bias):
        self.assertEqual(len(msgs), len(sent))
        for m, (_, g, a) in zip(msgs, sent):
            self.assertEqual(m.header.frame_id, "imu")
            self.assertEqual(m.orientation_covariance[0], -1.0)
            got = (m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z)
            for i in range(3):
                self.assertAlmostEqual(got[i], g[i] * GYRO_RAD_PER_COUNT - bias[i], places=9)
            acc = (m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z)
            for i in range(3):
                self.assertAlmostEqual(acc[i], a[i] * ACCEL_PER_COUNT, places=9)

    def test_driver_on_pty(self):
        # 1. Port missing at start: a diagnostic ERROR naming the port, no crash.
        self.wait_for(lambda: self.diag is not None, "diagnostics")
        self.assertEqual(self.diag[0], 2, self.diag)
        self.assertIn("unavailable", self.diag[1])
        self.wait_for(lambda: self.calibrated and self.calibrated[-1], "latched imu/is_calibrated")

        imu = Pty(self.link)
        imu.plug()
        self.wait_for(lambda: self.diag[2].get("connected") == "True", "connection")

        # 2. A fuzzed stream at 100 Hz with known counts of each kind of reject.
        sent, chunks = [], []
        expected = {"bad CRC": 0, "bad length": 0, "unknown type": 0, "truncated": 0}
        frames = self.valid_frames(300, 0)
        for k, (f, g, a) in enumerate(frames):
            chunk = b""
            if self.rng.random() < 0.2:
                chunk += bytes(self.rng.choice([b for b in range(256) if b not in (0x55, 0xAA)])
                               for _ in range(self.rng.randint(1, 20)))
            kind = k % 10 if k > 0 else -1
            if kind == 1:
                bad = bytearray(f)
                bad[10] = 0x01 if bad[10] != 0x01 else 0x02
                chunk += bytes(bad)
                expected["bad CRC"] += 1
            elif kind == 3:
                chunk += f[:3] + bytes([30]) + f[4:]
                expected["bad length"] += 1
            elif kind == 5:
                chunk += frame(0x42, b"\x01\x02\x03")
                expected["unknown type"] += 1
            elif kind == 7:
                chunk += f[:12]
                expected["truncated"] += 1
            chunks.append(chunk + f)
            sent.append((f, g, a))
        imu.write_paced(chunks)
        self.wait_for_driver_counts(len(sent), expected)
        self.check_values(self.msgs, sent, BIAS)
        stamps = [m.header.stamp.to_sec() for m in self.msgs]
        self.assertTrue(all(b > a for a, b in zip(stamps, stamps[1:])))
        # Host time, not the IMU's time since power-up: near when the message arrived here (a bound
        # far above any delivery delay on a loaded machine).
        self.assertLess(abs(stamps[-1] - self.received_s[len(stamps) - 1]), 30.0)
        cov = self.msgs[0].angular_velocity_covariance
        self.assertAlmostEqual(cov[0], 1e-6, places=12)
        self.assertAlmostEqual(cov[8], 9e-6, places=12)
        self.assertAlmostEqual(self.msgs[0].linear_acceleration_covariance[4], 0.0025, places=12)
        for key, n in expected.items():
            self.assertEqual(int(self.diag[2]["rejected: " + key]), n, key)
        self.assertEqual(int(self.diag[2]["sequence gaps"]), 0)

        # 3. Unplug mid-run, replug: the same driver process recovers.
        imu.unplug()
        self.wait_for(lambda: self.diag[2].get("disconnects") == "1", "disconnect in diagnostics")
        imu.plug()
        self.wait_for(lambda: self.diag[2].get("connected") == "True", "reconnection")
        more = self.valid_frames(100, 0)
        n_before = len(self.msgs)
        imu.write_paced([f for f, _, _ in more])
        self.wait_for_driver_counts(n_before + len(more))
        self.check_values(self.msgs[n_before:], more, BIAS)

        # 4. imu/calibrate: still data with a known gyro offset; the new bias is removed.
        rospy.wait_for_service("imu/calibrate", 5.0)
        res = rospy.ServiceProxy("imu/calibrate", Trigger)()
        self.assertTrue(res.success, res.message)
        offset = (40, -25, 10)
        still = self.valid_frames(200, 100, gyro=lambda: [o + self.rng.randint(-3, 3) for o in offset],
                                  accel=lambda: [self.rng.randint(-20, 20), self.rng.randint(-20, 20), 3278])
        n_before = len(self.msgs)
        imu.write_paced([f for f, _, _ in still])
        self.wait_for(lambda: len(self.msgs) >= n_before + len(still), "calibration data")
        path = os.path.join(self.dir, "gyro_calibration.yaml")
        self.wait_for(lambda: os.path.exists(path), "calibration file")
        self.assertTrue(self.calibrated[-1])
        last = self.msgs[-1].angular_velocity
        for got, o in zip((last.x, last.y, last.z), offset):
            self.assertLess(abs(got), 4 * GYRO_RAD_PER_COUNT, (got, o))
        # The measured noise replaces the configured sigma in the covariance: the
        # offsets carry uniform integer noise in [-3, 3] counts, sigma 2 counts.
        expected_var = (2.0 * GYRO_RAD_PER_COUNT) ** 2
        self.assertAlmostEqual(self.msgs[-1].angular_velocity_covariance[0] / expected_var, 1.0, delta=0.3)
        with open(path) as f:
            text = f.read()
        self.assertIn("gyro_bias_rad_s", text)
        imu.unplug()


if __name__ == "__main__":
    rostest.rosrun("imu_driver", "driver_on_pty", ImuDriverPtyTest, sys.argv)

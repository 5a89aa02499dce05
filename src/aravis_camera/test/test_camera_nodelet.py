#!/usr/bin/python3
"""CameraNodelet in a manager with the fake GigE camera: frames at the set rate
(10 Hz, then 5 Hz through dynamic_reconfigure: rates the software fake keeps up
with on a loaded machine),
size and encoding, camera_info from the calibration file, and the zero-copy
probe in the same manager receiving the driver's own buffers."""
import re
import threading
import unittest

import dynamic_reconfigure.client
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import String


class CameraNodeletTest(unittest.TestCase):
    def setUp(self):
        self.lock = threading.Lock()
        self.images, self.infos, self.probe, self.diag = [], [], None, None
        rospy.Subscriber("camera/image_raw", Image, self.on_image, queue_size=50)
        rospy.Subscriber("camera/camera_info", CameraInfo, self.on_info, queue_size=50)
        rospy.Subscriber("probe/stats", String, self.on_probe)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag)

    def on_image(self, msg):
        with self.lock:
            self.images.append((rospy.get_time(), msg.header.stamp.to_sec(), msg.width, msg.height, msg.encoding, msg.step, len(msg.data)))

    def on_info(self, msg):
        with self.lock:
            self.infos.append(msg)

    def on_probe(self, msg):
        self.probe = msg.data

    def on_diag(self, msg):
        for status in msg.status:
            if status.name.endswith("camera") and "not connected" not in status.message:
                self.diag = status

    def wait_for(self, predicate, timeout_s):
        deadline = rospy.get_time() + timeout_s
        while rospy.get_time() < deadline and not rospy.is_shutdown():
            if predicate():
                return True
            rospy.sleep(0.1)
        return predicate()

    def test_stream(self):
        self.assertTrue(self.wait_for(lambda: len(self.images) >= 40, 60.0), "got %d frames" % len(self.images))
        with self.lock:
            frames = list(self.images[-30:])
            info = self.infos[-1]
        _, _, width, height, encoding, step, size = frames[-1]
        self.assertEqual((width, height, encoding, step, size), (1024, 768, "rgb8", 3072, 1024 * 768 * 3))
        rate = (len(frames) - 1) / (frames[-1][1] - frames[0][1])
        self.assertAlmostEqual(rate, 10.0, delta=1.0)
        self.assertEqual(info.width, 1024)
        self.assertAlmostEqual(info.K[0], 770.0)
        self.assertEqual(info.distortion_model, "plumb_bob")
        self.assertEqual(info.header.frame_id, "camera_optical")

        # The probe shares the manager: every frame it saw was the driver's pool memory.
        self.assertTrue(self.wait_for(lambda: self.probe is not None and "frames=0 " not in self.probe, 60.0))
        counts = dict(re.findall(r"(\w+)=([\d.]+)", self.probe))
        self.assertGreater(int(counts["frames"]), 0)
        self.assertEqual(counts["zero_copy"], counts["frames"], self.probe)

        # dynamic_reconfigure reaches the camera: half the frame rate.
        client = dynamic_reconfigure.client.Client("camera", timeout=10)
        client.update_configuration({"frame_rate": 5.0})

        def slowed():  # the last three intervals are beyond the old 10 Hz: the new rate is in effect
            with self.lock:
                t = [f[1] for f in self.images[-4:]]
            return len(t) == 4 and all(b - a > 1.0 / 7.5 for a, b in zip(t, t[1:]))
        self.assertTrue(self.wait_for(slowed, 60.0), "the frame rate did not drop after the reconfigure")
        with self.lock:
            start = len(self.images)
        self.assertTrue(self.wait_for(lambda: len(self.images) >= start + 20, 60.0))
        with self.lock:
            frames = list(self.images[start:])
        self.assertAlmostEqual((len(frames) - 1) / (frames[-1][1] - frames[0][1]), 5.0, delta=0.5)

        self.assertTrue(self.wait_for(lambda: self.diag is not None, 60.0), "no camera diagnostics")
        values = {kv.key: kv.value for kv in self.diag.values}
        self.assertGreater(int(values["frames published"]), 0)
        self.assertEqual(values["camera_info size mismatches"], "0")


if __name__ == "__main__":
    rospy.init_node("test_camera_nodelet")
    rostest.rosrun("aravis_camera", "test_camera_nodelet", CameraNodeletTest)

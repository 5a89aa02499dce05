#!/usr/bin/env python3
"""Feeds OverlayNodelet grey frames and checks that the model lands at the image centre."""
import threading
import unittest

import numpy as np
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import CameraInfo, Image

W, H, GREY = 640, 480, 128


class OverlayNodeletTest(unittest.TestCase):
    def setUp(self):
        self.lock = threading.Lock()
        self.out = None
        self.diag = None
        rospy.Subscriber("ar_overlay/image", Image, self.on_image)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag)
        self.image_pub = rospy.Publisher("camera/image_raw", Image, queue_size=2)
        self.info_pub = rospy.Publisher("camera/camera_info", CameraInfo, queue_size=2)
        # T_cones_camera: 2 m up, optical axis down (a half turn about x).
        t = TransformStamped()
        t.header.stamp, t.header.frame_id, t.child_frame_id = rospy.Time(0), "cones", "camera_optical"
        t.transform.translation.z = 2.0
        t.transform.rotation.x, t.transform.rotation.w = 1.0, 0.0
        self.tf = tf2_ros.StaticTransformBroadcaster()
        self.tf.sendTransform(t)

    def on_image(self, msg):
        with self.lock:
            self.out = msg

    def on_diag(self, msg):
        for s in msg.status:
            if s.name.endswith("overlay"):
                with self.lock:
                    self.diag = {kv.key: kv.value for kv in s.values}
                    self.diag_keys = [kv.key for kv in s.values]

    def publish(self):
        stamp = rospy.Time.now()
        img = Image(height=H, width=W, encoding="rgb8", step=3 * W, data=bytes([GREY]) * (3 * W * H))
        img.header.stamp, img.header.frame_id = stamp, "camera_optical"
        info = CameraInfo(height=H, width=W, distortion_model="plumb_bob", D=[-0.1, 0.01, 0, 0, 0],
                          K=[500, 0, 319.5, 0, 500, 239.5, 0, 0, 1])
        info.header = img.header
        self.image_pub.publish(img)
        self.info_pub.publish(info)

    def test_model_drawn_at_centre(self):
        deadline = rospy.Time.now() + rospy.Duration(60)
        rate = rospy.Rate(10)
        px = None
        while not rospy.is_shutdown() and rospy.Time.now() < deadline:
            self.publish()
            rate.sleep()
            with self.lock:
                out, diag = self.out, self.diag
            if out is None:
                continue
            px = np.frombuffer(out.data, np.uint8).reshape(out.height, out.width, 3)
            if px[H // 2, W // 2, 1] > 60 and diag is not None and int(diag["frames rendered"]) > 0:
                break
        self.assertIsNotNone(px, "no ar_overlay/image")
        self.assertEqual((out.width, out.height, out.encoding), (W, H, "rgb8"))
        centre = px[H // 2, W // 2]
        # Pure green, lit (the surface slopes at its centre, so not at full brightness).
        self.assertGreater(int(centre[1]), 60, "no green model at the image centre: %s" % centre)
        self.assertLess(int(centre[0]), 40)
        self.assertLess(int(centre[2]), 40)
        # The peaks surface is 0.3 m across 1.95 m away: about 38 px each side of the centre.
        self.assertEqual(px[H // 2, W // 2 + 80].tolist(), [GREY] * 3)
        self.assertEqual(px[5, 5].tolist(), [GREY] * 3)
        self.assertIsNotNone(diag, "no diagnostics")
        self.assertIn("does_not_exist.dae", diag.get("model not loaded", ""))
        # Frames before tf's first message may lack a pose; once drawn, every frame has one.
        # Until ten more frames are rendered (a condition, however slow the machine; 120 s is a hang guard).
        without, rendered = diag["frames without pose"], int(diag["frames rendered"])
        end = rospy.Time.now() + rospy.Duration(120)
        while not rospy.is_shutdown() and rospy.Time.now() < end:
            self.publish()
            rate.sleep()
            with self.lock:
                diag = self.diag
            if int(diag["frames rendered"]) >= rendered + 10:
                break
        self.assertEqual(diag["frames without pose"], without)
        self.assertGreaterEqual(int(diag["frames rendered"]), rendered + 10)

    def test_bad_frames_counted_by_reason(self):
        short = "frames skipped: image data shorter than height x step"
        encoding = "frames skipped: unsupported encoding '32FC1'"
        rate = rospy.Rate(10)
        for _ in range(600):  # a bound on attempts, not a timing assertion
            if rospy.is_shutdown():
                break
            stamp = rospy.Time.now()
            info = CameraInfo(height=H, width=W, distortion_model="plumb_bob", D=[0.0] * 5,
                              K=[500, 0, 319.5, 0, 500, 239.5, 0, 0, 1])
            info.header.stamp, info.header.frame_id = stamp, "camera_optical"
            bad = Image(height=H, width=W, encoding="rgb8", step=3 * W, data=bytes([GREY]) * (3 * W))  # one row
            bad.header = info.header
            self.image_pub.publish(bad)
            self.info_pub.publish(info)
            rate.sleep()
            info.header.stamp = stamp = rospy.Time.now()
            odd = Image(height=H, width=W, encoding="32FC1", step=4 * W, data=bytes(4 * W * H))
            odd.header = info.header
            self.image_pub.publish(odd)
            self.info_pub.publish(info)
            rate.sleep()
            with self.lock:
                diag = self.diag
            if diag and int(diag.get(short, 0)) > 0 and int(diag.get(encoding, 0)) > 0:
                break
        self.assertIsNotNone(diag, "no diagnostics")
        self.assertGreater(int(diag.get(short, 0)), 0, diag)
        self.assertGreater(int(diag.get(encoding, 0)), 0, diag)
        self.assertGreaterEqual(int(diag["frames skipped (bad input)"]), int(diag[short]) + int(diag[encoding]))


if __name__ == "__main__":
    rospy.init_node("test_overlay_nodelet")
    rostest.rosrun("ar_overlay", "test_overlay_nodelet", OverlayNodeletTest)

#!/usr/bin/python3
"""rostest (test/two_hosts.test): the rig and the base station as two ROS hosts on one master.

The rig side (ROS_HOSTNAME 127.0.0.2; see the .test for why not ROS_IP) replays a sample bag through the pipeline on sim time; this node runs
on the base-station side (127.0.0.3) next to image_transport's republish, which decodes the
overlay through the project's compressed subscriber plugin. Checks: the nodes advertise the two
addresses, and poses, the tf cones -> camera_optical, the overlay as JPEG on ar_overlay/image/compressed
(the standard format string, decodable by OpenCV alone as by a stock viewer) and the republished raw
overlay all arrive here. Waits on these conditions only; rostest's time-limit bounds the whole.
"""
import threading
import unittest
from urllib.parse import urlparse

import cv2
import numpy as np
import rosgraph
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import PoseWithCovarianceStamped
from sensor_msgs.msg import CompressedImage, Image

NEEDED = 3  # messages of each kind (the bag plays once; a loaded machine drops frames)


class TwoHosts(unittest.TestCase):
    def setUp(self):
        self.cond = threading.Condition()
        self.poses, self.jpegs, self.raws = 0, [], []
        self.tf = tf2_ros.Buffer()
        self.tf_listener = tf2_ros.TransformListener(self.tf)
        rospy.Subscriber("pose_ekf/pose", PoseWithCovarianceStamped, self.on_pose)
        rospy.Subscriber("ar_overlay/image/compressed", CompressedImage, self.on_jpeg, queue_size=5)
        rospy.Subscriber("base_station/overlay", Image, self.on_raw, queue_size=5)

    def on_pose(self, _):
        with self.cond:
            self.poses += 1
            self.cond.notify_all()

    def on_jpeg(self, m):
        img = cv2.imdecode(np.frombuffer(m.data, np.uint8), cv2.IMREAD_UNCHANGED)
        with self.cond:
            self.jpegs.append((m.format, None if img is None else img.shape, len(m.data)))
            self.cond.notify_all()

    def on_raw(self, m):
        with self.cond:
            self.raws.append((m.encoding, m.width, m.height))
            self.cond.notify_all()

    def tf_found(self):
        return self.tf.can_transform("cones", "camera_optical", rospy.Time(0))

    def done(self):
        return self.poses >= NEEDED and len(self.jpegs) >= NEEDED and len(self.raws) >= NEEDED and self.tf_found()

    def host_of(self, node):
        return urlparse(rosgraph.Master("/two_hosts").lookupNode(node)).hostname

    def test_base_station_receives(self):
        with self.cond:
            while not rospy.is_shutdown() and not self.done():
                self.cond.wait(1.0)  # woken by every message; the tf is polled at each wake
        self.assertTrue(self.done(), "poses %d, jpegs %d, raws %d, tf %s" % (self.poses, len(self.jpegs),
                                                                              len(self.raws), self.tf_found()))
        # Two hosts: the rig's manager advertises 127.0.0.2, this node and the republisher 127.0.0.3.
        self.assertEqual(self.host_of("/ar_manager"), "127.0.0.2")
        self.assertEqual(urlparse(rospy.get_node_uri()).hostname, "127.0.0.3")
        self.assertEqual(self.host_of("/base_republish"), "127.0.0.3")
        fmt, shape, size = self.jpegs[-1]
        self.assertRegex(fmt, r"^(rgb8|bgr8); jpeg compressed bgr8$")
        self.assertIsNotNone(shape, "the compressed overlay does not decode with OpenCV")
        encoding, width, height = self.raws[-1]
        self.assertEqual((height, width), shape[:2])
        self.assertEqual(encoding, fmt.split(";")[0])
        self.assertLess(size, width * height * 3 / 4, "JPEG not smaller than a quarter of raw")


if __name__ == "__main__":
    rospy.init_node("two_hosts_test")
    rostest.rosrun("ar_bringup", "two_hosts", TwoHosts)

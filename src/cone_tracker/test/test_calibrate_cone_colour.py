#!/usr/bin/env python3
"""calibrate_cone_colour with --bag: frames taken from a bag's image topic (Image or CompressedImage)
and named frame_<i> for the boxes CSV, a model that classifies the cone's orange as cone and the
asphalt as not, and one clear line for a missing topic or missing boxes."""
import os
import shutil
import subprocess
import tempfile
import unittest

import cv2
import numpy as np
import rosbag
import rospy
from sensor_msgs.msg import CompressedImage, Image

TOOL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts", "calibrate_cone_colour")
ASPHALT_BGR = (70, 62, 60)
ORANGE_BGR = (20, 95, 250)
CONE = np.array([[160, 40], [120, 200], [200, 200]], np.int32)  # apex, base corners (x, y)


def frame(shift):
    img = np.zeros((240, 320, 3), np.uint8)
    img[:] = ASPHALT_BGR
    cv2.fillConvexPoly(img, CONE + [shift, 0], ORANGE_BGR)
    return img


def image_msg(img, stamp):
    msg = Image(height=img.shape[0], width=img.shape[1], encoding="rgb8", step=img.shape[1] * 3)
    msg.header.stamp = stamp
    msg.data = cv2.cvtColor(img, cv2.COLOR_BGR2RGB).tobytes()
    return msg


def run(*args):
    p = subprocess.run(["/usr/bin/python3", TOOL] + list(args), capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def llr_of(model_path, bgr):
    with open(model_path) as f:
        text = f.read()
    fields = dict(line.split(":", 1) for line in text.splitlines() if line and not line.startswith("#"))
    table = np.frombuffer(bytes.fromhex(fields["llr"].split("#")[0].strip().strip('"')), np.int8)
    scale = float(fields["llr_scale"].split("#")[0])
    threshold = float(fields["threshold"].split("#")[0])
    b, g, r = (v >> 3 for v in bgr)
    return table[(r * 32 + g) * 32 + b] * scale, threshold


class BagInputTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="calibrate_cone_colour_")
        self.bag = os.path.join(self.dir, "run.bag")
        with rosbag.Bag(self.bag, "w") as bag:
            for i in range(5):  # the cone moves 10 px per frame
                t = rospy.Time(1 + i)
                bag.write("/camera/image_raw", image_msg(frame(10 * i), t), t)
            c = CompressedImage(format="jpeg")
            c.data = cv2.imencode(".png", frame(0))[1].tobytes()
            bag.write("/camera/image_raw/compressed", c, rospy.Time(1))

    def tearDown(self):
        shutil.rmtree(self.dir)

    def boxes(self, lines):
        path = os.path.join(self.dir, "boxes.csv")
        with open(path, "w") as f:
            f.write("image,x,y,w,h\n" + "".join(l + "\n" for l in lines))
        return path

    def test_frames_from_the_bag_give_a_model_that_knows_the_cone(self):
        # Three frames spread over five: indices 0, 2, 4; the boxes follow the cone.
        boxes = self.boxes(["frame_0,115,38,90,165", "frame_2,135,38,90,165", "frame_4,155,38,90,165"])
        out, frames = os.path.join(self.dir, "model.yaml"), os.path.join(self.dir, "frames")
        code, stdout, stderr = run("--bag", self.bag, "--frames", "3", "--save-frames", frames, "--boxes", boxes,
                                   "--output", out)
        self.assertEqual(code, 0, stderr)
        self.assertEqual(sorted(os.listdir(frames)), ["frame_0.png", "frame_2.png", "frame_4.png"])
        self.assertIn("3 cones (0 boxes refused) in 3 images of run.bag", stdout)
        cone, threshold = llr_of(out, ORANGE_BGR)
        asphalt, _ = llr_of(out, ASPHALT_BGR)
        self.assertGreaterEqual(cone, threshold)
        self.assertLess(asphalt, threshold)

    def test_compressed_topic(self):
        boxes = self.boxes(["frame_0,115,38,90,165"])
        out = os.path.join(self.dir, "model.yaml")
        code, stdout, stderr = run("--bag", self.bag, "--topic", "camera/image_raw/compressed", "--boxes", boxes,
                                   "--output", out)
        self.assertEqual(code, 0, stderr)
        self.assertIn("1 cones (0 boxes refused) in 1 images", stdout)

    def test_a_box_on_asphalt_is_refused_naming_the_frame(self):
        boxes = self.boxes(["frame_0,10,10,60,80"])
        code, _, stderr = run("--bag", self.bag, "--frames", "1", "--boxes", boxes, "--output",
                              os.path.join(self.dir, "m.yaml"))
        self.assertEqual(code, 1)
        self.assertIn("frame_0: box 1 refused: no cone-coloured pixels", stderr)
        self.assertIn("nothing written", stderr)

    def test_missing_topic_names_the_bag_and_its_image_topics(self):
        code, _, stderr = run("--bag", self.bag, "--topic", "cam/image", "--boxes", self.boxes([]), "--output",
                              os.path.join(self.dir, "m.yaml"))
        self.assertEqual(code, 1)
        self.assertIn("run.bag: no topic cam/image; its image topics: /camera/image_raw, "
                      "/camera/image_raw/compressed", stderr)

    def test_bad_arguments(self):
        code, _, stderr = run("--bag", self.bag, "--output", os.path.join(self.dir, "m.yaml"))
        self.assertEqual(code, 2)
        self.assertIn("--bag needs --boxes", stderr)
        code, _, stderr = run("--bag", self.bag, "--boxes", self.boxes([]), "--output", "m.yaml", "x.png")
        self.assertEqual(code, 2)
        self.assertIn("give --bag or image files, not both", stderr)
        code, _, stderr = run("--bag", os.path.join(self.dir, "none.bag"), "--boxes", self.boxes([]), "--output",
                              os.path.join(self.dir, "m.yaml"))
        self.assertEqual(code, 1)
        self.assertIn("none.bag: cannot read the bag", stderr)


if __name__ == "__main__":
    import rostest
    rostest.rosrun("cone_tracker", "calibrate_cone_colour", BagInputTest)

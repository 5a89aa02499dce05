#!/usr/bin/env python3
"""Known-value tests of evaluate_detections (cone_tracker.detection_eval) on tiny synthetic label and
JSONL files: the IoU, the greedy matching by score, the AP, a wrong detection counted as false, bad
lines reported and skipped, and the command-line tool's output files."""
import json
import os
import shutil
import subprocess
import tempfile
import unittest

import cv2
import numpy as np

from cone_tracker import detection_eval as de


def result(labels, detections, scores):
    return de.ImageResult("x.jpg", np.array(labels, float).reshape(-1, 4), np.array(detections, float).reshape(-1, 4),
                          np.array(scores, float), (100, 100))


class IouTest(unittest.TestCase):
    def test_known_values(self):
        a = [[0, 0, 10, 10]]
        np.testing.assert_allclose(de.iou(a, a), [[1.0]])
        np.testing.assert_allclose(de.iou(a, [[5, 0, 10, 10]]), [[50.0 / 150.0]])  # half overlap
        np.testing.assert_allclose(de.iou(a, [[20, 20, 5, 5]]), [[0.0]])           # apart
        np.testing.assert_allclose(de.iou(a, [[2, 2, 5, 5]]), [[25.0 / 100.0]])    # inside
        np.testing.assert_allclose(de.iou(a, [[0, 0, 0, 0]]), [[0.0]])             # no area
        self.assertEqual(de.iou(np.zeros((0, 4)), a).shape, (0, 1))


class MatchingTest(unittest.TestCase):
    def test_higher_score_takes_the_label(self):
        # Two detections on one label: the higher score wins even though the other overlaps more.
        im = result([[0, 0, 10, 10]], [[0, 0, 10, 10], [1, 0, 10, 10]], [0.2, 0.9])
        s = de.score([im])
        self.assertEqual((s.tp, s.fp, s.fn), (1, 1, 0))
        np.testing.assert_array_equal(im.tp, [False, True])
        np.testing.assert_array_equal(im.matched_label, [-1, 0])

    def test_each_label_once_and_best_free_label(self):
        # Detection 0 (score 0.9) overlaps both labels, label 1 better; detection 1 only label 1.
        # Greedy: det 0 takes label 1, det 1 finds label 1 taken and label 0 below 0.5: false.
        labels = [[0, 0, 10, 10], [4, 0, 10, 10]]
        im = result(labels, [[3, 0, 10, 10], [5, 0, 10, 10]], [0.9, 0.8])
        s = de.score([im])
        np.testing.assert_array_equal(im.matched_label, [1, -1])
        self.assertEqual((s.tp, s.fp, s.fn), (1, 1, 1))
        self.assertEqual(im.missed(), [0])

    def test_wrong_detection_is_false_and_label_missed(self):
        im = result([[0, 0, 10, 10]], [[50, 50, 10, 10]], [1.0])
        s = de.score([im])
        self.assertEqual((s.tp, s.fp, s.fn), (0, 1, 1))
        self.assertEqual(s.precision, 0.0)
        self.assertEqual(s.recall, 0.0)
        # IoU 0.47 (just below the threshold) is false too.
        near = result([[0, 0, 10, 10]], [[0, 0, 10, 4.7]], [1.0])
        self.assertEqual(de.score([near]).fp, 1)
        self.assertEqual(de.score([result([[0, 0, 10, 10]], [[0, 0, 10, 5]], [1.0])]).tp, 1)  # exactly 0.5

    def test_detections_on_an_image_without_labels_are_false(self):
        s = de.score([result([], [[0, 0, 5, 5]], [0.5]), result([[0, 0, 10, 10]], [], [])])
        self.assertEqual((s.tp, s.fp, s.fn, s.labelled), (0, 1, 1, 1))


class ApTest(unittest.TestCase):
    def test_known_ap(self):
        # Ranked over two images: TP (0.9), FP (0.8), TP (0.7); 4 labels.
        # Precision 1, 1/2, 2/3 at recall 1/4, 1/4, 1/2: interpolated AP = 1/4 * 1 + 1/4 * 2/3.
        a = result([[0, 0, 10, 10], [50, 50, 10, 10]], [[0, 0, 10, 10], [80, 0, 5, 5]], [0.9, 0.8])
        b = result([[0, 0, 10, 10], [50, 50, 10, 10]], [[50, 50, 10, 10]], [0.7])
        s = de.score([a, b])
        self.assertAlmostEqual(s.ap, 0.25 + 0.25 * 2.0 / 3.0, places=12)
        np.testing.assert_allclose(s.curve_recall, [0.25, 0.25, 0.5])
        np.testing.assert_allclose(s.curve_precision, [1.0, 0.5, 2.0 / 3.0])
        self.assertEqual((s.tp, s.fp, s.fn), (2, 1, 2))

    def test_score_order_matters(self):
        # The same boxes with the false one ranked first: a lower AP.
        a = result([[0, 0, 10, 10]], [[0, 0, 10, 10], [80, 0, 5, 5]], [0.1, 0.9])
        self.assertAlmostEqual(de.score([a]).ap, 0.5, places=12)
        a.scores = np.array([0.9, 0.1])
        self.assertAlmostEqual(de.score([a]).ap, 1.0, places=12)

    def test_equal_scores_are_one_point(self):
        # Without scores (all 1.0) the order of the images must not matter: one point, AP = P x R.
        a = result([[0, 0, 10, 10]], [[0, 0, 10, 10]], [1.0])
        b = result([[0, 0, 10, 10]], [[80, 0, 5, 5]], [1.0])
        for images in ([a, b], [b, a]):
            s = de.score(images)
            np.testing.assert_allclose(s.curve_recall, [0.5])
            np.testing.assert_allclose(s.curve_precision, [0.5])
            self.assertAlmostEqual(s.ap, 0.25, places=12)

    def test_interpolation(self):
        self.assertAlmostEqual(de.average_precision(np.array([0.5, 0.5, 1.0]), np.array([1.0, 0.5, 2 / 3.0])),
                               0.5 + 0.5 * 2 / 3.0)


class FilesTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="cone_tracker_eval_det_")
        os.makedirs(os.path.join(self.dir, "data", "images"))
        os.makedirs(os.path.join(self.dir, "data", "labels"))
        self.img = lambda name: os.path.join(self.dir, "data", "images", name)
        for name in ("a.jpg", "b.jpg", "c.jpg"):
            im = np.full((100, 200, 3), 90, np.uint8)
            cv2.rectangle(im, (20, 10), (60, 90), (0, 120, 255), -1)
            cv2.imwrite(self.img(name), im)
        # a: one cone at x 20-60, y 10-90 of 200x100; b: none (no label file); c: two cones.
        with open(os.path.join(self.dir, "data", "labels", "a.txt"), "w") as f:
            f.write("0 0.2 0.5 0.2 0.8\n")
        with open(os.path.join(self.dir, "data", "labels", "c.txt"), "w") as f:
            f.write("0 0.2 0.5 0.2 0.8\n0 0.75 0.5 0.1 0.4\n")
        self.jsonl = os.path.join(self.dir, "det.jsonl")
        lines = [json.dumps({"image": self.img("a.jpg"), "cones": [{"bbox": [21, 11, 40, 80], "score": 0.8}]}),
                 json.dumps({"image": self.img("b.jpg"), "cones": [{"bbox": [100, 10, 20, 20]}]}),
                 "{not json",
                 json.dumps({"image": self.img("missing.jpg"), "cones": []}),
                 json.dumps({"image": self.img("x.jpg"), "error": "cannot read"}),
                 json.dumps({"image": self.img("c.jpg"), "cones": [{"bbox": [20, 10, 40, 80], "score": 0.9}]})]
        with open(self.jsonl, "w") as f:
            f.write("\n".join(lines) + "\n")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def test_labels_beside_images_and_bad_lines(self):
        self.assertEqual(de.label_path("/d/images/cone (1).jpg"), "/d/labels/cone (1).txt")
        self.assertEqual(de.label_path("/d/images/x.png", "/l"), "/l/x.txt")
        warnings = []
        images = de.load(self.jsonl, warn=warnings.append)
        self.assertEqual([os.path.basename(i.image) for i in images], ["a.jpg", "b.jpg", "c.jpg"])
        np.testing.assert_allclose(images[0].labels, [[20, 10, 40, 80]])
        self.assertEqual(len(images[1].labels), 0)
        self.assertEqual(len(warnings), 3, warnings)
        self.assertIn("det.jsonl:3: not JSON", warnings[0])
        self.assertIn("det.jsonl:4: cannot read the image", warnings[1])
        self.assertIn("det.jsonl:5: detect_cones could not process", warnings[2])
        s = de.score(images)
        # a: TP; b: the box without a label is FP (score 1.0 by default, ranked first); c: one TP, one missed.
        self.assertEqual((s.tp, s.fp, s.fn), (2, 1, 1))
        self.assertEqual(images[1].scores[0], 1.0)
        worst = de.worst(s, 5)
        self.assertEqual(sorted(os.path.basename(i.image) for i in worst), ["b.jpg", "c.jpg"])
        errs = de.errors_json(s)
        c = [e for e in errs["images"] if e["image"].endswith("c.jpg")][0]
        self.assertEqual(c["missed"], [{"bbox": [140.0, 30.0, 20.0, 40.0]}])
        self.assertEqual(c["false"], [])

    def test_bad_label_line_names_file_and_line(self):
        with open(os.path.join(self.dir, "data", "labels", "a.txt"), "a") as f:
            f.write("0 0.5 0.5 oops 0.1\n")
        warnings = []
        images = de.load(self.jsonl, warn=warnings.append)
        self.assertTrue(any("a.txt:2: bad label line" in w for w in warnings), warnings)
        self.assertNotIn("a.jpg", [os.path.basename(i.image) for i in images])

    def test_command_line_tool(self):
        out = os.path.join(self.dir, "out")
        p = subprocess.run(["rosrun", "cone_tracker", "evaluate_detections", self.jsonl, "--output-dir", out],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True, timeout=120)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("evaluate_detections: 3 images, 3 labelled cones, TP 2 FP 1 FN 1, precision 0.667, "
                      "recall 0.667 (IoU >= 0.5)", p.stdout)
        self.assertEqual(p.stderr.count("\n"), 3, p.stderr)
        for name in ("errors.json", "pr_curve.png", "worst_images.png"):
            self.assertTrue(os.path.getsize(os.path.join(out, name)) > 0, name)
        with open(os.path.join(out, "errors.json")) as f:
            errs = json.load(f)
        self.assertEqual((errs["tp"], errs["fp"], errs["fn"]), (2, 1, 1))
        self.assertEqual(len(errs["skipped_lines"]), 3)


if __name__ == "__main__":
    import rostest
    rostest.rosrun("cone_tracker", "evaluate_detections", __name__)

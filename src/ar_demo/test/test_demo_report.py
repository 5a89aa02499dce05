#!/usr/bin/env python3
"""make demo's report generator on a small recorded bag with known errors (fixture_bag.py).

Checks the numbers, not only that files appear: the EKF's position and rotation RMS equal the
fixture's offsets, the outage splits the visible periods, the gate counter's steps are events,
the overlay error is zero for a perfect EKF and grows with the offset, and the command-line tool
writes the report, the plots, the video and the contact sheet.
"""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import cv2
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fixture_bag  # noqa: E402
from ar_demo import from_evaluation, summary as summary_mod  # noqa: E402


def figure(figs, name):
    matches = [v for n, v, _ in figs if n == name]
    assert len(matches) == 1, "figure %r not in %s" % (name, [n for n, _, _ in figs])
    return matches[0]


class ReportTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="ar_demo_test_")
        cls.bag = fixture_bag.write(os.path.join(cls.dir, "run.bag"))
        cls.perfect = fixture_bag.write(os.path.join(cls.dir, "perfect.bag"), ekf_offset=False)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_errors_against_truth(self):
        s, t0 = from_evaluation.summarize(self.bag)
        self.assertAlmostEqual(t0, fixture_bag.T0, places=6)
        self.assertAlmostEqual(s.duration_s, fixture_bag.DURATION_S, places=6)
        self.assertEqual(len(s.ekf), 301)
        np.testing.assert_allclose(s.ekf.pos_err_m, np.tile(fixture_bag.OFFSET_M, (301, 1)), atol=1e-6)
        np.testing.assert_allclose(np.degrees(s.ekf.rot_err_rad[:, 2]), fixture_bag.OFFSET_DEG, atol=1e-6)
        np.testing.assert_allclose(s.ekf.pos_3sigma_m, 3 * fixture_bag.SIGMA_POS_M, rtol=1e-9)
        np.testing.assert_allclose(s.ekf.rot_3sigma_rad, 3 * fixture_bag.SIGMA_ROT_RAD, rtol=1e-9)
        figs = summary_mod.figures(s)
        self.assertAlmostEqual(figure(figs, "EKF position RMS, cones visible"), 10.0, places=3)
        self.assertAlmostEqual(figure(figs, "EKF orientation RMS, cones visible"), 0.5, places=4)
        # 10 mm < 3σ = 15 mm and 0.5° < 3σ = 0.69°: every sample inside.
        self.assertAlmostEqual(figure(figs, "EKF position error inside ±3σ (all three axes)"), 100.0)
        # The orientation inside ±3σ and the tracker's RMS are the evaluation's figures, shown beside them.
        self.assertAlmostEqual(s.evaluation["orientation_within_3sigma"], 1.0)
        self.assertAlmostEqual(s.evaluation["tracker_position_rms_m"], 0.0, places=6)

    def test_command_line_tool_on_a_truncated_or_missing_bag(self):
        # Exit status 1 and one stderr line naming the bag, not a traceback.
        with open(self.bag, "rb") as f:
            data = f.read()
        cut = os.path.join(self.dir, "cut.bag")
        with open(cut, "wb") as f:
            f.write(data[:len(data) // 2])
        for bag in (cut, os.path.join(self.dir, "missing.bag")):
            p = subprocess.run(["rosrun", "ar_demo", "demo_report", "--run", bag, "--out",
                                os.path.join(self.dir, "bad_report"), "--no-video"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)
            self.assertEqual(p.returncode, 1, p.stderr)
            self.assertIn("demo_report: ", p.stderr)
            self.assertIn(bag, p.stderr)
            self.assertNotIn("Traceback", p.stderr)
            self.assertEqual(p.stderr.count("\n"), 1, p.stderr)

    def test_visible_periods_gates_rates(self):
        s, _ = from_evaluation.summarize(self.bag)
        self.assertEqual(len(s.visible), 2)
        self.assertAlmostEqual(s.visible[0][0], 0.0, places=6)
        self.assertAlmostEqual(s.visible[0][1], 1.0, places=6)
        self.assertAlmostEqual(s.visible[1][0], 1.6, places=6)
        self.assertAlmostEqual(s.visible[1][1], 3.0, places=6)
        self.assertEqual(sum(len(v) for v in s.gates.values()), fixture_bag.GATE_REJECTIONS)
        np.testing.assert_allclose(list(s.gates.values())[0], 2.0, atol=1e-6)
        rates = {topic: hz for topic, hz, _ in s.rates}
        self.assertAlmostEqual(rates["pose_ekf/pose"], 100.0, places=3)
        self.assertAlmostEqual(rates["ar_overlay/image"], 30.0, places=3)
        self.assertEqual(rates["imu/data_raw"], 0.0)  # not in the fixture

    def test_errors_by_cones_in_the_true_view(self):
        # The three cones stay in view; the tracker skips the frames of the outage (1.0-1.6 s).
        s, _ = from_evaluation.summarize(self.bag)
        three = s.view_figures["3plus"]
        self.assertEqual(three["frames"], 91.0)
        self.assertAlmostEqual(three["updated_fraction"], 74 / 91.0, places=9)
        self.assertAlmostEqual(three["position_rms_m"], 0.010, places=6)
        self.assertAlmostEqual(three["orientation_rms_deg"], fixture_bag.OFFSET_DEG, places=4)
        self.assertGreater(three["overlay_median_px"], 1.0)  # 10 mm and 0.5 deg, x 1024 / 256
        for key in ("1to2", "none_0to1s", "none_1to2s", "none_over2s"):
            self.assertEqual(s.view_figures[key]["frames"], 0.0)
        perfect, _ = from_evaluation.summarize(self.perfect)
        self.assertLess(perfect.view_figures["3plus"]["overlay_rms_px"], 5e-3)  # interpolation only, x 4
        self.assertEqual(np.count_nonzero(s.view_ekf_since_s), 0)  # always in view

    def test_overlay_error(self):
        perfect, _ = from_evaluation.summarize(self.perfect)
        self.assertEqual(perfect.overlay_err_px.size, 91)
        self.assertLess(np.max(perfect.overlay_err_px), 1e-3)  # interpolation between EKF samples only
        off, _ = from_evaluation.summarize(self.bag)
        # 10 mm and 0.5° at about 3.2 m with f = 192 px: of the order of 1-2 px.
        self.assertGreater(np.median(off.overlay_err_px), 0.5)
        self.assertLess(np.max(off.overlay_err_px), 5.0)

    def test_command_line_tool(self):
        out = os.path.join(self.dir, "out")
        subprocess.check_call(["rosrun", "ar_demo", "demo_report", "--run", self.bag, "--out", out])
        with open(os.path.join(out, "report.md")) as f:
            text = f.read()
        for needle in ("## Figures", "pose_error.png", "overlay_error.png", "gate_rejections.png",
                       "| EKF position RMS, cones visible | 10 | mm |", "Tracker poses: 0.00–1.00 s, 1.60–3.00 s",
                       "| three or more cones in view | 91 | 81.3 | 10 |", "error_since_view.png"):
            self.assertIn(needle, text)
        for name in ("pose_error.png", "pose_error_norm.png", "overlay_error.png", "gate_rejections.png",
                     "rates.png", "overlay_sheet.png", "error_since_view.png"):
            self.assertGreater(os.path.getsize(os.path.join(out, name)), 1000, name)
        video = cv2.VideoCapture(os.path.join(out, "overlay.mp4"))
        self.assertTrue(video.isOpened())
        # 91 frames at 30 Hz, each held until the next: 3 s of video at 30 fps.
        self.assertEqual(int(video.get(cv2.CAP_PROP_FRAME_COUNT)), 91)
        ok, frame = video.read()
        self.assertTrue(ok)
        self.assertGreaterEqual(frame.shape[1], 480)


EXCERPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "handheld_run_excerpt.bag")


class RecordedRunTest(unittest.TestCase):
    """2.5 s that launch/demo.launch recorded from the real pipeline on handheld_sample.bag (the
    messages as the nodelets publish them: cone_tracker's detections with their rejection reasons,
    the nodelets' diagnostics, overlay images). How it was cut: data/README.md."""

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="ar_demo_excerpt_")
        cls.summary, cls.t0 = from_evaluation.summarize(EXCERPT)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_series_from_the_real_messages(self):
        s = self.summary
        self.assertAlmostEqual(s.duration_s, 2.46, places=2)
        self.assertGreater(len(s.ekf), 200)  # pose_ekf at ~100 Hz
        self.assertGreater(len(s.tracker), 20)
        self.assertIsNotNone(s.ekf.rot_3sigma_rad)
        self.assertTrue(np.all(np.isfinite(s.ekf.rot_err_rad)))
        # What this pipeline does on the 256x192 sample (see README.md): about a degree, decimetres.
        self.assertLess(np.degrees(np.linalg.norm(s.ekf.rot_err_rad, axis=1)).max(), 5.0)
        self.assertLess(np.linalg.norm(s.ekf.pos_err_m, axis=1).max(), 1.0)
        self.assertTrue(s.visible and s.accepted)
        self.assertGreater(s.overlay_err_px.size, 50)
        reasons = [k for k in s.gates if k.startswith("cone_tracker/detections: ")]
        self.assertTrue(reasons, "no per-frame rejection reasons read from cone_tracker/detections")
        rates = {topic: hz for topic, hz, _ in s.rates}
        self.assertAlmostEqual(rates["camera/camera_info"], 30.0, delta=1.0)
        self.assertAlmostEqual(rates["cone_tracker/detections"], 30.0, delta=1.0)

    def test_report_and_video(self):
        out = os.path.join(self.dir, "out")
        subprocess.check_call(["rosrun", "ar_demo", "demo_report", "--run", EXCERPT, "--out", out])
        with open(os.path.join(out, "report.md")) as f:
            text = f.read()
        self.assertIn("| `orientation_rms_deg` |", text)
        self.assertIn("cone_tracker/detections: ", text)
        video = cv2.VideoCapture(os.path.join(out, "overlay.mp4"))
        # 6 overlay images 0.4 s apart, each held until the next: 2.0 s at 30 fps, plus the last frame.
        self.assertEqual(int(video.get(cv2.CAP_PROP_FRAME_COUNT)), 61)


if __name__ == "__main__":
    import rostest

    # One run, one result file: both test cases, loaded by module name (this file's folder is on sys.path).
    rostest.rosrun("ar_demo", "test_demo_report", "test_demo_report")

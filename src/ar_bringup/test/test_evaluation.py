#!/usr/bin/env python3
"""Known-value tests of ar_bringup.evaluation on synthetic recordings (no bag, no pipeline)."""
import unittest

import numpy as np
from sensor_msgs.msg import CameraInfo

from ar_bringup import evaluation, quat


def rot_z(angle_rad):
    return np.array([0.0, 0.0, np.sin(angle_rad / 2), np.cos(angle_rad / 2)])


def camera_info():
    info = CameraInfo()
    info.width, info.height = 640, 480
    info.K = [500.0, 0, 320, 0, 500.0, 240, 0, 0, 1]
    info.D = [0.0] * 5
    info.distortion_model = "plumb_bob"
    return info


def looking_at_cones(t):
    """Camera 5 m from the cones on -y, looking along +y (optical z = cones y, x = cones x, y = -z)."""
    n = len(t)
    # R_cones_camera columns: camera x -> cones x, camera y -> cones -z, camera z -> cones y.
    R = np.array([[1.0, 0, 0], [0, 0, 1], [0, -1, 0]])
    w = np.sqrt(1 + np.trace(R)) / 2
    q = np.array([(R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w), w])
    return np.tile([0.0, -5.0, 0.5], (n, 1)), np.tile(q, (n, 1))


def recording(truth, ekf, image_t, info=None, tracker_t=None):
    tracker_t = ekf.t if tracker_t is None else tracker_t
    tracker = evaluation.Poses(tracker_t, np.zeros((len(tracker_t), 3)), np.tile([0, 0, 0, 1.0], (len(tracker_t), 1)))
    return evaluation.Recording(truth=truth, ekf=ekf, tracker=tracker, image_t=image_t, camera_info=info,
                                detection_t=np.zeros(0), detection_count=np.zeros(0, dtype=int),
                                imu_t=np.arange(0, 10, 0.01), diagnostics={"pose_ekf: filter": {
                                    "gate rejected": "3", "camera updates": "7"}}, counts={})


class QuatTest(unittest.TestCase):
    def test_rotvec_and_slerp(self):
        q = rot_z(0.3)
        np.testing.assert_allclose(quat.to_rotvec(q), [0, 0, 0.3], atol=1e-12)
        np.testing.assert_allclose(quat.to_rotvec(-q), [0, 0, 0.3], atol=1e-12)  # double cover
        np.testing.assert_allclose(quat.slerp(rot_z(0.0)[None], rot_z(0.4)[None], [0.25])[0], rot_z(0.1), atol=1e-12)
        R = quat.to_matrix(rot_z(np.pi / 2))
        np.testing.assert_allclose(R @ [1, 0, 0], [0, 1, 0], atol=1e-12)


class EvaluationTest(unittest.TestCase):
    def setUp(self):
        t = np.arange(0.0, 10.0 + 1e-9, 1.0 / 300)
        p, q = looking_at_cones(t)
        self.truth = evaluation.Poses(t, p, q)

    def test_known_errors_and_3sigma(self):
        t = np.arange(0.5, 9.5, 0.01)
        p, q = looking_at_cones(t)
        q_err = quat.multiply(np.tile(rot_z(np.radians(0.5)), (len(t), 1)), q)  # 0.5 deg about cones z
        cov = np.tile(np.diag([1e-4, 1e-4, 1e-4, 1e-6, 1e-6, np.radians(0.2) ** 2]), (len(t), 1, 1))
        ekf = evaluation.Poses(t, p + [0.003, -0.004, 0.0], q_err, cov)
        ev = evaluation.evaluate(recording(self.truth, ekf, np.arange(0.0, 10.0, 1 / 30.0), camera_info()))
        self.assertAlmostEqual(ev.summary["orientation_rms_deg"], 0.5, places=6)
        self.assertAlmostEqual(ev.summary["position_rms_m"], 0.005, places=9)
        np.testing.assert_allclose(ev.ekf.rot_error_deg[0], [0, 0, 0.5], atol=1e-6)
        np.testing.assert_allclose(ev.ekf.sigma3_rot_deg[0, 2], 0.6, atol=1e-9)
        self.assertEqual(ev.summary["orientation_within_3sigma"], 1.0)
        self.assertEqual(ev.rejections, {"pose_ekf: filter: gate rejected": 3.0})
        self.assertAlmostEqual(ev.rates_hz["imu"], 100.0, places=6)

    def test_overlay_error_of_a_shift(self):
        # Moving the camera 1 cm along its own x shifts a point at depth d by f * 0.01 / d pixels.
        t = np.arange(0.0, 10.0, 0.01)
        p, q = looking_at_cones(t)
        ekf = evaluation.Poses(t, p + [0.01, 0, 0], q, np.zeros((len(t), 6, 6)))
        rec = recording(self.truth, ekf, np.arange(1.0, 9.0, 1 / 30.0), camera_info())
        ov_t, ov_px = evaluation.overlay_errors(rec, model_points=np.array([[0.0, 0.0, 0.5]]))
        self.assertEqual(len(ov_t), len(rec.image_t))
        np.testing.assert_allclose(ov_px, 500.0 * 0.01 / 5.0, rtol=1e-9)

    def test_overlay_error_capped_at_the_diagonal(self):
        t = np.arange(0.0, 10.0, 0.01)
        p, q = looking_at_cones(t)
        ekf = evaluation.Poses(t, p + [0.0, 10.0, 0.0], q, np.zeros((len(t), 6, 6)))  # 5 m past the cones
        rec = recording(self.truth, ekf, np.arange(1.0, 9.0, 1 / 30.0), camera_info())
        _, ov_px = evaluation.overlay_errors(rec)
        np.testing.assert_allclose(ov_px, 800.0)  # every point behind the estimated camera: 640x480's diagonal

    def test_distortion_matches_opencv_formula(self):
        info = camera_info()
        info.D = [-0.2, 0.05, 0.001, -0.002, 0.01]
        px = evaluation.project(np.array([[0.3, -0.2, 1.0]]), info)[0]
        x, y = 0.3, -0.2
        r2 = x * x + y * y
        radial = 1 - 0.2 * r2 + 0.05 * r2 ** 2 + 0.01 * r2 ** 3
        xd = x * radial + 2 * 0.001 * x * y - 0.002 * (r2 + 2 * x * x)
        yd = y * radial + 0.001 * (r2 + 2 * y * y) + 2 * -0.002 * x * y
        np.testing.assert_allclose(px, [500 * xd + 320, 500 * yd + 240], rtol=1e-12)

    def test_outages_and_recovery_window(self):
        t = np.concatenate([np.arange(0.5, 3.0, 1 / 30.0), np.arange(5.0, 9.0, 1 / 30.0)])
        p, q = looking_at_cones(t)
        p = p.copy()
        p[(t > 5.0) & (t < 5.5)] += [0.1, 0, 0]  # a 10 cm error just after the outage
        ekf = evaluation.Poses(t, p, q, np.zeros((len(t), 6, 6)))
        ev = evaluation.evaluate(recording(self.truth, ekf, t, camera_info()))
        self.assertEqual(len(ev.outages), 1)
        self.assertAlmostEqual(ev.outages[0][0], t[t < 3.0][-1])
        self.assertAlmostEqual(ev.outages[0][1], 5.0)
        self.assertAlmostEqual(ev.ekf_error_after(5.6, 1.0)[1], 0.0, places=9)
        self.assertAlmostEqual(ev.ekf_error_after(5.0, 1.0)[1], 0.1, places=9)

    def test_tracking_figures_leave_out_the_outage(self):
        # EKF at 100 Hz over 1-9 s, tracker poses over 1-4 s and 6-9 s; in the outage between them the
        # EKF drifts by 1 m. The tracking figures cover the tracked spans and 0.5 s after the last pose.
        t = np.arange(1.0, 9.0, 0.01)
        p, q = looking_at_cones(t)
        p = p.copy()
        drift = (t > 4.5) & (t < 6.0)
        p[drift] += [1.0, 0, 0]
        tracker_t = np.concatenate([np.arange(1.0, 4.0, 1 / 30.0), np.arange(6.0, 9.0, 1 / 30.0)])
        ekf = evaluation.Poses(t, p, q, np.zeros((len(t), 6, 6)))
        ev = evaluation.evaluate(recording(self.truth, ekf, np.arange(1.0, 9.0, 1 / 30.0), camera_info(), tracker_t),
                                 settle_s=0.0, tracking_window_s=0.5)
        self.assertAlmostEqual(ev.summary["tracking_position_rms_m"], 0.0, places=12)
        self.assertAlmostEqual(ev.summary["position_rms_m"], np.sqrt(drift.mean()), places=9)
        self.assertAlmostEqual(ev.summary["tracking_fraction"], 6.5 / 8.0, delta=0.01)
        np.testing.assert_array_equal(evaluation.tracking(np.array([0.5, 1.0, 1.4, 1.6]), [1.0], 0.5),
                                      [False, True, True, False])
        self.assertFalse(evaluation.tracking(np.array([1.0]), [], 0.5).any())

    def test_empty_recording_does_not_crash(self):
        empty = evaluation.Poses(np.zeros(0), np.zeros((0, 3)), np.zeros((0, 4)), np.zeros((0, 6, 6)))
        ev = evaluation.evaluate(recording(self.truth, empty, np.zeros(0)))
        self.assertTrue(np.isnan(ev.summary["orientation_rms_deg"]))
        self.assertEqual(len(ev.overlay_t), 0)


class EvaluateBagCliTest(unittest.TestCase):
    """rosrun ar_bringup evaluate_bag on a bag cut short: exit 1, one stderr line saying so."""

    def test_truncated_bag(self):
        import os
        import shutil
        import subprocess
        import tempfile

        import rosbag
        import rospy
        from geometry_msgs.msg import PoseStamped

        d = tempfile.mkdtemp(prefix="ar_bringup_evaluate_bag_")
        try:
            whole, cut = os.path.join(d, "whole.bag"), os.path.join(d, "cut.bag")
            with rosbag.Bag(whole, "w") as bag:
                for k in range(500):
                    m = PoseStamped()
                    m.header.stamp = rospy.Time(1.0 + 0.01 * k)
                    m.pose.orientation.w = 1.0
                    bag.write("rig_sim/ground_truth", m, m.header.stamp)
            with open(whole, "rb") as f:
                data = f.read()
            with open(cut, "wb") as f:
                f.write(data[:len(data) // 2])
            p = subprocess.run(["rosrun", "ar_bringup", "evaluate_bag", cut], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, universal_newlines=True, timeout=120)
            self.assertEqual(p.returncode, 1, p.stderr)
            self.assertEqual(p.stderr.count("\n"), 1, p.stderr)
            self.assertIn("evaluate_bag: cannot read %s: the bag is truncated" % cut, p.stderr)
            self.assertIn("rosbag reindex %s" % cut, p.stderr)
        finally:
            shutil.rmtree(d)


class AllTests(unittest.TestSuite):
    def __init__(self):
        loader = unittest.defaultTestLoader
        super().__init__([loader.loadTestsFromTestCase(QuatTest), loader.loadTestsFromTestCase(EvaluationTest),
                          loader.loadTestsFromTestCase(EvaluateBagCliTest)])


if __name__ == "__main__":
    import rostest
    rostest.rosrun("ar_bringup", "evaluation", "test_evaluation.AllTests")

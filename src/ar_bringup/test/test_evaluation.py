#!/usr/bin/env python3
"""Known-value tests of ar_bringup.evaluation on synthetic recordings (no bag, no pipeline)."""
import unittest

import numpy as np
from sensor_msgs.msg import CameraInfo

from ar_bringup import evaluation, quat, visibility


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
        # EKF drifts by 1 m. The tracking figures cover the tracked spans, less the first 0.1 s after each
        # (re-)acquisition, and 0.5 s after the last pose.
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
        self.assertAlmostEqual(ev.summary["tracking_fraction"], (3.4 + 2.9) / 8.0, delta=0.01)
        np.testing.assert_array_equal(evaluation.tracking(np.array([0.5, 1.0, 1.4, 1.6]), [1.0], 0.5),
                                      [False, True, True, False])
        # The first camera pose after an outage: its own stamp is not yet tracked, one 30 Hz frame later is.
        np.testing.assert_array_equal(evaluation.tracking(np.array([6.0, 6.05, 6.1, 6.2]), [1.0, 6.0, 6.033, 6.067,
                                                                                             6.1], 0.5, 0.1),
                                      [False, False, True, True])
        self.assertFalse(evaluation.tracking(np.array([1.0]), [], 0.5).any())

    def test_empty_recording_does_not_crash(self):
        empty = evaluation.Poses(np.zeros(0), np.zeros((0, 3)), np.zeros((0, 4)), np.zeros((0, 6, 6)))
        ev = evaluation.evaluate(recording(self.truth, empty, np.zeros(0)))
        self.assertTrue(np.isnan(ev.summary["orientation_rms_deg"]))
        self.assertEqual(len(ev.overlay_t), 0)


CONES = np.array([[1.0, 0.0, 0.71], [-0.4, 0.85, 0.71], [-0.6, -0.85, 0.46]])  # asymmetric.yaml: x, y, height


def cone_markers(cones=CONES, radius_m=0.15, sides=24):
    """rig_sim/cones as rig_sim draws it: per cone a TRIANGLE_LIST of (ring point, ring point, apex)."""
    from geometry_msgs.msg import Point
    from visualization_msgs.msg import Marker, MarkerArray
    out = MarkerArray()
    for x, y, h in cones:
        m = Marker()
        for k in range(sides):
            for j in (k, k + 1):
                a = 2 * np.pi * j / sides
                m.points.append(Point(x + radius_m * np.cos(a), y + radius_m * np.sin(a), 0.0))
            m.points.append(Point(x, y, h))
        out.markers.append(m)
    return out


class VisibilityTest(unittest.TestCase):
    """The spans by the cones in the TRUE view (ar_bringup.visibility) on synthetic poses."""

    def setUp(self):
        self.cones = visibility.cones_from_markers(cone_markers())

    def test_cones_from_markers(self):
        np.testing.assert_allclose(self.cones[:, 0], CONES, atol=1e-12)  # peaks
        np.testing.assert_allclose(self.cones[:, 1], np.c_[CONES[:, :2], np.zeros(3)], atol=1e-12)  # base centres

    def test_cones_in_view(self):
        p, q = looking_at_cones(np.zeros(3))
        info = camera_info()
        q_away = quat.multiply(np.tile(rot_z(np.pi), (3, 1)), q)  # turned round: every cone behind
        q_side = quat.multiply(np.tile(rot_z(np.radians(30)), (3, 1)), q)  # 30 deg left: 1 cone off the edge
        n = visibility.cones_in_view(self.cones, p, np.array([q[0], q_away[0], q_side[0]]), info, evaluation.project)
        self.assertEqual(list(n), [3, 0, 2])
        # A cone whose peak is inside and base below the image is out of view: 1 m before cone 1, 0.9 m up.
        low = visibility.cones_in_view(self.cones[:1], np.array([[1.0, -1.0, 0.9]]), q[:1], info)
        self.assertEqual(list(visibility.cones_in_view(self.cones[:1], np.array([[1.0, -3.0, 0.9]]), q[:1], info)), [1])
        self.assertEqual(list(low), [0])

    def test_classes_and_time_since_view(self):
        frame_t = np.arange(0.0, 10.0, 0.1)
        counts = np.where(frame_t < 2.05, 3, np.where(frame_t < 3.05, 1, 0))  # 3 cones to 2.0, 1 to 3.0, then none
        counts[(frame_t > 7.95) & (frame_t < 8.05)] = 2  # one frame at 8.0 with two cones
        t = np.array([-0.5, 1.0, 2.5, 3.5, 4.5, 5.5, 8.02, 8.5, 9.5])
        cls, since = visibility.classify(t, frame_t, counts)
        names = [visibility.CLASSES[c][0] if c >= 0 else None for c in cls]
        self.assertEqual(names, [None, "3plus", "1to2", "none_0to1s", "none_1to2s", "none_over2s", "1to2",
                                 "none_0to1s", "none_1to2s"])
        np.testing.assert_allclose(since[1:], [0, 0, 0.5, 1.5, 2.5, 0, 0.5, 1.5], atol=1e-9)
        self.assertTrue(np.isinf(since[0]))
        # Never in view: everything is "none > 2 s".
        cls, _ = visibility.classify(np.array([0.5, 1.0]), frame_t, np.zeros(len(frame_t), int))
        self.assertEqual(list(cls), [4, 4])

    def test_overlay_counts_cones_near_the_view_only(self):
        # A cone just off the image edge counts; one at 80 deg off the axis (pinhole x of 3000 px) does not.
        p, q = looking_at_cones(np.zeros(1))
        info = camera_info()
        near_cone = np.array([[[1.5, 0.0, 0.5], [1.5, 0.0, 0.0]]])  # pinhole x 320 + 500 * 1.5 / 5 = 470 px
        far_cone = np.array([[[10.0, -4.0, 0.5], [10.0, -4.0, 0.0]]])
        shift = p + [0.0, 0.0, 0.01]  # 1 cm up: every point moves 500 * 0.01 / depth px
        ov, centre = visibility.overlay_full_res_px(near_cone, p, q, shift, q, info, full_width_px=640)
        self.assertAlmostEqual(ov[0], 500 * 0.01 / 5.0, places=9)
        ov, _ = visibility.overlay_full_res_px(far_cone, p, q, shift, q, info, full_width_px=640)
        self.assertTrue(np.isnan(ov[0]))
        both = np.concatenate([near_cone, far_cone])
        ov, _ = visibility.overlay_full_res_px(both, p, q, shift, q, info, full_width_px=1280)
        self.assertAlmostEqual(ov[0], 2 * 500 * 0.01 / 5.0, places=9)  # the far cone left out; x 1280 / 640

    def test_updated_frames(self):
        frame_t = np.arange(0.0, 1.0, 1 / 30.0)
        pose_t = frame_t[:10] + 1e-6
        obs_t = frame_t[20:25]
        up = visibility.updated_frames(frame_t, pose_t, obs_t)
        self.assertEqual(int(up.sum()), 15)
        self.assertTrue(up[:10].all() and up[20:25].all() and not up[10:20].any())
        self.assertFalse(visibility.updated_frames(frame_t, [0.5 + 1 / 60.0], []).any())  # between frames

    def test_evaluate_splits_by_true_view(self):
        # Truth: looking at the cones until 5 s, then turned round. The EKF is 1 cm off along cones x
        # throughout; tracker poses on the frames to 3 s, observations on 3.0-3.4 s.
        t = np.arange(0.0, 10.0 + 1e-9, 1.0 / 300)
        p, q = looking_at_cones(t)
        q = np.where((t >= 5.0)[:, None], quat.multiply(np.tile(rot_z(np.pi), (len(t), 1)), q), q)
        truth = evaluation.Poses(t, p, q)
        te = np.arange(0.0, 10.0, 0.01)
        ok, pe, qe = truth.interpolate(te)
        ekf = evaluation.Poses(te, pe + [0.01, 0, 0], qe, np.zeros((len(te), 6, 6)))
        frame_t = np.round(np.arange(0.0, 10.0, 0.1), 9)
        rec = recording(truth, ekf, frame_t, camera_info(), tracker_t=frame_t[frame_t < 2.95])
        rec.cones = self.cones
        rec.observation_t = frame_t[(frame_t > 2.95) & (frame_t < 3.45)]
        ev = evaluation.evaluate(rec, settle_s=0.0, full_width_px=1024)
        s = ev.summary
        self.assertEqual(s["view_3plus_frames"], 50.0)
        self.assertEqual(s["view_1to2_frames"], 0.0)
        self.assertEqual(s["view_3plus_frames"] + s["view_none_0to1s_frames"] + s["view_none_1to2s_frames"]
                         + s["view_none_over2s_frames"], 100.0)
        self.assertAlmostEqual(s["view_3plus_updated_fraction"], 35 / 50.0)
        self.assertEqual(s["view_none_over2s_updated_fraction"], 0.0)
        for key in ("3plus", "none_0to1s", "none_over2s"):
            self.assertAlmostEqual(s["view_%s_position_rms_m" % key], 0.01, places=9)
            self.assertAlmostEqual(s["view_%s_position_median_m" % key], 0.01, places=9)
            self.assertAlmostEqual(s["view_%s_orientation_rms_deg" % key], 0.0, places=6)
        # The camera's x is cones x while looking: a point at depth z moves 500 * 0.01 / z px, x 1024 / 640.
        pts = self.cones.reshape(-1, 3)
        depth = pts[:, 1] + 5.0
        self.assertAlmostEqual(s["view_3plus_overlay_rms_px"], np.mean(500 * 0.01 / depth) * 1.6, places=9)
        self.assertTrue(np.isnan(s["view_none_over2s_overlay_rms_px"]))  # every cone behind the true camera
        self.assertEqual(s["view_none_over2s_overlay_frames"], 0.0)
        self.assertEqual(s["view_3plus_overlay_frames"], 50.0)
        # At the centre of the view, at the distance of the cones' centroid, the 1 cm shows in every span.
        centre = 500 * 0.01 / np.linalg.norm(pts.mean(axis=0) - [0.0, -5.0, 0.5]) * 1.6
        for key in ("3plus", "none_0to1s", "none_1to2s", "none_over2s"):
            self.assertAlmostEqual(s["view_%s_centre_median_px" % key], centre, places=9)
            self.assertAlmostEqual(s["view_%s_centre_rms_px" % key], centre, places=9)
        self.assertEqual(set(ev.view.ekf_class[te < 4.99]), {0})
        self.assertEqual(set(ev.view.ekf_class[(te > 5.05) & (te < 5.85)]), {2})
        self.assertEqual(set(ev.view.ekf_class[te > 6.95]), {4})
        # The existing figures are still there.
        self.assertAlmostEqual(s["position_rms_m"], 0.01, places=9)

    def test_recording_from_messages_reads_cones_and_observations(self):
        from cone_tracker.msg import ConeObservation, ConeObservations
        import rospy
        empty, full = ConeObservations(), ConeObservations()
        empty.header.stamp, full.header.stamp = rospy.Time(1.0), rospy.Time(2.0)
        full.cones.append(ConeObservation())
        rec = evaluation.recording_from_messages([("/rig_sim/cones", cone_markers()),
                                                  ("cone_tracker/observations", empty),
                                                  ("cone_tracker/observations", full)])
        np.testing.assert_allclose(rec.cones[:, 0], CONES, atol=1e-12)
        np.testing.assert_allclose(rec.observation_t, [2.0])
        self.assertIsNone(evaluation.evaluate(rec).view)  # no truth: no view figures, no crash


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
                          loader.loadTestsFromTestCase(VisibilityTest),
                          loader.loadTestsFromTestCase(EvaluateBagCliTest)])


if __name__ == "__main__":
    import rostest
    rostest.rosrun("ar_bringup", "evaluation", "test_evaluation.AllTests")

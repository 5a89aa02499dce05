#!/usr/bin/env python3
"""Real-data checks of the 3.2 calibrations on the BROAD benchmark (real IMU + optical truth).

Skips with a message when ../shared/data/imu is absent. BROAD's optical orientation is
already aligned to the IMU frame, so the camera-IMU method (3.32) (3.33) (3.34) must find the
identity: the optical body frame plays the camera, the ENU world plays the grid.
"""
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np
from rig_model.strict_yaml import load_yaml_file

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "scripts"))
import gyro_bias_report as gbr  # noqa: E402

CANDIDATES = [os.path.join(HERE, "..", "..", "..", "..", "shared", "data", "imu", "broad"),
              "/work/shared/data/imu/broad"]
DATA = next((p for p in CANDIDATES if os.path.isdir(p)), None)
TRIALS = ["01_undisturbed_slow_rotation_A", "21_undisturbed_fast_combined"]


def load(trial):
    import scipy.io as sio

    d = sio.loadmat(os.path.join(DATA, trial + ".mat"))
    fs = float(d["sampling_rate"][0, 0])
    return np.arange(len(d["imu_gyr"])) / fs, d["imu_gyr"], d["imu_acc"], d["opt_quat"], fs


def quat_rotate_inv(q_wxyz, v):
    """R(q)^T v for a unit quaternion [w x y z] (body -> world)."""
    w, x, y, z = q_wxyz
    R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                  [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                  [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
    return R.T @ v, R


def rotvec_to_matrix(r):
    th = np.linalg.norm(r)
    if th < 1e-12:
        return np.eye(3)
    k = r / th
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(th) * K + (1 - np.cos(th)) * K @ K


def matrix_from_xyzw(q):
    x, y, z, w = q
    _, R = quat_rotate_inv((w, x, y, z), np.zeros(3))
    return R


def angle_deg(A, B):
    return np.degrees(np.arccos(np.clip((np.trace(A.T @ B) - 1) / 2, -1, 1)))


def find_tool():
    devel = os.environ.get("CMAKE_PREFIX_PATH", "").split(":")
    for prefix in devel:
        p = os.path.join(prefix, "lib", "imu_driver", "calibrate_camera_imu")
        if os.path.exists(p):
            return p
    return None


@unittest.skipIf(DATA is None, "real IMU data not found (looked in %s); skipping" % CANDIDATES)
class RealData(unittest.TestCase):
    def test_static_bias_is_the_same_at_both_rests(self):
        """3.2.1: each trial starts and ends at rest; the bias is non-zero and the same at both."""
        for trial in TRIALS:
            t, g, a, _, _ = load(trial)
            segs = gbr.static_segments(t, g, a, 0.5, 0.02, 0.2, 2.0)
            self.assertGreaterEqual(len(segs), 2, trial)
            b0, s0, _, _ = gbr.compute(g, [segs[0]])
            b1, s1, _, _ = gbr.compute(g, [segs[-1]])
            print("%s: bias start %s end %s rad/s, sigma %s" % (trial, b0, b1, s0))
            self.assertGreater(np.abs(b0).max(), 1e-3, trial)  # a real, non-zero bias
            self.assertLess(np.abs(b0 - b1).max(), 3e-4, trial)
            self.assertTrue(np.all((s0 > 5e-4) & (s0 < 5e-3)), trial)

    def test_report_script_writes_histogram_and_yaml(self):
        """gyro_bias_report.py end to end on a CSV of the real trial: PNG and the driver's YAML keys."""
        t, g, a, _, _ = load(TRIALS[0])
        with tempfile.TemporaryDirectory() as d:
            csv, png, out = (os.path.join(d, n) for n in ("still.csv", "bias.png", "gyro.yaml"))
            np.savetxt(csv, np.column_stack([t, g, a]), delimiter=",", header="t,gx,gy,gz,ax,ay,az")
            bias, sigma, segs = gbr.main([csv, "--png", png, "--yaml", out])
            self.assertGreater(os.path.getsize(png), 10000)
            y = load_yaml_file(out)
            np.testing.assert_allclose(y["gyro_bias_rad_s"], bias, atol=1e-9)
            np.testing.assert_allclose(y["gyro_noise_sigma_rad_s"], sigma, atol=1e-9)
            self.assertEqual(len(segs), 2)

    def test_bias_correction_reduces_integration_error(self):
        """Integrating bias-corrected gyro over 5 s windows matches the optical truth better."""
        t, g, a, q, fs = load(TRIALS[0])
        segs = gbr.static_segments(t, g, a, 0.5, 0.02, 0.2, 2.0)
        bias, _, _, _ = gbr.compute(g, [segs[0]])
        W = int(5 * fs)

        def median_error(b):
            errs = []
            for s in range(segs[0][1], segs[-1][0] - W, W):
                if np.isnan(q[s]).any() or np.isnan(q[s + W]).any():
                    continue
                R = np.eye(3)
                for w in g[s:s + W] - b:
                    R = R @ rotvec_to_matrix(w / fs)
                _, R0 = quat_rotate_inv(q[s], np.zeros(3))
                _, R1 = quat_rotate_inv(q[s + W], np.zeros(3))
                errs.append(angle_deg(R0.T @ R1, R))
            return np.median(errs)

        raw, corrected = median_error(np.zeros(3)), median_error(bias)
        print("5 s integration error vs optical truth: raw %.2f deg, bias-corrected %.2f deg" % (raw, corrected))
        self.assertLess(corrected, 0.8 * raw)

    def poses(self, trial, R_camera_body=np.eye(3)):
        """Quasi-static 0.1 s windows: accel mean in {I}, extrinsics R_camera_world."""
        _, g, a, q, fs = load(trial)
        W = int(0.1 * fs)
        out = []
        for s in range(0, len(g) - W, W):
            qq = q[s:s + W]
            if np.isnan(qq).any() or (np.linalg.norm(qq, axis=1) < 0.5).any():
                continue
            if np.linalg.norm(g[s:s + W], axis=1).max() > 0.6 or a[s:s + W].std(axis=0).max() > 0.3:
                continue
            am = a[s:s + W].mean(axis=0)
            if abs(np.linalg.norm(am) - 9.81) > 0.2:
                continue
            _, R_world_body = quat_rotate_inv(q[s + W // 2], np.zeros(3))
            R = R_camera_body @ R_world_body.T
            w = np.sqrt(max(1.0 + np.trace(R), 1e-12)) / 2
            xyzw = [(R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w), w]
            out.append((am, xyzw))
        return out

    def run_tool(self, poses):
        tool = find_tool()
        self.assertIsNotNone(tool, "calibrate_camera_imu not built")
        with tempfile.TemporaryDirectory() as d:
            src, dst = os.path.join(d, "in.yaml"), os.path.join(d, "out.yaml")
            with open(src, "w") as f:
                f.write("up_in_grid: [0, 0, 1]  # ENU\nposes:\n")
                for am, xyzw in poses:
                    f.write("  - accel_mean_m_s2: [%.9f, %.9f, %.9f]\n" % tuple(am))
                    f.write("    q_camera_grid_xyzw: [%.12f, %.12f, %.12f, %.12f]\n" % tuple(xyzw))
            proc = subprocess.run([tool, src, dst], capture_output=True, text=True)
            if proc.returncode != 0:
                return proc, None
            # What the tool writes is what the static tf node accepts (strict keys, unit quaternion).
            script = os.path.join(HERE, "..", "scripts", "camera_imu_static_tf.py")
            check = subprocess.run([sys.executable, script, "--check", dst], capture_output=True, text=True)
            self.assertEqual(check.returncode, 0, check.stderr)
            return proc, load_yaml_file(dst)["camera_imu"]

    def test_camera_imu_rotation_on_real_data(self):
        """(3.32) (3.33) (3.34) on 700+ real quasi-static poses: identity, then a known rotation, within 0.5 deg."""
        poses = self.poses(TRIALS[0])
        self.assertGreater(len(poses), 500)
        proc, out = self.run_tool(poses)
        self.assertIsNotNone(out, proc.stderr)
        R = matrix_from_xyzw(out["rotation_xyzw"])
        print("BROAD %s: %d poses, R_camera_imu %.3f deg from identity, rms residual %.3f deg, SVD vs Euler %.5f deg"
              % (TRIALS[0], len(poses), angle_deg(R, np.eye(3)), out["rms_residual_deg"], out["svd_vs_euler_deg"]))
        self.assertLess(angle_deg(R, np.eye(3)), 0.5)
        self.assertLess(out["svd_vs_euler_deg"], 0.05)
        R_true = rotvec_to_matrix(np.array([0.2, -0.3, 0.5]))
        proc, out = self.run_tool(self.poses(TRIALS[0], R_true))
        self.assertIsNotNone(out, proc.stderr)
        self.assertLess(angle_deg(matrix_from_xyzw(out["rotation_xyzw"]), R_true), 0.5)

    def test_nearly_parallel_gravity_is_refused(self):
        """Trial 21's quasi-static poses hardly tilt: the rotation about gravity is unobservable."""
        proc, out = self.run_tool(self.poses(TRIALS[1]))
        self.assertIsNone(out)
        self.assertIn("parallel", proc.stderr)


if __name__ == "__main__":
    import rostest

    rostest.rosrun("imu_driver", "real_data", RealData, sys.argv)

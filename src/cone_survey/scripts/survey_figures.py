#!/usr/bin/env python3
"""Survey accuracy on random layouts: for each (cones, seed), make_layout, a survey walk (make_bag
--scenario survey), survey_layout, and the surveyed positions against the truth: the RMS of all
pairwise distances (no frame alignment) and each cone's error after the best rigid alignment.

usage: survey_figures.py [--duration S] [--scale F] CONES:SEED [CONES:SEED ...]
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
import yaml


def cones_of(path):
    with open(path) as f:
        return [(np.array([c["x_m"], c["y_m"], c.get("z_m", 0.0)]), c["height_m"], c.get("style", "road"))
                for c in yaml.safe_load(f)["cones"]]


def sigmas_of(path):
    with open(path) as f:
        return np.array([c.get("sigma_m", [np.nan] * 3) for c in yaml.safe_load(f)["cones"]], dtype=float)


def devel(tool, package):
    return os.path.join(os.environ.get("CATKIN_DEVEL", os.path.join(os.path.dirname(__file__), "../../../catkin_ws/devel")),
                        "lib", package, tool)


# The simulated rig's camera-IMU calibration (launch/replay.launch's): rig_sim's bags hold only the truth edge.
CAMERA_IMU = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../ar_bringup/config/rig_sim_camera_imu.yaml")


def rigid(src, dst):
    """R, t minimising |R src + t - dst| (Kabsch)."""
    ms, md = src.mean(axis=0), dst.mean(axis=0)
    u, _, vt = np.linalg.svd((dst - md).T @ (src - ms))
    d = np.diag([1, 1, np.sign(np.linalg.det(u @ vt))])
    r = u @ d @ vt
    return r, md - r @ ms


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--duration", type=float, default=20.0)
    ap.add_argument("--scale", type=float, default=0.5)
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="survey_figures_")
    all_errors, all_normalised = [], []
    for run in a.runs:
        n, seed = (int(x) for x in run.split(":"))
        layout, inv, bag, out = (os.path.join(work, f"{n}_{seed}.{e}") for e in ("layout.yaml", "inv.yaml", "bag", "out.yaml"))
        subprocess.run([devel("make_layout", "rig_sim"), "--cones", str(n), "--seed", str(seed), "--output", layout],
                       check=True, stdout=subprocess.DEVNULL)
        truth = cones_of(layout)
        with open(inv, "w") as f:
            f.write("cones:\n" + "".join(f"  - {{height_m: {h}, style: {s}}}\n" for _, h, s in truth) +
                    "origin: 0\nx_axis: 1\n")
        subprocess.run([devel("make_bag", "rig_sim"), "--scenario", "survey", "--layout", layout, "--seed", str(seed),
                        "--duration", str(a.duration), "--scale", str(a.scale), "--output", bag],
                       check=True, stdout=subprocess.DEVNULL)
        p = subprocess.run([devel("survey_layout", "cone_survey"), "--bag", bag, "--inventory", inv, "--output", out,
                            "--camera-imu", CAMERA_IMU],
                           capture_output=True, text=True)
        os.remove(bag)
        if p.returncode != 0:
            print(f"{n} cones seed {seed}: survey_layout refused: {p.stderr.strip()}")
            continue
        rms_px = [l for l in p.stdout.splitlines() if "reprojection RMS" in l][0].split("RMS")[1].strip()
        got = cones_of(out)
        # Cones of one height are interchangeable: pair each surveyed cone with the nearest true cone of its
        # height in the anchors' frame (cone 0 at the origin, cone 1 on +x).
        o, d = truth[0][0], truth[1][0] - truth[0][0]
        c, s = np.cos(-np.arctan2(d[1], d[0])), np.sin(-np.arctan2(d[1], d[0]))
        rz = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
        free = list(range(len(truth)))
        match = []
        for g, h, _ in got:
            j = min((j for j in free if abs(truth[j][1] - h) < 1e-6), key=lambda j: np.linalg.norm(rz @ (truth[j][0] - o) - g))
            free.remove(j)
            match.append(j)
        src = np.array([g for g, _, _ in got])
        dst = np.array([truth[j][0] for j in match])
        pair = [np.linalg.norm(src[i] - src[j]) - np.linalg.norm(dst[i] - dst[j]) for i in range(len(src)) for j in range(i)]
        r, t = rigid(src, dst)
        err = np.linalg.norm((r @ src.T).T + t - dst, axis=1)
        all_errors += list(err)
        dist = [np.linalg.norm(dst[i] - dst[j]) for i in range(len(src)) for j in range(i)]
        scale = np.dot(pair, dist) / np.dot(dist, dist)  # the distances' common scale error
        print(f"{n} cones seed {seed}: pairwise RMS {1e3 * np.sqrt(np.mean(np.square(pair))):.1f} mm "
              f"(scale {1e2 * scale:+.2f} %), per-cone error "
              f"mean {1e3 * err.mean():.1f} mm, max {1e3 * err.max():.1f} mm, reprojection RMS {rms_px}")
        print("    per cone (mm): " + " ".join(f"{1e3 * e:.1f}" for e in err))
        # The sigmas are in the survey's frame (the anchors'): each axis's error there over its sigma.
        sig = sigmas_of(out)
        anchored = np.array([rz @ (dst[i] - o) for i in range(len(dst))])
        e_axes, s_axes = (src - anchored).ravel(), sig.ravel()
        keep = s_axes > 0
        z = e_axes[keep] / s_axes[keep]
        all_normalised += list(z)
        print(f"    error / sigma per axis: RMS {np.sqrt(np.mean(z ** 2)):.2f}, |z| > 2 in {np.mean(np.abs(z) > 2):.0%}, "
              f"> 3 in {np.mean(np.abs(z) > 3):.0%} ({keep.sum()} axes; median sigma {1e3 * np.median(s_axes[keep]):.1f} mm)")
    if all_errors:
        e = np.array(all_errors)
        print(f"all {len(e)} cones: error RMS {1e3 * np.sqrt(np.mean(e ** 2)):.1f} mm, p95 {1e3 * np.percentile(e, 95):.1f} mm, "
              f"max {1e3 * e.max():.1f} mm")
    if all_normalised:
        z = np.array(all_normalised)
        print(f"all {len(z)} axes: error / sigma RMS {np.sqrt(np.mean(z ** 2)):.2f}, |z| > 2 in {np.mean(np.abs(z) > 2):.0%}, "
              f"> 3 in {np.mean(np.abs(z) > 3):.0%} (1.00, 5 % and 0.3 % if the sigmas are honest)")


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The look-away gyro experiment (thesis 7.3) on one recorded tracker output: the bag a look_away_gyro.sh
run recorded (cone_tracker's poses and observations, the IMU, the truth) is replayed through ekf_replay
with each filter configuration, so they all see the same cones, and scored by ar_bringup.evaluation at the
image stamps with the pose the overlay would draw (platform_offline.display_pose: tf's interpolation, or
the last output held when the filter published nothing, as with gyros and accelerometer off).

  look_away_offline.py --bag RUN.bag --layout LAYOUT.yaml --out DIR NAME=EKF_CONFIG.yaml... [NAME=live]

Prints, per run, the overlay error (RMS px at 1024x768 of the 1 m cube on the cones' centroid) by the cones
in the true view, the whole run's overlay RMS, the position (m) and orientation (deg) RMS, and how many of the
images where the cube is out of the true view still have it drawn in the image (a frozen overlay: the
thesis's users' complaint in 7.3; the overlay error figures cannot see it, they need the cube in view)."""
import argparse
import dataclasses
import os
import sys

import numpy as np

from ar_bringup import evaluation

# The sibling script, also when run through catkin's devel wrapper (whose folder holds a wrapper of that name).
sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from platform_offline import display_pose, replay  # noqa: E402

SPANS = (("3plus", "3+ cones"), ("1to2", "1-2 cones"), ("none_0to1s", "none 0-1 s"),
         ("none_1to2s", "none 1-2 s"), ("none_over2s", "none > 2 s"))


def ghosts(rec, shown):
    """(images where no point of the model is in the true view, of those the ones where the estimate still
    draws one in the image): a frozen overlay stays on the screen while the user looks away (7.3)."""
    pts = evaluation.DEFAULT_MODEL_POINTS
    ok_e, p_e, q_e = shown.interpolate(rec.image_t)
    ok_t, p_t, q_t = rec.truth.interpolate(rec.image_t)
    ok = ok_e & ok_t
    w, h = rec.camera_info.width, rec.camera_info.height

    def in_image(p, q):
        c = evaluation._to_camera(pts, p, q)
        front = c[..., 2] > 0.05
        px = evaluation.project(np.where(front[..., None], c, 1.0), rec.camera_info)
        return (front & (px[..., 0] >= 0) & (px[..., 0] < w) & (px[..., 1] >= 0) & (px[..., 1] < h)).any(axis=1)

    away = ~in_image(p_t[ok], q_t[ok])
    drawn = in_image(p_e[ok], q_e[ok])
    return int(away.sum()), int((away & drawn).sum())


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bag", required=True)
    ap.add_argument("--layout", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("runs", nargs="+", metavar="NAME=EKF_CONFIG|live")
    a = ap.parse_args(argv[1:])
    for path in (a.bag, a.layout):
        if not os.path.isfile(path):
            raise SystemExit("look_away_offline: %s: no such file" % path)
    for run in a.runs:
        name, _, config = run.partition("=")
        if not name or not config or (config != "live" and not os.path.isfile(config)):
            raise SystemExit("look_away_offline: run '%s': expected NAME=EKF_CONFIG.yaml (an existing file) or "
                             "NAME=live" % run)
    os.makedirs(a.out, exist_ok=True)
    rec = evaluation.load_bag(a.bag)
    if rec.camera_info is None or len(rec.truth) < 2:
        raise SystemExit("look_away_offline: %s: needs camera/camera_info and rig_sim/ground_truth" % a.bag)
    print("| run | " + " | ".join(label for _, label in SPANS) + " | whole run px | position m | orientation deg "
          "| drawn while out of view |")
    print("|---" * (len(SPANS) + 5) + "|")
    notes = []
    for run in a.runs:
        name, _, config = run.partition("=")
        if not config:
            raise SystemExit("look_away_offline: run '%s': expected NAME=EKF_CONFIG.yaml or NAME=live" % run)
        if config == "live":
            est, note = rec.ekf, "pose_ekf/pose as recorded"
        else:
            est, note = replay(a.bag, config, a.layout, a.out, name)
        ok, p, q = display_pose(est, rec.image_t)
        shown = evaluation.Poses(rec.image_t[ok], p[ok], q[ok])
        ev = evaluation.evaluate(dataclasses.replace(rec, ekf=shown))
        s = ev.summary
        cells = ["%.1f" % s.get("view_%s_overlay_rms_px" % key, float("nan")) for key, _ in SPANS]
        away, drawn = ghosts(rec, shown)
        print("| %s | %s | %.1f | %.3f | %.2f | %d of %d |" % (
            name, " | ".join(cells), s.get("overlay_rms_px", float("nan")), s.get("position_rms_m", float("nan")),
            s.get("orientation_rms_deg", float("nan")), drawn, away))
        notes.append("%s: %s" % (name, note))
    print()
    for n in notes:
        print("- " + n)


if __name__ == "__main__":
    main(sys.argv)

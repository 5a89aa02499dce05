#!/usr/bin/env python3
"""Tracking errors on a large layout split by the cones the camera can resolve: ar_bringup.evaluation's
view_* classes count every cone whose peak and base project into the true image, and on rig_sim's `site`
(14 cones over 19 m x 19 m) the far ring is nearly always in the image, a few pixels tall, so every frame
is "3plus". Here a cone counts when it also stands at least --min-px tall in the image (default 15 px:
cone_tracker's min_area_px 30 for a cone of tau 1/7, whose silhouette covers h^2 / 7 px). The classes and
the figures are otherwise ar_bringup.visibility's: 3plus, 1to2, none for 0-1 s, 1-2 s, > 2 s.

usage: scripts/site_view_split.py [--min-px PX] OUT.bag [OUT.bag ...]   (bags recorded by launch/replay.launch)
"""
import argparse
import sys

import numpy as np

from ar_bringup import evaluation, visibility


def resolved_counts(rec, min_px):
    """Cones in the true view at each frame stamp that stand at least min_px tall."""
    valid, p, q = rec.truth.interpolate(rec.image_t)
    info = rec.camera_info
    K = np.reshape(info.K, (3, 3))
    w, h = float(info.width), float(info.height)
    c = visibility.to_camera(rec.cones.reshape(-1, 3), p, q).reshape(len(p), -1, 2, 3)  # frame, cone, peak/base
    z = np.where(c[..., 2] > visibility.MIN_DEPTH_M, c[..., 2], 1.0)
    u, v = K[0, 0] * c[..., 0] / z + K[0, 2], K[1, 1] * c[..., 1] / z + K[1, 2]
    inside = (c[..., 2] > visibility.MIN_DEPTH_M) & (u >= 0) & (u < w) & (v >= 0) & (v < h)
    tall = np.hypot(u[..., 0] - u[..., 1], v[..., 0] - v[..., 1]) >= min_px
    return np.where(valid, (inside.all(axis=2) & tall).sum(axis=1), 0)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bags", nargs="+")
    ap.add_argument("--min-px", type=float, default=15.0)
    ap.add_argument("--settle-s", type=float, default=1.0)
    a = ap.parse_args()
    print("bag | whole run: position RMS m, orientation RMS deg | per class (" +
          ", ".join(k for k, _ in visibility.CLASSES) + "): share of time, position RMS m, orientation RMS deg, "
          "frames updating the filter")
    for path in a.bags:
        rec = evaluation.load_bag(path)
        if rec.cones is None or rec.camera_info is None:
            print(f"{path}: no rig_sim/cones or camera_info recorded", file=sys.stderr)
            return 1
        ev = evaluation.evaluate(rec, settle_s=a.settle_s)
        counts = resolved_counts(rec, a.min_px)
        t0 = ev.ekf.t[0] + a.settle_s
        m = ev.ekf.t >= t0
        cls, _ = visibility.classify(ev.ekf.t, rec.image_t, counts)
        fcls, _ = visibility.classify(rec.image_t, rec.image_t, counts)
        updated = visibility.updated_frames(rec.image_t, rec.tracker.t, rec.observation_t)
        rms = lambda x: float(np.sqrt(np.mean(np.square(x)))) if len(x) else float("nan")  # noqa: E731
        parts = []
        for k, (key, _) in enumerate(visibility.CLASSES):
            e = m & (cls == k)
            f = (fcls == k) & (rec.image_t >= t0)
            parts.append(f"{key} {e.sum() / max(1, m.sum()):.0%} {rms(ev.ekf.position_error_m[e]):.3f} "
                         f"{rms(ev.ekf.orientation_error_deg[e]):.2f} {updated[f].mean() if f.any() else float('nan'):.2f}")
        print(f"{path}: {rms(ev.ekf.position_error_m[m]):.4f} {rms(ev.ekf.orientation_error_deg[m]):.3f} | " +
              " | ".join(parts))
    return 0


if __name__ == "__main__":
    sys.exit(main())

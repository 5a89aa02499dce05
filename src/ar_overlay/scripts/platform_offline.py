#!/usr/bin/env python3
"""The overlay test platform (thesis 7.2) scored without images, for the gyro study (issue 16, item 7).

One recorded run of the pipeline (overlay_platform.sh's <run>.outputs.bag: cone_tracker's poses and
observations, the IMU, rig_sim's truth, camera_info and pose_ekf/pose) is replayed through pose_ekf's
`ekf_replay` with each filter configuration, so every configuration sees the same tracker output, and
each estimate is scored as the platform monitor scores the rendered overlay: at every image stamp the
16 red dots (scene_platform.yaml: a 4 x 4 grid 10 cm apart on the board's top face, z = 0.05 m) are
projected with the estimate and with the truth; a dot is lost when it lands half a cell (5 cm) or more
from its place on the platform, otherwise its error counts into mu and sigma (inches through the dot's
own metres per pixel, x image right, y image down). Images count when the true camera sees the whole
blue grid (no occlusion test: more frames than the monitor, which also drops frames the cones hide).

  platform_offline.py --bag RUN.outputs.bag --layout LAYOUT.yaml --out DIR [--order arrival|stamp]
                      [--series] NAME=EKF_CONFIG.yaml... [NAME=live]

NAME=live scores the recorded pose_ekf/pose (what the overlay drew in that run). --order stamp rewrites
the bag with every message at its header stamp first (no tracker latency: the camera frames reach the
filter when they were exposed); arrival (default) keeps the recorded order, i.e. the live run's latency.
The estimate at an image stamp is the filter's output then (display_pose): interpolated as tf does between
outputs at most 50 ms apart, else the last output held (the overlay frozen); with --order arrival a frame's
own camera update is in it only if the frame reached the filter before the next IMU sample was processed.
--series writes DIR/<NAME>.series.csv: per image, the time, the dots' mean and max platform error (m), the
dots lost, and the age (s) of the newest camera pose and of the newest camera frame (a pose or cones)."""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

from ar_bringup import evaluation, visibility

INCH_M = 0.0254
SPACING_M = 0.1
RED = np.array([[(k - 1.5) * SPACING_M, (r - 1.5) * SPACING_M, 0.05] for r in range(4) for k in range(4)])
HOLD_GAP_S = 0.05  # ar_overlay's tf_timeout_s: a later output than this does not reach the overlay in time
BLUE = np.array([[(k - 2) * SPACING_M, (r - 2) * SPACING_M, 0.05] for r in range(5) for k in range(5)])


def load_tum(path):
    d = np.loadtxt(path, ndmin=2)
    if d.size == 0:
        raise SystemExit("platform_offline: %s: no poses" % path)
    order = np.argsort(d[:, 0], kind="stable")
    d = d[order]
    return evaluation.Poses(d[:, 0], d[:, 1:4], d[:, 4:8])


def display_pose(est, t, max_gap_s=HOLD_GAP_S):
    """The pose the overlay draws at image stamps t: interpolated between the two outputs around the stamp
    when they are at most max_gap_s apart (tf's interpolation, at the filter's IMU rate), otherwise the last
    output before the stamp held (a filter that publishes nothing in an outage: the overlay freezes, as the
    thesis's users saw with the gyros off). Returns (valid, p, q)."""
    t = np.asarray(t, dtype=float)
    valid, p, q = est.interpolate(t)
    j = np.searchsorted(est.t, t, side="right") - 1
    inside = (j >= 0) & (j < len(est.t) - 1)
    gap = np.full(len(t), np.inf)
    gap[inside] = est.t[j[inside] + 1] - est.t[j[inside]]
    hold = (j >= 0) & (gap > max_gap_s)
    p[hold], q[hold] = est.p[j[hold]], est.q[j[hold]]
    return valid | hold, p, q


def restamp(src, dst):
    """A copy of src with every message at its header stamp (messages without one keep their time)."""
    import rosbag
    with rosbag.Bag(src) as bag, rosbag.Bag(dst, "w") as out:
        items = []
        for topic, msg, t in bag.read_messages():
            stamp = getattr(getattr(msg, "header", None), "stamp", None)
            items.append((stamp if stamp is not None and stamp.to_sec() > 0 else t, topic, msg))
        items.sort(key=lambda x: x[0].to_sec())
        for t, topic, msg in items:
            out.write(topic, msg, t)


def replay(bag, config, layout, out_dir, name):
    """ekf_replay of the bag with config (plus the layout, for camera_update: cones)."""
    cfg = os.path.join(out_dir, name + ".yaml")
    with open(config) as f:
        lines = [ln for ln in f if not ln.startswith("layout_file:")]
    with open(cfg, "w") as f:
        f.writelines(lines)
        f.write("layout_file: '%s'\n" % layout)
    traj = os.path.join(out_dir, name + ".tum")
    log = subprocess.run(["rosrun", "pose_ekf", "ekf_replay", "--bag", bag, "--config", cfg, "--output", traj],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
    if log.returncode != 0:
        raise SystemExit("platform_offline: ekf_replay %s --config %s failed:\n%s" % (bag, cfg, log.stdout))
    summary = [ln for ln in log.stdout.splitlines() if ln.startswith("ekf_replay:")]
    return load_tum(traj), (summary[-1] if summary else "")


def score(rec, est):
    """Per image: (t, errors px (16, 2), platform error m (16,), m per px (16,)) where the true camera
    sees the whole blue grid and the estimate covers the stamp."""
    info = rec.camera_info
    w, h = info.width, info.height
    t = rec.image_t
    ok_t, p_t, q_t = rec.truth.interpolate(t)
    ok_e, p_e, q_e = display_pose(est, t)
    ok = ok_t & ok_e
    t, p_t, q_t, p_e, q_e = t[ok], p_t[ok], q_t[ok], p_e[ok], q_e[ok]
    blue_c = evaluation._to_camera(BLUE, p_t, q_t)
    blue_px = evaluation.project(blue_c, info)
    seen = (blue_c[..., 2] > 0.1).all(axis=1) & (blue_px[..., 0] >= 0).all(axis=1) & \
        (blue_px[..., 0] < w).all(axis=1) & (blue_px[..., 1] >= 0).all(axis=1) & (blue_px[..., 1] < h).all(axis=1)
    seen &= p_t[:, 2] > 0.05  # the camera above the board's top face
    t, p_t, q_t, p_e, q_e = t[seen], p_t[seen], q_t[seen], p_e[seen], q_e[seen]
    red_true_c = evaluation._to_camera(RED, p_t, q_t)
    red_est_c = evaluation._to_camera(RED, p_e, q_e)
    e_px = evaluation.project(red_est_c, info) - evaluation.project(red_true_c, info)
    # Where the estimate's ray through each dot meets the board, seen from the true camera.
    with np.errstate(divide="ignore", invalid="ignore"):
        ray_c = red_est_c / red_est_c[..., 2:3]
        R_t = evaluation.quat.to_matrix(q_t)
        ray_m = np.einsum("nij,nmj->nmi", R_t, ray_c)
        s = (0.05 - p_t[:, None, 2]) / ray_m[..., 2]
        hit = p_t[:, None, :] + s[..., None] * ray_m
        err_m = np.linalg.norm(hit[..., :2] - RED[None, :, :2], axis=-1)
        err_m[~np.isfinite(err_m) | (s <= 0) | (red_est_c[..., 2] <= 0)] = np.inf  # behind: lost
        # Metres per pixel on the board at each dot: the cell's size (10 cm) over its size in the image.
        right = evaluation.project(evaluation._to_camera(RED + [SPACING_M / 2, 0, 0], p_t, q_t), info)
        left = evaluation.project(evaluation._to_camera(RED - [SPACING_M / 2, 0, 0], p_t, q_t), info)
        up = evaluation.project(evaluation._to_camera(RED + [0, SPACING_M / 2, 0], p_t, q_t), info)
        down = evaluation.project(evaluation._to_camera(RED - [0, SPACING_M / 2, 0], p_t, q_t), info)
        cell_px = 0.5 * (np.linalg.norm(right - left, axis=-1) + np.linalg.norm(up - down, axis=-1))
        m_per_px = SPACING_M / cell_px
    return t, e_px, err_m, m_per_px


def lost_mask(e_px, err_m, m_per_px):
    return (np.abs(e_px).max(axis=-1) * m_per_px >= SPACING_M / 2) | ~np.isfinite(err_m)


def summarise(t, e_px, err_m, m_per_px):
    lost = lost_mask(e_px, err_m, m_per_px)
    keep = ~lost
    px = e_px[keep]
    inch = e_px[keep] * m_per_px[keep][:, None] / INCH_M
    frames_lost = int(lost.any(axis=1).sum())
    if len(px) < 2:
        mu_i = sd_i = mu_p = sd_p = np.full(2, np.nan)
    else:
        mu_i, sd_i, mu_p, sd_p = inch.mean(0), inch.std(0, ddof=1), px.mean(0), px.std(0, ddof=1)
    return dict(frames=len(t), dots=int(keep.sum()), lost=int(lost.sum()), frames_lost=frames_lost,
                mu_in=mu_i, sd_in=sd_i, mu_px=mu_p, sd_px=sd_p,
                median_mm=1000 * float(np.median(np.where(np.isfinite(err_m), err_m, 1e3))) if len(t) else np.nan)


def layout_cones(rec, bag_path):
    """(N, 2, 3) true [peak, base] per cone, from the bag's rig_sim/cones (the layout is parsed only by
    rig_model, so the script does not read the layout's keys itself)."""
    if rec.cones is None or not len(rec.cones):
        raise SystemExit("platform_offline: %s: no rig_sim/cones in the bag; cannot tell which cones the true "
                         "camera saw (record rig_sim/cones with the run)" % bag_path)
    return rec.cones


AGE_SPANS = ((0.0, 0.1, "pose < 0.1 s old"), (0.1, 1.0, "0.1-1 s"), (1.0, 2.0, "1-2 s"), (2.0, np.inf, "> 2 s"))


def pose_age_class(t, pose_t):
    """Index into AGE_SPANS per image: the age of the tracker's newest pose (a full three-cone pose)."""
    j = np.searchsorted(pose_t, t, side="right") - 1
    age = np.where(j >= 0, t - pose_t[np.maximum(j, 0)], np.inf) if len(pose_t) else np.full(len(t), np.inf)
    return np.searchsorted([hi for _, hi, _ in AGE_SPANS], age, side="right")


def view_cell(err_m, e_px, m_per_px, cls, k):
    """Median board error (mm) and the share of dots lost over the images of class k."""
    m = cls == k
    if not m.any():
        return "-"
    e = err_m[m]
    return "%.0f mm, %.0f %% (%d)" % (1000 * np.median(np.where(np.isfinite(e), e, 1e3)),
                                      100.0 * lost_mask(e_px[m], e, m_per_px[m]).mean(), m.sum())


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bag", required=True)
    ap.add_argument("--layout", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--order", choices=("arrival", "stamp"), default="arrival")
    ap.add_argument("--series", action="store_true")
    ap.add_argument("runs", nargs="+", metavar="NAME=EKF_CONFIG|live")
    a = ap.parse_args(argv[1:])
    os.makedirs(a.out, exist_ok=True)
    for path in (a.bag, a.layout):
        if not os.path.isfile(path):
            raise SystemExit("platform_offline: %s: no such file" % path)
    for run in a.runs:
        name, _, config = run.partition("=")
        if not name or not config:
            raise SystemExit("platform_offline: run '%s': expected NAME=EKF_CONFIG.yaml or NAME=live" % run)
        if config != "live" and not os.path.isfile(config):
            raise SystemExit("platform_offline: run '%s': %s: no such file" % (run, config))
    rec = evaluation.load_bag(a.bag)
    if rec.camera_info is None or len(rec.truth) < 2:
        raise SystemExit("platform_offline: %s: needs camera/camera_info and rig_sim/ground_truth" % a.bag)
    bag = a.bag
    tmp = None
    if a.order == "stamp":
        tmp = tempfile.NamedTemporaryFile(suffix=".bag", dir=a.out, delete=False)
        tmp.close()
        restamp(a.bag, tmp.name)
        bag = tmp.name
    print("| run | images | dots | lost | images with a lost dot | µx in | µy in | σx in | σy in | σx px | σy px "
          "| median board error mm |")
    print("|---" * 12 + "|")
    notes, scored = [], []
    camera_t = np.union1d(rec.tracker.t, rec.observation_t)
    try:
        for run in a.runs:
            name, _, config = run.partition("=")
            if not config:
                raise SystemExit("platform_offline: run '%s': expected NAME=EKF_CONFIG.yaml or NAME=live" % run)
            if config == "live":
                est, note = rec.ekf, "pose_ekf/pose as recorded"
            else:
                est, note = replay(bag, config, a.layout, a.out, name)
            t, e_px, err_m, m_per_px = score(rec, est)
            scored.append((name, (t, e_px, err_m, m_per_px)))
            s = summarise(t, e_px, err_m, m_per_px)
            print("| %s | %d | %d | %d | %d | %.3f | %.3f | %.3f | %.3f | %.2f | %.2f | %.0f |" % (
                name, s["frames"], s["dots"], s["lost"], s["frames_lost"], s["mu_in"][0], s["mu_in"][1],
                s["sd_in"][0], s["sd_in"][1], s["sd_px"][0], s["sd_px"][1], s["median_mm"]))
            notes.append("%s: %s" % (name, note))
            if a.series:
                with open(os.path.join(a.out, name + ".series.csv"), "w") as f:
                    f.write("t_s,mean_error_m,max_error_m,dots_lost,camera_pose_age_s,camera_frame_age_s\n")
                    for i, ti in enumerate(t):
                        ages = []
                        for stamps in (rec.tracker.t, camera_t):
                            j = np.searchsorted(stamps, ti, side="right") - 1
                            ages.append(ti - stamps[j] if j >= 0 else np.nan)
                        e = np.where(np.isfinite(err_m[i]), err_m[i], 99.0)
                        lost = int(lost_mask(e_px[i], err_m[i], m_per_px[i]).sum())
                        f.write("%.4f,%.4f,%.4f,%d,%.3f,%.3f\n" % (ti, e.mean(), e.max(), lost, ages[0], ages[1]))
    finally:
        if tmp is not None:
            os.unlink(tmp.name)
    print()
    print("Board error by the cones in the true camera's view (ar_bringup.visibility's classes): median mm, "
          "share of dots lost; images in brackets.")
    print()
    print("| run | " + " | ".join(label for _, label in visibility.CLASSES) + " |")
    print("|---" * (len(visibility.CLASSES) + 1) + "|")
    cones = layout_cones(rec, a.bag)
    counts = visibility.cones_in_view(cones, *rec.truth.interpolate(rec.image_t)[1:], rec.camera_info,
                                      project=evaluation.project)
    for name, (t, e_px, err_m, m_per_px) in scored:
        cls, _ = visibility.classify(t, rec.image_t, counts)
        print("| %s | %s |" % (name, " | ".join(view_cell(err_m, e_px, m_per_px, cls, k)
                                               for k in range(len(visibility.CLASSES)))))
    print()
    print("The same by the age of the tracker's newest full pose at the image (the same recorded tracker output "
          "for every run; camera_update: cones also fuses frames of one or two cones in between).")
    print()
    print("| run | " + " | ".join(label for _, _, label in AGE_SPANS) + " |")
    print("|---" * (len(AGE_SPANS) + 1) + "|")
    for name, (t, e_px, err_m, m_per_px) in scored:
        cls = pose_age_class(t, rec.tracker.t)
        print("| %s | %s |" % (name, " | ".join(view_cell(err_m, e_px, m_per_px, cls, k)
                                               for k in range(len(AGE_SPANS)))))
    print()
    for n in notes:
        print("- " + n)


if __name__ == "__main__":
    main(sys.argv)

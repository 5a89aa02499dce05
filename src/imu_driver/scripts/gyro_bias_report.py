#!/usr/bin/env python3
"""Static gyro bias report (thesis 3.2.1) from still IMU data at several orientations.

Input: a bag with sensor_msgs/Imu (record the driver with _subtract_gyro_bias:=false), or a
CSV with columns t, gx, gy, gz (rad/s), ax, ay, az (m/s^2). Static segments are found
automatically (low gyro and accel spread over a sliding window); each is one orientation.

Writes: a histogram per axis with the fitted normal density (PNG), the calibration YAML
the driver loads (gyro_bias_rad_s, gyro_noise_sigma_rad_s), and with --segments the
per-orientation accelerometer means that calibrate_camera_imu takes as accel_mean_m_s2.

  gyro_bias_report.py still.bag --topic imu/data_raw --png bias.png --yaml gyro_calibration.yaml
"""
import argparse
import os
import struct
import sys

import numpy as np


def bag_truncation_note(path):
    """A bag's index sits at its end (the header's index_pos): a bag cut short (recorder killed, disk
    full, partial copy) has its header pointing past the end of the file, and rosbag then reports only
    a short read. Returns the explanation, or "" when the bag is not cut."""
    try:
        with open(path, "rb") as f:
            if f.read(13) != b"#ROSBAG V2.0\n":
                return ""
            header = f.read(struct.unpack("<I", f.read(4))[0])
            size = os.fstat(f.fileno()).st_size
    except (OSError, struct.error):
        return ""
    i = 0
    while i + 4 <= len(header):
        n = struct.unpack_from("<I", header, i)[0]
        field = header[i + 4:i + 4 + n]
        i += 4 + n
        if field.startswith(b"index_pos=") and len(field) == 18:
            index_pos = struct.unpack_from("<Q", field, 10)[0]
            if index_pos >= size:
                return ("the bag is truncated (its index should start at byte %d but the file has %d bytes); "
                        "try `rosbag reindex %s` to recover the messages before the cut" % (index_pos, size, path))
    return ""


def load(path, topic):
    if path.endswith(".csv"):
        try:
            d = np.loadtxt(path, delimiter=",", comments="#", ndmin=2)
        except (OSError, ValueError) as e:
            sys.exit("gyro_bias_report: cannot read %s: %s" % (path, e))
        if d.shape[1] < 7:
            sys.exit("gyro_bias_report: %s: need 7 columns (t, gyro x y z, accel x y z), found %d"
                     % (path, d.shape[1]))
        return d[:, 0], d[:, 1:4], d[:, 4:7]
    import rosbag  # only needed for bags

    t, g, a = [], [], []
    try:
        with rosbag.Bag(path) as bag:
            for _, m, _ in bag.read_messages(topics=[topic]):
                t.append(m.header.stamp.to_sec())
                g.append((m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z))
                a.append((m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z))
    except Exception as e:  # rosbag raises several kinds (and OSError) for a missing or broken bag
        note = bag_truncation_note(path)
        sys.exit("gyro_bias_report: cannot read %s: %s" % (path, "%s (rosbag: %s)" % (note, e) if note else e))
    if not t:
        sys.exit("gyro_bias_report: no %s messages in %s" % (topic, path))
    return np.array(t), np.array(g), np.array(a)


def static_segments(t, gyro, accel, window_s, max_gyro_std, max_accel_std, min_duration_s):
    """Index ranges [i0, i1) where the IMU is still: every window's spread is small."""
    rate = (len(t) - 1) / max(t[-1] - t[0], 1e-9)
    w = max(int(window_s * rate), 5)
    still = np.zeros(len(t), dtype=bool)
    for i in range(0, len(t) - w + 1, max(w // 4, 1)):
        if gyro[i:i + w].std(axis=0).max() < max_gyro_std and accel[i:i + w].std(axis=0).max() < max_accel_std:
            still[i:i + w] = True
    segments, i = [], 0
    while i < len(t):
        if not still[i]:
            i += 1
            continue
        j = i
        while j < len(t) and still[j]:
            j += 1
        if t[j - 1] - t[i] >= min_duration_s:
            segments.append((i, j))
        i = j
    return segments


def compute(gyro, segments):
    """Bias: mean of all static samples. Noise: pooled within-segment sigma (3.27)."""
    samples = np.concatenate([gyro[i:j] for i, j in segments])
    resid = np.concatenate([gyro[i:j] - gyro[i:j].mean(axis=0) for i, j in segments])
    dof = len(resid) - len(segments)
    return samples.mean(axis=0), np.sqrt((resid ** 2).sum(axis=0) / dof), samples, resid


def plot(png, samples, bias, sigma, segments, gyro):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    for k, ax in enumerate(axes):
        ax.hist(samples[:, k], bins=60, density=True, alpha=0.6, label="all orientations")
        for n, (i, j) in enumerate(segments):
            ax.axvline(gyro[i:j, k].mean(), color="C%d" % (n + 1), lw=0.8)
        x = np.linspace(samples[:, k].min(), samples[:, k].max(), 200)
        ax.plot(x, np.exp(-0.5 * ((x - bias[k]) / sigma[k]) ** 2) / (sigma[k] * np.sqrt(2 * np.pi)), "k",
                label="N(bias, sigma)")
        ax.set_title("gyro %s: bias %.5f, sigma %.5f rad/s" % ("xyz"[k], bias[k], sigma[k]), fontsize=9)
        ax.set_xlabel("rad/s (lines: per-orientation means)")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("input")
    p.add_argument("--topic", default="imu/data_raw")
    p.add_argument("--png", default="gyro_bias.png")
    p.add_argument("--yaml", default="")
    p.add_argument("--segments", action="store_true", help="print accel means per static orientation")
    p.add_argument("--window-s", type=float, default=0.5)
    p.add_argument("--max-gyro-std", type=float, default=0.02, help="rad/s")
    p.add_argument("--max-accel-std", type=float, default=0.2, help="m/s^2")
    p.add_argument("--min-duration-s", type=float, default=2.0)
    args = p.parse_args(argv)

    t, gyro, accel = load(args.input, args.topic)
    segs = static_segments(t, gyro, accel, args.window_s, args.max_gyro_std, args.max_accel_std,
                           args.min_duration_s)
    if not segs:
        sys.exit("gyro_bias_report: no static segment of %.1f s found" % args.min_duration_s)
    bias, sigma, samples, _ = compute(gyro, segs)
    print("static orientations: %d, samples: %d" % (len(segs), len(samples)))
    print("gyro_bias_rad_s: [%.7f, %.7f, %.7f]" % tuple(bias))
    print("gyro_noise_sigma_rad_s: [%.7f, %.7f, %.7f]" % tuple(sigma))
    for n, (i, j) in enumerate(segs):
        print("  orientation %d: %.1f s, gyro mean [%s], accel mean [%s]" % (
            n + 1, t[j - 1] - t[i], ", ".join("%.5f" % v for v in gyro[i:j].mean(axis=0)),
            ", ".join("%.4f" % v for v in accel[i:j].mean(axis=0))))
    if args.segments:
        print("poses:")
        for i, j in segs:
            print("  - accel_mean_m_s2: [%s]" % ", ".join("%.6f" % v for v in accel[i:j].mean(axis=0)))
    if args.png:
        plot(args.png, samples, bias, sigma, segs, gyro)
        print("histogram: " + args.png)
    if args.yaml:
        with open(args.yaml, "w") as f:
            f.write("# Static gyro bias (thesis 3.2.1) from %s, %d orientations\n" % (args.input, len(segs)))
            f.write("gyro_bias_rad_s: [%.9f, %.9f, %.9f]\n" % tuple(bias))
            f.write("gyro_noise_sigma_rad_s: [%.9f, %.9f, %.9f]\n" % tuple(sigma))
        print("calibration: " + args.yaml)
    return bias, sigma, segs


if __name__ == "__main__":
    main()

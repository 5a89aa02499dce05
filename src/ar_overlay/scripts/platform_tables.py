#!/usr/bin/env python3
"""The overlay test platform's tables (thesis 7.2, figures 7.8 and 7.9) from the CSVs of
ar_overlay_platform_monitor, beside the thesis's numbers.

  platform_tables.py --tables DIR TRIALS [CONFIG...]   markdown to stdout, summary CSV to DIR/summary.csv
                                         (CONFIG: overlay_platform.sh's filter configurations, default
                                         thesis shipped cones; runs named trial<N>_<CONFIG>_gyro_<true|false>)
  platform_tables.py --heading BAG         the start bearing atan2(y, x) of the first true position (deg)

Inches are on the platform: each dot's pixel error times its cell's metres per pixel (the
dot spacing over the cell's size in the image), as the thesis's "simple scale factor".
x is image right, y image down."""
import csv
import math
import os
import sys

INCH_M = 0.0254
# Figures 7.8 (without gyros) and 7.9 (with gyros), inches, trials 1-3: mu_x, mu_y, sigma_x, sigma_y.
THESIS = {
    "false": [(0.6719, -0.5526, 1.3154, 1.5251), (0.5030, -0.4178, 1.4680, 1.2923), (0.6635, -0.3707, 1.3901, 1.4203)],
    "true": [(0.3352, -0.3235, 0.8382, 1.0786), (0.4105, -0.2114, 1.2336, 1.3096), (0.4591, -0.3156, 1.2451, 1.1880)],
}


def load(path, spacing_m=0.1):
    """Per-dot errors (px, inch) of the dots within half a cell of their place, the number of dots
    further off (the overlay is lost: which cell such a dot belongs to, and so its error, means
    nothing, so they are counted, not averaged), and the number of frames measured."""
    rows = []
    if os.path.exists(path):
        with open(path) as f:
            rows = list(csv.DictReader(f))
    px, inch, lost = [], [], 0
    for r in rows:
        ex, ey, m_per_px = float(r["error_x_px"]), float(r["error_y_px"]), float(r["m_per_px"])
        if max(abs(ex), abs(ey)) * m_per_px >= spacing_m / 2:
            lost += 1
            continue
        px.append((ex, ey))
        inch.append((ex * m_per_px / INCH_M, ey * m_per_px / INCH_M))
    return px, inch, lost, {r["stamp_s"] for r in rows}


def stats(pairs):
    n = len(pairs)
    if n < 2:
        return (float("nan"),) * 4
    mx = sum(p[0] for p in pairs) / n
    my = sum(p[1] for p in pairs) / n
    sx = math.sqrt(sum((p[0] - mx) ** 2 for p in pairs) / (n - 1))
    sy = math.sqrt(sum((p[1] - my) ** 2 for p in pairs) / (n - 1))
    return mx, my, sx, sy


DESCRIPTIONS = {
    "thesis": "pose_ekf_rig_sim.yaml with the accelerometer updates off, as the thesis ran it (ch. 8)",
    "shipped": "pose_ekf_rig_sim.yaml as the project ships it (camera_update: pose, accelerometer and its bias on)",
    "cones": "pose_ekf_rig_sim.yaml with camera_update: cones (per-cone updates)",
}


def row_cells(folder, name, truth_frames=None):
    """frames (or, with truth_frames, 'frames (unmeasured)': the true-pose run's frames this run did not
    measure: the overlay was not drawn, or drawn over the blue dots or off the board), dots, lost, stats."""
    px, inch, lost, frames = load(os.path.join(folder, name + ".csv"))
    shown = "%d" % len(frames) if truth_frames is None else "%d (%d)" % (len(frames), len(truth_frames - frames))
    return shown, len(px), lost, stats(inch), stats(px)


def tables(folder, trials, configs=("thesis", "shipped", "cones")):
    out, summary = ["frames: overlay frames with the whole blue grid seen, and in brackets the frames measured in "
                    "the true-pose run that this run did not measure (no overlay drawn, or red dots drawn over blue "
                    "ones or off the board: the monitor cannot see those losses); dots: red dots within half a cell "
                    "of their place (µ and σ over these); lost: red dots further off (the overlay has lost the "
                    "platform; counted, not averaged). x is image right, y image down.", ""], []
    truth = {t: load(os.path.join(folder, "trial%d_truth.csv" % t))[3] for t in range(1, trials + 1)}
    head = "| trial | frames | dots | lost | µx in | µy in | σx in | σy in | µx px | µy px | σx px | σy px |"
    compare = ["### Gyros on against off, per configuration and trial\n",
               "lost: share of the measured red dots that are lost; σ: the larger of σx, σy (inches) over the "
               "dots kept.\n",
               "| configuration | trial | lost, gyros off | lost, gyros on | σ in, gyros off | σ in, gyros on "
               "| unmeasured, gyros off | unmeasured, gyros on |",
               "|---|---|---|---|---|---|---|---|"]
    for config in configs:
        out.append("## Configuration `%s`: %s\n" % (config, DESCRIPTIONS.get(config, config)))
        cells = {}
        for gyro, title in (("false", "Figure 7.8 equivalent: overlay accuracy without gyros"),
                            ("true", "Figure 7.9 equivalent: overlay accuracy with gyros")):
            out.append("### %s (`%s`)\n" % (title, config))
            out.append(head + " thesis µx | µy | σx | σy (in) |")
            out.append("|---" * 16 + "|")
            for t in range(1, trials + 1):
                name = "trial%d_%s_gyro_%s" % (t, config, gyro)
                frames, ndots, lost, si, sp = cells[gyro, t] = row_cells(folder, name, truth[t])
                th = THESIS[gyro][t - 1] if t <= 3 else (float("nan"),) * 4
                out.append("| %d | %s | %d | %d | " % (t, frames, ndots, lost) + " | ".join("%.4f" % v for v in si + sp)
                           + " | " + " | ".join("%.4f" % v for v in th) + " |")
                summary.append([name, int(frames.split()[0]), ndots, lost] + ["%.5f" % v for v in si + sp])
            out.append("")
        for t in range(1, trials + 1):
            def share(c):
                return "%d of %d (%.1f %%)" % (c[2], c[1] + c[2], 100.0 * c[2] / max(1, c[1] + c[2]))
            off, on = cells["false", t], cells["true", t]
            compare.append("| %s | %d | %s | %s | %.3f | %.3f | %s | %s |" % (
                config, t, share(off), share(on), max(off[3][2:]), max(on[3][2:]),
                off[0].split("(")[-1].rstrip(")"), on[0].split("(")[-1].rstrip(")")))
    out.append("### Measurement floor: overlay drawn at the true pose (rig_sim)\n")
    out.append(head)
    out.append("|---" * 12 + "|")
    for t in range(1, trials + 1):
        name = "trial%d_truth" % t
        frames, ndots, lost, si, sp = row_cells(folder, name)
        out.append("| %d | %s | %d | %d | " % (t, frames, ndots, lost) + " | ".join("%.4f" % v for v in si + sp) + " |")
        summary.append([name, int(frames.split()[0]), ndots, lost] + ["%.5f" % v for v in si + sp])
    out.append("")
    out.extend(compare)
    out.append("")
    with open(os.path.join(folder, "summary.csv"), "w") as f:
        w = csv.writer(f)
        w.writerow(["run", "frames", "dots", "lost_dots", "mu_x_in", "mu_y_in", "sigma_x_in", "sigma_y_in",
                    "mu_x_px", "mu_y_px", "sigma_x_px", "sigma_y_px"])
        w.writerows(summary)
    return "\n".join(out)


def heading(bag_path):
    import rosbag
    with rosbag.Bag(bag_path) as bag:
        for _, msg, _ in bag.read_messages(topics=["rig_sim/ground_truth", "/rig_sim/ground_truth"]):
            p = msg.pose.position
            return math.degrees(math.atan2(p.y, p.x))
    raise SystemExit("platform_tables: no rig_sim/ground_truth in " + bag_path)


def main(argv):
    try:
        if len(argv) == 3 and argv[1] == "--heading":
            print("%.1f" % heading(argv[2]))
        elif len(argv) >= 4 and argv[1] == "--tables":
            print(tables(argv[2], int(argv[3]), argv[4:] or ("thesis", "shipped", "cones")))
        else:
            raise SystemExit(__doc__)
    except Exception as e:  # a missing or broken CSV (OSError, ValueError, KeyError) or bag (rosbag's own kinds)
        raise SystemExit("platform_tables: %s: %s" % (" ".join(argv[1:]), e))


if __name__ == "__main__":
    main(sys.argv)

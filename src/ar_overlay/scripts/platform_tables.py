#!/usr/bin/env python3
"""The overlay test platform's tables (thesis 7.2, figures 7.8 and 7.9) from the CSVs of
ar_overlay_platform_monitor, beside the thesis's numbers.

  platform_tables.py --tables DIR TRIALS   markdown to stdout, summary CSV to DIR/summary.csv
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
    return px, inch, lost, len({r["stamp_s"] for r in rows})


def stats(pairs):
    n = len(pairs)
    if n < 2:
        return (float("nan"),) * 4
    mx = sum(p[0] for p in pairs) / n
    my = sum(p[1] for p in pairs) / n
    sx = math.sqrt(sum((p[0] - mx) ** 2 for p in pairs) / (n - 1))
    sy = math.sqrt(sum((p[1] - my) ** 2 for p in pairs) / (n - 1))
    return mx, my, sx, sy


def tables(folder, trials):
    out, summary = ["frames: overlay frames with the whole blue grid seen; dots: red dots within half a cell of "
                    "their place (µ and σ over these); lost: red dots further off (the overlay has lost the "
                    "platform; counted, not averaged). x is image right, y image down.", ""], []
    titles = {"false": "Figure 7.8 equivalent: overlay accuracy without gyros",
              "true": "Figure 7.9 equivalent: overlay accuracy with gyros",
              "truth": "Measurement floor: overlay drawn at the true pose (rig_sim)"}
    for run in ("false", "true", "truth"):
        out.append("### " + titles[run] + "\n")
        out.append("| trial | frames | dots | lost | µx in | µy in | σx in | σy in | µx px | µy px | σx px | σy px |"
                   + (" thesis µx | µy | σx | σy (in) |" if run != "truth" else ""))
        out.append("|---" * (12 + (4 if run != "truth" else 0)) + "|")
        for t in range(1, trials + 1):
            name = "trial%d_%s" % (t, run if run == "truth" else "gyro_" + run)
            px, inch, lost, frames = load(os.path.join(folder, name + ".csv"))
            si, sp = stats(inch), stats(px)
            row = "| %d | %d | %d | %d | " % (t, frames, len(px), lost) + " | ".join("%.4f" % v for v in si + sp) + " |"
            if run != "truth":
                th = THESIS[run][t - 1] if t <= 3 else (float("nan"),) * 4
                row += " " + " | ".join("%.4f" % v for v in th) + " |"
            out.append(row)
            summary.append([name, frames, len(px), lost] + ["%.5f" % v for v in si + sp])
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
        elif len(argv) == 4 and argv[1] == "--tables":
            print(tables(argv[2], int(argv[3])))
        else:
            raise SystemExit(__doc__)
    except Exception as e:  # a missing or broken CSV (OSError, ValueError, KeyError) or bag (rosbag's own kinds)
        raise SystemExit("platform_tables: %s: %s" % (" ".join(argv[1:]), e))


if __name__ == "__main__":
    main(sys.argv)

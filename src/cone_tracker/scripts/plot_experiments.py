#!/usr/bin/env python3
"""Notched box plots of the chapter 7.1 experiments (figures 9.1-9.9 and the cone layout).

Usage: plot_experiments.py DIR   (DIR holds trials.csv from cone_tracker_experiments)
Writes one PNG per thesis figure: rows are noise levels, columns rotation error,
position error and runtime. As in the thesis, outliers are not drawn; their
count is printed at the end of the upper whisker. Failed solves are counted
in the method's label.
"""
import csv
import os
import sys
from collections import OrderedDict, defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

FIGURES = [
    ("fig9_1_group1_10pts", 1, 10, [5, 10]),
    ("fig9_2_group1_25pts", 1, 25, [5, 10]),
    ("fig9_3_group2_10pts", 2, 10, [5, 10]),
    ("fig9_4_group2_25pts", 2, 25, [5, 10]),
    ("fig9_5_group3_10pts", 3, 10, [5, 10]),
    ("fig9_6_group3_25pts", 3, 25, [5, 10]),
    ("fig9_7_group4_10pts", 4, 10, [5, 10]),
    ("fig9_8_group4_25pts", 4, 25, [5, 10]),
    ("fig9_9_group5_10pts", 5, 10, [25, 50, 75]),
    ("cone_layout_9pts", 0, 9, [0.5, 1, 2, 3]),
]
METRICS = [("rot_err_deg", "rotation error (deg)"), ("pos_err_mm", "position error (mm)"), ("time_us", "runtime (us)")]


def load(path):
    data = defaultdict(lambda: OrderedDict())  # (group, points, sigma) -> method -> rows
    with open(path) as f:
        for row in csv.DictReader(f):
            key = (int(row["group"]), int(row["points"]), float(row["sigma_px"]))
            data[key].setdefault(row["method"], []).append(row)
    return data


def boxplot(ax, methods, metric):
    values, labels = [], []
    for name, rows in methods.items():
        ok = [float(r[metric]) for r in rows if r["ok"] == "1"]
        failed = len(rows) - len(ok)
        values.append(np.array(ok) if ok else np.array([np.nan]))
        labels.append(name + (" [%d failed]" % failed if failed else ""))
    ax.boxplot(values, notch=True, vert=False, showfliers=False, whis=1.5)
    ax.set_yticks(range(1, len(labels) + 1))
    ax.set_yticklabels(labels, fontsize=7)
    ax.set_xscale("log")
    for i, v in enumerate(values, start=1):
        v = v[np.isfinite(v)]
        if v.size == 0:
            continue
        q1, q3 = np.percentile(v, [25, 75])
        upper = q3 + 1.5 * (q3 - q1)
        outliers = int(np.sum(v > upper))
        whisker = v[v <= upper].max() if np.any(v <= upper) else q3
        if outliers:
            ax.annotate(str(outliers), (whisker, i), xytext=(3, -3), textcoords="offset points", fontsize=6)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    try:
        data = load(os.path.join(out, "trials.csv"))
    except (OSError, ValueError, KeyError) as e:
        sys.exit("plot_experiments: cannot read %s: %s" % (os.path.join(out, "trials.csv"), e))
    for name, group, points, sigmas in FIGURES:
        keys = [(group, points, float(s)) for s in sigmas if (group, points, float(s)) in data]
        if not keys:
            continue
        fig, axes = plt.subplots(len(keys), 3, figsize=(15, 3.2 * len(keys)), squeeze=False)
        for r, key in enumerate(keys):
            for c, (metric, label) in enumerate(METRICS):
                boxplot(axes[r][c], data[key], metric)
                axes[r][c].set_title("%s, sigma = %g px: %s" % (name.split("_", 2)[-1], key[2], label), fontsize=8)
        fig.tight_layout()
        path = os.path.join(out, name + ".png")
        fig.savefig(path, dpi=90)
        plt.close(fig)
        print("wrote", path)


if __name__ == "__main__":
    main()

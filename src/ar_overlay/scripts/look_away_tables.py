#!/usr/bin/env python3
"""The look-away gyro experiment's tables (look_away_gyro.sh) from evaluate_bag's outputs.

  look_away_tables.py DIR SCENARIO "CONFIG..." "SEED..."

Reads DIR/<SCENARIO>_seed<S>_<CONFIG>_gyro_<true|false>.txt and prints, per configuration, the overlay
error (RMS px at 1024x768 of the 1 m cube on the cones' centroid, ar_bringup.evaluation's view_* figures)
by the cones in the true view, gyros on against off, and the position and orientation RMS of the whole run."""
import math
import os
import sys

SPANS = (("3plus", "3+ cones"), ("1to2", "1-2 cones"), ("none_0to1s", "none 0-1 s"),
         ("none_1to2s", "none 1-2 s"), ("none_over2s", "none > 2 s"))


def read(path):
    out = {}
    if not os.path.exists(path):
        return out
    with open(path) as f:
        for line in f:
            parts = line.split()
            if len(parts) == 2:
                try:
                    out[parts[0]] = float(parts[1])
                except ValueError:
                    pass
    return out


def cell(v, fmt="%.1f"):
    return "n/a" if v is None or not math.isfinite(v) else fmt % v


def tables(folder, scenario, configs, seeds):
    out = ["Overlay error: RMS px at 1024x768 of the 1 m cube's corners and centre (ar_bringup.evaluation), "
           "by the cones in the true camera's view; gyros off / on. Position (m) and orientation (deg) RMS over "
           "the whole run after the first second.", ""]
    head = "| configuration | seed | " + " | ".join(label for _, label in SPANS) + \
        " | whole run | position m | orientation deg |"
    out += [head, "|---" * (len(SPANS) + 5) + "|"]
    worse = []
    for config in configs:
        for seed in seeds:
            r = {g: read(os.path.join(folder, "%s_seed%s_%s_gyro_%s.txt" % (scenario, seed, config, g)))
                 for g in ("false", "true")}
            cells = []
            for key, label in SPANS:
                off = r["false"].get("view_%s_overlay_rms_px" % key)
                on = r["true"].get("view_%s_overlay_rms_px" % key)
                cells.append("%s / %s" % (cell(off), cell(on)))
                if off is not None and on is not None and math.isfinite(off) and math.isfinite(on) and on > off:
                    worse.append("%s seed %s, %s: %.1f px with gyros, %.1f without" % (config, seed, label, on, off))
            whole = "%s / %s" % (cell(r["false"].get("overlay_rms_px")), cell(r["true"].get("overlay_rms_px")))
            pos = "%s / %s" % (cell(r["false"].get("position_rms_m"), "%.3f"), cell(r["true"].get("position_rms_m"), "%.3f"))
            rot = "%s / %s" % (cell(r["false"].get("orientation_rms_deg"), "%.2f"),
                               cell(r["true"].get("orientation_rms_deg"), "%.2f"))
            out.append("| %s | %s | %s | %s | %s | %s |" % (config, seed, " | ".join(cells), whole, pos, rot))
    out += ["", "Spans where the gyros made the overlay worse: " + ("none" if not worse else "")]
    out += ["- " + w for w in worse]
    return "\n".join(out)


def main(argv):
    if len(argv) != 5:
        raise SystemExit(__doc__)
    print(tables(argv[1], argv[2], argv[3].split(), argv[4].split()))


if __name__ == "__main__":
    main(sys.argv)

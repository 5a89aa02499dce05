"""The Markdown report of one replay: headline figures, the plots, the rates, the video.

write_report() draws the plots next to the report and links everything by relative path, so the
out/ folder can be moved or zipped as a whole.
"""
import datetime
import os

import numpy as np

from . import plots
from .summary import figures


def _fmt(value):
    if not np.isfinite(value):
        return "n/a"
    if abs(value) < 1e-9:
        return "0"
    return "%.0f" % value if abs(value) >= 100 else "%.3g" % value


def draw_plots(summary, out_dir):
    """Writes the PNGs; returns [(file name, caption)] in report order."""
    drawn = []
    ekf = summary.ekf
    if ekf is not None and len(ekf) and ekf.pos_3sigma_m is not None:
        plots.pose_error(os.path.join(out_dir, "pose_error.png"), ekf.t_s, ekf.pos_err_m,
                         ekf.pos_3sigma_m, ekf.rot_err_rad, ekf.rot_3sigma_rad, summary.visible)
        drawn.append(("pose_error.png", "EKF pose error per axis against ground truth, with the "
                      "EKF's own ±3σ (from `pose_ekf/pose`'s covariance); green: cones in view"))
    if ekf is not None and len(ekf):
        tracker = None
        if summary.tracker is not None:
            tracker = (summary.tracker.t_s, summary.tracker.pos_err_m, summary.tracker.rot_err_rad)
        plots.error_norms(os.path.join(out_dir, "pose_error_norm.png"), ekf.t_s, ekf.pos_err_m,
                          ekf.rot_err_rad, summary.visible, tracker)
        drawn.append(("pose_error_norm.png", "error magnitudes: the EKF (line) and cone_tracker's "
                      "single-frame poses (dots)"))
    if summary.overlay_err_px.size:
        plots.overlay_error(os.path.join(out_dir, "overlay_error.png"), summary.overlay_t_s,
                            summary.overlay_err_px, summary.visible)
        drawn.append(("overlay_error.png", "overlay error: model points drawn at the estimated "
                      "pose against the same points at the true pose, in pixels"))
    if summary.view_figures is not None and ekf is not None and len(ekf):
        plots.error_since_view(os.path.join(out_dir, "error_since_view.png"), summary.view_ekf_since_s,
                               ekf.pos_err_m, ekf.rot_err_rad, summary.view_frame_since_s, summary.view_overlay_px,
                               summary.view_centre_px, summary.view_full_width_px)
        drawn.append(("error_since_view.png", "error against the time since any cone was last in the true "
                      "camera view (0: in view); the overlay errors at full resolution: the cones' peaks and "
                      "bases near the view, and the centre of the view at the cones' distance"))
    plots.gate_rejections(os.path.join(out_dir, "gate_rejections.png"), summary.gates,
                          summary.duration_s, summary.visible)
    drawn.append(("gate_rejections.png", "measurements rejected by each gate, cumulative"))
    if summary.rates:
        names, measured, expected = zip(*summary.rates)
        plots.rates(os.path.join(out_dir, "rates.png"), names, measured, expected)
        drawn.append(("rates.png", "message rates during the replay"))
    return drawn


VIEW_COLUMNS = (("frames", "frames", 1.0), ("updated_fraction", "frames that updated the filter [%]", 100.0),
                ("position_rms_m", "position RMS [mm]", 1e3), ("position_median_m", "position median [mm]", 1e3),
                ("orientation_rms_deg", "orientation RMS [deg]", 1.0),
                ("overlay_frames", "frames with a cones' overlay figure", 1.0),
                ("overlay_rms_px", "cones' overlay RMS [px]", 1.0),
                ("overlay_median_px", "cones' overlay median [px]", 1.0),
                ("centre_rms_px", "centre RMS [px]", 1.0), ("centre_median_px", "centre median [px]", 1.0))


def view_table(summary):
    """Markdown lines: the EKF's errors by the cones in the TRUE camera view (ar_bringup.visibility)."""
    if summary.view_figures is None:
        return []
    from ar_bringup.visibility import CLASSES
    lines = ["What a user sees: the errors split by the cones in the *true* camera view (a cone is in view when "
             "its peak and base project inside the image under the true pose); with none in view, by the time "
             "since one last was. In pixels of the full-resolution image (%d px wide), through camera_info's K: "
             "the cones' overlay is their peaks and bases drawn at the EKF pose against the true pose, over the "
             "points in the image or within half its size around it (none in a long outage: n/a); the centre is "
             "the point at the centre of the true view at the cones' distance, drawn at the EKF pose. A frame "
             "updated the filter when the tracker published a `cone_tracker/pose` or a non-empty "
             "`cone_tracker/observations` for it. Errors skip the EKF's first second." % summary.view_full_width_px,
             "",
             "| cones in the true view | " + " | ".join(c[1] for c in VIEW_COLUMNS) + " |",
             "|---|" + "---:|" * len(VIEW_COLUMNS)]
    for key, label in CLASSES:
        figs = summary.view_figures.get(key, {})
        lines.append("| %s | " % label + " | ".join(_fmt(figs.get(name, float("nan")) * scale)
                                                    for name, _, scale in VIEW_COLUMNS) + " |")
    return lines + [""]


def write_report(summary, out_dir, video=None, screenshot=None, path=None):
    """Writes out_dir/report.md (or `path`) with the plots; returns the path."""
    os.makedirs(out_dir, exist_ok=True)
    path = path or os.path.join(out_dir, "report.md")
    drawn = draw_plots(summary, out_dir)
    lines = ["# Demo report", "",
             "Generated by `make demo` on %s: the whole pipeline (cone_tracker, pose_ekf, "
             "ar_overlay in one nodelet manager) replayed on `%s` (%.1f s), the outputs recorded "
             "and compared with rig_sim's ground truth."
             % (datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC"), summary.name,
                summary.duration_s), ""]
    lines += ["## Files", ""]
    if video is not None and video.path:
        rel = os.path.relpath(video.path, out_dir)
        what = "MP4 (H.264)" if video.kind == "mp4" else "PNG sequence"
        lines.append("- overlay video, %s: [`%s`](%s) — %d frames at %.1f Hz, %dx%d"
                     % (what, rel, rel, video.frames, video.fps, video.size[0], video.size[1]))
    if video is not None and video.sheet:
        rel = os.path.relpath(video.sheet, out_dir)
        lines.append("- contact sheet of the overlay video: [`%s`](%s)" % (rel, rel))
    if screenshot:
        rel = os.path.relpath(screenshot, out_dir)
        lines.append("- rviz screenshot of the running replay: [`%s`](%s)" % (rel, rel))
    if video is None or not video.path:
        lines.append("- overlay video: **none** (no `ar_overlay/image` frames were recorded)")
    lines += [""]
    if screenshot:
        lines += ["![rviz](%s)" % os.path.relpath(screenshot, out_dir), ""]
    if video is not None and video.sheet:
        lines += ["![overlay frames](%s)" % os.path.relpath(video.sheet, out_dir), ""]

    lines += ["## Figures", "", "| figure | value | unit |", "|---|---:|---|"]
    lines += ["| %s | %s | %s |" % (name, _fmt(value), unit) for name, value, unit in figures(summary)]
    lines += [""]
    spans = lambda periods: ", ".join("%.2f–%.2f s" % p for p in periods) or "never"  # noqa: E731
    lines += ["Cones in view (at least three detected): %s. Tracker poses: %s." % (spans(summary.visible),
              spans(summary.accepted)), ""]

    lines += view_table(summary)
    if summary.evaluation:
        lines += ["`ar_bringup.evaluation`'s summary of the same run (the system tests' figures; RMS "
                  "figures skip the EKF's first second; the `view_*` figures are in the table above):", "",
                  "| figure | value |", "|---|---:|"]
        lines += ["| `%s` | %s |" % (k, _fmt(v)) for k, v in summary.evaluation.items()
                  if not k.startswith("view_")] + [""]
    lines += ["## Plots", ""]
    for name, caption in drawn:
        lines += [caption[0].upper() + caption[1:] + ":", "", "![%s](%s)" % (name, name), ""]

    names = sorted(set(summary.gates) | set(summary.rejection_totals))
    if names:
        lines += ["## Gate rejections", "", "Counters from `/diagnostics` (value at the end of the run) and "
                  "cone_tracker's per-frame rejection reasons:", "",
                  "| gate or counter | rejections | first at |", "|---|---:|---:|"]
        for name in names:
            times = summary.gates.get(name, [])
            total = summary.rejection_totals.get(name, len(times))
            first = "%.2f s" % min(times) if len(times) else "—"
            lines.append("| %s | %s | %s |" % (name.replace("|", "\\|"), _fmt(total), first))
        lines += [""]
    if summary.rates:
        lines += ["## Rates", "", "| topic | measured [Hz] | expected [Hz] |", "|---|---:|---:|"]
        for topic, hz, expected in summary.rates:
            lines.append("| `%s` | %.1f | %s |" % (topic, hz, "%.0f" % expected if expected else "—"))
        lines += [""]
    if summary.notes:
        lines += ["## Notes", ""] + ["- " + n for n in summary.notes] + [""]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path

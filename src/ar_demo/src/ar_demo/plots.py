"""The report's figures, drawn with matplotlib's Agg backend (no display needed).

Every function takes plain numpy arrays (times in seconds from the start of the replay) and writes
one PNG. Periods when the cones were visible are shaded green in every time plot, so an error that
grows during an outage and shrinks when the cones come back reads at a glance.
"""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after use("Agg"))
import numpy as np  # noqa: E402

VISIBLE_COLOUR = "#d8f0d0"
DPI = 110


def _shade_visible(ax, visible):
    for i, (t0, t1) in enumerate(visible):
        ax.axvspan(t0, t1, color=VISIBLE_COLOUR, lw=0, zorder=0,
                   label="cones visible" if i == 0 else None)


def _time_strip(visible):
    """One wide, short time plot with the visible periods shaded and a grid."""
    fig, ax = plt.subplots(figsize=(11, 3.5))
    _shade_visible(ax, visible)
    ax.set_xlabel("time [s]")
    ax.grid(alpha=0.3)
    return fig, ax


def _save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def pose_error(path, t_s, pos_err_m, pos_3sigma_m, rot_err_rad, rot_3sigma_rad, visible=(),
               title="EKF pose error against ground truth"):
    """Six panels: x, y, z position error (mm) and rotation error about x, y, z (deg), each with
    the EKF's ±3σ band. Errors and σ in the `cones` frame."""
    fig, axes = plt.subplots(3, 2, figsize=(11, 7.5), sharex=True)
    series = [(pos_err_m * 1e3, pos_3sigma_m * 1e3, "position error %s [mm]"),
              (np.degrees(rot_err_rad), np.degrees(rot_3sigma_rad), "rotation error about %s [deg]")]
    for col, (err, sig, label) in enumerate(series):
        for row, axis in enumerate("xyz"):
            ax = axes[row, col]
            _shade_visible(ax, visible)
            ax.fill_between(t_s, -sig[:, row], sig[:, row], color="#9ecae1", alpha=0.6, lw=0,
                            label="EKF ±3σ")
            ax.plot(t_s, err[:, row], color="#c0392b", lw=1.0, label="error")
            ax.axhline(0.0, color="k", lw=0.5)
            ax.set_ylabel(label % axis, fontsize=8)
            ax.set_ylim(*_robust_limits(err[:, row], sig[:, row]))
            ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    axes[0, 0].legend(loc="upper right", fontsize=7)
    fig.suptitle(title)
    _save(fig, path)


def _robust_limits(err, sig):
    """Limits that show the error and the band, ignoring the huge σ right after a reset."""
    values = np.concatenate([np.abs(err[np.isfinite(err)]), sig[np.isfinite(sig)]])
    if values.size == 0:
        return -1.0, 1.0
    top = max(np.percentile(values, 98) * 1.3, 1e-6)
    return -top, top


def error_norms(path, t_s, pos_err_m, rot_err_rad, visible=(), tracker=None, outages=(),
                title="Pose error magnitude"):
    """|position error| (mm) and rotation error angle (deg) of the EKF, and of the single-frame
    tracker when `tracker` = (t_s, pos_err_m (N,3), rot_err_rad (N,3)) is given."""
    fig, axes = plt.subplots(2, 1, figsize=(11, 5.5), sharex=True)
    for ax in axes:
        _shade_visible(ax, visible)
        ax.grid(alpha=0.3)
    axes[0].plot(t_s, np.linalg.norm(pos_err_m, axis=1) * 1e3, color="#2c7fb8", lw=1.2, label="EKF")
    axes[1].plot(t_s, np.degrees(np.linalg.norm(rot_err_rad, axis=1)), color="#2c7fb8", lw=1.2,
                 label="EKF")
    if tracker is not None and len(tracker[0]):
        axes[0].plot(tracker[0], np.linalg.norm(tracker[1], axis=1) * 1e3, ".", color="#e67e22",
                     ms=3, label="cone_tracker (single frame)")
        axes[1].plot(tracker[0], np.degrees(np.linalg.norm(tracker[2], axis=1)), ".",
                     color="#e67e22", ms=3, label="cone_tracker (single frame)")
    pos_mm = np.linalg.norm(pos_err_m, axis=1) * 1e3
    if pos_mm.size and np.nanmax(pos_mm) > 50 * max(np.nanpercentile(pos_mm, 10), 1e-3):
        axes[0].set_yscale("log")  # a drift of metres in an outage would flatten the rest
    axes[0].set_ylabel("|position error| [mm]")
    axes[1].set_ylabel("rotation error [deg]")
    axes[1].set_xlabel("time [s]")
    axes[0].legend(loc="upper right", fontsize=8)
    fig.suptitle(title)
    _save(fig, path)


def overlay_error(path, t_s, err_px, visible=(), title="Overlay error (model points, pixels)"):
    fig, ax = _time_strip(visible)
    ax.plot(t_s, err_px, color="#8e44ad", lw=1.0, label="overlay error")
    ax.set_ylabel("error [px]")
    finite = np.asarray(err_px)[np.isfinite(err_px)]
    if finite.size:
        ax.set_ylim(0, max(1.0, np.percentile(finite, 99) * 1.2))
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(title)
    _save(fig, path)


def gate_rejections(path, events, t_end_s, visible=(), title="Gate rejections (cumulative)"):
    """events: {gate name: array of times [s]} -> one cumulative step line per gate."""
    fig, ax = _time_strip(visible)
    any_events = False
    for name, times in sorted(events.items()):
        times = np.sort(np.asarray(times, float))
        if not times.size:
            continue  # listed in the report's table; a flat line at zero says nothing here
        any_events = True
        ax.step(np.concatenate([[0.0], times, [t_end_s]]),
                np.concatenate([[0], np.arange(1, times.size + 1), [times.size]]),
                where="post", lw=1.3, label="%s (%d)" % (name, times.size))
    if not any_events:
        ax.text(0.5, 0.5, "no gate rejected a measurement", transform=ax.transAxes, ha="center")
    ax.set_xlim(0, t_end_s)
    ax.set_ylabel("rejections")
    if any_events:
        ax.legend(loc="upper left", fontsize=8)
    ax.set_title(title)
    _save(fig, path)


def rates(path, names, measured_hz, expected_hz, title="Message rates"):
    """Horizontal bars: measured rate per topic, with the expected rate as a tick."""
    fig, ax = plt.subplots(figsize=(9, 0.45 * len(names) + 1.2))
    y = np.arange(len(names))
    ax.barh(y, measured_hz, color="#74a9cf")
    for yi, exp in zip(y, expected_hz):
        if exp:
            ax.plot([exp, exp], [yi - 0.4, yi + 0.4], color="k", lw=2)
    ax.set_yticks(y)
    ax.set_yticklabels(names, fontsize=8)
    ax.invert_yaxis()
    ax.set_xlabel("Hz (bar: measured, black tick: expected)")
    ax.grid(axis="x", alpha=0.3)
    ax.set_title(title)
    _save(fig, path)


def error_since_view(path, ekf_since_s, pos_err_m, rot_err_rad, frame_since_s, overlay_px, centre_px, full_width_px,
                     title="Error against the time since a cone was last in the true view"):
    """Three panels against the seconds since the last frame with any cone in the TRUE view (0: a cone is
    in view): the EKF's |position error| (mm) and rotation error (deg) per sample, and per frame the overlay
    errors at full resolution (the cones' peaks and bases near the view; the centre of the view at the cones'
    distance). Samples with no cone in view yet are left out."""
    fig, axes = plt.subplots(3, 1, figsize=(11, 8), sharex=True)
    ekf_since_s, frame_since_s = np.asarray(ekf_since_s, float), np.asarray(frame_since_s, float)
    panels = [[(ekf_since_s, np.linalg.norm(pos_err_m, axis=1) * 1e3, "#2c7fb8", "EKF")],
              [(ekf_since_s, np.degrees(np.linalg.norm(rot_err_rad, axis=1)), "#2c7fb8", "EKF")],
              [(frame_since_s, np.asarray(centre_px, float), "#e67e22", "centre of the view"),
               (frame_since_s, np.asarray(overlay_px, float), "#8e44ad", "cones near the view")]]
    labels = ["|position error| [mm]", "rotation error [deg]", "overlay error [px at %d px wide]" % full_width_px]
    finite = ekf_since_s[np.isfinite(ekf_since_s)]
    x_max = max(2.5, float(finite.max()) * 1.02) if finite.size else 2.5
    for ax, series, label in zip(axes, panels, labels):
        for a, b, shade in ((0.0, 1.0, "#f4f4f4"), (1.0, 2.0, "#e6e6e6"), (2.0, x_max, "#d6d6d6")):
            ax.axvspan(a, b, color=shade, lw=0, zorder=0)
        values = []
        for x, y, colour, name in series:
            keep = np.isfinite(x) & np.isfinite(y)
            ax.plot(x[keep], y[keep], ".", ms=2.5, color=colour, alpha=0.6, label=name)
            values.append(y[keep])
        values = np.concatenate(values)
        ax.set_ylabel(label, fontsize=9)
        ax.grid(alpha=0.3)
        if values.size and values.max() > 50 * max(np.percentile(values, 10), 1e-3):
            ax.set_yscale("log")  # metres of drift in an outage would flatten the rest
        ax.legend(loc="upper left", fontsize=8, markerscale=3)
    axes[-1].set_xlim(-0.05, x_max)
    axes[-1].set_xlabel("seconds since any cone was last in the true camera view (bands: 0-1, 1-2, > 2 s)")
    fig.suptitle(title)
    _save(fig, path)

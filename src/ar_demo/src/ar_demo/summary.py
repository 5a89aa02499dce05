"""What the report shows about one replay, as plain arrays, and the figures computed from them.

`RunSummary` is filled from ar_bringup's evaluation of a recorded replay against rig_sim's ground
truth (see `from_evaluation.py`); the plots and the Markdown only read it. Times are seconds from the
start of the replay; errors are estimate minus truth in the `cones` frame (rotation errors as the
rotation vector of R_est R_truth^T, i.e. a left perturbation, as ROS's covariance is defined).
"""
import numpy as np
from ar_bringup.evaluation import rms

VISIBLE_MARGIN_S = 0.1
MIN_SAMPLES = 10  # fewer samples than this in a class (visible / out of view): no figure


class PoseErrors:
    """Error series of one estimator; the 3σ arrays are None when it gives no covariance."""

    def __init__(self, t_s, pos_err_m, rot_err_rad, pos_3sigma_m=None, rot_3sigma_rad=None):
        self.t_s = np.asarray(t_s, float).reshape(-1)
        self.pos_err_m = np.asarray(pos_err_m, float).reshape(-1, 3)
        self.rot_err_rad = np.asarray(rot_err_rad, float).reshape(-1, 3)
        self.pos_3sigma_m = None if pos_3sigma_m is None else np.asarray(pos_3sigma_m, float).reshape(-1, 3)
        self.rot_3sigma_rad = None if rot_3sigma_rad is None else np.asarray(rot_3sigma_rad, float).reshape(-1, 3)

    def __len__(self):
        return self.t_s.size


class RunSummary:
    def __init__(self):
        self.name = ""
        self.duration_s = 0.0
        self.ekf = None  # PoseErrors with the 3σ arrays
        self.tracker = None  # PoseErrors of cone_tracker's single-frame poses, or None
        self.visible = []  # [(t0_s, t1_s)] when the cones were in view (>= 3 detected)
        self.accepted = []  # [(t0_s, t1_s)] when the tracker published poses
        self.overlay_t_s = np.zeros(0)
        self.overlay_err_px = np.zeros(0)
        self.gates = {}  # {gate name: array of rejection times [s]}
        self.rejection_totals = {}  # {counter name: final value}, from ar_bringup.evaluation
        self.evaluation = {}  # ar_bringup.evaluation's summary figures, by name
        self.rates = []  # [(topic, measured_hz, expected_hz or None)]
        self.notes = []  # lines the evaluation wants shown (what it could not compute, and why)
        # By the cones in the TRUE camera view (ar_bringup.visibility), None without rig_sim/cones:
        self.view_figures = None  # {class key: {figure name: value}}, in visibility.CLASSES order
        self.view_full_width_px = 0.0  # the overlay figures' full-resolution width
        self.view_ekf_since_s = np.zeros(0)  # per EKF sample (self.ekf): seconds since a cone was in view
        self.view_frame_t_s = np.zeros(0)  # per camera frame: time, seconds since a cone was in view,
        self.view_frame_since_s = np.zeros(0)  # and the full-resolution overlay error of the cones
        self.view_overlay_px = np.zeros(0)
        self.view_centre_px = np.zeros(0)  # per camera frame: the overlay error at the centre of the view


def in_periods(t_s, periods):
    """Boolean mask: t inside any of the (t0, t1) periods."""
    mask = np.zeros(np.shape(t_s), bool)
    for t0, t1 in periods:
        mask |= (t_s >= t0) & (t_s <= t1)
    return mask


def figures(summary):
    """The headline numbers ar_bringup.evaluation's summary (printed beside them in the report) does not
    have: [(name, value, unit)]. The EKF's errors split by whether the cones were in view, the position
    error inside the EKF's ±3σ, and the frames without a tracker pose; the tracker's RMS, the overlay
    error and the orientation inside ±3σ are the evaluation's."""
    out = []
    ekf = summary.ekf
    if ekf is not None and len(ekf):
        # A period's ends are camera frames: widen them by half a gap so the IMU-rate samples
        # around the first and last frame count as visible.
        seen = in_periods(ekf.t_s, [(t0 - VISIBLE_MARGIN_S, t1 + VISIBLE_MARGIN_S) for t0, t1 in summary.visible])
        pos = np.linalg.norm(ekf.pos_err_m, axis=1)
        ang = np.degrees(np.linalg.norm(ekf.rot_err_rad, axis=1))
        for label, mask in (("cones visible", seen), ("cones out of view", ~seen)):
            if mask.sum() >= MIN_SAMPLES:
                out.append(("EKF position RMS, %s" % label, rms(pos[mask]) * 1e3, "mm"))
                out.append(("EKF orientation RMS, %s" % label, rms(ang[mask]), "deg"))
                out.append(("EKF orientation max, %s" % label, float(ang[mask].max()), "deg"))
        if ekf.pos_3sigma_m is not None:
            inside = np.all(np.abs(ekf.pos_err_m) <= ekf.pos_3sigma_m, axis=1)
            out.append(("EKF position error inside ±3σ (all three axes)", 100.0 * inside.mean(), "% of samples"))
    frames = sum(len(v) for k, v in summary.gates.items() if k.startswith("cone_tracker/detections"))
    if any(k.startswith("cone_tracker/detections") for k in summary.gates):
        out.append(("frames without a tracker pose, by reason (sum)", float(frames), "frames"))
    return out

"""A recorded replay -> RunSummary: errors against rig_sim's ground truth and the rest of the report.

Reads the bag launch/demo.launch records (and the replayed input bag for the ground truth, when the
recording lacks it). Conventions (DESIGN.md): poses are camera_optical in `cones`; the position
error is p_est - p_true in `cones`; the rotation error is the rotation vector of R_est R_true^T,
the fixed-axis (left) perturbation that ROS's pose covariance describes, so its 3σ bounds are
3 sqrt(diag) of the message's covariance (x y z rx ry rz).
"""
import numpy as np
import rosbag
from scipy.spatial.transform import Rotation

from .overlay_points import overlay_error_px
from .summary import PoseErrors, RunSummary

TRUTH = "rig_sim/ground_truth"
EKF = "pose_ekf/pose"
TRACKER = "cone_tracker/pose"
OVERLAY = "ar_overlay/image"
# Topics whose rate the report shows, with the rate the rig runs them at.
EXPECTED_HZ = {"imu/data_raw": 100.0, "camera/camera_info": 30.0, TRACKER: 30.0, EKF: 100.0,
               "pose_ekf/odometry": 100.0, OVERLAY: 30.0, TRUTH: 300.0}
TRUTH_TOLERANCE_S = 0.002  # rig_sim's truth is at every camera and IMU stamp (300 Hz)
VISIBLE_GAP_S = 0.2  # tracker poses further apart than this split a visible period


def _read(bag_path, topics):
    """{topic: [msg]} for the wanted topics (with or without a leading slash)."""
    out = {t: [] for t in topics}
    names = {("/" + t if not t.startswith("/") else t): t for t in topics}
    names.update({t: t for t in topics})
    with rosbag.Bag(bag_path) as bag:
        for topic, msg, _ in bag.read_messages(topics=list(names)):
            out[names[topic]].append(msg)
    return out


def _poses(msgs):
    """Stamped poses (PoseStamped or PoseWithCovarianceStamped) -> t, p (N,3), Rotation, cov (N,6,6)."""
    t = np.array([m.header.stamp.to_sec() for m in msgs])
    poses = [getattr(m.pose, "pose", m.pose) for m in msgs]
    p = np.array([[q.position.x, q.position.y, q.position.z] for q in poses]).reshape(-1, 3)
    xyzw = np.array([[q.orientation.x, q.orientation.y, q.orientation.z, q.orientation.w] for q in poses])
    cov = None
    if msgs and hasattr(msgs[0].pose, "covariance"):
        cov = np.array([np.reshape(m.pose.covariance, (6, 6)) for m in msgs])
    return t, p, (Rotation.from_quat(xyzw) if len(msgs) else None), cov


class Truth:
    def __init__(self, msgs):
        order = np.argsort([m.header.stamp.to_sec() for m in msgs])
        self.t, self.p, self.R, _ = _poses([msgs[i] for i in order])

    def at(self, t):
        """Indices of the truth samples at stamps t, or -1 where none is within tolerance."""
        i = np.clip(np.searchsorted(self.t, t), 1, len(self.t) - 1)
        i = np.where(np.abs(self.t[i - 1] - t) < np.abs(self.t[i] - t), i - 1, i)
        return np.where(np.abs(self.t[i] - t) <= TRUTH_TOLERANCE_S, i, -1)


def pose_errors(msgs, truth, t0):
    t, p, R, cov = _poses(msgs)
    if not len(t):
        return None, 0
    idx = truth.at(t)
    ok = idx >= 0
    idx = idx[ok]
    pos_err = p[ok] - truth.p[idx]
    rot_err = (R[np.flatnonzero(ok)] * truth.R[idx].inv()).as_rotvec()
    sig3 = None if cov is None else 3.0 * np.sqrt(np.maximum(np.diagonal(cov[ok], axis1=1, axis2=2), 0.0))
    errors = PoseErrors(t[ok] - t0, pos_err, rot_err,
                        None if sig3 is None else sig3[:, :3], None if sig3 is None else sig3[:, 3:])
    return errors, int((~ok).sum())


def visible_periods(t_s, max_gap_s=VISIBLE_GAP_S):
    """Runs of tracker poses (times in s) -> [(t0, t1)]."""
    t_s = np.sort(np.asarray(t_s, float))
    if not t_s.size:
        return []
    breaks = np.flatnonzero(np.diff(t_s) > max_gap_s)
    starts = np.concatenate([[0], breaks + 1])
    ends = np.concatenate([breaks, [t_s.size - 1]])
    return [(float(t_s[a]), float(t_s[b])) for a, b in zip(starts, ends)]


def gate_events(diag_msgs, t0):
    """Rejection times from the counters in /diagnostics: every key/value whose key mentions a
    gate or a rejection and whose value is a count; each increase is an event at that message."""
    last, events = {}, {}
    for msg in diag_msgs:
        t = msg.header.stamp.to_sec() - t0
        for status in msg.status:
            for kv in status.values:
                key = kv.key.lower()
                if "reject" not in key and "gate" not in key:
                    continue
                try:
                    count = int(float(kv.value))
                except ValueError:
                    continue
                name = "%s: %s" % (status.name, kv.key)
                events.setdefault(name, [])
                grew = count - last.get(name, 0)
                events[name] += [t] * max(0, grew)
                last[name] = count
    return {k: np.array(v) for k, v in events.items()}


def rates(msgs_by_topic):
    out = []
    for topic, expected in EXPECTED_HZ.items():
        stamps = sorted(m.header.stamp.to_sec() for m in msgs_by_topic.get(topic, []))
        hz = (len(stamps) - 1) / (stamps[-1] - stamps[0]) if len(stamps) > 2 and stamps[-1] > stamps[0] else 0.0
        out.append((topic, hz, expected))
    return out


def summarize(run_bag, truth_bag=None, name=None):
    """-> (RunSummary, t0): t0 is the stamp that the summary's times count from."""
    wanted = [TRUTH, EKF, TRACKER, "/diagnostics", "camera/camera_info", "imu/data_raw", "pose_ekf/odometry"]
    msgs = _read(run_bag, wanted)
    if not msgs[TRUTH] and truth_bag:
        msgs[TRUTH] = _read(truth_bag, [TRUTH])[TRUTH]
    summary = RunSummary()
    summary.name = name or (truth_bag or run_bag).rsplit("/", 1)[-1]
    if not msgs[TRUTH]:
        summary.notes.append("no %s in the bags: no errors against ground truth" % TRUTH)
        return summary, 0.0
    truth = Truth(msgs[TRUTH])
    t0 = truth.t[0]
    summary.duration_s = float(truth.t[-1] - t0)
    summary.ekf, missed = pose_errors(msgs[EKF], truth, t0)
    if missed:
        summary.notes.append("%d EKF poses had no ground truth within %.0f ms" % (missed, TRUTH_TOLERANCE_S * 1e3))
    summary.tracker, _ = pose_errors(msgs[TRACKER], truth, t0)
    if summary.ekf is None:
        summary.notes.append("no %s messages were recorded" % EKF)
    tracker_t = [m.header.stamp.to_sec() - t0 for m in msgs[TRACKER]]
    summary.visible = visible_periods(tracker_t)
    summary.gates = gate_events(msgs["/diagnostics"], t0)
    counted = dict(msgs)
    counted[OVERLAY] = _overlay_headers(run_bag)
    summary.rates = rates(counted)
    if msgs["camera/camera_info"] and summary.ekf is not None:
        frames = [m.header.stamp.to_sec() for m in counted[OVERLAY]] or None
        summary.overlay_t_s, summary.overlay_err_px = overlay_error_px(
            msgs["camera/camera_info"][0], msgs[EKF], truth, t0, frames)
    return summary, t0


def _overlay_headers(run_bag):
    """The overlay frames' headers only (their pixels are read once, by the video writer)."""
    class _H:
        def __init__(self, header):
            self.header = header
    out = []
    with rosbag.Bag(run_bag) as bag:
        for _, msg, _ in bag.read_messages(topics=[OVERLAY, "/" + OVERLAY]):
            out.append(_H(msg.header))
    return out

"""Evaluation of a pipeline run against rig_sim's ground truth.

Input: the pipeline's outputs and rig_sim's truth, either from a bag (``load_bag``, e.g. the one
``launch/replay.launch record:=...`` writes) or collected live (``Recorder``, used by the system tests).
Both give a ``Recording``; ``evaluate`` turns it into an ``Evaluation``::

    from ar_bringup import evaluation
    rec = evaluation.load_bag("/tmp/out.bag")
    ev = evaluation.evaluate(rec)
    print(ev.summary)            # dict of figures (orientation_rms_deg, position_rms_m, overlay_rms_px, ...)
    ev.ekf.t, ev.ekf.orientation_error_deg, ev.ekf.sigma3_rot_deg   # time series for plots

Conventions: poses are T_cones_camera (camera_optical in ``cones``), quaternions [x y z w]. The truth
(``rig_sim/ground_truth``, 300 Hz) is interpolated at each estimate's stamp (linear position, slerp).
Orientation error vectors are left perturbations in ``cones`` (rotation vector of R_est R_true^T) and
position errors are p_est - p_true in ``cones``, so both compare with the 6x6 ROS covariance's diagonal
(x y z rx ry rz) of ``pose_ekf/pose``: ``sigma3_*`` are 3 sqrt(diag). The overlay error is, per image
(``camera/camera_info`` stamps), the mean pixel distance between model points projected (plumb_bob
distortion, from camera_info) with the EKF pose interpolated at the image stamp and with the true pose.
"""
import dataclasses
import threading
import warnings
from typing import Dict, Iterable, List, Optional, Tuple

import cv2
import image_geometry
import numpy as np

from ar_bringup import quat, visibility

TOPICS = ("rig_sim/ground_truth", "pose_ekf/pose", "cone_tracker/pose", "cone_tracker/detections",
          "camera/camera_info", "imu/data_raw", "/diagnostics", "rig_sim/cones", "cone_tracker/observations")
# The default overlay model: a 1 m cube standing on the cones' centroid (its 8 corners and centre),
# the size of the models ar_overlay places among the cones.
DEFAULT_MODEL_POINTS = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (0.0, 1.0)]
                                + [[0.0, 0.0, 0.5]])
# The tracking_* figures' defaults: stamps with a tracker pose at most 0.5 s and at least 0.1 s before them.
TRACKING_WINDOW_S, TRACKING_FUSE_S = 0.5, 0.1
# Words in a diagnostic key that mark a rejection counter (cone_tracker's gates, pose_ekf's rejections).
REJECTION_WORDS = ("gate", "reject", "dropped")


def is_rejection_key(key):
    """Whether a diagnostic key names a rejection counter (REJECTION_WORDS)."""
    return any(w in key.lower() for w in REJECTION_WORDS)


@dataclasses.dataclass
class Poses:
    """Stamped poses T_cones_camera; ``cov`` is the ROS 6x6 covariance (None for the truth)."""
    t: np.ndarray
    p: np.ndarray
    q: np.ndarray
    cov: Optional[np.ndarray] = None

    def __len__(self):
        return len(self.t)

    def interpolate(self, t):
        """Poses at times t (only inside [t0, t_end]); returns (mask of valid t, p, q)."""
        t = np.asarray(t, dtype=float)
        if len(self.t) < 2:
            return np.zeros(len(t), dtype=bool), np.zeros((len(t), 3)), np.tile([0.0, 0, 0, 1], (len(t), 1))
        valid = (t >= self.t[0]) & (t <= self.t[-1])
        i = np.clip(np.searchsorted(self.t, t, side="right") - 1, 0, len(self.t) - 2)
        f = np.clip((t - self.t[i]) / np.maximum(self.t[i + 1] - self.t[i], 1e-12), 0.0, 1.0)
        p = self.p[i] + f[:, None] * (self.p[i + 1] - self.p[i])
        return valid, p, quat.slerp(self.q[i], self.q[i + 1], f)


@dataclasses.dataclass
class Recording:
    """Everything ``evaluate`` needs, as arrays. Stamps are header stamps in seconds."""
    truth: Poses
    ekf: Poses
    tracker: Poses
    image_t: np.ndarray                     # camera_info stamps (= image stamps)
    camera_info: Optional[object]           # the first sensor_msgs/CameraInfo
    detection_t: np.ndarray
    detection_count: np.ndarray             # detections per message (-1 when the type has no list)
    imu_t: np.ndarray
    diagnostics: Dict[str, Dict[str, str]]  # status name -> last key/value pairs
    counts: Dict[str, int]
    pose_rejections: Dict[str, float] = dataclasses.field(default_factory=dict)  # per reason, from detections
    cones: Optional[np.ndarray] = None      # (N, 2, 3) true [peak, base] per cone from rig_sim/cones
    observation_t: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(0))  # non-empty observations


def _pose_arrays(msgs, with_cov):
    t = np.array([m.header.stamp.to_sec() for m in msgs], dtype=float)
    poses = [m.pose.pose if with_cov else m.pose for m in msgs]
    p = np.array([[o.position.x, o.position.y, o.position.z] for o in poses], dtype=float).reshape(-1, 3)
    q = np.array([[o.orientation.x, o.orientation.y, o.orientation.z, o.orientation.w] for o in poses],
                 dtype=float).reshape(-1, 4)
    cov = np.array([np.reshape(m.pose.covariance, (6, 6)) for m in msgs], dtype=float).reshape(-1, 6, 6) \
        if with_cov else None
    order = np.argsort(t, kind="stable")
    return Poses(t[order], p[order], q[order], None if cov is None else cov[order])


def _detection_count(msg):
    """Cones accepted on one image (cone_tracker/ConeDetections.accepted_count), -1 when unknown."""
    if hasattr(msg, "accepted_count"):
        return int(msg.accepted_count)
    return len(msg.detections) if hasattr(msg, "detections") else -1


def _pose_rejections(msgs):
    """Frames per pose-stage rejection reason (ConeDetections.pose_rejected_by_names)."""
    out: Dict[str, float] = {}
    for m in msgs:
        for name in getattr(m, "pose_rejected_by_names", []):
            key = "cone_tracker/detections: " + name
            out[key] = out.get(key, 0.0) + 1.0
    return out


def recording_from_messages(messages: Iterable[Tuple[str, object]]) -> Recording:
    """Builds a Recording from (topic, message) pairs; topics as in TOPICS, leading '/' optional."""
    by_topic: Dict[str, List[object]] = {}
    for topic, msg in messages:
        by_topic.setdefault(topic.lstrip("/"), []).append(msg)
    get = lambda name: by_topic.get(name.lstrip("/"), [])  # noqa: E731
    infos = get("camera/camera_info")
    dets = get("cone_tracker/detections")
    diagnostics: Dict[str, Dict[str, str]] = {}
    for arr in get("/diagnostics"):
        for s in arr.status:
            diagnostics[s.name] = {kv.key: kv.value for kv in s.values}
    return Recording(
        truth=_pose_arrays(get("rig_sim/ground_truth"), with_cov=False),
        ekf=_pose_arrays(get("pose_ekf/pose"), with_cov=True),
        tracker=_pose_arrays(get("cone_tracker/pose"), with_cov=True),
        image_t=np.sort(np.array([m.header.stamp.to_sec() for m in infos], dtype=float)),
        camera_info=infos[0] if infos else None,
        detection_t=np.array([m.header.stamp.to_sec() for m in dets if hasattr(m, "header")], dtype=float),
        detection_count=np.array([_detection_count(m) for m in dets if hasattr(m, "header")], dtype=int),
        imu_t=np.sort(np.array([m.header.stamp.to_sec() for m in get("imu/data_raw")], dtype=float)),
        diagnostics=diagnostics,
        counts={name: len(by_topic.get(name.lstrip("/"), [])) for name in TOPICS},
        pose_rejections=_pose_rejections(dets),
        cones=visibility.cones_from_markers(get("rig_sim/cones")[-1]) if get("rig_sim/cones") else None,
        observation_t=np.sort(np.array([m.header.stamp.to_sec() for m in get("cone_tracker/observations")
                                        if len(getattr(m, "cones", []))], dtype=float)))


def bag_messages(path: str, topics=TOPICS):
    """(topic, message) pairs of a bag in time order, on these topics with or without a leading '/'."""
    import rosbag  # only here: the rest of the module works without ROS's Python packages
    names = {t.lstrip("/") for t in topics}
    with rosbag.Bag(path) as bag:
        for topic, msg, _ in bag.read_messages(topics=list(names | {"/" + t for t in names})):
            yield topic, msg


def load_bag(path: str, topics=TOPICS) -> Recording:
    """Reads a bag (e.g. from launch/replay.launch record:=PATH) into a Recording."""
    return recording_from_messages(bag_messages(path, topics))


def message_types():
    """topic -> message class for TOPICS (cone_tracker's detections only when its messages are built)."""
    from diagnostic_msgs.msg import DiagnosticArray
    from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped
    from sensor_msgs.msg import CameraInfo, Imu
    from visualization_msgs.msg import MarkerArray
    types = {"rig_sim/ground_truth": PoseStamped, "pose_ekf/pose": PoseWithCovarianceStamped,
             "cone_tracker/pose": PoseWithCovarianceStamped, "camera/camera_info": CameraInfo,
             "imu/data_raw": Imu, "/diagnostics": DiagnosticArray, "rig_sim/cones": MarkerArray}
    try:
        from cone_tracker.msg import ConeDetections
        types["cone_tracker/detections"] = ConeDetections
        from cone_tracker.msg import ConeObservations
        types["cone_tracker/observations"] = ConeObservations
    except ImportError:
        pass
    return types


class Recorder:
    """Subscribes to TOPICS in a running rospy node and keeps every message (for live tests).

    Subscribe before the data flows (the publishers may start later: rospy connects when they appear)."""

    def __init__(self, queue_size=10000):
        import rospy
        self._lock = threading.Lock()
        self._messages: List[Tuple[str, object]] = []
        self._counts: Dict[str, int] = {}  # per topic without the leading '/': count() is polled
        self._subs = [rospy.Subscriber(topic, cls, self._callback, callback_args=topic, queue_size=queue_size)
                      for topic, cls in message_types().items()]

    def _callback(self, msg, topic):
        with self._lock:
            self._messages.append((topic, msg))
            key = topic.lstrip("/")
            self._counts[key] = self._counts.get(key, 0) + 1

    def count(self, topic):
        with self._lock:
            return self._counts.get(topic.lstrip("/"), 0)

    def unregister(self):
        for s in self._subs:
            s.unregister()

    def recording(self) -> Recording:
        with self._lock:
            return recording_from_messages(list(self._messages))


def project(points_camera, info):
    """Raw (distorted) pixels of camera-frame points for a CameraInfo: image_geometry reads K and D, and
    OpenCV's projectPoints applies plumb_bob or rational_polynomial, the model the C++ side uses.
    (image_geometry's own project3dToPixel gives rectified pixels, and it has no distort.)"""
    camera = image_geometry.PinholeCameraModel()
    with warnings.catch_warnings():  # image_geometry builds numpy.matrix objects (PendingDeprecationWarning)
        warnings.simplefilter("ignore", PendingDeprecationWarning)
        camera.fromCameraInfo(info)
    points = np.ascontiguousarray(np.reshape(points_camera, (-1, 3)), dtype=np.float64)
    if len(points) == 0:
        return np.zeros(points_camera.shape[:-1] + (2,))
    pixels, _ = cv2.projectPoints(points, np.zeros(3), np.zeros(3), np.asarray(camera.intrinsicMatrix()),
                                  np.asarray(camera.distortionCoeffs()).ravel())
    return np.reshape(pixels, points_camera.shape[:-1] + (2,))


def _to_camera(points_cones, p, q):
    """p_camera = R^T (p_cones - t) for T_cones_camera = (p, q), per pose: (N, M, 3)."""
    R = quat.to_matrix(q)
    return np.einsum("nji,nmj->nmi", R, points_cones[None, :, :] - p[:, None, :])


@dataclasses.dataclass
class EstimateErrors:
    """Errors of one estimate stream at its own stamps (where the truth covers them)."""
    t: np.ndarray
    orientation_error_deg: np.ndarray   # angle of R_est R_true^T
    rot_error_deg: np.ndarray           # (N, 3) rotation vector in cones, degrees
    position_error_m: np.ndarray        # |p_est - p_true|
    pos_error_m: np.ndarray             # (N, 3) in cones
    sigma3_rot_deg: Optional[np.ndarray] = None   # (N, 3)
    sigma3_pos_m: Optional[np.ndarray] = None     # (N, 3)


@dataclasses.dataclass
class Evaluation:
    ekf: EstimateErrors
    tracker: EstimateErrors
    overlay_t: np.ndarray               # image stamps with an estimate and the truth
    overlay_error_px: np.ndarray        # mean over the visible model points
    accepted_periods: List[Tuple[float, float]]   # spans with tracker poses (cones seen and accepted)
    outages: List[Tuple[float, float]]            # gaps between them
    visible_periods: List[Tuple[float, float]]    # spans of frames with at least min_visible_cones accepted
    rejections: Dict[str, float]
    rates_hz: Dict[str, float]
    summary: Dict[str, float]
    view: Optional[visibility.ViewSeries] = None  # errors by the cones in the true view (visibility.py)

    def ekf_error_after(self, t0, window_s):
        """Max orientation (deg) and position (m) error of the EKF in [t0, t0 + window_s]."""
        m = (self.ekf.t >= t0) & (self.ekf.t <= t0 + window_s)
        if not m.any():
            return float("nan"), float("nan")
        return float(self.ekf.orientation_error_deg[m].max()), float(self.ekf.position_error_m[m].max())


def _errors(est: Poses, truth: Poses) -> EstimateErrors:
    valid, p_true, q_true = truth.interpolate(est.t)
    q_est, p_est = est.q[valid], est.p[valid]
    rot = np.degrees(quat.to_rotvec(quat.multiply(q_est, quat.conjugate(q_true[valid]))))
    pos = p_est - p_true[valid]
    e = EstimateErrors(est.t[valid], np.linalg.norm(rot, axis=1), rot, np.linalg.norm(pos, axis=1), pos)
    if est.cov is not None and len(est.cov):
        d = np.clip(np.diagonal(est.cov[valid], axis1=1, axis2=2), 0.0, None)
        e.sigma3_pos_m = 3.0 * np.sqrt(d[:, :3])
        e.sigma3_rot_deg = 3.0 * np.degrees(np.sqrt(d[:, 3:]))
    return e


def _periods(t, max_gap_s):
    """Spans of t whose consecutive gaps are at most max_gap_s, and the gaps between them."""
    if len(t) == 0:
        return [], []
    cuts = np.nonzero(np.diff(t) > max_gap_s)[0]
    starts = np.concatenate([[t[0]], t[cuts + 1]])
    ends = np.concatenate([t[cuts], [t[-1]]])
    spans = [(float(a), float(b)) for a, b in zip(starts, ends)]
    return spans, [(spans[i][1], spans[i + 1][0]) for i in range(len(spans) - 1)]


def _rate(t):
    return float((len(t) - 1) / (t[-1] - t[0])) if len(t) > 1 and t[-1] > t[0] else 0.0


def rms(x):
    return float(np.sqrt(np.mean(np.square(x)))) if len(x) else float("nan")


def overlay_errors(rec: Recording, model_points=DEFAULT_MODEL_POINTS):
    """(image stamps, mean pixel error) for images where the EKF and the truth both cover the stamp.

    A model point counts when its true projection is in front of the camera and inside the image with a
    50 % margin. Its error is capped at the image diagonal: an estimate that puts the point behind the
    camera or far off-screen is "the overlay is gone", not an error of 10^12 pixels from the distortion
    polynomial evaluated far outside the lens's field."""
    if rec.camera_info is None or len(rec.ekf) < 2:
        return np.zeros(0), np.zeros(0)
    pts = np.asarray(model_points, dtype=float)
    ok_e, p_e, q_e = rec.ekf.interpolate(rec.image_t)
    ok_t, p_t, q_t = rec.truth.interpolate(rec.image_t)
    ok = ok_e & ok_t
    c_est, c_true = _to_camera(pts, p_e[ok], q_e[ok]), _to_camera(pts, p_t[ok], q_t[ok])
    w, h = rec.camera_info.width, rec.camera_info.height
    diagonal = float(np.hypot(w, h))
    front_true, front_est = c_true[..., 2] > 0.05, c_est[..., 2] > 0.05
    px_true = project(np.where(front_true[..., None], c_true, 1.0), rec.camera_info)
    px_est = project(np.where(front_est[..., None], c_est, 1.0), rec.camera_info)
    inside = front_true & (px_true[..., 0] > -0.5 * w) & (px_true[..., 0] < 1.5 * w) & \
        (px_true[..., 1] > -0.5 * h) & (px_true[..., 1] < 1.5 * h)
    with np.errstate(invalid="ignore", over="ignore"):
        dist = np.linalg.norm(px_est - px_true, axis=-1)
    dist = np.where(front_est & np.isfinite(dist), np.minimum(dist, diagonal), diagonal)
    n = inside.sum(axis=1)
    keep = n > 0
    mean = np.where(keep, (dist * inside).sum(axis=1) / np.maximum(n, 1), np.nan)
    return rec.image_t[ok][keep], mean[keep]


def tracking(t, tracker_t, window_s, fuse_s=0.0):
    """Whether each stamp of t has a tracker pose between window_s and fuse_s before it: the cones are
    being tracked, as against an IMU-only outage, where the EKF extrapolates.

    fuse_s leaves out the first fuse_s after a re-acquisition: the pose the EKF published for the stamp
    of the first camera pose after an outage is its IMU-only prediction unless that camera pose reached
    it within one IMU period, which a loaded machine does not promise (one such image, 87 px off, was
    all of a failed look_away_recovery run in CI). Within a tracked span the previous camera pose is
    always old enough."""
    tracker_t = np.sort(np.asarray(tracker_t, dtype=float))
    t = np.asarray(t, dtype=float)
    if len(tracker_t) == 0:
        return np.zeros(len(t), dtype=bool)
    i = np.searchsorted(tracker_t, t - fuse_s, side="right") - 1
    last = tracker_t[np.clip(i, 0, None)]
    return (i >= 0) & (t - last <= window_s)


def evaluate(rec: Recording, model_points=DEFAULT_MODEL_POINTS, settle_s=1.0, max_gap_s=0.2,
             min_visible_cones=1, tracking_window_s=TRACKING_WINDOW_S, tracking_fuse_s=TRACKING_FUSE_S,
             full_width_px=visibility.FULL_WIDTH_PX) -> Evaluation:
    """Errors, periods, rejections, rates and the summary figures of a Recording.

    settle_s: the summary's RMS figures skip the first settle_s after the EKF's first output (the filter
    initialises from the first camera pose and settles its velocity and bias states).
    max_gap_s: tracker poses further apart than this split the accepted periods (an outage).
    min_visible_cones: a detections message with at least this many accepted cones counts as "visible".
    tracking_window_s, tracking_fuse_s: the tracking_* figures cover the stamps with a tracker pose at most
    tracking_window_s and at least tracking_fuse_s before them (``tracking``).
    full_width_px: the camera's full-resolution width, for the view_*_overlay figures (visibility.py).
    The view_<class>_<figure> figures split the errors by the cones in the TRUE view (visibility.CLASSES);
    they need rig_sim/cones in the recording.
    """
    ekf, trk = _errors(rec.ekf, rec.truth), _errors(rec.tracker, rec.truth)
    ov_t, ov_px = overlay_errors(rec, model_points)
    spans, gaps = _periods(rec.tracker.t, max_gap_s)
    visible, _ = _periods(rec.detection_t[rec.detection_count >= min_visible_cones], max_gap_s)
    rejections = dict(rec.pose_rejections)
    for name, values in rec.diagnostics.items():
        for key, value in values.items():
            if is_rejection_key(key):
                try:
                    rejections["%s: %s" % (name, key)] = float(value)
                except ValueError:
                    pass
    rates = {"camera": _rate(rec.image_t), "imu": _rate(rec.imu_t), "tracker_pose": _rate(rec.tracker.t),
             "ekf_pose": _rate(rec.ekf.t), "detections": _rate(rec.detection_t)}
    t0 = ekf.t[0] + settle_s if len(ekf.t) else 0.0
    m = ekf.t >= t0
    mo = ov_t >= t0
    mt = m & tracking(ekf.t, rec.tracker.t, tracking_window_s, tracking_fuse_s)
    mot = mo & tracking(ov_t, rec.tracker.t, tracking_window_s, tracking_fuse_s)
    inside3 = np.all(np.abs(ekf.rot_error_deg[m]) <= ekf.sigma3_rot_deg[m], axis=1) \
        if ekf.sigma3_rot_deg is not None and m.any() else np.zeros(0)
    summary = {
        "orientation_rms_deg": rms(ekf.orientation_error_deg[m]),
        "orientation_max_deg": float(ekf.orientation_error_deg[m].max()) if m.any() else float("nan"),
        "position_rms_m": rms(ekf.position_error_m[m]),
        "position_max_m": float(ekf.position_error_m[m].max()) if m.any() else float("nan"),
        "tracking_orientation_rms_deg": rms(ekf.orientation_error_deg[mt]),
        "tracking_position_rms_m": rms(ekf.position_error_m[mt]),
        "tracking_overlay_rms_px": rms(ov_px[mot]),
        "tracking_fraction": float(mt.sum()) / max(1, int(m.sum())),
        "tracker_orientation_rms_deg": rms(trk.orientation_error_deg),
        "tracker_position_rms_m": rms(trk.position_error_m),
        "orientation_within_3sigma": float(inside3.mean()) if len(inside3) else float("nan"),
        "overlay_rms_px": rms(ov_px[mo]),
        "overlay_median_px": float(np.median(ov_px[mo])) if mo.any() else float("nan"),
        "overlay_p95_px": float(np.percentile(ov_px[mo], 95)) if mo.any() else float("nan"),
        "overlay_max_px": float(ov_px[mo].max()) if mo.any() else float("nan"),
        "tracker_poses": float(len(rec.tracker)),
        "images": float(len(rec.image_t)),
        "accepted_fraction": float(len(rec.tracker)) / max(1, len(rec.image_t)),
        "outages": float(len(gaps)),
        "ekf_nan": float(np.count_nonzero(~np.isfinite(rec.ekf.p).all(axis=1) | ~np.isfinite(rec.ekf.q).all(axis=1))),
    }
    view = visibility.series(rec, ekf, t0, full_width_px, project)
    if view is not None:
        for key, figs in view.figures.items():
            summary.update({"view_%s_%s" % (key, name): value for name, value in figs.items()})
    return Evaluation(ekf, trk, ov_t, ov_px, spans, gaps, visible, rejections, rates, summary, view)

"""What a user sees: the pipeline's errors split by the cones' visibility in the TRUE camera.

Each camera frame (``camera/camera_info`` stamp) is classed by the cones in the true view: a cone is in
view when its peak and its base are in front of the true camera (z > 0) and project inside the image
(camera_info's K and D). The cones are rig_sim's own (``rig_sim/cones``: the apex of each marker and the
centre of its base ring). Every sample (an EKF pose, a frame) takes the class of the latest frame at or
before it: ``3plus`` (three or more cones in view), ``1to2``, or, with none in view, by the time since the
last frame with any cone in view: ``none_0to1s``, ``none_1to2s``, ``none_over2s`` (also before any cone was
ever in view). Per class: the EKF's position RMS and median, orientation RMS, the overlay errors and the
share of frames that updated the filter.

Overlay error here, in pixels of the full-resolution image (x ``full_width_px / camera_info.width``; a bag
does not say what the full resolution was, rig_sim's ``--scale`` shrinks the image and K together, so it is
a parameter, default 1024, rig_sim's camera), through camera_info's K (pinhole: near the edge of the view a
lens model's polynomial means nothing):
- ``overlay``: the cones' peaks and bases projected with the EKF pose and with the true pose, the mean
  distance over the points that the true camera sees in the image or within half its size around it (the
  rule of evaluation.overlay_errors; further out, pinhole pixels grow without bound with the angle off the
  axis, and the figure would measure tan(), not the overlay). NaN for a frame with no such point: in a
  long outage the cones are far out of the view.
- ``centre``: what is drawn at the centre of the view, always defined: the point on the true optical axis at
  the distance of the cones' centroid, projected with the EKF pose; its distance from the principal point.
A point behind the estimated camera counts as the full-resolution diagonal.

A frame "updated the filter" when the tracker published, for its stamp, a ``cone_tracker/pose`` or a
``cone_tracker/observations`` message with at least one cone (what pose_ekf fuses); only what was recorded
counts.
"""
import dataclasses
from typing import Dict, Optional

import numpy as np

from ar_bringup import quat

# (key, what it means); the key names the summary figures view_<key>_<figure>.
CLASSES = (("3plus", "three or more cones in view"), ("1to2", "one or two cones in view"),
           ("none_0to1s", "no cone in view for 0-1 s"), ("none_1to2s", "no cone in view for 1-2 s"),
           ("none_over2s", "no cone in view for > 2 s"))
FULL_WIDTH_PX = 1024  # rig_sim's camera (1024x768); make_bag --scale 0.25 records 256x192
STAMP_TOLERANCE_S = 1e-4  # a tracker message belongs to the frame with this stamp (frames are 33 ms apart)
MIN_DEPTH_M = 1e-3


def cones_from_markers(marker_array):
    """(N, 2, 3) [peak, base centre] in ``cones`` of rig_sim/cones (one TRIANGLE_LIST per cone: per side two
    base-ring points and the apex). Markers without points are skipped."""
    out = []
    for m in marker_array.markers:
        pts = np.array([[p.x, p.y, p.z] for p in m.points], dtype=float).reshape(-1, 3)
        if len(pts) < 3:
            continue
        apex = pts[2::3]
        ring = np.delete(pts, np.s_[2::3], axis=0)
        out.append([apex.mean(axis=0), ring.mean(axis=0)])
    return np.array(out, dtype=float).reshape(-1, 2, 3)


def to_camera(points_cones, p, q):
    """p_camera = R^T (p_cones - t) for each pose T_cones_camera = (p, q): (M, K, 3)."""
    R = quat.to_matrix(np.reshape(q, (-1, 4)))
    return np.einsum("nji,nmj->nmi", R, np.reshape(points_cones, (-1, 3))[None] - np.reshape(p, (-1, 3))[:, None])


def _pinhole(c, K):
    z = np.where(c[..., 2] > MIN_DEPTH_M, c[..., 2], 1.0)
    return np.stack([K[0, 0] * c[..., 0] / z + K[0, 2], K[1, 1] * c[..., 1] / z + K[1, 2]], axis=-1)


def cones_in_view(cones, p_true, q_true, info, project=None):
    """Cones in the true view per pose: (M,) counts. project(points (..., 3), info) -> raw pixels (with the
    lens's distortion; default: the pinhole K). A point must be in front (z > 0), inside the pinhole
    image plus its size on each side (where the distortion polynomial still holds) and, projected, inside
    the image."""
    if len(cones) == 0 or len(p_true) == 0:
        return np.zeros(len(p_true), dtype=int)
    c = to_camera(cones.reshape(-1, 3), p_true, q_true)  # (M, 2N, 3): peak, base per cone
    K = np.reshape(info.K, (3, 3))
    w, h = float(info.width), float(info.height)
    front = c[..., 2] > MIN_DEPTH_M
    ideal = _pinhole(c, K)
    near = (ideal[..., 0] > -w) & (ideal[..., 0] < 2 * w) & (ideal[..., 1] > -h) & (ideal[..., 1] < 2 * h)
    ok = front & near
    px = project(np.where(ok[..., None], c, [0.0, 0.0, 1.0]), info) if project is not None else ideal
    inside = ok & (px[..., 0] >= 0) & (px[..., 0] < w) & (px[..., 1] >= 0) & (px[..., 1] < h)
    return inside.reshape(len(p_true), -1, 2).all(axis=2).sum(axis=1)


def latest_frame(t, frame_t):
    """Index of the latest frame at or before each t (-1 before the first)."""
    return np.searchsorted(frame_t, np.asarray(t, dtype=float) + STAMP_TOLERANCE_S, side="right") - 1


def time_since_view(t, frame_t, counts):
    """Seconds since the last frame at or before t with a cone in view: 0 when the latest frame has one,
    inf when none had (or t is before the first frame)."""
    t = np.asarray(t, dtype=float)
    seen_t = np.asarray(frame_t, dtype=float)[np.asarray(counts) > 0]
    i = latest_frame(t, frame_t)
    j = np.searchsorted(seen_t, t + STAMP_TOLERANCE_S, side="right") - 1
    since = np.where(j >= 0, t - seen_t[np.clip(j, 0, None)] if len(seen_t) else np.inf, np.inf)
    latest_seen = (i >= 0) & (np.asarray(counts)[np.clip(i, 0, None)] > 0) if len(frame_t) else np.zeros(len(t), bool)
    return np.where(latest_seen, 0.0, np.maximum(since, 0.0))


def classify(t, frame_t, counts):
    """(class index into CLASSES per t (-1 before the first frame), seconds since a cone was in view)."""
    t = np.asarray(t, dtype=float)
    frame_t, counts = np.asarray(frame_t, dtype=float), np.asarray(counts, dtype=int)
    i = latest_frame(t, frame_t)
    n = counts[np.clip(i, 0, None)] if len(frame_t) else np.zeros(len(t), dtype=int)
    since = time_since_view(t, frame_t, counts)
    cls = np.where(n >= 3, 0, np.where(n >= 1, 1, np.where(since <= 1.0, 2, np.where(since <= 2.0, 3, 4))))
    return np.where(i >= 0, cls, -1), since


def updated_frames(frame_t, pose_t, observation_t):
    """Whether each frame had a tracker pose or a non-empty observations message at its stamp."""
    stamps = np.sort(np.concatenate([np.asarray(pose_t, float), np.asarray(observation_t, float)]))
    if len(stamps) == 0:
        return np.zeros(len(frame_t), dtype=bool)
    i = np.clip(np.searchsorted(stamps, frame_t), 0, len(stamps) - 1)  # the first stamp at or after
    near = np.minimum(np.abs(stamps[i] - frame_t), np.abs(stamps[np.maximum(i - 1, 0)] - frame_t))
    return near <= STAMP_TOLERANCE_S


def _distances(c_true, c_est, K, scale, diagonal):
    """Full-resolution pixel distances of the pinhole projections; the diagonal where c_est is behind."""
    with np.errstate(invalid="ignore", over="ignore"):
        d = np.linalg.norm(_pinhole(c_est, K) - _pinhole(c_true, K), axis=-1) * scale
    return np.where((c_est[..., 2] > MIN_DEPTH_M) & np.isfinite(d), np.minimum(d, diagonal), diagonal)


def overlay_full_res_px(cones, p_true, q_true, p_est, q_est, info, full_width_px=FULL_WIDTH_PX):
    """Per pose pair -> (overlay, centre), full-resolution pixels (see the module's docstring): the mean
    distance of the cones' peaks and bases near the true view (NaN with none), and the error at the centre
    of the view at the cones' distance."""
    if len(p_true) == 0 or len(cones) == 0:
        return np.full(len(p_true), np.nan), np.full(len(p_true), np.nan)
    K = np.reshape(info.K, (3, 3))
    w, h = float(info.width), float(info.height)
    scale = float(full_width_px) / w if full_width_px else 1.0
    diagonal = float(np.hypot(w, h)) * scale
    pts = cones.reshape(-1, 3)
    c_true, c_est = to_camera(pts, p_true, q_true), to_camera(pts, p_est, q_est)
    px_true = _pinhole(c_true, K)
    near = (c_true[..., 2] > MIN_DEPTH_M) & (px_true[..., 0] > -0.5 * w) & (px_true[..., 0] < 1.5 * w) & \
        (px_true[..., 1] > -0.5 * h) & (px_true[..., 1] < 1.5 * h)
    d = _distances(c_true, c_est, K, scale, diagonal)
    n = near.sum(axis=1)
    overlay = np.where(n > 0, (d * near).sum(axis=1) / np.maximum(n, 1), np.nan)
    # The centre: the point on the true optical axis at the distance of the cones' centroid.
    dist = np.linalg.norm(pts.mean(axis=0)[None] - np.reshape(p_true, (-1, 3)), axis=1)
    on_axis = np.reshape(p_true, (-1, 3)) + quat.to_matrix(np.reshape(q_true, (-1, 4)))[:, :, 2] * dist[:, None]
    c_axis_true = np.c_[np.zeros((len(dist), 2)), dist][:, None]
    c_axis_est = np.einsum("nji,nj->ni", quat.to_matrix(np.reshape(q_est, (-1, 4))),
                           on_axis - np.reshape(p_est, (-1, 3)))[:, None]
    centre = _distances(c_axis_true, c_axis_est, K, scale, diagonal)[:, 0]
    return overlay, centre


@dataclasses.dataclass
class ViewSeries:
    """The per-frame and per-EKF-sample series behind the class figures (stamps in seconds)."""
    frame_t: np.ndarray
    frame_cones: np.ndarray         # cones in the true view
    frame_class: np.ndarray         # index into CLASSES
    frame_since_s: np.ndarray
    frame_updated: np.ndarray       # a tracker pose or observations for this frame
    overlay_px: np.ndarray          # full resolution, per frame (NaN without an estimate or no cone near)
    centre_px: np.ndarray           # full resolution, per frame, at the centre of the view (NaN without an estimate)
    ekf_class: np.ndarray           # per EKF error sample
    ekf_since_s: np.ndarray
    full_width_px: float
    figures: Dict[str, Dict[str, float]]  # class key -> figure name -> value


def _rms(x):
    return float(np.sqrt(np.mean(np.square(x)))) if len(x) else float("nan")


def _median(x):
    return float(np.median(x)) if len(x) else float("nan")


def view_figures(frame_class, frame_updated, overlay_px, ekf_class, position_error_m, orientation_error_deg,
                 ekf_mask=None, centre_px=None):
    """class key -> {frames, updated_fraction, position_rms_m, position_median_m, orientation_rms_deg,
    overlay_rms_px, overlay_median_px, overlay_frames, centre_rms_px, centre_median_px}: frames and updates over
    every frame, the overlay figures over the frames where they are finite (overlay_frames: how many), the
    EKF errors over ekf_mask (the EKF's settling time left out)."""
    centre_px = np.full(len(frame_class), np.nan) if centre_px is None else centre_px
    fm = np.ones(len(frame_class), bool)
    em = np.ones(len(ekf_class), bool) if ekf_mask is None else ekf_mask
    out = {}
    for k, (key, _) in enumerate(CLASSES):
        f, e = fm & (frame_class == k), em & (ekf_class == k)
        ov = overlay_px[f]
        ov = ov[np.isfinite(ov)]
        ce = centre_px[f]
        ce = ce[np.isfinite(ce)]
        out[key] = {
            "frames": float(f.sum()),
            "updated_fraction": float(frame_updated[f].mean()) if f.any() else float("nan"),
            "position_rms_m": _rms(position_error_m[e]),
            "position_median_m": _median(position_error_m[e]),
            "orientation_rms_deg": _rms(orientation_error_deg[e]),
            "overlay_rms_px": _rms(ov),
            "overlay_median_px": _median(ov),
            "overlay_frames": float(len(ov)),
            "centre_rms_px": _rms(ce),
            "centre_median_px": _median(ce),
        }
    return out


def series(rec, ekf_errors, settle_t, full_width_px=FULL_WIDTH_PX, project=None) -> Optional[ViewSeries]:
    """The ViewSeries of a Recording (None without rig_sim/cones or camera_info): ekf_errors is
    evaluation's EstimateErrors of the EKF; its errors and the overlay before settle_t are left out of the
    figures (every frame counts in frames and updated_fraction)."""
    cones = getattr(rec, "cones", None)
    if cones is None or len(cones) == 0 or rec.camera_info is None or len(rec.truth) < 2:
        return None
    ok_t, p_t, q_t = rec.truth.interpolate(rec.image_t)
    frame_t = rec.image_t[ok_t]
    counts = cones_in_view(cones, p_t[ok_t], q_t[ok_t], rec.camera_info, project)
    frame_class, frame_since = classify(frame_t, frame_t, counts)
    updated = updated_frames(frame_t, rec.tracker.t, getattr(rec, "observation_t", np.zeros(0)))
    overlay, centre = np.full(len(frame_t), np.nan), np.full(len(frame_t), np.nan)
    ok_e, p_e, q_e = rec.ekf.interpolate(frame_t)
    ok_e &= frame_t >= settle_t
    if ok_e.any():
        overlay[ok_e], centre[ok_e] = overlay_full_res_px(cones, p_t[ok_t][ok_e], q_t[ok_t][ok_e], p_e[ok_e],
                                                          q_e[ok_e], rec.camera_info, full_width_px)
    ekf_class, ekf_since = classify(ekf_errors.t, frame_t, counts)
    figs = view_figures(frame_class, updated, overlay, ekf_class, ekf_errors.position_error_m,
                        ekf_errors.orientation_error_deg, ekf_mask=ekf_errors.t >= settle_t, centre_px=centre)
    return ViewSeries(frame_t, counts, frame_class, frame_since, updated, overlay, centre, ekf_class, ekf_since,
                      float(full_width_px or rec.camera_info.width), figs)

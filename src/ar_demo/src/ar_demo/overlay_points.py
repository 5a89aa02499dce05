"""Overlay error: where the model is drawn (at the EKF's pose) against where it belongs (at the true
pose), in pixels of the raw, distorted image.

The points are the corners and the centre of the box around the demo scene's model
(src/ar_overlay/config/scene_peaks.yaml: the peaks surface 0.3 m wide, 0.08-0.8 m above the
centroid of the cone bases). For each overlay frame, both poses are taken at the frame's stamp
(the overlay's default `image_stamp` mode renders at that stamp) and the points are projected
with cv2.projectPoints through the camera_info's plumb_bob model. The error is the mean distance.
"""
import itertools

import cv2
import numpy as np
from scipy.spatial.transform import Rotation, Slerp

MODEL_POINTS_M = np.array([[0.0, 0.0, 0.44]] + [list(c) for c in itertools.product((-0.15, 0.15), (-0.15, 0.15), (0.08, 0.8))])


def project(camera_info, R_cones_camera, p_cones_camera, points_m=MODEL_POINTS_M):
    """Pixels of cones-frame points seen by a camera at (R, p) = T_cones_camera."""
    K = np.reshape(camera_info.K, (3, 3))
    D = np.asarray(camera_info.D, float) if len(camera_info.D) else np.zeros(5)
    R_camera_cones = R_cones_camera.inv()
    rvec = R_camera_cones.as_rotvec()
    tvec = -R_camera_cones.apply(p_cones_camera)
    px, _ = cv2.projectPoints(points_m.reshape(-1, 1, 3), rvec, tvec, K, D)
    return px.reshape(-1, 2)


def overlay_error_px(camera_info, ekf_msgs, truth, t0, frame_stamps=None):
    """-> (t_s, mean pixel error) at each overlay frame stamp (default: the EKF's own stamps
    thinned to the camera rate when no frame stamps are given)."""
    t = np.array([m.header.stamp.to_sec() for m in ekf_msgs])
    if t.size < 2:
        return np.zeros(0), np.zeros(0)
    order = np.argsort(t)
    t = t[order]
    keep = np.concatenate([[True], np.diff(t) > 1e-9])
    t = t[keep]
    msgs = [ekf_msgs[i] for i in order[keep]]
    p = np.array([[m.pose.pose.position.x, m.pose.pose.position.y, m.pose.pose.position.z] for m in msgs])
    q = np.array([[m.pose.pose.orientation.x, m.pose.pose.orientation.y, m.pose.pose.orientation.z,
                   m.pose.pose.orientation.w] for m in msgs])
    slerp = Slerp(t, Rotation.from_quat(q))
    stamps = np.asarray(frame_stamps if frame_stamps is not None else truth.t[::10], float)
    stamps = stamps[(stamps >= t[0]) & (stamps <= t[-1])]
    idx = truth.at(stamps)
    stamps, idx = stamps[idx >= 0], idx[idx >= 0]
    errors = np.empty(stamps.size)
    R_est = slerp(stamps)
    p_est = np.column_stack([np.interp(stamps, t, p[:, k]) for k in range(3)])
    for k in range(stamps.size):
        drawn = project(camera_info, R_est[k], p_est[k])
        true = project(camera_info, truth.R[idx[k]], truth.p[idx[k]])
        errors[k] = np.mean(np.linalg.norm(drawn - true, axis=1))
    return stamps - t0, errors

"""Small numpy quaternion helpers in ROS order [x, y, z, w] (vectorised over the first axis).

Rotation vectors follow pose_math's ROS covariance convention: the error of an estimate R_est against
the truth R_true is the rotation vector of R_est R_true^T, a left (fixed-axis) perturbation in the
parent frame, so its components compare with the rx ry rz block of a ROS 6x6 covariance.
"""
import numpy as np


def normalize(q):
    q = np.asarray(q, dtype=float)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def conjugate(q):
    q = np.asarray(q, dtype=float)
    return np.concatenate([-q[..., :3], q[..., 3:]], axis=-1)


def multiply(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    ax, ay, az, aw = np.moveaxis(a, -1, 0)
    bx, by, bz, bw = np.moveaxis(b, -1, 0)
    return np.stack([aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw,
                     aw * bw - ax * bx - ay * by - az * bz], axis=-1)


def to_rotvec(q):
    """Rotation vector (rad) of unit quaternions, taking the shorter way round."""
    q = normalize(q)
    q = np.where(q[..., 3:] < 0.0, -q, q)
    s = np.linalg.norm(q[..., :3], axis=-1)
    angle = 2.0 * np.arctan2(s, q[..., 3])
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.where(s > 1e-12, angle / np.maximum(s, 1e-300), 2.0)
    return q[..., :3] * scale[..., None]


def to_matrix(q):
    x, y, z, w = np.moveaxis(normalize(q), -1, 0)
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], axis=-1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], axis=-1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], axis=-1)], axis=-2)


def slerp(q0, q1, f):
    """Spherical interpolation between rows of q0 and q1 at fractions f in [0, 1]."""
    q0, q1 = normalize(q0), normalize(q1)
    f = np.asarray(f, dtype=float)[..., None]
    d = np.sum(q0 * q1, axis=-1, keepdims=True)
    q1 = np.where(d < 0.0, -q1, q1)
    d = np.abs(d)
    theta = np.arccos(np.clip(d, -1.0, 1.0))
    sin_t = np.sin(theta)
    small = sin_t < 1e-9
    w0 = np.where(small, 1.0 - f, np.sin((1.0 - f) * theta) / np.where(small, 1.0, sin_t))
    w1 = np.where(small, f, np.sin(f * theta) / np.where(small, 1.0, sin_t))
    return normalize(w0 * q0 + w1 * q1)

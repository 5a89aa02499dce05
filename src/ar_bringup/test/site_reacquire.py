#!/usr/bin/env python3
"""Re-acquisition after the outages of rig_sim's ``site_look_away`` walk (the walker looks down at the
ground, no cone in view, then at exactly two cones before more appear), from a bag recorded by
``launch/replay.launch record:=...`` (or, in site_reacquire_test.py, a live recording).

Per outage (a stretch of at least --min-outage-s with no cone in the true view, ar_bringup.visibility's rule):
- the two-cone span: from the first frame after the outage with two cones in view at least --min-px-full tall
  (full-resolution pixels, 1024 px wide: 60 is 30 px at 512x384, ar_bringup's "resolved" split) while it
  keeps two such cones, and when three or more first stand in view;
- the first fused camera update: the first pose_ekf/pose sample after the outage whose largest position
  sigma is smaller than the sample before (only a camera measurement lowers it; the IMU alone only raises
  it); the frame it came from (the latest cone_tracker/observations or cone_tracker/pose stamp at or before
  it), that frame's cones and whether their ids are right (each observed cone's peak and base within
  max(4 px, 0.25 x its length) of the true projection of the cone it was given, at the bag's resolution);
- the EKF's position and orientation error just before that update, at it, the largest 0.5-1.5 s after it
  and at the end of the two-cone span.

usage: site_reacquire.py [--min-px-full PX] OUT.bag [OUT.bag ...]
"""
import argparse
import dataclasses
import sys
from typing import List, Optional, Sequence, Tuple

import numpy as np

from ar_bringup import evaluation, visibility

MIN_PX_FULL = 60.0
MIN_OUTAGE_S = 1.5
SIGMA_DROP = 0.005  # relative: a fused camera update lowers the position sigma by far more


@dataclasses.dataclass
class Observed:
    """One cone_tracker/observations message: stamp and, per cone, (cone_id, peak_px, base_px)."""
    t: float
    cones: List[Tuple[int, np.ndarray, np.ndarray]]


def observations_from_messages(msgs) -> List[Observed]:
    out = [Observed(m.header.stamp.to_sec(), [(int(c.cone_id), np.array(c.peak_px, float), np.array(c.base_px, float))
                                              for c in m.cones]) for m in msgs if len(m.cones)]
    return sorted(out, key=lambda o: o.t)


@dataclasses.dataclass
class Reacquisition:
    outage: Tuple[float, float]            # no cone in view (first and last such frame)
    two_t: float = float("nan")            # first frame after it with two resolved cones
    two_ids: Tuple[int, ...] = ()
    two_end_t: float = float("nan")        # last frame of that two-cone span
    three_t: float = float("nan")          # first frame after the outage with three or more resolved cones
    fused_t: float = float("nan")          # first fused camera update after the outage
    fused_frame_t: float = float("nan")    # the frame it came from
    fused_kind: str = ""                   # "observations" or "pose" (the tracker's 3+ cone pose)
    fused_ids: Tuple[int, ...] = ()
    fused_ids_right: Optional[bool] = None
    before_m: float = float("nan")         # EKF position error just before the update
    before_deg: float = float("nan")
    at_m: float = float("nan")
    after_max_m: float = float("nan")      # largest 0.5-1.5 s after the update
    after_max_deg: float = float("nan")
    span_end_m: float = float("nan")       # at the end of the two-cone span
    first_pose_t: float = float("nan")     # the tracker's first pose after the outage

    @property
    def latency_s(self):
        return self.fused_t - self.two_t

    def line(self, k, t0=0.0):
        """One line per outage; times in seconds after t0 (the first frame)."""
        ids = lambda x: " ".join(str(i) for i in x) or "-"  # noqa: E731
        right = {None: "ids not checked", True: "ids right", False: "IDS WRONG"}[self.fused_ids_right]
        return (f"outage {k}: no cone in view {self.outage[0] - t0:.2f}-{self.outage[1] - t0:.2f} s "
                f"({self.outage[1] - self.outage[0]:.2f} s); two cones from {self.two_t - t0:.2f} s "
                f"(cones {ids(self.two_ids)}) to {self.two_end_t - t0:.2f} s, 3+ from {self.three_t - t0:.2f} s; "
                f"first fused camera update {self.fused_t - t0:.2f} s ({self.latency_s:+.2f} s after the first "
                f"two-cone frame; frame {self.fused_frame_t - t0:.2f} s, {self.fused_kind} of cones "
                f"{ids(self.fused_ids)}, {right}); position error before it {self.before_m:.3f} m, at it "
                f"{self.at_m:.3f} m, max 0.5-1.5 s after {self.after_max_m:.3f} m / {self.after_max_deg:.2f} deg, "
                f"at the two-cone span's end {self.span_end_m:.3f} m; first tracker pose {self.first_pose_t - t0:.2f} s")


def resolved(rec, min_px_full):
    """(frames, cones) bool: each cone whole in the true image and at least min_px_full tall (full res)."""
    valid, p, q = rec.truth.interpolate(rec.image_t)
    info = rec.camera_info
    K = np.reshape(info.K, (3, 3))
    w, h = float(info.width), float(info.height)
    c = visibility.to_camera(rec.cones.reshape(-1, 3), p, q).reshape(len(p), -1, 2, 3)
    z = np.where(c[..., 2] > visibility.MIN_DEPTH_M, c[..., 2], 1.0)
    u, v = K[0, 0] * c[..., 0] / z + K[0, 2], K[1, 1] * c[..., 1] / z + K[1, 2]
    inside = (c[..., 2] > visibility.MIN_DEPTH_M) & (u >= 0) & (u < w) & (v >= 0) & (v < h)
    tall = np.hypot(u[..., 0] - u[..., 1], v[..., 0] - v[..., 1]) >= min_px_full * w / visibility.FULL_WIDTH_PX
    return inside.all(axis=2) & tall & valid[:, None]


def ids_right(rec, obs: Observed) -> bool:
    """Whether every observed cone lies on the true projection of the cone it was given (pinhole K: the
    observations' pixels are undistorted)."""
    ok, p, q = rec.truth.interpolate([obs.t])
    if not ok[0]:
        return False
    K = np.reshape(rec.camera_info.K, (3, 3))
    for cone_id, peak, base in obs.cones:
        c = visibility.to_camera(rec.cones[cone_id], p, q)[0]  # peak, base
        if (c[:, 2] <= visibility.MIN_DEPTH_M).any():
            return False
        px = np.c_[K[0, 0] * c[:, 0] / c[:, 2] + K[0, 2], K[1, 1] * c[:, 1] / c[:, 2] + K[1, 2]]
        tol = max(4.0, 0.25 * np.linalg.norm(px[0] - px[1]))
        if np.linalg.norm(px[0] - peak) > tol or np.linalg.norm(px[1] - base) > tol:
            return False
    return True


def fused_times(ekf):
    """Stamps of the EKF samples whose largest position sigma fell from the sample before."""
    if ekf.cov is None or len(ekf.t) < 2:
        return np.zeros(0)
    s = np.sqrt(np.clip(np.diagonal(ekf.cov, axis1=1, axis2=2)[:, :3], 0.0, None).max(axis=1))
    return ekf.t[1:][s[1:] < (1.0 - SIGMA_DROP) * s[:-1]]


def _runs(mask):
    """(start, end) index pairs of the runs of True."""
    d = np.diff(np.r_[0, mask.astype(int), 0])
    return list(zip(np.nonzero(d == 1)[0], np.nonzero(d == -1)[0] - 1))


def analyse(rec, observations: Sequence[Observed], min_px_full=MIN_PX_FULL,
            min_outage_s=MIN_OUTAGE_S) -> List[Reacquisition]:
    ev = evaluation.evaluate(rec)
    ft = rec.image_t
    ok, p_t, q_t = rec.truth.interpolate(ft)
    in_view = visibility.cones_in_view(rec.cones, p_t, q_t, rec.camera_info)
    res = resolved(rec, min_px_full)
    n_res = res.sum(axis=1)
    fused = fused_times(rec.ekf)
    obs_t = np.array([o.t for o in observations])
    out = []
    for a, b in _runs((in_view == 0) & ok):
        if ft[b] - ft[a] < min_outage_s:
            continue
        r = Reacquisition((float(ft[a]), float(ft[b])))
        after = np.arange(b + 1, len(ft))
        two = after[n_res[after] >= 2]
        three = after[n_res[after] >= 3]
        r.three_t = float(ft[three[0]]) if len(three) else float("nan")
        if len(two) and (not len(three) or two[0] < three[0]):
            i = two[0]
            r.two_t, r.two_ids = float(ft[i]), tuple(int(k) for k in np.nonzero(res[i])[0])
            j = i
            while j + 1 < len(ft) and n_res[j + 1] == 2:
                j += 1
            r.two_end_t = float(ft[j])
        f = fused[fused > ft[b]]
        if len(f):
            r.fused_t = float(f[0])
            frames = [(t, "observations") for t in obs_t[obs_t <= r.fused_t]] + \
                [(t, "pose") for t in rec.tracker.t[rec.tracker.t <= r.fused_t]]
            if frames:
                r.fused_frame_t, r.fused_kind = max(frames)
                k = int(np.argmin(np.abs(obs_t - r.fused_frame_t))) if len(obs_t) else -1
                if k >= 0 and abs(obs_t[k] - r.fused_frame_t) < visibility.STAMP_TOLERANCE_S:
                    r.fused_ids = tuple(c[0] for c in observations[k].cones)
                    r.fused_ids_right = ids_right(rec, observations[k])
            e = ev.ekf
            before = np.nonzero(e.t < r.fused_t)[0]
            if len(before):
                r.before_m, r.before_deg = float(e.position_error_m[before[-1]]), float(e.orientation_error_deg[before[-1]])
            at = np.nonzero(e.t >= r.fused_t)[0]
            if len(at):
                r.at_m = float(e.position_error_m[at[0]])
            r.after_max_deg, r.after_max_m = ev.ekf_error_after(r.fused_t + 0.5, 1.0)
            if r.two_end_t == r.two_end_t:
                end = np.nonzero(e.t <= r.two_end_t)[0]
                r.span_end_m = float(e.position_error_m[end[-1]]) if len(end) else float("nan")
        poses = rec.tracker.t[rec.tracker.t > ft[b]]
        r.first_pose_t = float(poses[0]) if len(poses) else float("nan")
        out.append(r)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bags", nargs="+")
    ap.add_argument("--min-px-full", type=float, default=MIN_PX_FULL)
    ap.add_argument("--min-outage-s", type=float, default=MIN_OUTAGE_S)
    a = ap.parse_args()
    for path in a.bags:
        msgs = list(evaluation.bag_messages(path))
        rec = evaluation.recording_from_messages(msgs)
        if rec.cones is None or rec.camera_info is None:
            print(f"{path}: no rig_sim/cones or camera_info recorded", file=sys.stderr)
            return 1
        obs = observations_from_messages([m for t, m in msgs if t.lstrip("/") == "cone_tracker/observations"])
        found = analyse(rec, obs, a.min_px_full, a.min_outage_s)
        if not found:
            print(f"{path}: no outage of at least {a.min_outage_s} s")
        for k, r in enumerate(found, 1):
            print(r.line(k, rec.image_t[0]))
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""A recorded replay -> RunSummary, through ar_bringup's evaluation module.

ar_bringup.evaluation (the system tests use the same code) computes the errors against rig_sim's
ground truth, the EKF's 3σ, the overlay error, the periods, the rejection totals and the rates.
This module adds what a report over time needs and the evaluation keeps only as totals: when each
rejection happened (from each cone_tracker/detections message's reasons, and from every increase of
a rejection counter in /diagnostics), and the rate of the overlay images.
"""
import numpy as np
from ar_bringup import evaluation, visibility

from .summary import PoseErrors, RunSummary

OVERLAY = "ar_overlay/image"
DETECTIONS = "cone_tracker/detections"
MIN_VISIBLE_CONES = 3  # the tracker needs three cones for a pose
# ar_bringup.evaluation's rate names -> (topic shown, the rate the rig runs it at)
RATES = {"camera": ("camera/camera_info", 30.0), "imu": ("imu/data_raw", 100.0),
         "detections": (DETECTIONS, 30.0), "tracker_pose": ("cone_tracker/pose", 30.0),
         "ekf_pose": ("pose_ekf/pose", 100.0)}


def read_run(bag_path):
    """One pass over the run bag -> ((topic, message) pairs of evaluation.TOPICS, overlay image stamps)."""
    messages, overlay = [], []
    for topic, msg in evaluation.bag_messages(bag_path, evaluation.TOPICS + (OVERLAY,)):
        if topic.lstrip("/") == OVERLAY:
            overlay.append(msg.header.stamp.to_sec())
        else:
            messages.append((topic, msg))
    return messages, np.sort(overlay)


def rejection_events(messages, t0):
    """{name: times [s]} from the run's detections (per frame) and diagnostics (counter increases
    after the first message); messages: (topic, message) pairs in bag order."""
    events, last = {}, {}
    for topic, msg in messages:
        topic = topic.lstrip("/")
        if topic not in (DETECTIONS, "diagnostics"):
            continue
        t = msg.header.stamp.to_sec() - t0
        if topic == DETECTIONS:
            for reason in getattr(msg, "pose_rejected_by_names", []):
                events.setdefault("%s: %s" % (DETECTIONS, reason), []).append(t)
            continue
        for status in msg.status:
            for kv in status.values:
                if not evaluation.is_rejection_key(kv.key):
                    continue
                try:
                    count = int(float(kv.value))
                except ValueError:
                    continue
                name = "%s: %s" % (status.name, kv.key)
                # The first value is the baseline: a bag cut from a longer run starts mid-count.
                events.setdefault(name, []).extend([t] * max(0, count - last.get(name, count)))
                last[name] = count
    return {k: np.array(v) for k, v in events.items()}


def _errors(e, t0):
    if e is None or not len(e.t):
        return None
    rad = np.radians
    return PoseErrors(e.t - t0, e.pos_error_m, rad(e.rot_error_deg),
                      e.sigma3_pos_m, None if e.sigma3_rot_deg is None else rad(e.sigma3_rot_deg))


def summarize(run_bag, truth_bag=None, name=None, full_width_px=visibility.FULL_WIDTH_PX):
    """-> (RunSummary, t0): t0 is the stamp that the summary's times count from (the first truth).
    full_width_px: the camera's full-resolution width, for the overlay error by cones in view."""
    messages, frames = read_run(run_bag)
    rec = evaluation.recording_from_messages(messages)
    missing = [t for t, absent in (("rig_sim/ground_truth", not len(rec.truth)), ("rig_sim/cones", rec.cones is None))
               if absent]
    if missing and truth_bag:
        truth = evaluation.load_bag(truth_bag, topics=tuple(missing))
        rec.truth = truth.truth if len(truth.truth) else rec.truth
        rec.cones = truth.cones if truth.cones is not None else rec.cones
    summary = RunSummary()
    summary.name = name or (truth_bag or run_bag).rsplit("/", 1)[-1]
    if not len(rec.truth):
        summary.notes.append("no rig_sim/ground_truth in the bags: no errors against ground truth")
        return summary, 0.0
    ev = evaluation.evaluate(rec, min_visible_cones=MIN_VISIBLE_CONES, full_width_px=full_width_px)
    t0 = float(rec.truth.t[0])
    summary.duration_s = float(rec.truth.t[-1] - t0)
    summary.ekf = _errors(ev.ekf, t0)
    summary.tracker = _errors(ev.tracker, t0)
    if summary.ekf is None:
        summary.notes.append("no pose_ekf/pose messages were recorded")
    shift = lambda spans: [(a - t0, b - t0) for a, b in spans]  # noqa: E731
    summary.accepted = shift(ev.accepted_periods)
    summary.visible = shift(ev.visible_periods) if ev.visible_periods else summary.accepted
    if not ev.visible_periods:
        summary.notes.append("no %s with %d cones: the periods shown are those with tracker poses"
                             % (DETECTIONS, MIN_VISIBLE_CONES))
    summary.overlay_t_s, summary.overlay_err_px = ev.overlay_t - t0, ev.overlay_error_px
    summary.gates = rejection_events(messages, t0)
    summary.rejection_totals = dict(ev.rejections)
    summary.evaluation = dict(ev.summary)
    summary.rates = [(RATES[k][0], hz, RATES[k][1]) for k, hz in ev.rates_hz.items() if k in RATES]
    if frames.size > 1:
        summary.rates.append((OVERLAY, (frames.size - 1) / (frames[-1] - frames[0]), 30.0))
    if ev.view is None:
        summary.notes.append("no rig_sim/cones in the bags: no errors by the cones in the true view")
    else:
        summary.view_figures = ev.view.figures
        summary.view_full_width_px = ev.view.full_width_px
        summary.view_ekf_since_s = ev.view.ekf_since_s
        summary.view_frame_t_s = ev.view.frame_t - t0
        summary.view_frame_since_s = ev.view.frame_since_s
        summary.view_overlay_px = ev.view.overlay_px
        summary.view_centre_px = ev.view.centre_px
        if not rec.counts.get("cone_tracker/observations"):
            summary.notes.append("no cone_tracker/observations recorded: a frame counts as updating the filter "
                                 "only with a cone_tracker/pose")
    return summary, t0

"""The soak run shared by the soak test (test/soak_short.test) and the bench (ar_bringup_bench).

launch/sim.launch runs with probe:=true (ar_bringup/LatencyProbeNodelet in the manager writes its
counters, latencies and the manager's RSS as JSON every wall second) and sim_required:=false. When
the simulated time has advanced by the target, the simulator is stopped, its queued messages drain,
and this process keeps /clock moving so the nodelets' sim-time diagnostics report their final
counters. Then the counts are balanced per inter-nodelet topic:

  camera/image_raw   probe's images           == cone_tracker "frames"
  cone_tracker/pose  cone_tracker "poses published" == probe's tracker poses
                     == pose_ekf's camera outcomes (updates + dropped late + NaN/invalid rejected + numerical failures)
  imu/data_raw       imu_driver "samples" == probe's IMU messages
                     == pose_ekf's IMU outcomes (gyro updates + before the first pose + without tf + dropped late)

("dropped late" is shared by camera and IMU, so the two EKF balances are checked as one sum.)
"""
import json
import time

import numpy as np
import rosnode
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from rosgraph_msgs.msg import Clock


class Soak:
    def __init__(self, probe_file, sim_node="/rig_sim"):
        self.probe_file, self.sim_node = probe_file, sim_node
        self.status = {}  # status name -> {key: value}
        self.last_clock = None
        rospy.Subscriber("/diagnostics", DiagnosticArray, self._on_diag, queue_size=100)
        rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=10)

    def _on_diag(self, msg):
        for s in msg.status:
            self.status[s.name] = {kv.key: kv.value for kv in s.values}

    def _on_clock(self, msg):
        self.last_clock = msg.clock

    def probe(self):
        try:
            with open(self.probe_file) as f:
                return json.load(f)
        except (OSError, ValueError):
            return None

    def find_status(self, key):
        """The key/value pairs of the status that has this key (statuses are named after the manager)."""
        for values in self.status.values():
            if key in values:
                return values
        return {}

    def run(self, sim_seconds, timeout_s, log=print):
        """Waits for sim_seconds of simulated time, stops the simulator, returns the figures."""
        wall0 = time.monotonic()
        while self.last_clock is None and time.monotonic() - wall0 < 60.0 and not rospy.is_shutdown():
            time.sleep(0.1)
        if self.last_clock is None:
            raise RuntimeError("no /clock from the simulator within 60 s")
        t0 = self.last_clock.to_sec()
        next_log = 0.0
        while not rospy.is_shutdown():
            elapsed = self.last_clock.to_sec() - t0
            if elapsed >= sim_seconds or time.monotonic() - wall0 > timeout_s:
                break
            if time.monotonic() - wall0 > next_log:
                log("soak: %.0f / %.0f s simulated, %.0f s wall" % (elapsed, sim_seconds, time.monotonic() - wall0))
                next_log += 30.0
            time.sleep(0.2)
        wall_s = time.monotonic() - wall0
        sim_s = self.last_clock.to_sec() - t0
        rosnode.kill_nodes([self.sim_node])
        time.sleep(2.0)  # the queues drain
        # Keep sim time moving (the simulator was the clock) so the 1 Hz sim-time diagnostics report.
        pub = rospy.Publisher("/clock", Clock, queue_size=10)
        now = self.last_clock
        for _ in range(30):
            now = now + rospy.Duration(0.25)
            pub.publish(Clock(clock=now))
            time.sleep(0.1)
        time.sleep(1.5)  # the probe writes its file once a wall second
        return self.figures(sim_s, wall_s)

    def figures(self, sim_s, wall_s):
        probe = self.probe() or {}
        ekf = self.find_status("camera updates")
        trk = self.find_status("poses published")
        imu = self.find_status("samples missed")
        num = lambda d, k: float(d.get(k, "nan"))  # noqa: E731
        # Every camera pose ends in one of these (in cones mode a pose whose image's cones were fused is
        # not fused again, and one that re-acquires re-initialises the filter).
        ekf_camera = sum(num(ekf, k) for k in ("camera updates", "camera poses rejected (chi2 gate)", "NaN rejected",
                                                "invalid rejected", "numerical failures",
                                                "camera poses not fused (their frame's cones were)",
                                                "re-acquisitions from a camera pose (cones mode)"))
        ekf_imu = sum(num(ekf, k) for k in ("gyro updates", "IMU before the first pose",
                                             "IMU without camera-IMU tf"))
        out = {
            "sim_s": sim_s, "wall_s": wall_s, "speed": sim_s / max(wall_s, 1e-9),
            "images_probe": probe.get("images", float("nan")), "images_tracker": num(trk, "frames"),
            "poses_tracker": num(trk, "poses published"), "poses_probe": probe.get("tracker_poses", float("nan")),
            "imu_driver": num(imu, "samples"), "imu_probe": probe.get("imu", float("nan")),
            "imu_missed_on_serial": num(imu, "samples missed"),
            "ekf_inputs": ekf_camera + ekf_imu + num(ekf, "dropped late"),
            "ekf_dropped_late": num(ekf, "dropped late"), "ekf_nan_rejected": num(ekf, "NaN rejected"),
            "ekf_resets": num(ekf, "resets"),
            "ekf_nan_outputs": probe.get("ekf_nan", float("nan")), "ekf_outputs": probe.get("ekf_poses", 0),
            "latency_median_ms": probe.get("latency", {}).get("median_ms", float("nan")),
            "latency_p99_ms": probe.get("latency", {}).get("p99_ms", float("nan")),
            "latency_count": probe.get("latency", {}).get("count", 0),
            "tracker_latency_median_ms": probe.get("tracker_latency", {}).get("median_ms", float("nan")),
        }
        out["ekf_inputs_expected"] = out["poses_probe"] + out["imu_probe"]
        out.update(rss_figures(probe.get("rss_kb", [])))
        return out


def rss_figures(rss_kb, warmup_fraction=0.25):
    """RSS growth after the warm-up: mean of the last quarter minus mean of the first quarter after
    the warm-up (MB), and the least-squares slope over the post-warm-up samples (MB per hour; samples
    are 1 s of wall time apart)."""
    rss = np.array([r for r in rss_kb if r > 0], dtype=float) / 1024.0
    if len(rss) < 8:
        return {"rss_samples": len(rss), "rss_start_mb": float("nan"), "rss_end_mb": float("nan"),
                "rss_growth_mb": float("nan"), "rss_slope_mb_per_h": float("nan")}
    steady = rss[int(len(rss) * warmup_fraction):]
    q = max(1, len(steady) // 4)
    slope = np.polyfit(np.arange(len(steady)), steady, 1)[0] * 3600.0
    return {"rss_samples": len(rss), "rss_start_mb": float(steady[:q].mean()), "rss_end_mb": float(steady[-q:].mean()),
            "rss_growth_mb": float(steady[-q:].mean() - steady[:q].mean()), "rss_slope_mb_per_h": float(slope),
            "rss_max_mb": float(rss.max())}

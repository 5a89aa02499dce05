// End-to-end latency of the pipeline, ROS-free: a frame's arrival in the manager (t_image), the
// tracker's pose for that frame (matched by the image stamp), and the first cones -> camera_optical
// transform published after that pose whose stamp is not older than the frame: latency = t_tf - t_image.
// pose_ekf publishes tf whenever an update makes the newest state newer, so this is the first tf that
// can contain the frame's measurement. Times are steady-clock seconds; stamps are message stamps.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <vector>

namespace ar_bringup {

struct LatencyStats {
  size_t count = 0;
  double median_ms = 0.0;
  double p99_ms = 0.0;
  double max_ms = 0.0;
};

// Nearest-rank quantile (q in [0, 1]) of a copy of values; 0 for an empty set.
double Quantile(std::vector<double> values, double q);
LatencyStats Summarise(const std::vector<double>& values_ms);

class LatencyMatcher {
 public:
  // Frames without a pose or tf after max_pending frames are dropped (frames the tracker rejected).
  explicit LatencyMatcher(size_t max_pending = 300) : max_pending_(max_pending) {}

  void OnImage(int64_t stamp_ns, double arrival_s);
  void OnPose(int64_t stamp_ns, double arrival_s);
  void OnTf(int64_t stamp_ns, double arrival_s);

  const std::vector<double>& end_to_end_ms() const { return end_to_end_ms_; }
  const std::vector<double>& tracker_ms() const { return tracker_ms_; }
  size_t unmatched_poses() const { return unmatched_poses_; }

 private:
  struct Pending {
    double image_s = 0.0;
    double pose_s = -1.0;  // < 0: no pose yet
  };
  size_t max_pending_;
  std::map<int64_t, Pending> pending_;  // by image stamp
  std::vector<double> end_to_end_ms_, tracker_ms_;
  size_t unmatched_poses_ = 0;
};

}  // namespace ar_bringup

#include "ar_bringup/latency_matcher.h"

#include <algorithm>
#include <cmath>

namespace ar_bringup {

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  q = std::min(1.0, std::max(0.0, q));
  const size_t rank = static_cast<size_t>(std::ceil(q * values.size()));
  const size_t k = rank == 0 ? 0 : rank - 1;
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

LatencyStats Summarise(const std::vector<double>& values_ms) {
  LatencyStats s;
  s.count = values_ms.size();
  if (values_ms.empty()) return s;
  s.median_ms = Quantile(values_ms, 0.5);
  s.p99_ms = Quantile(values_ms, 0.99);
  s.max_ms = *std::max_element(values_ms.begin(), values_ms.end());
  return s;
}

void LatencyMatcher::OnImage(int64_t stamp_ns, double arrival_s) {
  pending_[stamp_ns] = Pending{arrival_s, -1.0};
  while (pending_.size() > max_pending_) pending_.erase(pending_.begin());
}

void LatencyMatcher::OnPose(int64_t stamp_ns, double arrival_s) {
  const auto it = pending_.find(stamp_ns);
  if (it == pending_.end() || it->second.pose_s >= 0.0) {
    ++unmatched_poses_;
    return;
  }
  it->second.pose_s = arrival_s;
  tracker_ms_.push_back(1e3 * (arrival_s - it->second.image_s));
}

void LatencyMatcher::OnTf(int64_t stamp_ns, double arrival_s) {
  // Every frame with a pose already seen and a stamp not newer than this tf is now in the estimate.
  for (auto it = pending_.begin(); it != pending_.end() && it->first <= stamp_ns;) {
    if (it->second.pose_s >= 0.0) {
      end_to_end_ms_.push_back(1e3 * (arrival_s - it->second.image_s));
      it = pending_.erase(it);
    } else {
      ++it;
    }
  }
}

}  // namespace ar_bringup

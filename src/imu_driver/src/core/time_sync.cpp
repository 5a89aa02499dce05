#include "imu_driver/core/time_sync.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace imu_driver {
namespace {
// Windows needed before the slope beats the jitter of a single minimum.
constexpr size_t kMinWindowsForFit = 3;

// Formats a reset reason. Only called on a reset: Update runs for every sample,
// and a stream per sample would allocate each time.
template <typename... Args>
std::string Reason(const Args&... args) {
  std::ostringstream s;
  (s << ... << args);
  return s.str();
}
}  // namespace

TimeSync::TimeSync(const TimeSyncConfig& config) : config_(config) {}

void TimeSync::Reset() {
  initialised_ = false;
  window_open_ = false;
  envelope_.clear();
  skew_ = 0.0;
  high_since_s_ = -1.0;
}

std::string TimeSync::TakeResetReason() {
  std::string r;
  r.swap(reset_reason_);
  return r;
}

void TimeSync::Start(double device_s, double observation_s) {
  Reset();
  initialised_ = true;
  last_device_s_ = device_s;
  offset_s_ = observation_s;
  AddToWindow(device_s, observation_s);
}

double TimeSync::Update(double device_s, double arrival_s) {
  const double observation_s = arrival_s - device_s;
  if (!std::isfinite(observation_s)) return arrival_s;
  if (!initialised_) {
    Start(device_s, observation_s);
    return device_s + offset_s_;
  }
  const double dt = device_s - last_device_s_;
  const double predicted = offset_s_ + skew_ * dt;
  std::string why;
  if (dt <= 0.0) {
    why = Reason("device time did not increase (", dt, " s)");
  } else if (observation_s < predicted - config_.jump_threshold_s) {
    why = Reason("arrival ", predicted - observation_s, " s earlier than the clock model");
  } else if (observation_s > predicted + config_.jump_threshold_s) {
    if (high_since_s_ < 0.0) high_since_s_ = device_s;
    if (device_s - high_since_s_ > config_.max_high_s) {
      why = Reason("arrivals later than the clock model by > ", config_.jump_threshold_s, " s for ", config_.max_high_s,
                   " s");
    }
  } else {
    high_since_s_ = -1.0;
  }
  if (!why.empty()) {
    reset_reason_ = std::move(why);
    ++resets_;
    Start(device_s, observation_s);
    return device_s + offset_s_;
  }
  // Until the skew is fitted, allow any plausible skew so the estimate cannot
  // lag far below the envelope of a fast-drifting clock.
  const double slack = (envelope_.size() < kMinWindowsForFit ? config_.max_skew_ppm : config_.slack_ppm) * 1e-6;
  const double rise_limited = offset_s_ + (skew_ + slack) * dt;
  offset_s_ = std::min(observation_s, rise_limited);
  last_device_s_ = device_s;
  AddToWindow(device_s, observation_s);
  return device_s + offset_s_;
}

void TimeSync::AddToWindow(double device_s, double observation_s) {
  if (window_open_ && device_s - window_start_s_ >= config_.window_s) {
    envelope_.push_back(window_min_);
    while (envelope_.size() > config_.num_windows) envelope_.pop_front();
    window_open_ = false;
    FitSkew();
  }
  if (!window_open_) {
    window_open_ = true;
    window_start_s_ = device_s;
    window_min_ = {device_s, observation_s};
  } else if (observation_s < window_min_.offset_s) {
    window_min_ = {device_s, observation_s};
  }
}

void TimeSync::FitSkew() {
  if (envelope_.size() < kMinWindowsForFit) return;
  double md = 0.0, mo = 0.0;
  for (const auto& p : envelope_) {
    md += p.device_s;
    mo += p.offset_s;
  }
  md /= envelope_.size();
  mo /= envelope_.size();
  double sdd = 0.0, sdo = 0.0;
  for (const auto& p : envelope_) {
    sdd += (p.device_s - md) * (p.device_s - md);
    sdo += (p.device_s - md) * (p.offset_s - mo);
  }
  if (sdd <= 0.0) return;
  const double limit = config_.max_skew_ppm * 1e-6;
  skew_ = std::clamp(sdo / sdd, -limit, limit);
}

}  // namespace imu_driver

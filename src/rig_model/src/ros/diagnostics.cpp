#include "rig_model/ros/diagnostics.h"

#include <algorithm>
#include <cmath>

namespace rig_model {

using diagnostic_msgs::DiagnosticStatus;

double RosWallNowS() { return ros::WallTime::now().toSec(); }

std::string CleanReason(const std::string& reason) {
  std::string out;
  size_t begin = 0;
  while (begin <= reason.size()) {
    size_t end = reason.find(';', begin);
    if (end == std::string::npos) end = reason.size();
    const size_t first = reason.find_first_not_of(" \t\r\n", begin);
    if (first != std::string::npos && first < end) {
      const size_t last = reason.find_last_not_of(" \t\r\n", end - 1);
      if (!out.empty()) out += "; ";
      out += reason.substr(first, last - first + 1);
    }
    begin = end + 1;
  }
  return out;
}

RateCheckConfig RateCheckConfig::Around(double expected_hz, double tolerance) {
  RateCheckConfig c;
  c.min_hz = expected_hz * (1.0 - tolerance);
  c.max_hz = expected_hz * (1.0 + tolerance);
  return c;
}

StampRateTask::StampRateTask(const std::string& name, const RateCheckConfig& config, WallClock wall_now)
    : DiagnosticTask(name), config_(config), wall_now_(std::move(wall_now)), created_wall_s_(wall_now_()) {}

void StampRateTask::Tick(double stamp_s) {
  const double now = wall_now_();
  std::lock_guard<std::mutex> lock(mutex_);
  ++messages_;
  last_arrival_wall_s_ = now;
  if (!(stamp_s > 0.0) || !std::isfinite(stamp_s)) {
    ++unstamped_;
    return;
  }
  if (stamp_s < newest_s_ - config_.jump_back_s) {  // a new time line: the old stamps say nothing about it
    ++jumps_back_;
    stamps_s_.clear();
    newest_s_ = -std::numeric_limits<double>::infinity();
  }
  stamps_s_.push_back(stamp_s);
  newest_s_ = std::max(newest_s_, stamp_s);
  while (!stamps_s_.empty() && stamps_s_.front() < newest_s_ - config_.window_s) stamps_s_.pop_front();
}

void StampRateTask::SetRateLimits(double min_hz, double max_hz) {
  std::lock_guard<std::mutex> lock(mutex_);
  config_.min_hz = min_hz;
  config_.max_hz = max_hz;
}

// Messages per stamp second over the window: (n - 1) intervals between the oldest and newest stamp.
double StampRateTask::RateLocked() const {
  if (stamps_s_.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  const auto [lo, hi] = std::minmax_element(stamps_s_.begin(), stamps_s_.end());
  const double span = *hi - *lo;
  return span > 0.0 ? double(stamps_s_.size() - 1) / span : std::numeric_limits<double>::quiet_NaN();
}

double StampRateTask::rate_hz() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return RateLocked();
}

uint64_t StampRateTask::jumps_back() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return jumps_back_;
}

void StampRateTask::run(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const double now = wall_now_();
  std::lock_guard<std::mutex> lock(mutex_);
  const double rate = RateLocked();
  const double silent_s = now - (messages_ ? last_arrival_wall_s_ : created_wall_s_);
  if (silent_s > config_.stale_after_s) {
    if (messages_)
      stat.summaryf(config_.stale_level, "no message for %.1f s (wall clock)", silent_s);
    else
      stat.summaryf(config_.stale_level, "no message yet, %.1f s after start (wall clock)", silent_s);
  } else if (!messages_) {
    stat.summary(DiagnosticStatus::WARN, "no message yet");
  } else if (unstamped_ == messages_) {
    stat.summary(DiagnosticStatus::WARN, "messages arrive but carry no stamp: no rate");
  } else if (std::isnan(rate)) {
    stat.summary(DiagnosticStatus::OK, "messages arrive; too few stamps in the window for a rate yet");
  } else if (rate < config_.min_hz) {
    stat.summaryf(DiagnosticStatus::WARN, "rate too low: %.2f Hz < %.2f Hz", rate, config_.min_hz);
  } else if (rate > config_.max_hz) {
    stat.summaryf(DiagnosticStatus::WARN, "rate too high: %.2f Hz > %.2f Hz", rate, config_.max_hz);
  } else {
    stat.summary(DiagnosticStatus::OK, "rate ok");
  }
  stat.addf("rate of stamps (Hz)", "%.3f", std::isnan(rate) ? 0.0 : rate);
  stat.add("rate measured", !std::isnan(rate));
  stat.addf("minimum acceptable rate (Hz)", "%.3f", config_.min_hz);
  if (std::isfinite(config_.max_hz)) stat.addf("maximum acceptable rate (Hz)", "%.3f", config_.max_hz);
  stat.add("stamps in window", stamps_s_.size());
  stat.addf("window (stamp s)", "%.1f", config_.window_s);
  stat.add("messages", messages_);
  stat.add("messages without a stamp", unstamped_);
  stat.add("stamp jumps back", jumps_back_);
  stat.addf("since last message (wall s)", "%.2f", messages_ ? now - last_arrival_wall_s_ : -1.0);
}

WallDiagnostics::WallDiagnostics(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& node_name,
                                 const std::string& hardware_id, double period_s)
    : updater_(nh, pnh, node_name), namespace_(pnh.getNamespace()) {
  updater_.setHardwareID(hardware_id);
  ros::NodeHandle timer_nh(nh);
  // ~diagnostic_period, as for diagnostic_updater's own timer (the Updater read it in its constructor).
  if (pnh.hasParam("diagnostic_period")) {
    if (updater_.getPeriod() > 0.0 && updater_.getPeriod() <= 60.0) {
      period_s = updater_.getPeriod();
    } else {  // the diagnostics themselves must run: keep the default, say why
      ROS_WARN("%s: parameter ~diagnostic_period must be in (0, 60] s (got %g); publishing every %g s",
               namespace_.c_str(), updater_.getPeriod(), period_s);
    }
  }
  timer_ = timer_nh.createWallTimer(ros::WallDuration(period_s), [this](const ros::WallTimerEvent&) {
    try {
      updater_.force_update();
    } catch (const std::exception& e) {  // a task that throws must not take the nodelet manager down
      ROS_ERROR_THROTTLE(5.0, "%s: diagnostics not published: %s", namespace_.c_str(), e.what());
    }
  });
}

void WallDiagnostics::Add(const std::string& name,
                          std::function<void(diagnostic_updater::DiagnosticStatusWrapper&)> fn) {
  task_names_.push_back(name);
  updater_.add(name, std::move(fn));
}

void WallDiagnostics::Add(diagnostic_updater::DiagnosticTask& task) {
  task_names_.push_back(task.getName());
  updater_.add(task);
}

std::string WallDiagnostics::RefuseConfig(const std::string& task_name, const std::string& what,
                                          const std::string& reason) {
  const std::string message = what + " not started: " + CleanReason(reason);
  for (const std::string& n : task_names_) updater_.removeByName(n);
  task_names_ = {task_name};
  const std::string ns = namespace_;
  updater_.add(task_name, [message, ns](diagnostic_updater::DiagnosticStatusWrapper& stat) {
    stat.summary(DiagnosticStatus::ERROR, message);
    stat.add("parameter namespace", ns);
  });
  updater_.force_update();
  return message;
}

}  // namespace rig_model

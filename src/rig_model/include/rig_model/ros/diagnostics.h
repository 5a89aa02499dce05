// Diagnostics that never go stale: one driver and one rate check for every component.
//
// WallDiagnostics publishes /diagnostics on a ros::WallTimer. diagnostic_updater::Updater alone
// does not fit: Updater::update() publishes only once ros::Time::now() reaches next_time_, which
// force_update() set to "now + period" on the old time line. After sim time jumps back (rosbag play
// --loop, a simulator reset) next_time_ lies in the future by the size of the jump, so update()
// returns without publishing until sim time climbs past it again; an 8 s bag looping every ~8 s
// never gets there, and the last message, counters and all, stays frozen. (roscpp's ros::Timer does
// re-arm after the jump; it is the Updater's own rate limit that blocks.) The driver calls
// force_update() from a wall timer instead, which publishes whatever ROS time does, also while sim
// time is paused or before the first /clock.
//
// StampRateTask replaces diagnostic_updater::FrequencyStatus, whose window is measured in
// ros::Time::now(): under sim time it starts at 0 before /clock arrives (a 1.7e9 s window, "actual
// frequency 0.000000"), and after a jump back its windows are negative. StampRateTask measures the
// rate of the message stamps instead: on the rig the stamps are the sensor's own clock, under
// `rosbag play --clock` they are the recorded ones, so the figure is the sensor's rate whatever the
// playback rate (-r 0.5 does not halve it) and is never 0.0 while messages flow. A stamp earlier
// than the newest by more than jump_back_s starts a new time line (the window is cleared and the
// jump counted). Whether messages still arrive is a separate question answered in wall time, the
// clock that keeps running when an input dies: no message for stale_after_s wall seconds raises
// stale_level.
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>

#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

namespace rig_model {

// Seconds on a monotonic-enough wall clock; tests inject their own.
using WallClock = std::function<double()>;
double RosWallNowS();

// A refusal message made fit for one line: "a must be > 0; b must be set; " (validators that append
// "; " after each problem) becomes "a must be > 0; b must be set". Empty clauses are dropped.
std::string CleanReason(const std::string& reason);

struct RateCheckConfig {
  double min_hz = 0.0;                                         // below: WARN "rate too low"
  double max_hz = std::numeric_limits<double>::infinity();     // above: WARN "rate too high"
  double window_s = 5.0;                                       // stamp seconds the rate is measured over
  double stale_after_s = 2.0;                                  // wall seconds without a message
  int stale_level = diagnostic_msgs::DiagnosticStatus::ERROR;  // level when stale (WARN for optional inputs)
  double jump_back_s = 0.5;                                    // stamp going back by more: a new time line

  // expected_hz * (1 -/+ tolerance).
  static RateCheckConfig Around(double expected_hz, double tolerance);
};

class StampRateTask : public diagnostic_updater::DiagnosticTask {
 public:
  StampRateTask(const std::string& name, const RateCheckConfig& config, WallClock wall_now = RosWallNowS);

  // One message; thread-safe (drivers tick from their I/O threads). A zero stamp is counted as
  // unstamped and does not enter the rate.
  void Tick(const ros::Time& stamp) { Tick(stamp.isZero() ? 0.0 : stamp.toSec()); }
  void Tick(double stamp_s);
  void SetRateLimits(double min_hz, double max_hz);  // e.g. after dynamic_reconfigure changed the rate

  void run(diagnostic_updater::DiagnosticStatusWrapper& stat) override;

  // For tests and callers that want the figure: messages per stamp second, NaN if unknown.
  double rate_hz() const;
  uint64_t jumps_back() const;

 private:
  double RateLocked() const;

  mutable std::mutex mutex_;
  RateCheckConfig config_;
  WallClock wall_now_;
  double created_wall_s_;
  std::deque<double> stamps_s_;  // arrival order, the current time line only
  double newest_s_ = -std::numeric_limits<double>::infinity();
  double last_arrival_wall_s_ = -1.0;
  uint64_t messages_ = 0, unstamped_ = 0, jumps_back_ = 0;
};

// The Updater of one component, published on a wall-clock timer (see the top of this file).
// Construct it first in onInit(), before the configuration is read, so a refusal is published.
class WallDiagnostics {
 public:
  // node_name prefixes every status ("pose_ekf: filter"); pass the nodelet's getName(). The timer
  // runs on nh's callback queue, with the component's other callbacks.
  WallDiagnostics(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& node_name,
                  const std::string& hardware_id, double period_s = 1.0);  // ~diagnostic_period, if set, wins

  // Tasks go through these (not the Updater) so that RefuseConfig can drop them.
  void Add(const std::string& name, std::function<void(diagnostic_updater::DiagnosticStatusWrapper&)> fn);
  void Add(diagnostic_updater::DiagnosticTask& task);

  // The component refused its configuration and did not start: from now on its status task_name
  // is ERROR "<what> not started: <reason>" (reason cleaned by CleanReason; it names the parameter
  // or file), with pnh's namespace beside it, and every other task is dropped. Returns the message
  // for the log line.
  std::string RefuseConfig(const std::string& task_name, const std::string& what, const std::string& reason);

  void SetHardwareID(const std::string& hardware_id) { updater_.setHardwareID(hardware_id); }
  void Publish() { updater_.force_update(); }

 private:
  diagnostic_updater::Updater updater_;
  std::vector<std::string> task_names_;
  std::string namespace_;
  ros::WallTimer timer_;
};

}  // namespace rig_model

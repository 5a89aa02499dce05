// Host timestamps for IMU samples without the host's arrival jitter.
//
// Method (a one-way minimum-delay clock model, the idea behind the convex-hull
// and "bounded offset" time translators used by many ROS drivers):
//   * The IMU's own clock is its sample counter: device time d_k = k * period,
//     with k the unwrapped sequence number (gaps included).
//   * Each packet gives an observation o_k = a_k - d_k, where a_k is the host
//     time the packet's first byte left the IMU: the read() time of its last
//     byte minus the transmission time bytes * 10 / baud (8N1: 10 bits a byte).
//     o_k = offset(d_k) + delay_k with delay_k >= 0 (USB/serial latency and
//     scheduling), so the true offset lies *below* every observation.
//   * The offset is a slowly drifting line (the two crystals' skew). Its
//     estimate follows the lower envelope of the observations:
//         offset_k = min(o_k, offset_{k-1} + (skew + slack) * (d_k - d_{k-1}))
//     It snaps down at once to any observation with less delay, and between
//     such observations rises only at the estimated skew plus a small slack.
//   * The skew is the least-squares slope through the per-window minima of o
//     (windows of window_s of device time, the last num_windows of them):
//     each window's minimum is a low-delay sample, so the slope is not biased
//     by the jitter.
//   * stamp_k = d_k + offset_k. A delayed packet is stamped where the clock
//     model says it was sampled, not when it arrived.
// Resets (with a reason the caller logs once): device time not increasing,
// an observation far below the model (host clock jumped back, IMU restarted),
// or observations far above the model for longer than max_high_s (host clock
// jumped forward).
#pragma once

#include <cstddef>
#include <deque>
#include <string>

namespace imu_driver {

struct TimeSyncConfig {
  double slack_ppm = 20.0;        // allowed rise beyond the estimated skew
  double window_s = 1.0;          // device-time window for one envelope point
  size_t num_windows = 30;        // envelope points in the skew fit
  double max_skew_ppm = 1000.0;   // fitted skews beyond this are clamped
  double jump_threshold_s = 0.1;  // |o - model| beyond this is a clock jump candidate
  double max_high_s = 2.0;        // how long o may stay above model + threshold
};

class TimeSync {
 public:
  explicit TimeSync(const TimeSyncConfig& config = TimeSyncConfig());

  // Returns the smoothed host stamp for a sample with device time device_s whose
  // first byte left the IMU at host time arrival_s (already delay-corrected).
  double Update(double device_s, double arrival_s);

  void Reset();
  // Non-empty once after a reset caused by the data (then cleared by this call).
  std::string TakeResetReason();
  size_t resets() const { return resets_; }
  double skew_ppm() const { return skew_ * 1e6; }
  bool initialised() const { return initialised_; }

 private:
  struct EnvelopePoint {
    double device_s;
    double offset_s;
  };
  void Start(double device_s, double observation_s);
  void AddToWindow(double device_s, double observation_s);
  void FitSkew();

  TimeSyncConfig config_;
  bool initialised_ = false;
  double last_device_s_ = 0.0;
  double offset_s_ = 0.0;
  double skew_ = 0.0;  // d(offset)/d(device time)
  double high_since_s_ = -1.0;
  bool window_open_ = false;
  double window_start_s_ = 0.0;
  EnvelopePoint window_min_{0.0, 0.0};
  std::deque<EnvelopePoint> envelope_;
  size_t resets_ = 0;
  std::string reset_reason_;
};

}  // namespace imu_driver

// Synthetic arrival times for the clock model: a 100 Hz IMU with a skewed
// crystal, read by a host with random latency. Shared by the test and the bench.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "imu_driver/core/time_sync.h"

namespace imu_driver {
namespace test {

struct JitterScenario {
  double skew_ppm = 50.0;  // IMU clock rate error
  double seconds = 120.0;
  double rate_hz = 100.0;
  double mean_latency_s = 1e-3;  // exponential scheduling/USB latency
  double stall_probability = 0.01;
  double stall_s = 0.02;  // occasional long stalls (bursts)
  unsigned seed = 3;
};

struct JitterResult {
  double raw_std_s = 0, raw_max_abs_s = 0;  // arrival - true sample time, mean removed
  double smoothed_std_s = 0, smoothed_max_abs_s = 0;
  double final_skew_ppm = 0;
  size_t resets = 0;
};

inline void MeanStdMax(std::vector<double> e, double* std_s, double* max_abs_s) {
  double m = 0;
  for (double x : e) m += x;
  m /= e.size();
  double v = 0, mx = 0;
  for (double x : e) {
    v += (x - m) * (x - m);
    mx = std::max(mx, std::abs(x - m));
  }
  *std_s = std::sqrt(v / e.size());
  *max_abs_s = mx;
}

inline JitterResult RunJitterScenario(const JitterScenario& sc) {
  std::mt19937 rng(sc.seed);
  std::exponential_distribution<double> latency(1.0 / sc.mean_latency_s);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  TimeSync ts;
  std::vector<double> raw_err, smooth_err;
  const int n = static_cast<int>(sc.seconds * sc.rate_hz);
  double stall_until = -1.0;
  for (int k = 0; k < n; ++k) {
    const double device_s = k / sc.rate_hz;
    const double true_host_s = 1000.0 + device_s * (1.0 + sc.skew_ppm * 1e-6);  // sample time on the host clock
    double arrival = true_host_s + latency(rng);
    if (u(rng) < sc.stall_probability) stall_until = true_host_s + sc.stall_s;
    arrival = std::max(arrival, stall_until);  // bytes queue up during a stall
    const double stamp = ts.Update(device_s, arrival);
    if (k < 5 * sc.rate_hz) continue;  // let the skew fit settle before measuring
    raw_err.push_back(arrival - true_host_s);
    smooth_err.push_back(stamp - true_host_s);
  }
  JitterResult r;
  MeanStdMax(raw_err, &r.raw_std_s, &r.raw_max_abs_s);
  MeanStdMax(smooth_err, &r.smoothed_std_s, &r.smoothed_max_abs_s);
  r.final_skew_ppm = ts.skew_ppm();
  r.resets = ts.resets();
  return r;
}

}  // namespace test
}  // namespace imu_driver

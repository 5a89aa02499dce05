// What pose_ekf's benches share: the median, a wall-clock timer in microseconds and the BENCH line.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

namespace pose_ekf_bench {

inline double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

template <typename Fn>
double TimeUs(const Fn& fn) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  fn();
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}

inline void Print(const char* name, double value, const char* unit) {
  std::printf("BENCH pose_ekf.%s %.3f %s\n", name, value, unit);
}

}  // namespace pose_ekf_bench

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "imu_driver/core/time_sync.h"
#include "imu_driver/testing/jitter_sim.h"

namespace imu_driver {
namespace {

TEST(TimeSync, FirstSampleUsesArrival) {
  TimeSync ts;
  EXPECT_DOUBLE_EQ(ts.Update(0.0, 100.0), 100.0);
  // Before the skew is fitted the estimate may rise at max_skew_ppm, no faster.
  EXPECT_DOUBLE_EQ(ts.Update(0.01, 100.0105), 100.01 + 1000e-6 * 0.01);
  EXPECT_DOUBLE_EQ(ts.Update(0.02, 100.0199), 100.0199);  // snaps down
}

TEST(TimeSync, JitterIsRemovedAndSkewTracked) {
  for (double skew_ppm : {-80.0, 0.0, 150.0}) {
    test::JitterScenario sc;
    sc.skew_ppm = skew_ppm;
    const test::JitterResult r = test::RunJitterScenario(sc);
    std::printf("skew %+.0f ppm: raw std %.1f us max %.1f us -> smoothed std %.1f us max %.1f us, skew est %.1f ppm\n",
                skew_ppm, r.raw_std_s * 1e6, r.raw_max_abs_s * 1e6, r.smoothed_std_s * 1e6, r.smoothed_max_abs_s * 1e6,
                r.final_skew_ppm);
    // Raw arrivals carry the full latency jitter (exponential, mean 1 ms, plus
    // 20 ms stalls); the model keeps the stamps within tens of microseconds.
    EXPECT_GT(r.raw_std_s, 1e-3) << skew_ppm;
    EXPECT_LT(r.smoothed_std_s, r.raw_std_s / 100.0) << skew_ppm;
    EXPECT_LT(r.smoothed_max_abs_s, 0.1e-3) << skew_ppm;
    EXPECT_NEAR(r.final_skew_ppm, skew_ppm, 5.0);
    EXPECT_EQ(r.resets, 0u);
  }
}

TEST(TimeSync, HostClockJumpsResetOnce) {
  TimeSync ts;
  double stamp = 0;
  for (int k = 0; k < 500; ++k) stamp = ts.Update(k * 0.01, 1000.0 + k * 0.01 + 0.001);
  EXPECT_NEAR(stamp, 1004.99 + 0.001, 1e-4);
  stamp = ts.Update(5.0, 900.0);  // host clock went back by 100 s
  EXPECT_EQ(ts.resets(), 1u);
  EXPECT_FALSE(ts.TakeResetReason().empty());
  EXPECT_TRUE(ts.TakeResetReason().empty());
  EXPECT_DOUBLE_EQ(stamp, 900.0);
  // Forward jump: a short stall is not a jump, a lasting one is.
  for (int k = 1; k <= 100; ++k) ts.Update(5.0 + k * 0.01, 900.0 + k * 0.01 + 0.15);
  EXPECT_EQ(ts.resets(), 1u);
  for (int k = 101; k <= 400; ++k) stamp = ts.Update(5.0 + k * 0.01, 900.0 + k * 0.01 + 0.15);
  EXPECT_EQ(ts.resets(), 2u);
  EXPECT_NEAR(stamp, 904.0 + 0.15, 1e-3);
}

TEST(TimeSync, NonIncreasingDeviceTimeResets) {
  TimeSync ts;
  ts.Update(1.0, 5.0);
  ts.Update(1.01, 5.01);
  ts.Update(0.5, 6.0);
  EXPECT_EQ(ts.resets(), 1u);
}

}  // namespace
}  // namespace imu_driver

// Camera-free tests: pixel formats, settings validation, timestamp mapping.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "aravis_camera/core/camera_config.h"
#include "aravis_camera/core/pixel_format.h"
#include "aravis_camera/core/timestamp_mapper.h"

namespace aravis_camera {
namespace {

TEST(PixelFormat, EncodingsMatchRos) {
  EXPECT_EQ(EncodingForPixelFormat("RGB8"), "rgb8");
  EXPECT_EQ(EncodingForPixelFormat("BayerRG8"), "bayer_rggb8");
  EXPECT_EQ(EncodingForPixelFormat("BayerGR8"), "bayer_grbg8");
  EXPECT_EQ(EncodingForPixelFormat("BayerGB8"), "bayer_gbrg8");
  EXPECT_EQ(EncodingForPixelFormat("BayerBG8"), "bayer_bggr8");
  EXPECT_EQ(EncodingForPixelFormat("Mono8"), "mono8");
  EXPECT_EQ(EncodingForPixelFormat("Mono16"), "");  // not supported: refused at start
  EXPECT_EQ(BytesPerPixel("RGB8"), 3);
  EXPECT_EQ(BytesPerPixel("BayerRG8"), 1);
}

TEST(Config, DefaultsAreValid) { EXPECT_EQ(Validate(CameraConfig{}), ""); }

TEST(Config, BadValuesNameTheParameter) {
  CameraConfig c;
  c.pixel_format = "YUV422";
  EXPECT_NE(Validate(c).find("~pixel_format"), std::string::npos);
  c = CameraConfig{};
  c.frame_rate_hz = 0.0;
  EXPECT_NE(Validate(c).find("~frame_rate"), std::string::npos);
  c = CameraConfig{};
  c.exposure_us = std::nan("");
  EXPECT_NE(Validate(c).find("~exposure"), std::string::npos);
  c = CameraConfig{};
  c.n_buffers = 1;
  EXPECT_NE(Validate(c).find("~n_buffers"), std::string::npos);
  c = CameraConfig{};
  c.packet_size_bytes = 100;
  EXPECT_NE(Validate(c).find("~packet_size"), std::string::npos);
}

double StdDev(const std::vector<double>& v) {
  double mean = 0.0, var = 0.0;
  for (double x : v) mean += x / v.size();
  for (double x : v) var += (x - mean) * (x - mean) / (v.size() - 1);
  return std::sqrt(var);
}

// Frames every 33.3 ms on the device clock; the host sees them after 2 ms plus
// exponential jitter (mean 0.5 ms), on a clock 1000 s away.
TEST(TimestampMapper, RemovesArrivalJitter) {
  std::mt19937 rng(3);
  std::exponential_distribution<double> jitter_ms(2.0);
  TimestampMapper mapper;
  std::vector<double> host_period_err_ms, mapped_period_err_ms;
  int64_t prev_host = 0, prev_mapped = 0;
  const int64_t period_ns = 33'333'333;
  for (int k = 0; k < 3000; ++k) {
    const uint64_t device = 5'000'000'000ULL + k * period_ns;
    const int64_t host =
        static_cast<int64_t>(device) + 1'000'000'000'000LL + 2'000'000 + static_cast<int64_t>(jitter_ms(rng) * 1e6);
    const int64_t mapped = mapper.Map(device, host);
    if (k > 100) {
      host_period_err_ms.push_back((host - prev_host - period_ns) * 1e-6);
      mapped_period_err_ms.push_back((mapped - prev_mapped - period_ns) * 1e-6);
      // On the host clock, late by the window's smallest delay: 2 ms plus the least jitter.
      EXPECT_NEAR((mapped - static_cast<int64_t>(device) - 1'000'000'000'000LL) * 1e-6, 2.0, 0.15);
    }
    prev_host = host;
    prev_mapped = mapped;
  }
  const double host_jitter = StdDev(host_period_err_ms), mapped_jitter = StdDev(mapped_period_err_ms);
  EXPECT_GT(host_jitter, 0.5);  // ~0.7 ms: the arrival jitter
  EXPECT_LT(mapped_jitter, 0.05 * host_jitter);
  EXPECT_EQ(mapper.resets(), 0u);
}

TEST(TimestampMapper, ResetsWhenTheCameraClockJumps) {
  TimestampMapper mapper;
  int64_t host = 1'000'000'000'000LL;
  for (int k = 0; k < 10; ++k) mapper.Map(1'000'000'000ULL + k * 33'000'000ULL, host += 33'000'000);
  // The camera rebooted: its clock starts again near zero.
  const int64_t mapped = mapper.Map(1'000'000ULL, host += 33'000'000);
  EXPECT_EQ(mapper.resets(), 1u);
  EXPECT_EQ(mapped, host);  // a fresh window: the only sample defines the offset
}

}  // namespace
}  // namespace aravis_camera

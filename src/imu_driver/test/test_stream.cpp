#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "imu_driver/core/crista_stream.h"
#include "imu_driver/testing/packet_gen.h"

namespace imu_driver {
namespace {

struct StreamCollector {
  std::vector<ImuSample> samples;
  CristaStream stream;
  explicit StreamCollector(const StreamConfig& c = StreamConfig())
      : stream(c, [this](const ImuSample& s) { samples.push_back(s); }) {}
};

std::vector<uint8_t> Frame(uint8_t seq, int16_t gx = 0) {
  HighSpeedRaw r;
  r.sequence = seq;
  r.gyro_counts[0] = gx;
  return EncodeHighSpeedFrame(r);
}

TEST(Stream, TransmissionDelayCorrection) {
  StreamCollector c;
  std::vector<uint8_t> bytes = Frame(0);
  const auto second = Frame(1);
  bytes.insert(bytes.end(), second.begin(), second.end());
  bytes.push_back(0x00);  // one garbage byte after the frames, in the same read
  c.stream.Feed(bytes.data(), bytes.size(), 10.0);
  ASSERT_EQ(c.samples.size(), 2u);
  const double byte_s = 10.0 / 115200.0;
  EXPECT_NEAR(c.samples[0].arrival_s, 10.0 - (1 + 24 + 24) * byte_s, 1e-12);
  EXPECT_NEAR(c.samples[1].arrival_s, 10.0 - (1 + 24) * byte_s, 1e-12);
}

TEST(Stream, SequenceGapsAndWrap) {
  StreamCollector c;
  double t = 0.0;
  auto feed = [&](uint8_t seq, double dt) {
    t += dt;
    const auto f = Frame(seq);
    c.stream.Feed(f.data(), f.size(), t);
  };
  feed(250, 0.0);
  for (uint8_t s : {251, 252, 253, 254, 255, 0, 1}) feed(s, 0.01);  // wrap, no gap
  EXPECT_EQ(c.stream.counts().sequence_gaps, 0u);
  feed(4, 0.03);  // 2 and 3 missing
  EXPECT_EQ(c.stream.counts().sequence_gaps, 1u);
  EXPECT_EQ(c.stream.counts().samples_missed, 2u);
  feed(4, 0.0);  // repeated
  EXPECT_EQ(c.stream.counts().sequence_repeats, 1u);
  feed(5, 0.01 + 2.56);  // an outage of exactly one wrap: the host clock reveals it
  EXPECT_EQ(c.stream.counts().sequence_gaps, 2u);
  EXPECT_EQ(c.stream.counts().samples_missed, 2u + 256u);
  EXPECT_EQ(c.samples.back().device_ticks, 11u + 256u);
}

// Sim time starts at 0 and then jumps to the bag's epoch; a bag loop steps it
// back. Neither is an outage: no samples may be counted missed.
TEST(Stream, HostClockJumpIsNotAnOutage) {
  StreamCollector c;
  auto feed = [&](uint8_t seq, double t) {
    const auto f = Frame(seq);
    c.stream.Feed(f.data(), f.size(), t);
  };
  feed(7, 0.0);
  feed(8, 1.7e9);  // /clock arrives
  feed(9, 1.7e9 + 0.01);
  feed(10, 1.7e9 - 30);  // loop back
  feed(11, 1.7e9 - 29.99);
  EXPECT_EQ(c.stream.counts().samples_missed, 0u);
  EXPECT_EQ(c.stream.counts().sequence_gaps, 0u);
  EXPECT_EQ(c.stream.counts().host_clock_jumps, 2u);
  EXPECT_EQ(c.samples.back().device_ticks - c.samples.front().device_ticks, 4u);
}

TEST(Stream, ScriptedFuzzGapsMatchDroppedFrames) {
  std::mt19937 rng(5);
  const test::ScriptedStream s = test::MakeScriptedStream(rng, 2000);
  StreamCollector c;
  c.stream.Feed(s.bytes.data(), s.bytes.size(), 1.0);
  ASSERT_EQ(c.samples.size(), s.valid.size());
  uint64_t gaps = 0, missed = 0;
  for (size_t i = 1; i < s.valid.size(); ++i) {
    const int d = static_cast<uint8_t>(s.valid[i].sequence - s.valid[i - 1].sequence);
    if (d > 1) {
      ++gaps;
      missed += d - 1;
    }
  }
  EXPECT_GT(gaps, 100u);
  EXPECT_EQ(c.stream.counts().sequence_gaps, gaps);
  EXPECT_EQ(c.stream.counts().samples_missed, missed);
  for (size_t i = 0; i < s.valid.size(); ++i) {
    const ImuSampleSi want = ToSi(s.valid[i]);
    ASSERT_EQ(c.samples[i].si.omega_imu_rad_s, want.omega_imu_rad_s);
    ASSERT_EQ(c.samples[i].si.accel_imu_m_s2, want.accel_imu_m_s2);
  }
}

TEST(Stream, ReconnectKeepsDeviceTimeIncreasing) {
  StreamCollector c;
  auto f = Frame(10);
  c.stream.Feed(f.data(), f.size(), 1.0);
  f = Frame(11);
  c.stream.Feed(f.data(), f.size(), 1.01);
  c.stream.EndOfStream();
  f = Frame(0);  // the IMU restarted its counter
  c.stream.Feed(f.data(), f.size(), 3.01);
  ASSERT_EQ(c.samples.size(), 3u);
  EXPECT_EQ(c.samples[2].device_ticks, 1u + 200u);
  EXPECT_EQ(c.stream.time_sync().resets(), 0u);
  EXPECT_NEAR(c.samples[2].stamp_s, c.samples[2].arrival_s, 1e-3);
}

// An IMU whose real rate is 0.5 % off the nominal 100 Hz (5000 ppm, beyond any
// crystal skew the model accepts): the sequence clock cannot follow it, the
// PPS clock can.
TEST(Stream, PpsTimeSourceFollowsTheImuClock) {
  for (auto source : {StreamConfig::TimeSource::kSequence, StreamConfig::TimeSource::kPps}) {
    StreamConfig cfg;
    cfg.time_source = source;
    StreamCollector c(cfg);
    std::mt19937 rng(3);
    std::exponential_distribution<double> latency(1000.0);
    std::vector<double> truth;
    const double period_s = 1.0 / 99.5;
    for (int k = 0; k < 99.5 * 300; ++k) {  // 300 s: the PPS count wraps once
      const double t = k * period_s;
      HighSpeedRaw r;
      r.sequence = static_cast<uint8_t>(k);
      r.pps_count = static_cast<uint8_t>(static_cast<int>(t));
      r.time_since_pps_100us = static_cast<uint32_t>(std::lround((t - std::floor(t)) * 1e4));
      const auto f = EncodeHighSpeedFrame(r);
      truth.push_back(100.0 + t);
      c.stream.Feed(f.data(), f.size(), 100.0 + t + 24 * 10.0 / 115200 + latency(rng));
    }
    double worst = 0.0;
    for (size_t i = 1000; i < truth.size(); ++i) worst = std::max(worst, std::abs(c.samples[i].stamp_s - truth[i]));
    if (source == StreamConfig::TimeSource::kPps) {
      EXPECT_EQ(c.stream.time_sync().resets(), 0u);
      EXPECT_LT(worst, 2e-4);  // the 100 us resolution of the PPS field, plus the model
    } else {
      EXPECT_GT(c.stream.time_sync().resets(), 0u);  // the mismatch is detected, not hidden
    }
  }
}

TEST(Stream, ConfigurationRepliesAreDecodedAndChecked) {
  StreamCollector c;
  const auto settings = EncodeSettingsPayload(100.0, 20);
  const auto res = EncodeResolutionPayload(300.0f, 10.0f);
  const uint8_t version[8] = {2, 1, 7, 0, 5, 12, 0x07, 0xD6};
  const uint8_t timing[8] = {0, 0, 0, 5, 1, 2, 0xFF, 0xFE};
  std::vector<uint8_t> bytes;
  for (const auto& f : {EncodeFrame(0x08, settings.data(), settings.size()), EncodeFrame(0x04, res.data(), res.size()),
                        EncodeFrame(0x0B, version, 8), EncodeFrame(0x03, timing, 8)}) {
    bytes.insert(bytes.end(), f.begin(), f.end());
  }
  c.stream.Feed(bytes.data(), bytes.size(), 1.0);
  const DeviceInfo& d = c.stream.counts().device;
  EXPECT_TRUE(c.samples.empty());
  EXPECT_DOUBLE_EQ(d.output_rate_hz, 100.0);
  EXPECT_EQ(d.oversample_ratio, 20);
  EXPECT_DOUBLE_EQ(d.gyro_range_deg_s, 300.0);
  EXPECT_DOUBLE_EQ(d.accel_range_g, 10.0);
  EXPECT_EQ(d.software_version, "2.1.7");
  EXPECT_EQ(d.clock_error, -2);
  EXPECT_EQ(c.stream.counts().frames_by_type[0x03], 1u);
  EXPECT_EQ(CheckDeviceInfo(d, 100.0), "");
  EXPECT_NE(CheckDeviceInfo(d, 50.0).find("100 Hz"), std::string::npos);
  DeviceInfo other = d;
  other.gyro_range_deg_s = 1200.0;
  EXPECT_NE(CheckDeviceInfo(other, 100.0).find("1200"), std::string::npos);
}

}  // namespace
}  // namespace imu_driver

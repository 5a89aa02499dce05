#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "imu_driver/core/crista_protocol.h"

namespace imu_driver {
namespace {

// Bitwise CRC-16/ARC, the textbook definition the nibble table must match.
uint16_t Crc16Bitwise(const uint8_t* d, size_t n) {
  uint16_t crc = 0;
  for (size_t i = 0; i < n; ++i) {
    crc ^= d[i];
    for (int b = 0; b < 8; ++b) crc = (crc & 1) ? static_cast<uint16_t>((crc >> 1) ^ 0xA001) : (crc >> 1);
  }
  return crc;
}

TEST(Crc16, StandardCheckValue) {
  const std::string s = "123456789";
  EXPECT_EQ(Crc16(reinterpret_cast<const uint8_t*>(s.data()), s.size()), 0xBB3D);
}

TEST(Crc16, NibbleTableMatchesBitwiseOnRandomData) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<uint8_t> d(rng() % 40);
    for (auto& b : d) b = static_cast<uint8_t>(rng());
    ASSERT_EQ(Crc16(d.data(), d.size()), Crc16Bitwise(d.data(), d.size()));
  }
}

TEST(Crc16, IncrementalEqualsWhole) {
  const uint8_t d[] = {0x55, 0xAA, 0xFF, 0x12, 1, 2, 3, 4};
  EXPECT_EQ(Crc16(d + 4, 4, Crc16(d, 4)), Crc16(d, 8));
}

TEST(Protocol, HandBuiltFrameDecodesToKnownValues) {
  // gyro x = 0x0100 (256), y = -1 (0xFFFF), z = 0x7FFF; accel x = -32768, y = 2, z = 0;
  // time since PPS 0x01020304, PPS count 9, sequence 200.
  const uint8_t payload[18] = {0x01, 0x00, 0xFF, 0xFF, 0x7F, 0xFF, 0x80, 0x00, 0x00,
                               0x02, 0x00, 0x00, 0x01, 0x02, 0x03, 0x04, 9,    200};
  const HighSpeedRaw raw = DecodeHighSpeedPayload(payload);
  EXPECT_EQ(raw.gyro_counts[0], 256);
  EXPECT_EQ(raw.gyro_counts[1], -1);
  EXPECT_EQ(raw.gyro_counts[2], 32767);
  EXPECT_EQ(raw.accel_counts[0], -32768);
  EXPECT_EQ(raw.accel_counts[1], 2);
  EXPECT_EQ(raw.time_since_pps_100us, 0x01020304u);
  EXPECT_EQ(raw.pps_count, 9);
  EXPECT_EQ(raw.sequence, 200);

  const auto frame = EncodeFrame(0xFF, payload, 18);
  ASSERT_EQ(frame.size(), 24u);
  EXPECT_EQ(frame[0], 0x55);
  EXPECT_EQ(frame[1], 0xAA);
  EXPECT_EQ(frame[2], 0xFF);
  EXPECT_EQ(frame[3], 18);
  const uint16_t crc = Crc16Bitwise(frame.data(), 22);
  EXPECT_EQ(frame[22], crc >> 8);  // big-endian
  EXPECT_EQ(frame[23], crc & 0xFF);
  EXPECT_EQ(EncodeHighSpeedFrame(raw), frame);
}

TEST(Protocol, ScaleFactors) {
  HighSpeedRaw raw;
  raw.gyro_counts = {1092, -1092, 0};    // 1092 * 600 / 65536 = 9.99755859375 deg/s
  raw.accel_counts = {3278, 0, -32768};  // 3278 * 196.1 / 65536 m/s^2
  raw.time_since_pps_100us = 12345;
  const ImuSampleSi si = ToSi(raw);
  EXPECT_NEAR(si.omega_imu_rad_s[0], 9.99755859375 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(si.omega_imu_rad_s[1], -9.99755859375 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(si.accel_imu_m_s2[0], 3278 * 196.1 / 65536.0, 1e-12);
  EXPECT_NEAR(si.accel_imu_m_s2[2], -98.05, 1e-12);
  EXPECT_NEAR(si.time_since_pps_s, 1.2345, 1e-12);
}

TEST(Protocol, SiRoundTripAndSaturation) {
  ImuSampleSi si;
  si.omega_imu_rad_s = {0.5, -1.0, 2.0};
  si.accel_imu_m_s2 = {0.0, 9.81, -3.0};
  const ImuSampleSi back = ToSi(FromSi(si));
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(back.omega_imu_rad_s[i], si.omega_imu_rad_s[i], 0.5 * kGyroDegPerSecPerCount * M_PI / 180);
    EXPECT_NEAR(back.accel_imu_m_s2[i], si.accel_imu_m_s2[i], 0.5 * kAccelMPerS2PerCount);
  }
  si.omega_imu_rad_s = {100.0, -100.0, std::nan("")};
  const HighSpeedRaw sat = FromSi(si);
  EXPECT_EQ(sat.gyro_counts[0], 32767);
  EXPECT_EQ(sat.gyro_counts[1], -32768);
  EXPECT_EQ(sat.gyro_counts[2], 0);
}

TEST(Protocol, OversizedPayloadIsRefused) {
  const uint8_t big[19] = {};
  EXPECT_THROW(EncodeFrame(0xFF, big, 19), std::invalid_argument);
}

TEST(Protocol, TypeTable) {
  EXPECT_TRUE(LookupType(0xFF).known);
  EXPECT_EQ(LookupType(0xFF).payload_bytes, 18);
  EXPECT_EQ(LookupType(0xFE).payload_bytes, 13);
  EXPECT_EQ(LookupType(0x03).payload_bytes, 8);
  EXPECT_TRUE(LookupType(0x1F).known);
  EXPECT_EQ(LookupType(0x1F).payload_bytes, 0);  // defined, length not published
  EXPECT_FALSE(LookupType(0x01).known);          // reserved
  EXPECT_FALSE(LookupType(0x80).known);
}

}  // namespace
}  // namespace imu_driver

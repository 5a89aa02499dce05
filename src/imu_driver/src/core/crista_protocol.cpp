#include "imu_driver/core/crista_protocol.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace imu_driver {
namespace {

// CRC-16/ARC, one nibble at a time: entry i is the CRC register after shifting
// nibble i through the reflected polynomial 0xA001 four times.
constexpr std::array<uint16_t, 16> kCrcNibbleTable = {0x0000, 0xCC01, 0xD801, 0x1400, 0xF001, 0x3C00, 0x2800, 0xE401,
                                                      0xA001, 0x6C00, 0x7800, 0xB401, 0x5000, 0x9C01, 0x8801, 0x4400};

void PutU16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v >> 8);
  p[1] = static_cast<uint8_t>(v);
}
void PutU32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (24 - 8 * i));
}
uint16_t GetU16(const uint8_t* p) { return static_cast<uint16_t>((p[0] << 8) | p[1]); }
uint32_t GetU32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}

int16_t SaturatedCount(double value, double unit) {
  const double c = std::round(value / unit);
  if (!(c == c)) return 0;  // NaN: nothing sensible to send
  if (c > std::numeric_limits<int16_t>::max()) return std::numeric_limits<int16_t>::max();
  if (c < std::numeric_limits<int16_t>::min()) return std::numeric_limits<int16_t>::min();
  return static_cast<int16_t>(c);
}

constexpr double kDegToRad = M_PI / 180.0;

}  // namespace

TypeInfo LookupType(uint8_t type) {
  switch (static_cast<MsgType>(type)) {
    case MsgType::kRawGyro:
    case MsgType::kRawAccel:
      return {true, 7};
    case MsgType::kTiming:
    case MsgType::kResolution:
    case MsgType::kSetSettings:
    case MsgType::kSettings:
    case MsgType::kMfrCalDate:
    case MsgType::kSerialNumConfig:
    case MsgType::kSwVersion:
      return {true, 8};
    case MsgType::kReqConfig:
    case MsgType::kReqCalParam:
      return {true, 1};
    case MsgType::kCalParam:
      return {true, 5};
    case MsgType::kRawGyroTempX:
    case MsgType::kRawGyroTempY:
    case MsgType::kRawGyroTempZ:
      return {true, 4};
    case MsgType::kHighSpeedRaw:
      return {true, 13};
    case MsgType::kHighSpeedConverted:
      return {true, static_cast<uint8_t>(kHighSpeedConvertedBytes)};
    case MsgType::kResUnitsGyro:
    case MsgType::kResUnitsAccel:
    case MsgType::kBoardReference:
    case MsgType::kSensorHeadCrcStatus:
    case MsgType::kGyroStdev:
    case MsgType::kAccelStdev:
    case MsgType::kGyroMinimum:
    case MsgType::kAccelMinimum:
    case MsgType::kGyroMaximum:
    case MsgType::kAccelMaximum:
    case MsgType::kHighSpeedRawGyroTemp:
      return {true, 0};
  }
  return {false, 0};
}

uint16_t Crc16(const uint8_t* data, size_t n, uint16_t crc) {
  for (size_t i = 0; i < n; ++i) {
    crc = static_cast<uint16_t>((crc >> 4) ^ kCrcNibbleTable[(crc ^ data[i]) & 0x0F]);
    crc = static_cast<uint16_t>((crc >> 4) ^ kCrcNibbleTable[(crc ^ (data[i] >> 4)) & 0x0F]);
  }
  return crc;
}

ImuSampleSi ToSi(const HighSpeedRaw& raw) {
  ImuSampleSi si;
  for (int i = 0; i < 3; ++i) {
    si.omega_imu_rad_s[i] = raw.gyro_counts[i] * kGyroDegPerSecPerCount * kDegToRad;
    si.accel_imu_m_s2[i] = raw.accel_counts[i] * kAccelMPerS2PerCount;
  }
  si.time_since_pps_s = raw.time_since_pps_100us * kTimeSincePpsSecPerCount;
  si.pps_count = raw.pps_count;
  si.sequence = raw.sequence;
  return si;
}

HighSpeedRaw FromSi(const ImuSampleSi& si) {
  HighSpeedRaw raw;
  for (int i = 0; i < 3; ++i) {
    raw.gyro_counts[i] = SaturatedCount(si.omega_imu_rad_s[i], kGyroDegPerSecPerCount * kDegToRad);
    raw.accel_counts[i] = SaturatedCount(si.accel_imu_m_s2[i], kAccelMPerS2PerCount);
  }
  const double t = std::round(si.time_since_pps_s / kTimeSincePpsSecPerCount);
  raw.time_since_pps_100us = (t > 0 && t < 4294967295.0) ? static_cast<uint32_t>(t) : 0;
  raw.pps_count = si.pps_count;
  raw.sequence = si.sequence;
  return raw;
}

std::array<uint8_t, kHighSpeedConvertedBytes> EncodeHighSpeedPayload(const HighSpeedRaw& raw) {
  std::array<uint8_t, kHighSpeedConvertedBytes> p{};
  for (int i = 0; i < 3; ++i) {
    PutU16(&p[2 * i], static_cast<uint16_t>(raw.gyro_counts[i]));
    PutU16(&p[6 + 2 * i], static_cast<uint16_t>(raw.accel_counts[i]));
  }
  PutU32(&p[12], raw.time_since_pps_100us);
  p[16] = raw.pps_count;
  p[17] = raw.sequence;
  return p;
}

HighSpeedRaw DecodeHighSpeedPayload(const uint8_t* p) {
  HighSpeedRaw raw;
  for (int i = 0; i < 3; ++i) {
    raw.gyro_counts[i] = static_cast<int16_t>(GetU16(&p[2 * i]));
    raw.accel_counts[i] = static_cast<int16_t>(GetU16(&p[6 + 2 * i]));
  }
  raw.time_since_pps_100us = GetU32(&p[12]);
  raw.pps_count = p[16];
  raw.sequence = p[17];
  return raw;
}

std::vector<uint8_t> EncodeFrame(uint8_t type, const uint8_t* payload, size_t n) {
  if (n > kMaxPayloadBytes) {
    throw std::invalid_argument("EncodeFrame: payload of " + std::to_string(n) + " bytes exceeds " +
                                std::to_string(kMaxPayloadBytes));
  }
  std::vector<uint8_t> f(kHeaderBytes + n + kCrcBytes);
  f[0] = kSync0;
  f[1] = kSync1;
  f[2] = type;
  f[3] = static_cast<uint8_t>(n);
  for (size_t i = 0; i < n; ++i) f[kHeaderBytes + i] = payload[i];
  PutU16(&f[kHeaderBytes + n], Crc16(f.data(), kHeaderBytes + n));
  return f;
}

std::vector<uint8_t> EncodeHighSpeedFrame(const HighSpeedRaw& raw) {
  const auto p = EncodeHighSpeedPayload(raw);
  return EncodeFrame(static_cast<uint8_t>(MsgType::kHighSpeedConverted), p.data(), p.size());
}

}  // namespace imu_driver

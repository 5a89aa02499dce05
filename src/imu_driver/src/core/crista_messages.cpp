#include "imu_driver/core/crista_messages.h"

#include <cmath>
#include <cstring>
#include <sstream>

#include "imu_driver/core/crista_protocol.h"

namespace imu_driver {
namespace {

uint32_t U32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}
float F32(const uint8_t* p) {
  const uint32_t u = U32(p);
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}
void PutU32(std::vector<uint8_t>* v, uint32_t u) {
  for (int i = 0; i < 4; ++i) v->push_back(static_cast<uint8_t>(u >> (24 - 8 * i)));
}
void PutF32(std::vector<uint8_t>* v, float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  PutU32(v, u);
}

// Full scales the driver's fixed conversion assumes (crista_protocol.h).
constexpr double kAssumedGyroRangeDegS = 300.0;
constexpr double kAssumedAccelRangeG = 10.0;

}  // namespace

bool UpdateDeviceInfo(const FrameView& f, DeviceInfo* info) {
  const uint8_t* p = f.payload;
  switch (static_cast<MsgType>(f.type)) {
    case MsgType::kSettings: {
      const uint32_t period_us = U32(p + 4);
      info->oversample_ratio = static_cast<uint16_t>((p[2] << 8) | p[3]);
      info->output_rate_hz = period_us > 0 ? 1e6 / period_us : 0.0;
      info->have_settings = true;
      return true;
    }
    case MsgType::kResolution:
      info->gyro_range_deg_s = F32(p);
      info->accel_range_g = F32(p + 4);
      info->have_resolution = true;
      return true;
    case MsgType::kTiming:
      info->clock_error = static_cast<int16_t>((p[6] << 8) | p[7]);
      info->have_timing = true;
      return true;
    case MsgType::kSwVersion:
      info->software_version = std::to_string(p[0]) + "." + std::to_string(p[1]) + "." + std::to_string(p[2]);
      return true;
    default:
      return false;
  }
}

std::vector<uint8_t> EncodeConfigRequest() {
  const uint8_t payload[1] = {0};
  return EncodeFrame(static_cast<uint8_t>(MsgType::kReqConfig), payload, 1);
}

std::vector<uint8_t> EncodeSettingsPayload(double output_rate_hz, uint16_t oversample_ratio) {
  std::vector<uint8_t> v = {0, 0, static_cast<uint8_t>(oversample_ratio >> 8), static_cast<uint8_t>(oversample_ratio)};
  PutU32(&v, static_cast<uint32_t>(std::lround(1e6 / output_rate_hz)));
  return v;
}

std::vector<uint8_t> EncodeResolutionPayload(float gyro_range_deg_s, float accel_range_g) {
  std::vector<uint8_t> v;
  PutF32(&v, gyro_range_deg_s);
  PutF32(&v, accel_range_g);
  return v;
}

std::string CheckDeviceInfo(const DeviceInfo& info, double rate_hz) {
  const bool rate_differs = info.have_settings && std::abs(info.output_rate_hz - rate_hz) > 0.01 * rate_hz;
  const bool ranges_differ = info.have_resolution && (std::abs(info.gyro_range_deg_s - kAssumedGyroRangeDegS) > 0.5 ||
                                                      std::abs(info.accel_range_g - kAssumedAccelRangeG) > 0.05);
  if (!rate_differs && !ranges_differ) return "";  // the serial reader asks after every read: no stream then
  std::ostringstream why;
  if (rate_differs) {
    why << "the IMU reports " << info.output_rate_hz << " Hz but rate_hz is " << rate_hz << "; ";
  }
  if (ranges_differ) {
    why << "the IMU reports ranges +-" << info.gyro_range_deg_s << " deg/s, +-" << info.accel_range_g
        << " g; the driver's scale assumes +-300 deg/s, +-10 g; ";
  }
  std::string s = why.str();
  if (!s.empty()) s.resize(s.size() - 2);
  return s;
}

}  // namespace imu_driver

// The Crista's configuration and telemetry replies other than the 0xFF data
// message, decoded as in Cloud Cap's host code (DecodeSettingsPacket,
// DecodeResolutionPacket, DecodeTimingPacket, DecodeSoftwareVersionPacket).
// The driver asks for them on connect (kReqConfig) and checks them against its
// configuration: a different output rate or sensor range would silently
// corrupt every timestamp or every value.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "imu_driver/core/crista_parser.h"

namespace imu_driver {

struct DeviceInfo {
  bool have_settings = false;
  double output_rate_hz = 0.0;  // 1e6 / period_us
  uint16_t oversample_ratio = 0;
  bool have_resolution = false;
  double gyro_range_deg_s = 0.0;  // full scale is ± this
  double accel_range_g = 0.0;
  bool have_timing = false;
  int16_t clock_error = 0;       // vendor units, as reported
  std::string software_version;  // "major.minor.sub" once reported
};

// Updates info from a frame of a type it knows; returns false for other types.
bool UpdateDeviceInfo(const FrameView& frame, DeviceInfo* info);

// What the driver sends on connect: request all configuration messages.
std::vector<uint8_t> EncodeConfigRequest();

// Payload builders for simulators and tests.
std::vector<uint8_t> EncodeSettingsPayload(double output_rate_hz, uint16_t oversample_ratio);
std::vector<uint8_t> EncodeResolutionPayload(float gyro_range_deg_s, float accel_range_g);

// Empty when the reported device matches the scale and rate the driver
// assumes (DESIGN.md: ±300 deg/s, ±10 g, rate_hz); otherwise why not.
std::string CheckDeviceInfo(const DeviceInfo& info, double rate_hz);

}  // namespace imu_driver

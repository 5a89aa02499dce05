#include "rig_sim/crista_link.h"

#include <cmath>

namespace rig_sim {

imu_driver::HighSpeedRaw ToCristaRaw(const ImuSample& sample, uint8_t sequence) {
  imu_driver::HighSpeedRaw raw;
  for (int i = 0; i < 3; ++i) {
    raw.gyro_counts[i] = sample.gyro_raw[i];
    raw.accel_counts[i] = sample.accel_raw[i];
  }
  const double whole_s = std::floor(sample.stamp_s);
  raw.time_since_pps_100us =
      static_cast<uint32_t>(std::llround((sample.stamp_s - whole_s) / imu_driver::kTimeSincePpsSecPerCount));
  raw.pps_count = static_cast<uint8_t>(static_cast<int64_t>(whole_s) & 0xFF);
  raw.sequence = sequence;
  return raw;
}

std::vector<uint8_t> EncodeCristaPacket(const ImuSample& sample, uint8_t sequence) {
  return imu_driver::EncodeHighSpeedFrame(ToCristaRaw(sample, sequence));
}

}  // namespace rig_sim

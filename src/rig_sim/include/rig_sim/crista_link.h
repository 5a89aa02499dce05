// The simulated IMU's samples as the Crista's wire packets. The protocol
// (framing, CRC-16/ARC, scales, the pseudo-terminal) is imu_driver's: the
// simulator speaks exactly what the driver parses, from one implementation.
#pragma once

#include <cstdint>
#include <vector>

#include "imu_driver/core/crista_protocol.h"
#include "rig_sim/imu_model.h"

namespace rig_sim {

// The 0xFF high-speed message for `sample`. The rig's PPS pulse is taken to
// fall on every whole second of the sample's stamp: time since PPS is the
// fraction of the second (in the Crista's 100 µs steps), the PPS count is the
// whole seconds modulo 256.
imu_driver::HighSpeedRaw ToCristaRaw(const ImuSample& sample, uint8_t sequence);

// The framed bytes of that message, ready for the serial line.
std::vector<uint8_t> EncodeCristaPacket(const ImuSample& sample, uint8_t sequence);

}  // namespace rig_sim

// The Crista IMU's serial byte stream (DESIGN.md, last paragraph): sync 0x55
// 0xAA, message type, payload length, payload, then CRC-16/ARC (reflected
// 0xA001 polynomial, nibble table) over sync + header + payload, big-endian.
// The high-speed converted-data message, type 0xFF, has an 18-byte
// big-endian payload: gyro x y z, accel x y z (int16 counts), uint32 time
// since PPS, uint8 PPS count, uint8 sequence number. ROS-free.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rig_sim/imu_model.h"

namespace rig_sim {

constexpr uint8_t kCristaSync0 = 0x55;
constexpr uint8_t kCristaSync1 = 0xAA;
constexpr uint8_t kCristaTypeHighSpeed = 0xFF;
constexpr size_t kCristaHighSpeedPayload = 18;
constexpr size_t kCristaHighSpeedPacket = 2 + 2 + kCristaHighSpeedPayload + 2;

uint16_t Crc16Arc(const uint8_t* data, size_t size);

// time_since_pps in microseconds (the unit the simulator uses for that field).
std::vector<uint8_t> EncodeCristaHighSpeed(const ImuSample& sample, uint32_t time_since_pps_us, uint8_t pps_count,
                                           uint8_t sequence);

// A pseudo-terminal whose slave side behaves like the Crista's serial port
// (raw, 115200 baud). Writes never block: when nobody reads and the buffer is
// full, packets are dropped and counted.
class CristaPty {
 public:
  CristaPty();  // throws std::runtime_error with the failing call's message
  ~CristaPty();
  CristaPty(const CristaPty&) = delete;
  CristaPty& operator=(const CristaPty&) = delete;
  const std::string& slave_path() const { return slave_path_; }
  // Also makes `link_path` a symlink to the slave (replacing an old symlink).
  bool Link(const std::string& link_path, std::string* error);
  bool Write(const std::vector<uint8_t>& bytes);
  uint64_t dropped() const { return dropped_; }

 private:
  int master_fd_ = -1;
  int slave_fd_ = -1;  // held open so writes succeed before a reader connects
  std::string slave_path_, link_path_;
  uint64_t dropped_ = 0;
};

}  // namespace rig_sim

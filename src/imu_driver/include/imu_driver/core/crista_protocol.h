// The Cloud Cap Crista IMU serial format (thesis 3.2; DESIGN.md, last paragraph).
//
// Frame: 0x55 0xAA, type (u8), payload length (u8), payload, CRC-16 (big-endian)
// over sync + header + payload. The CRC is CRC-16/ARC (reflected 0xA001, init 0),
// computed with the vendor's 16-entry nibble table.
//
// Message types: the numbering follows Cloud Cap's published host code
// (IMUPacket.h, enum IMUMessageTypes, and its Decode* functions, which give the
// payload layouts). The rig streams only kHighSpeedConverted (0xFF); the other
// telemetry and configuration replies are recognised, length-checked and
// counted, and the ones whose layout is published are decoded where useful.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace imu_driver {

constexpr uint8_t kSync0 = 0x55;
constexpr uint8_t kSync1 = 0xAA;
constexpr size_t kHeaderBytes = 4;  // sync0, sync1, type, length
constexpr size_t kCrcBytes = 2;
constexpr size_t kMaxPayloadBytes = 18;  // vendor's MAX_PAYLOAD_BYTES
constexpr size_t kMaxFrameBytes = kHeaderBytes + kMaxPayloadBytes + kCrcBytes;

enum class MsgType : uint8_t {
  kRawGyro = 0x00,     // 3 x u16 A/D counts + seq
  kRawAccel = 0x02,    // 3 x u16 A/D counts + seq
  kTiming = 0x03,      // u32 time since PPS (100 us), u8 PPS count, u8 seq, s16 clock error
  kResolution = 0x04,  // f32 gyro range (deg/s), f32 accel range (g)
  kResUnitsGyro = 0x05,
  kResUnitsAccel = 0x06,
  kSetSettings = 0x07,  // host -> IMU
  kSettings = 0x08,     // u8 device, u8 mode, u16 oversample, u32 period (us)
  kMfrCalDate = 0x09,
  kSerialNumConfig = 0x0A,
  kSwVersion = 0x0B,
  kBoardReference = 0x0C,
  kReqConfig = 0x0D,    // host -> IMU
  kReqCalParam = 0x16,  // host -> IMU
  kCalParam = 0x17,
  kRawGyroTempX = 0x18,  // f32 volts
  kRawGyroTempY = 0x19,
  kRawGyroTempZ = 0x1A,
  kSensorHeadCrcStatus = 0x1C,
  kGyroStdev = 0x1F,
  kAccelStdev = 0x20,
  kGyroMinimum = 0x21,
  kAccelMinimum = 0x22,
  kGyroMaximum = 0x23,
  kAccelMaximum = 0x24,
  kHighSpeedRawGyroTemp = 0xFD,
  kHighSpeedRaw = 0xFE,        // 6 x u16 A/D counts + seq
  kHighSpeedConverted = 0xFF,  // the 100 Hz data message
};

// What the parser knows about a type: whether it is defined, and its payload
// length when the vendor code fixes it (0 = defined but length not published;
// then any length up to kMaxPayloadBytes is accepted).
struct TypeInfo {
  bool known = false;
  uint8_t payload_bytes = 0;
};
TypeInfo LookupType(uint8_t type);

constexpr size_t kHighSpeedConvertedBytes = 18;

// CRC-16/ARC with the 16-entry nibble table (check value 0xBB3D for "123456789").
uint16_t Crc16(const uint8_t* data, size_t n, uint16_t crc = 0);

// The 0xFF message, raw integers as on the wire.
struct HighSpeedRaw {
  std::array<int16_t, 3> gyro_counts{};
  std::array<int16_t, 3> accel_counts{};
  uint32_t time_since_pps_100us = 0;
  uint8_t pps_count = 0;
  uint8_t sequence = 0;
};

// Scale factors from DESIGN.md: ±300 deg/s and ±98.05 m/s² (±10 g) over 16 bits.
constexpr double kGyroDegPerSecPerCount = 600.0 / 65536.0;
constexpr double kAccelMPerS2PerCount = 196.1 / 65536.0;
constexpr double kTimeSincePpsSecPerCount = 1e-4;

// Converted sample in SI units, in the IMU frame {I}.
struct ImuSampleSi {
  std::array<double, 3> omega_imu_rad_s{};
  std::array<double, 3> accel_imu_m_s2{};
  double time_since_pps_s = 0.0;
  uint8_t pps_count = 0;
  uint8_t sequence = 0;
};

ImuSampleSi ToSi(const HighSpeedRaw& raw);
// Inverse of ToSi up to rounding; saturates at the int16 range (used by simulators).
HighSpeedRaw FromSi(const ImuSampleSi& si);

// Payload codec for 0xFF. Decode requires exactly kHighSpeedConvertedBytes.
std::array<uint8_t, kHighSpeedConvertedBytes> EncodeHighSpeedPayload(const HighSpeedRaw& raw);
HighSpeedRaw DecodeHighSpeedPayload(const uint8_t* payload);

// Whole frame: sync, header, payload, big-endian CRC. Throws std::invalid_argument
// when the payload exceeds kMaxPayloadBytes.
std::vector<uint8_t> EncodeFrame(uint8_t type, const uint8_t* payload, size_t n);
std::vector<uint8_t> EncodeHighSpeedFrame(const HighSpeedRaw& raw);

}  // namespace imu_driver

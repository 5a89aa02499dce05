// From serial bytes to timestamped IMU samples: framing (CristaParser),
// decoding of the 0xFF message, sequence-gap detection and the clock model
// (TimeSync). ROS-free; the serial reader and the nodelet feed it.
#pragma once

#include <array>
#include <cstdint>
#include <functional>

#include "imu_driver/core/crista_messages.h"
#include "imu_driver/core/crista_parser.h"
#include "imu_driver/core/crista_protocol.h"
#include "imu_driver/core/time_sync.h"

namespace imu_driver {

struct StreamConfig {
  int baud = 115200;
  double rate_hz = 100.0;  // nominal output rate: the tick of the sequence clock
  // The device clock the timestamps are modelled on: the sequence counter
  // (ticks / rate_hz; the rig has no GPS), or the PPS fields (PPS count +
  // time since PPS), which follow a GPS pulse when one is wired to the IMU.
  enum class TimeSource { kSequence, kPps };
  TimeSource time_source = TimeSource::kSequence;
  TimeSyncConfig time_sync;
  // A host-clock step between two samples larger than this (or backwards) is a
  // clock jump (sim time starting, a bag loop), not an outage to bridge.
  double max_outage_s = 3600.0;
};

struct ImuSample {
  ImuSampleSi si;
  uint64_t device_ticks = 0;  // unwrapped sequence number since the first sample
  double arrival_s = 0.0;     // host time of the first byte, corrected for transmission
  double stamp_s = 0.0;       // arrival smoothed by the clock model: what gets published
};

struct StreamCounts {
  uint64_t samples = 0;                        // 0xFF messages delivered
  uint64_t sequence_gaps = 0;                  // events where at least one sample was missing
  uint64_t samples_missed = 0;                 // sum of the gap sizes
  uint64_t sequence_repeats = 0;               // same sequence number twice in a row
  uint64_t host_clock_jumps = 0;               // arrival clock went back or leapt: not used to bridge wraps
  std::array<uint64_t, 256> frames_by_type{};  // every CRC-valid frame of a defined type
  DeviceInfo device;                           // from the configuration replies
};

class CristaStream {
 public:
  using SampleCallback = std::function<void(const ImuSample&)>;

  CristaStream(const StreamConfig& config, SampleCallback on_sample);

  // Bytes from one read(), with the host time the read returned.
  void Feed(const uint8_t* data, size_t n, double read_time_s);
  // The port closed: resolve pending bytes and forget sequence continuity
  // (the clock model keeps running; a restarted IMU makes it reset itself).
  void EndOfStream();

  const ParserCounts& parser_counts() const { return parser_.counts(); }
  const StreamCounts& counts() const { return counts_; }
  TimeSync& time_sync() { return time_sync_; }

 private:
  void OnFrame(const FrameView& frame);
  uint64_t UnwrapSequence(uint8_t seq, double arrival_s);
  double HostGapS(double arrival_s);  // host-clock gap since the last sample; 0 on a clock jump
  double PpsDeviceTime(const ImuSampleSi& si);

  StreamConfig config_;
  SampleCallback on_sample_;
  CristaParser parser_;
  TimeSync time_sync_;
  StreamCounts counts_;
  double byte_time_s_;
  double read_time_s_ = 0.0;  // of the chunk being parsed
  bool have_sequence_ = false;
  uint8_t last_sequence_ = 0;
  uint64_t ticks_ = 0;
  double last_arrival_s_ = 0.0;
  double last_stamp_s_ = 0.0;
  bool have_pps_ = false;
  uint8_t last_pps_count_ = 0;
  uint64_t pps_wraps_ = 0;  // the PPS count is 8-bit: it wraps every 256 s
};

}  // namespace imu_driver

#include "imu_driver/core/crista_stream.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace imu_driver {

CristaStream::CristaStream(const StreamConfig& config, SampleCallback on_sample)
    : config_(config),
      on_sample_(std::move(on_sample)),
      parser_([this](const FrameView& f) { OnFrame(f); }),
      time_sync_(config.time_sync),
      byte_time_s_(config.baud > 0 ? 10.0 / config.baud : 0.0) {
  if (config.baud <= 0 || !(config.rate_hz > 0.0)) {
    throw std::invalid_argument("CristaStream: baud and rate_hz must be positive");
  }
}

void CristaStream::Feed(const uint8_t* data, size_t n, double read_time_s) {
  read_time_s_ = read_time_s;
  parser_.Feed(data, n);
}

void CristaStream::EndOfStream() {
  parser_.Flush();
  have_sequence_ = false;
}

double CristaStream::HostGapS(double arrival_s) {
  const double gap_s = arrival_s - last_arrival_s_;
  if (gap_s >= 0.0 && gap_s <= config_.max_outage_s) return gap_s;
  // Sim time starting from 0, or a bag loop: the arrival clock stepped, so it
  // says nothing about samples missed (it once made a sequence gap of 1.7e11).
  ++counts_.host_clock_jumps;
  return 0.0;
}

uint64_t CristaStream::UnwrapSequence(uint8_t seq, double arrival_s) {
  if (!have_sequence_) {
    have_sequence_ = true;
    last_sequence_ = seq;
    // After a reconnect the counter may have restarted: bridge the outage with
    // the host clock so the device time keeps increasing.
    if (counts_.samples > 0) {
      const double gap_s = HostGapS(arrival_s);
      ticks_ += static_cast<uint64_t>(std::max<int64_t>(1, std::llround(gap_s * config_.rate_hz)));
    }
    return ticks_;
  }
  int64_t delta = static_cast<uint8_t>(seq - last_sequence_);
  // The 8-bit counter wraps every 256 samples; after a long outage the host
  // clock says how many wraps were missed.
  const double expected = HostGapS(arrival_s) * config_.rate_hz;
  if (expected > 128.0) delta += 256 * std::llround((expected - static_cast<double>(delta)) / 256.0);
  last_sequence_ = seq;
  if (delta == 0) {
    ++counts_.sequence_repeats;
  } else if (delta > 1) {
    ++counts_.sequence_gaps;
    counts_.samples_missed += static_cast<uint64_t>(delta - 1);
  }
  ticks_ += static_cast<uint64_t>(delta);
  return ticks_;
}

double CristaStream::PpsDeviceTime(const ImuSampleSi& si) {
  if (have_pps_ && si.pps_count < last_pps_count_) ++pps_wraps_;
  have_pps_ = true;
  last_pps_count_ = si.pps_count;
  return static_cast<double>(pps_wraps_ * 256 + si.pps_count) + si.time_since_pps_s;
}

void CristaStream::OnFrame(const FrameView& frame) {
  ++counts_.frames_by_type[frame.type];
  if (frame.type != static_cast<uint8_t>(MsgType::kHighSpeedConverted)) {
    UpdateDeviceInfo(frame, &counts_.device);
    return;
  }
  // Host time at which the frame's first byte was sent: the read returned after
  // the chunk's last byte, and each byte takes 10 bit times at 8N1.
  const uint64_t bytes_after = parser_.counts().bytes_in - frame.end_offset;
  const size_t frame_bytes = kHeaderBytes + frame.payload_bytes + kCrcBytes;
  ImuSample s;
  s.arrival_s = read_time_s_ - static_cast<double>(bytes_after + frame_bytes) * byte_time_s_;
  s.si = ToSi(DecodeHighSpeedPayload(frame.payload));
  const uint64_t before = ticks_;
  const bool first = counts_.samples == 0;
  s.device_ticks = UnwrapSequence(s.si.sequence, s.arrival_s);
  if (!first && s.device_ticks == before) {
    s.stamp_s = last_stamp_s_;  // repeated sequence: no new device time to model
  } else {
    const double device_s = config_.time_source == StreamConfig::TimeSource::kPps
                                ? PpsDeviceTime(s.si)
                                : static_cast<double>(s.device_ticks) / config_.rate_hz;
    s.stamp_s = time_sync_.Update(device_s, s.arrival_s);
  }
  last_arrival_s_ = s.arrival_s;
  last_stamp_s_ = s.stamp_s;
  ++counts_.samples;
  on_sample_(s);
}

}  // namespace imu_driver

// Byte-stream framing for the Crista format: a resynchronising state machine.
//
// Rule that makes "nothing valid is lost" hold: a candidate frame is only
// skipped whole when its CRC is right; any rejected candidate advances the
// scan by a single byte, so a valid frame that starts inside garbage or inside
// a corrupt frame is still found. Every input byte ends up either in an
// accepted frame, in the garbage count, or (briefly) pending.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "imu_driver/core/crista_protocol.h"

namespace imu_driver {

// A CRC-valid frame. payload points into the parser's or the caller's buffer and
// is valid only during the callback.
struct FrameView {
  uint8_t type = 0;
  const uint8_t* payload = nullptr;
  uint8_t payload_bytes = 0;
  uint64_t end_offset = 0;  // stream offset (bytes since construction) just past the frame
};

struct ParserCounts {
  uint64_t bytes_in = 0;
  uint64_t bytes_accepted = 0;  // in CRC-valid frames (any type)
  uint64_t garbage_bytes = 0;   // skipped while looking for a frame
  uint64_t frames_ok = 0;       // CRC-valid frames of a defined type
  uint64_t bad_crc = 0;
  uint64_t bad_length = 0;    // length above kMaxPayloadBytes or not the type's fixed length
  uint64_t unknown_type = 0;  // CRC-valid frame of a type the format does not define
  uint64_t truncated = 0;     // frame cut short: the next sync starts inside it, or the stream ended
};

class CristaParser {
 public:
  using FrameCallback = std::function<void(const FrameView&)>;

  explicit CristaParser(FrameCallback on_frame) : on_frame_(std::move(on_frame)) {}

  // Consumes n bytes; calls on_frame for each valid frame of a defined type, in order.
  void Feed(const uint8_t* data, size_t n);
  // End of stream (port closed, device unplugged): whatever is pending can never
  // complete, so it is resolved now (a cut frame counts as truncated).
  void Flush();

  const ParserCounts& counts() const { return counts_; }
  size_t pending_bytes() const { return pending_.size(); }

 private:
  // Parses buf[0, n) and returns how many bytes were consumed. With at_end, a
  // candidate that cannot complete is rejected instead of waited for.
  size_t Parse(const uint8_t* buf, size_t n, bool at_end);

  FrameCallback on_frame_;
  uint64_t base_offset_ = 0;      // stream offset of buf[0] during Parse
  std::vector<uint8_t> pending_;  // unconsumed tail, always shorter than kMaxFrameBytes
  ParserCounts counts_;
};

}  // namespace imu_driver

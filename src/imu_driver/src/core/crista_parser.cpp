#include "imu_driver/core/crista_parser.h"

#include <cstring>

namespace imu_driver {
namespace {

// True when a sync pair starts at some offset in [from, to) of the frame at p:
// the sign of a frame cut short by the start of the next one.
bool HasInnerSync(const uint8_t* p, size_t from, size_t to) {
  for (size_t k = from; k + 1 < to; ++k) {
    if (p[k] == kSync0 && p[k + 1] == kSync1) return true;
  }
  return false;
}

}  // namespace

void CristaParser::Feed(const uint8_t* data, size_t n) {
  counts_.bytes_in += n;
  if (pending_.empty()) {
    // Fast path: parse the caller's buffer in place, keep only the tail.
    base_offset_ = counts_.bytes_in - n;
    const size_t used = Parse(data, n, false);
    pending_.assign(data + used, data + n);
    return;
  }
  pending_.insert(pending_.end(), data, data + n);
  base_offset_ = counts_.bytes_in - pending_.size();
  const size_t used = Parse(pending_.data(), pending_.size(), false);
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(used));
}

void CristaParser::Flush() {
  base_offset_ = counts_.bytes_in - pending_.size();
  const size_t used = Parse(pending_.data(), pending_.size(), true);
  (void)used;  // at_end consumes everything
  pending_.clear();
}

size_t CristaParser::Parse(const uint8_t* buf, size_t n, bool at_end) {
  size_t i = 0;
  while (i < n) {
    if (buf[i] != kSync0) {
      const void* hit = std::memchr(buf + i, kSync0, n - i);
      const size_t next = hit ? static_cast<size_t>(static_cast<const uint8_t*>(hit) - buf) : n;
      counts_.garbage_bytes += next - i;
      i = next;
      continue;
    }
    const size_t left = n - i;
    if (left < kHeaderBytes) {
      if (!at_end) break;
      if (left >= 2 && buf[i + 1] == kSync1) ++counts_.truncated;
      ++counts_.garbage_bytes;
      ++i;
      continue;
    }
    if (buf[i + 1] != kSync1) {
      ++counts_.garbage_bytes;
      ++i;
      continue;
    }
    const uint8_t type = buf[i + 2];
    const uint8_t len = buf[i + 3];
    const TypeInfo info = LookupType(type);
    if (len > kMaxPayloadBytes || (info.known && info.payload_bytes != 0 && len != info.payload_bytes)) {
      ++counts_.bad_length;
      ++counts_.garbage_bytes;
      ++i;
      continue;
    }
    const size_t frame = kHeaderBytes + len + kCrcBytes;
    if (left < frame) {
      if (!at_end) break;
      ++counts_.truncated;
      ++counts_.garbage_bytes;
      ++i;
      continue;
    }
    const uint8_t* f = buf + i;
    const uint16_t crc_wire = static_cast<uint16_t>((f[kHeaderBytes + len] << 8) | f[kHeaderBytes + len + 1]);
    if (Crc16(f, kHeaderBytes + len) != crc_wire) {
      if (HasInnerSync(f, 2, frame)) {
        ++counts_.truncated;
      } else {
        ++counts_.bad_crc;
      }
      ++counts_.garbage_bytes;
      ++i;
      continue;
    }
    counts_.bytes_accepted += frame;
    i += frame;
    if (!info.known) {
      ++counts_.unknown_type;
      continue;
    }
    ++counts_.frames_ok;
    on_frame_(FrameView{type, f + kHeaderBytes, len, base_offset_ + i});
  }
  return i;
}

}  // namespace imu_driver

// Test-only generator of Crista byte streams: valid 0xFF frames, garbage and
// each kind of corrupt frame, with the counts a correct parser must report.
#pragma once

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "imu_driver/core/crista_parser.h"
#include "imu_driver/core/crista_protocol.h"

namespace imu_driver {
namespace test {

inline bool HasSyncPairAfterStart(const std::vector<uint8_t>& f) {
  for (size_t k = 1; k + 1 < f.size(); ++k) {
    if (f[k] == kSync0 && f[k + 1] == kSync1) return true;
  }
  return false;
}

inline HighSpeedRaw RandomRaw(std::mt19937& rng, uint8_t seq) {
  std::uniform_int_distribution<int> v(-32768, 32767);
  HighSpeedRaw r;
  for (int i = 0; i < 3; ++i) {
    r.gyro_counts[i] = static_cast<int16_t>(v(rng));
    r.accel_counts[i] = static_cast<int16_t>(v(rng));
  }
  r.time_since_pps_100us = static_cast<uint32_t>(rng());
  r.pps_count = static_cast<uint8_t>(rng());
  r.sequence = seq;
  return r;
}

// A random valid frame; with clean, one with no sync pair after its start, so
// that corrupting it produces exactly one reject event.
inline HighSpeedRaw RandomFrame(std::mt19937& rng, uint8_t seq, bool clean, std::vector<uint8_t>* bytes) {
  for (;;) {
    HighSpeedRaw r = RandomRaw(rng, seq);
    *bytes = EncodeHighSpeedFrame(r);
    if (!clean || !HasSyncPairAfterStart(*bytes)) return r;
  }
}

inline bool SameRaw(const HighSpeedRaw& a, const HighSpeedRaw& b) {
  return a.gyro_counts == b.gyro_counts && a.accel_counts == b.accel_counts &&
         a.time_since_pps_100us == b.time_since_pps_100us && a.pps_count == b.pps_count && a.sequence == b.sequence;
}

// A stream whose reject counts are known exactly: garbage never contains a
// sync byte and frames have no inner sync pair, so every corruption is one
// event of a known kind.
struct ScriptedStream {
  std::vector<uint8_t> bytes;
  std::vector<HighSpeedRaw> valid;  // in order
  ParserCounts expected;
};

inline ScriptedStream MakeScriptedStream(std::mt19937& rng, int num_slots) {
  ScriptedStream s;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto garbage_byte = [&rng]() {
    for (;;) {
      const uint8_t b = static_cast<uint8_t>(rng());
      if (b != kSync0 && b != kSync1) return b;
    }
  };
  auto append = [&s](const std::vector<uint8_t>& f) { s.bytes.insert(s.bytes.end(), f.begin(), f.end()); };
  bool prev_truncated = false;  // garbage right after a cut frame would hide the cut
  for (int slot = 0; slot < num_slots; ++slot) {
    if (!prev_truncated && u(rng) < 0.2) {
      const int n = 1 + static_cast<int>(rng() % 30);
      for (int i = 0; i < n; ++i) s.bytes.push_back(garbage_byte());
      s.expected.garbage_bytes += n;
    }
    std::vector<uint8_t> f;
    const HighSpeedRaw raw = RandomFrame(rng, static_cast<uint8_t>(slot), true, &f);
    const double pick = u(rng);
    prev_truncated = false;
    if (pick < 0.06) {  // bad CRC: one payload byte changed to a value that is no sync byte
      const size_t k = kHeaderBytes + rng() % kHighSpeedConvertedBytes;
      uint8_t b;
      do b = static_cast<uint8_t>(rng());
      while (b == f[k] || b == kSync0 || b == kSync1);
      f[k] = b;
      if (HasSyncPairAfterStart(f)) continue;  // would be two events; keep the script exact
      ++s.expected.bad_crc;
      s.expected.garbage_bytes += f.size();
      append(f);
    } else if (pick < 0.10) {  // bad length for the 0xFF type
      f[3] = (rng() % 2) ? 17 : static_cast<uint8_t>(19 + rng() % 60);
      if (f[3] == kSync0 || f[3] == kSync1) f[3] = 30;
      ++s.expected.bad_length;
      s.expected.garbage_bytes += f.size();
      append(f);
    } else if (pick < 0.13) {  // a CRC-valid frame of an undefined type
      std::vector<uint8_t> payload(rng() % 10);
      for (auto& b : payload) b = garbage_byte();
      std::vector<uint8_t> g = EncodeFrame(0x01, payload.data(), payload.size());
      if (HasSyncPairAfterStart(g)) continue;
      ++s.expected.unknown_type;
      s.expected.bytes_accepted += g.size();
      append(g);
    } else if (pick < 0.17) {              // cut short: the next frame starts inside it
      const size_t keep = 4 + rng() % 19;  // header complete, next sync pair inside the 24-byte window
      f.resize(keep);
      prev_truncated = true;
      ++s.expected.truncated;
      s.expected.garbage_bytes += keep;
      append(f);
    } else {
      s.valid.push_back(raw);
      s.expected.frames_ok++;
      s.expected.bytes_accepted += f.size();
      append(f);
    }
  }
  // A final valid frame so that a truncated frame is never last.
  std::vector<uint8_t> f;
  s.valid.push_back(RandomFrame(rng, static_cast<uint8_t>(num_slots), true, &f));
  s.expected.frames_ok++;
  s.expected.bytes_accepted += f.size();
  append(f);
  s.expected.bytes_in = s.bytes.size();
  return s;
}

// Unconstrained fuzz: random bytes (sync bytes over-represented) between frames
// and inserted inside 10 % of them. valid lists the frames that survive intact.
struct RandomStream {
  std::vector<uint8_t> bytes;
  std::vector<HighSpeedRaw> valid;
};

inline RandomStream MakeRandomStream(std::mt19937& rng, int num_frames) {
  RandomStream s;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto noisy_byte = [&]() -> uint8_t {
    const double p = u(rng);
    return p < 0.2 ? 0x55 : p < 0.4 ? 0xAA : p < 0.45 ? 0xFF : p < 0.5 ? 18 : static_cast<uint8_t>(rng());
  };
  for (int k = 0; k < num_frames; ++k) {
    const int gap = u(rng) < 0.5 ? static_cast<int>(rng() % 40) : 0;
    for (int i = 0; i < gap; ++i) s.bytes.push_back(noisy_byte());
    std::vector<uint8_t> f;
    const HighSpeedRaw raw = RandomFrame(rng, static_cast<uint8_t>(k), false, &f);
    const std::vector<uint8_t> original = f;
    if (u(rng) < 0.1) {  // random bytes inside the frame: it must not be delivered
      const size_t at = 1 + rng() % (f.size() - 1);
      const int n = 1 + static_cast<int>(rng() % 5);
      for (int i = 0; i < n; ++i) f.insert(f.begin() + static_cast<std::ptrdiff_t>(at), noisy_byte());
    }
    // Some insertions leave the frame intact (a copy of the next byte, a 0x55
    // before the sync): then it is valid and must come out.
    if (std::search(f.begin(), f.end(), original.begin(), original.end()) != f.end()) s.valid.push_back(raw);
    s.bytes.insert(s.bytes.end(), f.begin(), f.end());
  }
  return s;
}

}  // namespace test
}  // namespace imu_driver
